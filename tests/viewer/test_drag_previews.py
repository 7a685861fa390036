"""ray view while something moves (issue 43, "fast enough to work in"): a client changes the
camera every 16 ms for 3 s, as a drag does, at a 1280x720 view, and reads the event stream
meanwhile. Complete previews must keep arriving (a request lets the preview in flight
finish instead of cancelling it: viewer/frame_schedule.cpp), each complete frame must arrive
whole (every pixel in its tiles, and its "done", even when the next frame began at once:
event_stream.cpp), no preview may be larger than the view, and once the camera rests the
view is refined at its own size. No browser needed.
Usage: python3 test_drag_previews.py RAY_BINARY SCENE"""
import http.client
import json
import sys
import threading
import time

from viewer_harness import Viewer

ray, scene = sys.argv[1], sys.argv[2]
WIDTH, HEIGHT = 1280, 720
DRAG_SECONDS = 3
# Far below what a loaded 2-core machine shows (40 and more a second with a script for a
# client): the point is that previews finish at all while requests keep coming.
MIN_COMPLETE = 10

viewer = Viewer(ray, scene, "--device", "cpu", "--width", str(WIDTH), "--height", str(HEIGHT))
frames = {}  # frame number -> {"event": frame event, "pixels": pixels in its tiles, "done": done event, "at": time}
stop = threading.Event()


def read_events():
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=60)
    connection.request("GET", "/events", headers=viewer.auth_headers())
    response = connection.getresponse()
    event = None
    while not stop.is_set():
        line = response.fp.readline().decode()
        if line.startswith("event: "):
            event = line[7:].strip()
        elif line.startswith("data: "):
            data = json.loads(line[6:])
            if event == "frame":
                frames[data["frame"]] = {"event": data, "pixels": 0, "done": None}
            elif event == "tile" and data["frame"] in frames:
                frames[data["frame"]]["pixels"] += data["w"] * data["h"]
            elif event == "done" and data["frame"] in frames:
                frames[data["frame"]]["done"] = data
                frames[data["frame"]]["at"] = time.perf_counter()
    connection.close()


try:
    viewer.wait_frame_done(final=True, timeout=300)
    _, state = viewer.json("GET", "/state")
    reader = threading.Thread(target=read_events, daemon=True)
    reader.start()
    time.sleep(0.5)
    began = time.perf_counter()
    moves = 0
    while time.perf_counter() - began < DRAG_SECONDS:
        angle = 0.02 * moves
        position = [state["position"][0] + angle, state["position"][1], state["position"][2]]
        status, _ = viewer.request("POST", "/view", json.dumps({"position": position}).encode())
        assert status == 200, status
        moves += 1
        time.sleep(0.016)
    ended = time.perf_counter()
    during = [f for f in frames.values() if f["done"] and began <= f["at"] <= ended]
    assert len(during) >= MIN_COMPLETE, \
        f"{len(during)} complete frames in {DRAG_SECONDS} s of {moves} camera changes (at least {MIN_COMPLETE})"
    for number, f in frames.items():
        e = f["event"]
        assert e["width"] <= e["view_width"] == WIDTH and e["height"] <= e["view_height"] == HEIGHT, e
        if f["done"]:
            assert f["pixels"] == e["width"] * e["height"], \
                f"frame {number} arrived complete with {f['pixels']} of its {e['width']}x{e['height']} pixels"
    sizes = sorted({f"{f['event']['width']}x{f['event']['height']}" for f in during})
    print(f"{moves} camera changes in {DRAG_SECONDS} s: {len(during)} complete previews arrived "
          f"({len(during) / DRAG_SECONDS:.1f} a second; sizes {', '.join(sizes)}), each with all its pixels")

    # At rest: refined at the view's own size.
    deadline = time.time() + 300
    while not any(f["done"] and f["done"]["final"] and f["event"]["width"] == WIDTH and f["at"] > ended
                  for f in list(frames.values()) if f["done"]):
        assert time.time() < deadline, "the view at rest was not refined"
        time.sleep(0.1)
    print(f"at rest: refined at {WIDTH}x{HEIGHT}")
finally:
    stop.set()
    viewer.close()
print("drag previews test passed")
