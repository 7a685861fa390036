"""ray view watches its scene file: a broken save shows file:line on the event stream and the
last good scene stays; a good save renders again.  Usage: python3 test_scene_watch.py RAY SCENE"""
import json
import sys
import time

from viewer_harness import Viewer

viewer = Viewer(sys.argv[1], sys.argv[2], "--width", "32", "--height", "24")


def next_event(response, wanted, timeout=30):
    event, deadline = None, time.time() + timeout
    while time.time() < deadline:
        line = response.fp.readline().decode()
        if line.startswith("event: "):
            event = line[7:].strip()
        elif line.startswith("data: ") and event == wanted:
            return json.loads(line[6:])
    raise TimeoutError(wanted)


try:
    viewer.wait_frame_done()
    good = open(viewer.scene).read()
    events = viewer.events()
    time.sleep(0.5)
    lines = good.splitlines(keepends=True)
    open(viewer.scene, "w").write("".join(lines[:len(lines) // 2]) + "<unclosed\n")  # a save cut short
    error = next_event(events, "scene")["error"]
    name = viewer.scene.split("/")[-1]
    assert f"{name}:" in error, error
    print("broken save:", error.splitlines()[0])
    status, state = viewer.json("GET", "/state")
    assert status == 200 and state["error"] == error
    status, tree = viewer.json("GET", "/explain?x=16&y=12")  # the last good scene still answers
    assert status == 200, tree
    time.sleep(1.1)  # a new modification time, whatever the file system's resolution
    open(viewer.scene, "w").write(good)
    assert next_event(events, "scene")["error"] == ""
    next_event(events, "done")
    print("good save: reloaded and rendered")
    # The terminal says both (the viewer logs reloads and broken saves).
    time.sleep(0.5)  # the reader thread catches up
    log = viewer.log()
    assert f"{name} not reloaded" in log and f"reloaded {name}" in log, log
    print("terminal log: the broken save and the reload")
    events.close()
finally:
    viewer.close()
