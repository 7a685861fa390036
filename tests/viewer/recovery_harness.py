"""What the recovery tests share (issue 49: unsaved work is never lost): `ray view` of a scene
where it lies (the recovery names the scene by its path), in a private HOME and
XDG_STATE_HOME so that nothing of the user's is read or touched, stopped by a signal."""
import os
import re
import shutil
import signal
import stat
import subprocess
import tempfile
import threading
import time

from viewer_harness import Viewer

EXTENSION = ".ray-recovery"


class Home:
    """A scratch HOME and XDG_STATE_HOME, and a scene copied into a folder of its own."""

    def __init__(self, scene):
        self.root = tempfile.mkdtemp(prefix="ray_recovery_")
        self.env = dict(os.environ, HOME=os.path.join(self.root, "home"),
                        XDG_STATE_HOME=os.path.join(self.root, "state"))
        os.makedirs(self.env["HOME"])
        self.folder = os.path.join(self.env["XDG_STATE_HOME"], "ray", "recovery")
        work = os.path.join(self.root, "work")
        os.makedirs(work)
        self.scene = os.path.join(work, "scene.xml")
        shutil.copy(scene, self.scene)
        self.original = open(self.scene, "rb").read()

    def recoveries(self):
        """The recovery files kept now, oldest first."""
        if not os.path.isdir(self.folder):
            return []
        found = []
        for name in os.listdir(self.folder):
            if name.endswith(EXTENSION) and not name.startswith("."):
                try:  # the viewer may remove it meanwhile
                    found.append((os.path.getmtime(os.path.join(self.folder, name)), os.path.join(self.folder, name)))
                except FileNotFoundError:
                    pass
        return [path for _, path in sorted(found)]

    def wait_recoveries(self, count, timeout=15):
        deadline = time.time() + timeout
        while time.time() < deadline:
            found = self.recoveries()
            if len(found) == count:
                return found
            time.sleep(0.05)
        raise TimeoutError(f"{count} recovery files expected, found {self.recoveries()}")

    def scene_untouched(self):
        return open(self.scene, "rb").read() == self.original

    def close(self):
        shutil.rmtree(self.root, ignore_errors=True)


class ViewerOf(Viewer):
    """`ray view FILE` of home.scene where it is (Viewer copies it elsewhere), with home's
    environment; stop(sig) ends it by a signal and returns its exit status."""

    def __init__(self, ray, home, *extra):
        self.folder = None
        self.scene = home.scene
        self.process = subprocess.Popen([ray, "view", home.scene, "--port", "0", "--device", "cpu",
                                         "--width", "64", "--height", "48", *extra],
                                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=home.env)
        # What it says before it listens (a recovery passed over) comes before the URL.
        self.output = []
        match = None
        while not match:
            line = self.process.stdout.readline()
            if not line:
                self.process.kill()
                raise RuntimeError("ray view did not start: " + "".join(self.output))
            self.output.append(line)
            match = re.search(r"http://127\.0\.0\.1:(\d+)/(\?token=([0-9a-f]+))?$", line.strip())
        self.port = int(match.group(1))
        self.token = match.group(3)
        self.url = match.group(0)
        self.reader = threading.Thread(target=self._read_output, daemon=True)
        self.reader.start()

    def op(self, request):
        import json
        status, answer = self.json("POST", "/op", json.dumps(request).encode())
        assert status == 200, (status, answer)
        return answer

    def stop(self, sig=signal.SIGTERM, timeout=30):
        self.process.send_signal(sig)
        code = self.process.wait(timeout)
        self.reader.join(5)
        return code

    def close(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(10)
        self.reader.join(5)


def mode_of(path):
    return stat.S_IMODE(os.lstat(path).st_mode)


def fnv1a64(data):
    """The hash that names a scene's recovery files (viewer/recovery.cpp)."""
    h = 0xcbf29ce484222325
    for byte in data:
        h = ((h ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def scene_key(scene):
    return fnv1a64(os.path.realpath(scene).encode())
