"""Starts `ray view` on a free port of 127.0.0.1 and talks to it (shared by the viewer tests)."""
import http.client
import json
import os
import re
import shutil
import subprocess
import tempfile
import time


class Viewer:
    def __init__(self, ray, scene, *extra):
        self.folder = tempfile.mkdtemp(prefix="ray_view_")
        self.scene = os.path.join(self.folder, os.path.basename(scene))
        shutil.copy(scene, self.scene)  # a copy the tests may edit (the watcher)
        self.process = subprocess.Popen([ray, "view", self.scene, "--port", "0", *extra],
                                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        line = self.process.stdout.readline()
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
        if not match:
            self.process.kill()
            raise RuntimeError("ray view did not start: " + line + self.process.stdout.read())
        self.port = int(match.group(1))
        self.url = f"http://127.0.0.1:{self.port}/"

    def request(self, method, path, body=None, timeout=30):
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        connection.request(method, path, body=body)
        response = connection.getresponse()
        data = response.read()
        connection.close()
        return response.status, data

    def json(self, method, path, body=None):
        status, data = self.request(method, path, body)
        return status, json.loads(data) if data else None

    def alive(self):
        return self.process.poll() is None

    def rss_kib(self):
        with open(f"/proc/{self.process.pid}/status") as f:
            return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))

    def wait_frame_done(self, timeout=120):
        """Reads /events until a `done` event arrives; returns its data."""
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        connection.request("GET", "/events")
        response = connection.getresponse()
        event = None
        deadline = time.time() + timeout
        while time.time() < deadline:
            line = response.fp.readline().decode()
            if line.startswith("event: "):
                event = line[7:].strip()
            elif line.startswith("data: ") and event == "done":
                connection.close()
                return json.loads(line[6:])
        connection.close()
        raise TimeoutError("no complete frame")

    def close(self):
        self.process.terminate()
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
        shutil.rmtree(self.folder, ignore_errors=True)
