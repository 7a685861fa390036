"""ray view watches the files its scene uses, and never holds its lock while it reads them
(scene_watch.cpp): a texture repainted on disk shows its new pixels in the view; the scene file
replaced by a FIFO is not opened (the page says what it is, and the viewer keeps answering);
the scene file deleted and then saved again (created, then written within one tick of a
coarse clock) is loaded again and the page stops saying it cannot be opened.  Usage: python3 test_watched_files.py RAY"""
import base64
import json
import os
import sys
import tempfile
import time

from viewer_harness import Viewer

ray = sys.argv[1]
textures = tempfile.mkdtemp(prefix="ray_paint_")
paint = os.path.join(textures, "paint.ppm")


def write_paint(rgb):
    """A 4x4 texture of one colour, written beside and renamed over the old one (as editors save)."""
    with open(paint + ".new", "wb") as f:
        f.write(b"P6 4 4 255\n" + bytes(rgb) * 16)
    os.replace(paint + ".new", paint)


SCENE = f"""<scenefile>
  <globaldata><ambientcoeff v="1"/><diffusecoeff v="1"/><specularcoeff v="0"/></globaldata>
  <cameradata><pos x="0" y="0" z="4"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/><heightangle v="40"/></cameradata>
  <lightdata><id v="0"/><type v="directional"/><color r="1" g="1" b="1"/><direction x="0" y="0" z="-1"/></lightdata>
  <object type="tree" name="root">
    <transblock>
      <scale x="3" y="3" z="1"/>
      <object type="primitive" name="cube">
        <diffuse r="1" g="1" b="1"/><ambient r="0.2" g="0.2" b="0.2"/>
        <texture file="{paint}" u="1" v="1"/><blend v="1"/>
      </object>
    </transblock>
  </object>
</scenefile>
"""
write_paint((230, 20, 20))
source = os.path.join(textures, "painted.xml")
open(source, "w").write(SCENE)
viewer = Viewer(ray, source, "--width", "32", "--height", "24")


class Events:
    """The viewer's event stream, read an event at a time."""

    def __init__(self):
        self.response = viewer.events()

    def next(self, deadline):
        event = None
        while time.time() < deadline:
            line = self.response.fp.readline().decode()
            if line.startswith("event: "):
                event = line[7:].strip()
            elif line.startswith("data: ") and event:
                return event, json.loads(line[6:])
        raise TimeoutError("no event")

    def scene(self, timeout=30):
        """The next scene event's data (a reload, or an error shown)."""
        deadline = time.time() + timeout
        while True:
            event, data = self.next(deadline)
            if event == "scene":
                return data

    def final_centre(self, scene=0, timeout=60):
        """The centre pixel of the next view at rest (a final frame, complete) of scene version
        `scene` or later."""
        deadline = time.time() + timeout
        size, tiles = None, []
        while True:
            event, data = self.next(deadline)
            if event == "frame":
                size, tiles = (data["width"], data["height"], data["final"] and data["scene"] >= scene), []
            elif event == "tile":
                tiles.append(data)
            elif event == "done" and size and size[2]:
                x, y = size[0] // 2, size[1] // 2
                for t in tiles:
                    if t["x"] <= x < t["x"] + t["w"] and t["y"] <= y < t["y"] + t["h"]:
                        rgb = base64.b64decode(t["rgb"])
                        at = ((y - t["y"]) * t["w"] + (x - t["x"])) * 3
                        return tuple(rgb[at:at + 3])


try:
    events = Events()
    red = events.final_centre()
    assert red[0] > 2 * red[2], red
    print("texture painted red: centre", red)

    # An edit first: reading the texture again keeps it and its history.
    op = json.dumps({"op": "set", "node": "globals", "fields": {"diffusecoeff": 0.9}})
    status, answer = viewer.json("POST", "/op", op)
    assert status == 200, answer
    edited = events.scene()["version"]
    time.sleep(0.5)
    write_paint((20, 20, 230))
    version = events.scene()["version"]  # read again
    assert version > edited
    blue = events.final_centre(version)
    assert blue[2] > 2 * blue[0], blue
    status, state = viewer.json("GET", "/state")
    assert state["can_undo"] and state["modified"], state
    print("texture repainted blue on disk: centre", blue, "(the edit kept, and its undo)")
    assert "read again paint.ppm" in viewer.log(), viewer.log()

    # The texture replaced by a FIFO: not opened, said so; the last good pixels stay.
    os.remove(paint)
    os.mkfifo(paint)
    error = events.scene()["error"]
    while "FIFO" not in error:  # the deletion may be seen first
        error = events.scene()["error"]
    assert "paint.ppm" in error and "last good version stays" in error, error
    status, state = viewer.json("GET", "/state", timeout=5)
    assert status == 200 and "FIFO" in state["error"], state
    print("texture replaced by a FIFO:", error.splitlines()[0])
    os.remove(paint)
    write_paint((20, 20, 230))
    error = events.scene()["error"]
    while error:
        error = events.scene()["error"]
    print("texture written again: the error gone")

    # The scene file replaced by a FIFO: not opened (which would wait for a writer), said so.
    os.remove(viewer.scene)
    os.mkfifo(viewer.scene)
    error = events.scene()["error"]
    while "FIFO" not in error:  # the deletion may be seen first
        error = events.scene()["error"]
    assert "not a regular file" in error, error
    status, state = viewer.json("GET", "/state", timeout=5)
    assert status == 200 and "FIFO" in state["error"], state
    status, _ = viewer.json("GET", "/outline", timeout=5)
    assert status == 200
    print("scene replaced by a FIFO:", error)

    # Deleted, then saved again by another program: loaded again, the error gone.
    os.remove(viewer.scene)
    error = events.scene()["error"]
    assert error and "FIFO" not in error, error
    print("scene deleted:", error.splitlines()[0])
    # The other program creates the file, then writes it within one tick of the file system's
    # clock (a coarse one: the same modification time).
    open(viewer.scene, "w").close()
    error = events.scene()["error"]
    assert error and "cannot open" not in error, error
    created = os.stat(viewer.scene).st_mtime_ns
    open(viewer.scene, "w").write(SCENE)
    os.utime(viewer.scene, ns=(created, created))
    reloaded = events.scene()
    while reloaded["error"]:  # a look may catch the file half written: the next one reads it whole
        reloaded = events.scene()
    status, state = viewer.json("GET", "/state", timeout=5)
    assert status == 200 and state["error"] == "", state
    again = events.final_centre(reloaded["version"])
    assert again[2] > 2 * again[0], again
    print("scene saved again: reloaded, no error, rendered")
finally:
    viewer.close()
    for name in os.listdir(textures):
        os.remove(os.path.join(textures, name))
    os.rmdir(textures)
