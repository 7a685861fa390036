"""Starts `ray view` on a free port of 127.0.0.1 and talks to it (shared by the viewer tests).
The viewer's access token is read from the URL it prints and sent with every request
(Authorization: token ...); pass "--no-token" to start it open. Everything it prints is kept
in `output` (read on a thread of its own, so that the pipe never fills)."""
import http.client
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time


class Viewer:
    def __init__(self, ray, scene, *extra, new_file=False, folder_prefix="ray_view_"):
        """new_file: `scene` is only a name: the viewer opens it in an empty folder, where it
        does not exist yet (a new scene). folder_prefix: the start of that folder's name (bytes
        that are not UTF-8 as surrogate escapes: os.fsdecode)."""
        self.folder = tempfile.mkdtemp(prefix=folder_prefix)
        self.scene = os.path.join(self.folder, os.path.basename(scene))
        if not new_file:
            shutil.copy(scene, self.scene)  # a copy the tests may edit (the watcher)
        # Unsaved edits a stopped viewer keeps (viewer/recovery.h) go to a scratch state
        # folder, never the user's.
        self.state = tempfile.mkdtemp(prefix="ray_view_state_")
        self.process = subprocess.Popen([ray, "view", self.scene, "--port", "0", *extra],
                                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                        env=dict(os.environ, XDG_STATE_HOME=self.state),
                                        errors="replace")  # a path's bytes that are not UTF-8
        line = self.process.stdout.readline()
        match = re.search(r"http://127\.0\.0\.1:(\d+)/(\?token=([0-9a-f]+))?$", line.strip())
        if not match:
            self.process.kill()
            raise RuntimeError("ray view did not start: " + line + self.process.stdout.read())
        self.port = int(match.group(1))
        self.token = match.group(3)  # None with --no-token
        self.url = match.group(0)    # what a user opens: with the token
        self.output = [line]
        self.reader = threading.Thread(target=self._read_output, daemon=True)
        self.reader.start()

    def _read_output(self):
        for line in self.process.stdout:
            self.output.append(line)

    def auth_headers(self):
        return {"Authorization": f"token {self.token}"} if self.token else {}

    def request(self, method, path, body=None, timeout=30, headers=None):
        """headers: None sends the token (if any) and, with a body, Content-Type: application/json,
        as the page does; a dict sends exactly those headers."""
        if headers is None:
            headers = self.auth_headers()
            if body is not None:
                headers["Content-Type"] = "application/json"
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        connection.request(method, path, body=body, headers=headers)
        response = connection.getresponse()
        data = response.read()
        connection.close()
        return response.status, data

    def json(self, method, path, body=None, headers=None, timeout=30):
        status, data = self.request(method, path, body, timeout=timeout, headers=headers)
        return status, json.loads(data) if data else None

    def alive(self):
        return self.process.poll() is None

    def rss_kib(self):
        with open(f"/proc/{self.process.pid}/status") as f:
            return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))

    def events(self, timeout=120):
        """An open /events stream (an http.client response)."""
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        connection.request("GET", "/events", headers=self.auth_headers())
        return connection.getresponse()

    def wait_frame_done(self, timeout=120, final=False):
        """Reads /events until a `done` event (with final: of a view at rest) arrives; returns its data."""
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        connection.request("GET", "/events", headers=self.auth_headers())
        response = connection.getresponse()
        event = None
        deadline = time.time() + timeout
        while time.time() < deadline:
            line = response.fp.readline().decode()
            if line.startswith("event: "):
                event = line[7:].strip()
            elif line.startswith("data: ") and event == "done":
                done = json.loads(line[6:])
                if final and not done.get("final"):
                    continue
                connection.close()
                return done
        connection.close()
        raise TimeoutError("no complete frame")

    def close(self):
        self.process.terminate()
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
        self.reader.join(5)
        shutil.rmtree(self.folder, ignore_errors=True)
        shutil.rmtree(self.state, ignore_errors=True)

    def log(self):
        """Everything the viewer printed so far."""
        return "".join(self.output)


def headless_chromium_or_skip(width, height):
    """A headless Chromium (Selenium's Chrome driver) with a width x height window, as the
    browser tests use it; prints SKIPPED and exits when Selenium, Chromium or chromedriver
    is missing."""
    try:
        from selenium import webdriver
    except ImportError:
        print("SKIPPED: python3-selenium is not installed")
        sys.exit(0)
    if not shutil.which("chromedriver") or not (shutil.which("chromium") or shutil.which("chromium-browser")):
        print("SKIPPED: chromium or chromium-driver is not installed")
        sys.exit(0)
    options = webdriver.ChromeOptions()
    # WebGL (the studio's gizmo) in software: Chromium no longer falls back to it unasked.
    for flag in ["--headless=new", "--no-sandbox", "--disable-gpu", f"--window-size={width},{height}",
                 "--disable-dev-shm-usage", "--enable-unsafe-swiftshader"]:
        options.add_argument(flag)
    return webdriver.Chrome(options=options)


def wait_for(driver, condition, timeout=120):
    """Polls the page's JavaScript expression `condition` until it is truthy; returns its value."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = driver.execute_script("return " + condition)
        if value:
            return value
        time.sleep(0.05)
    raise TimeoutError(condition)


def read_ppm(path):
    """A binary PPM's width, height and RGB bytes (what `ray ... -o x.ppm` writes)."""
    data = open(path, "rb").read()
    parts = data.split(maxsplit=4)
    assert parts[0] == b"P6" and int(parts[3]) == 255
    return int(parts[1]), int(parts[2]), parts[4]
