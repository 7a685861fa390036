"""ray view latency: from a camera change (POST /view) to the first tile of the new frame
and to its complete frame, as the server-sent event stream delivers them.
Usage: python3 bench/viewer_latency.py RAY SCENE [--size 640x480] [--changes 5]
The viewer renders through host/render/frame_source.h; see docs/user-guide.md ("The live viewer") for which renderer."""
import argparse
import http.client
import json
import os
import statistics
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "viewer"))
from viewer_harness import Viewer  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("ray")
parser.add_argument("scene")
parser.add_argument("--size", default="640x480")
parser.add_argument("--changes", type=int, default=5)
args = parser.parse_args()
width, height = args.size.split("x")
viewer = Viewer(args.ray, args.scene, "--width", width, "--height", height)
first_tile, complete = [], []
try:
    viewer.wait_frame_done(timeout=600)
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=600)
    connection.request("GET", "/events", headers=viewer.auth_headers())
    events = connection.getresponse()
    while not events.fp.readline().startswith(b"event: done"):  # the frame already shown
        pass
    events.fp.readline()
    _, state = viewer.json("GET", "/state")
    for i in range(args.changes):
        position = [p + 0.2 * (i + 1) for p in state["position"]]
        sent = time.perf_counter()
        viewer.request("POST", "/view", json.dumps({"position": position}).encode())
        frame, event, got_tile = None, None, False
        while True:
            line = events.fp.readline().decode()
            if line.startswith("event: "):
                event = line[7:].strip()
            elif line.startswith("data: "):
                data = json.loads(line[6:])
                if event == "frame":
                    frame = data["frame"]
                elif event == "tile" and data["frame"] == frame and not got_tile:
                    got_tile = True
                    first_tile.append(time.perf_counter() - sent)
                elif event == "done" and data["frame"] == frame:
                    complete.append(time.perf_counter() - sent)
                    break
    connection.close()
finally:
    viewer.close()
ms = lambda xs: f"median {statistics.median(xs) * 1000:.0f} ms (min {min(xs) * 1000:.0f}, max {max(xs) * 1000:.0f})"
print(f"{os.path.basename(args.scene)} {args.size}, {args.changes} camera changes")
print("  change -> first new tile:", ms(first_tile))
print("  change -> complete frame:", ms(complete))
