# cs123ray in Jupyter: images that show themselves, a scene shown as a picture and its
# outline, and the studio (`ray view`) beside the notebook, on the notebook's scene.
#
# Embedded into the module at build time (python/CMakeLists.txt) and run in its namespace
# when it is imported, so that cs123ray stays one file: Scene, render, save_image and the
# rest are the C++ module's, defined before this runs.
import atexit as _atexit
import base64 as _base64
import functools as _functools
import html as _html
import http.client as _http_client
import json as _json
import os as _os
import re as _re
import shutil as _shutil
import subprocess as _subprocess
import tempfile as _tempfile
import threading as _threading
import time as _time
import warnings as _warnings
import weakref as _weakref

import numpy as _numpy


class RenderedImage(_numpy.ndarray):
    """A rendered image: an H x W x 3 NumPy array (render() and Renderer.render() return one,
    float32 linear or uint8) that Jupyter shows as a picture (_repr_png_). It is an ndarray
    subclass, so everything NumPy does with an array it does with this; numpy.asarray(image)
    gives the plain array."""

    def _repr_png_(self):
        """The image as PNG bytes, as ray writes its 8-bit PNGs (floats linear, clamped to
        1.0); None for an array that is no longer an H x W x 3 image (a slice, a channel),
        which Jupyter then shows as numbers."""
        if self.ndim != 3 or self.shape[2] != 3 or self.shape[0] == 0 or self.shape[1] == 0:
            return None
        if self.dtype.kind != "f" and self.dtype != _numpy.uint8:
            return None
        return _png_bytes(_numpy.asarray(self))


def _png_bytes(image):
    """An H x W x 3 array (floats or uint8) as the bytes of a PNG file, written by save_image."""
    folder = _tempfile.mkdtemp(prefix="cs123ray-png-")
    try:
        path = _os.path.join(folder, "image.png")
        save_image(image, path)
        with open(path, "rb") as file:
            return file.read()
    finally:
        _shutil.rmtree(folder, ignore_errors=True)


def preview(scene, width=240, height=180, device="ref"):
    """A small render of `scene` (a RenderedImage), as a notebook shows a Scene: the reference
    renderer by default (no OpenCL kernel to build for a thumbnail), one sample a pixel."""
    return render(scene, device=device, dtype="uint8", width=width, height=height, aa="off")


def _outline_html(scene):
    """The scene's tree (Scene.outline()) as an indented HTML list of its nodes."""
    rows = []
    for entry in scene.outline():
        rows.append('<li style="margin-left:{0}em"><code>{1}</code> {2}</li>'.format(
            1.2 * entry["depth"], _html.escape(entry["node"]), _html.escape(entry["text"])))
    return '<ul style="list-style:none;padding:0;margin:0">' + "".join(rows) + "</ul>"


def _scene_html(self):
    """A scene in a notebook: a small picture (preview()) beside its outline."""
    try:
        png = _png_bytes(_numpy.asarray(preview(self)))
        picture = '<img alt="the scene, rendered" src="data:image/png;base64,{0}">'.format(
            _base64.b64encode(png).decode("ascii"))
    except Error as error:  # a device or scene error: the outline is still worth seeing
        picture = "<p>(no picture: {0})</p>".format(_html.escape(str(error)))
    return ('<div style="display:flex;gap:1em;align-items:flex-start">{0}'
            '<div style="max-height:240px;overflow:auto;font-size:smaller">{1}<p>{2}</p></div></div>').format(
                picture, _outline_html(self), _html.escape(repr(self)))


Scene._repr_html_ = _scene_html


# ---------------------------------------------------------------------------------------
# The studio: `ray view` on the notebook's scene


def _ray_command():
    """The ray command that runs the studio: $RAY_BINARY, ray beside the build folder's
    module (build/python/cs123ray*.so: build/ray), or ray on PATH (/usr/bin/ray of the
    Debian package)."""
    given = _os.environ.get("RAY_BINARY")
    if given:
        return given
    beside = _os.path.join(_os.path.dirname(_os.path.dirname(_os.path.abspath(__file__))), "ray")
    if _os.access(beside, _os.X_OK) and _os.path.isfile(beside):
        return beside
    found = _shutil.which("ray")
    if not found:
        raise Error("cs123ray.view needs the ray command: install ray's Debian package, put ray on PATH, "
                    "or set RAY_BINARY to it")
    return found


# The pages a notebook runs in, which may show the studio in a frame: Jupyter on this machine
# (any port) and VS Code's notebooks.
DEFAULT_FRAME_ANCESTORS = "http://localhost:* http://127.0.0.1:* https://localhost:* https://127.0.0.1:* vscode-webview:"

_URL_LINE = _re.compile(r"ray view: (http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]+))\s*$")
_studios = []  # the live studios, whose scenes' methods synchronize with them


class Studio:
    """`ray view` started on a scene for a notebook (cs123ray.view): shown in the notebook as
    an IFrame on its URL (token included); stopped by stop(), when it is collected, or when
    the kernel ends.

    The studio edits a copy of the scene in a file of its own (a temporary folder): the
    notebook's scene and the page are kept the same through it. Before each use of the
    scene in the notebook (its methods and properties, render()), the page's edits not yet
    read are saved by the studio (POST /save) and loaded into the notebook's scene; after
    each edit made in the notebook, the scene is written to the file, which the studio
    reloads (it watches the file). Edits made through a SceneObject handle reach the page
    with the next Scene call, or at once with push()."""

    def __init__(self, scene, port=0, device="auto", width=None, height=None,
                 frame_ancestors=DEFAULT_FRAME_ANCESTORS, timeout=60.0):
        self.scene = scene
        self._folder = _tempfile.mkdtemp(prefix="cs123ray-view-")
        self.file = _os.path.join(self._folder, "scene.xml")
        _original(Scene, "save")(scene, self.file)
        command = [_ray_command(), "view", self.file, "--port", str(port), "--device", device,
                   "--frame-ancestors", frame_ancestors]
        if width is not None or height is not None:
            command += ["--width", str(width or 640), "--height", str(height or 480)]
        self._log = open(_os.path.join(self._folder, "ray-view.log"), "w+")
        self._process = _subprocess.Popen(command, stdout=_subprocess.PIPE, stderr=self._log, text=True,
                                          stdin=_subprocess.DEVNULL)
        self.url, self.port, self._token = self._await_url(timeout)
        self._finalizer = _weakref.finalize(self, _stop_process, self._process, self._folder, self._log)
        _studios.append(_weakref.ref(self))

    def _await_url(self, timeout):
        """Reads the URL `ray view` prints once it listens; raises Error if it stops first."""
        found = []
        reader = _threading.Thread(target=lambda: found.append(self._process.stdout.readline()), daemon=True)
        reader.start()
        reader.join(timeout)
        match = _URL_LINE.match(found[0]) if found else None
        if not match:
            self._process.kill()
            self._process.wait()
            self._log.seek(0)
            message = self._log.read().strip() or "no output"
            self._log.close()
            _shutil.rmtree(self._folder, ignore_errors=True)
            raise Error("ray view did not start within {0} s: {1}".format(timeout, message))
        # The rest of its output goes nowhere, so that the pipe never fills.
        _threading.Thread(target=self._process.stdout.read, daemon=True).start()
        return match.group(1), int(match.group(2)), match.group(3)

    @property
    def running(self):
        """Whether the studio's `ray view` is still running."""
        return self._process.poll() is None

    def _request(self, method, path, body=None):
        """One request to the studio with its token, as the page makes it; the JSON answer."""
        connection = _http_client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        headers = {"Authorization": "token " + self._token}
        data = None
        if body is not None:
            data = _json.dumps(body)
            headers["Content-Type"] = "application/json"
        try:
            connection.request(method, path, body=data, headers=headers)
            response = connection.getresponse()
            answer = _json.loads(response.read() or b"{}")
        finally:
            connection.close()
        if response.status != 200:
            raise Error("ray view answered {0} to {1} {2}: {3}".format(
                response.status, method, path, answer.get("error", answer)))
        return answer

    def pull(self):
        """Loads the page's edits into the notebook's scene, if it has any not read yet (the
        studio saves them to its file first). Called before every use of the scene."""
        if not self.running:
            return False
        if not self._request("GET", "/state").get("modified"):  # the editor's state, at the top level
            return False
        self._request("POST", "/save", {})
        loaded = load_scene(self.file)
        _original(Scene, "_assign")(self.scene, loaded)
        return True

    def push(self):
        """Writes the notebook's scene to the studio's file, which the studio reloads (within
        a second) and shows. Called after every edit made through the scene's methods."""
        if self.running:
            # The studio's file is the notebook's copy, which the notebook's scene replaces
            # (the page's edits are pulled before each use): no change of another's is lost.
            _original(Scene, "save")(self.scene, self.file, overwrite_changes=True)

    def stop(self):
        """Stops the studio's `ray view` and removes its folder (the notebook's scene stays)."""
        self._finalizer()

    def _repr_html_(self):
        """The studio inside the notebook: an IFrame on its URL, token included."""
        if not self.running:
            return "<p>(the studio has stopped: {0})</p>".format(_html.escape(self.url))
        return ('<iframe src="{0}" width="100%" height="600" style="border:1px solid #ccc" '
                'allow="fullscreen"></iframe><p><a href="{0}" target="_blank">open the studio in a tab</a></p>'
                ).format(_html.escape(self.url, quote=True))

    def __repr__(self):
        return "<cs123ray.Studio {0} ({1})>".format(self.url, "running" if self.running else "stopped")


def _stop_process(process, folder, log):
    """Ends a studio's `ray view` (SIGTERM, then SIGKILL after 5 s) and removes its folder."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(5)
        except _subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    log.close()
    _shutil.rmtree(folder, ignore_errors=True)


def view(scene, port=0, device="auto", width=None, height=None, frame_ancestors=DEFAULT_FRAME_ANCESTORS,
         timeout=60.0):
    """Opens the studio (`ray view`) on `scene` and returns its Studio, which a notebook shows
    as an IFrame on the live viewer. Edits made in the page are seen by `scene` and the
    notebook's edits of `scene` by the page (Studio says how). port: 0 for a free one; device:
    as ray view --device takes it; width, height: a fixed view size (by default the view
    fills the frame); frame_ancestors: the pages that may show it in a frame (ray view
    --frame-ancestors). The studio stops with Studio.stop(), or when the kernel ends."""
    return Studio(scene, port=port, device=device, width=width, height=height,
                  frame_ancestors=frame_ancestors, timeout=timeout)


def _stop_all_studios():
    """At the kernel's end: every studio still running is stopped."""
    for reference in list(_studios):
        studio = reference()
        if studio is not None:
            studio.stop()


_atexit.register(_stop_all_studios)


def _studios_of(scene):
    """The live studios on `scene`."""
    live = []
    for reference in list(_studios):
        studio = reference()
        if studio is None or not studio.running:
            _studios.remove(reference)
        elif studio.scene is scene:
            live.append(studio)
    return live


def _pull_into(scene):
    for studio in _studios_of(scene):
        try:
            studio.pull()
        except (OSError, Error) as error:
            _warnings.warn("cs123ray: the studio's edits could not be read: {0}".format(error))


def _push_from(scene):
    for studio in _studios_of(scene):
        studio.push()


# The Scene methods that change the scene; the others only read it.
_EDITS = {"set_camera", "set_globals", "add_light", "add_material", "add_texture", "add_mesh", "add_primitive",
          "set_node_transform", "set_light", "remove_light", "set", "add", "delete", "duplicate", "group",
          "rename", "make_unique"}
_originals = {}


def _original(cls, name):
    """A class's attribute as the C++ module defined it, before the wrapping below."""
    return _originals.get((cls, name), getattr(cls, name))


def _synchronized(name, method):
    """`method` of Scene with the studios' edits read before it and, for an edit, the scene
    written to them after it."""
    edits = name in _EDITS

    @_functools.wraps(method)
    def synchronized(self, *args, **kwargs):
        if _studios:
            _pull_into(self)
        result = method(self, *args, **kwargs)
        if edits and _studios:
            _push_from(self)
        return result

    return synchronized


def _synchronize_scene_methods():
    """Wraps each public method and property of Scene with _synchronized."""
    for name, attribute in list(vars(Scene).items()):
        if name.startswith("_"):
            continue
        _originals[(Scene, name)] = attribute
        if isinstance(attribute, property):
            getter = _synchronized(name, attribute.fget)
            setattr(Scene, name, property(getter, None, None, attribute.__doc__))
        elif callable(attribute):
            setattr(Scene, name, _synchronized(name, attribute))


_synchronize_scene_methods()


def _reading_studios(function):
    """A module function that takes a scene first, reading the studios' edits before it."""

    @_functools.wraps(function)
    def reading(scene, *args, **kwargs):
        if _studios:
            _pull_into(scene)
        return function(scene, *args, **kwargs)

    return reading


render = _reading_studios(render)
