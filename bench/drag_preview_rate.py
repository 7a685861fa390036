"""ray view's preview rate while the user drags (issue 43: 10 or more a second at a
1280x720 view on a 2-core machine): headless Chromium opens the studio with the view at
--size, then drags for --seconds, as a user's mouse would (Chrome's own input events, one
move every 16 ms), and counts the frames that arrive complete in the page meanwhile.
Two drags: "orbit" turns the camera (a new view each move), "gizmo" moves the selected
object with the gizmo's centre handle (an edit of the scene each move). Prints, for each,
the complete frames a second, their preview sizes, and the time between frames.
Usage: python3 bench/drag_preview_rate.py RAY [SCENE] [--size 1280x720] [--seconds 5]
       [--drags orbit,gizmo] [--device cpu]
Needs Selenium, Chromium and chromedriver (scripts/install-deps.sh)."""
import argparse
import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "viewer"))
from viewer_harness import Viewer, headless_chromium_or_skip, wait_for  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("ray")
parser.add_argument("scene", nargs="?", default=os.path.join(os.path.dirname(__file__), "..", "scenes", "shadows.xml"))
parser.add_argument("--size", default="1280x720")
parser.add_argument("--seconds", type=float, default=5)
parser.add_argument("--drags", default="orbit,gizmo")
parser.add_argument("--device", default="cpu")
args = parser.parse_args()
width, height = (int(v) for v in args.size.split("x"))


def fit_view(driver):
    """Sizes the window so that the view (#viewport) is width x height CSS pixels."""
    for _ in range(4):
        size = driver.get_window_size()
        inner = driver.execute_script("const v = document.getElementById('viewport');"
                                      "return [v.clientWidth, v.clientHeight]")
        if inner == [width, height]:
            return
        driver.set_window_size(size["width"] + width - inner[0], size["height"] + height - inner[1])
        time.sleep(0.3)
    raise RuntimeError(f"the view is {inner}, not {width}x{height}")


def mouse(driver, kind, x, y, buttons=1):
    event = {"type": kind, "x": x, "y": y, "button": "left", "buttons": buttons, "clickCount": 1,
             "pointerType": "mouse"}
    driver.execute_cdp_cmd("Input.dispatchMouseEvent", event)


def drag(driver, start, path):
    """Presses at `start` (page pixels), moves along path(t) for --seconds, one move every
    16 ms, releases: one W3C action sequence, which chromedriver plays with its own timing
    (a command for each move would wait for each answer, and move only a dozen times a
    second on a loaded machine). Returns the page's clock at the press and at the release."""
    from selenium.webdriver.common.actions.action_builder import ActionBuilder
    from selenium.webdriver.common.actions.pointer_input import PointerInput
    from selenium.webdriver.common.actions import interaction
    mouse_input = PointerInput(interaction.POINTER_MOUSE, "mouse")
    actions = ActionBuilder(driver, mouse=mouse_input, duration=16)  # each move takes 16 ms
    actions.pointer_action.move_to_location(int(start[0]), int(start[1])).pointer_down()
    steps = int(args.seconds / 0.016)
    for i in range(1, steps + 1):
        x, y = path(i * 0.016)
        actions.pointer_action.move_to_location(int(round(x)), int(round(y)))
    actions.pointer_action.pointer_up()
    began = driver.execute_script("return window.rayViewer.dragBegan = performance.now()")
    actions.perform()
    ended = driver.execute_script("return performance.now()")
    return began, ended


def report(driver, name, began, ended):
    frames = [f for f in driver.execute_script("return window.rayViewer.frameLog") if began <= f["at"] <= ended]
    seconds = (ended - began) / 1000
    rate = len(frames) / seconds
    gaps = [b["at"] - a["at"] for a, b in zip(frames, frames[1:])]
    sizes = {}
    for f in frames:
        sizes[f"{f['width']}x{f['height']}"] = sizes.get(f"{f['width']}x{f['height']}", 0) + 1
    render = [f["seconds"] * 1000 for f in frames]
    draw = [f["drawMs"] for f in frames]
    print(f"{name}: {len(frames)} complete frames in {seconds:.2f} s = {rate:.1f} a second; "
          f"previews {', '.join(f'{k} x{v}' for k, v in sorted(sizes.items(), key=lambda kv: -kv[1]))}; "
          + (f"between frames median {statistics.median(gaps):.0f} ms (max {max(gaps):.0f}); " if gaps else "")
          + (f"render median {statistics.median(render):.0f} ms, decoding and drawing in the page median "
             f"{statistics.median(draw):.0f} ms" if render else ""))
    return rate


def centre_of_view(driver):
    r = driver.execute_script("return document.getElementById('viewport').getBoundingClientRect().toJSON()")
    return r["left"] + r["width"] / 2, r["top"] + r["height"] / 2, r


driver = headless_chromium_or_skip(1900, 1000)
viewer = Viewer(args.ray, args.scene, "--device", args.device)
rates = {}
try:
    driver.get(viewer.url)
    wait_for(driver, "window.rayViewer.restFrame")
    fit_view(driver)
    wait_for(driver, f"window.rayViewer.restFrame && document.getElementById('view').width === {width} && "
                     f"document.getElementById('view').height === {height} && "
                     f"window.rayViewer.completeFrame === window.rayViewer.restFrame.frame", timeout=300)
    print(f"{os.path.basename(args.scene)}, view {width}x{height}, device {args.device}, {os.cpu_count()} cores, "
          f"{args.seconds:.0f} s drags")
    cx, cy, rect = centre_of_view(driver)
    if "orbit" in args.drags:
        radius = min(rect["width"], rect["height"]) / 4
        began, ended = drag(driver, (cx + radius, cy),
                            lambda t: (cx + radius * math.cos(t * 2), cy + radius * math.sin(t * 2)))
        rates["orbit"] = report(driver, "orbit", began, ended)
        wait_for(driver, "window.rayViewer.completeFrame === window.rayViewer.restFrame.frame", timeout=300)
    if "gizmo" in args.drags:
        # Select what the centre shows, then drag the gizmo's centre handle (moves in the
        # view's plane) to and fro.
        mouse(driver, "mouseMoved", cx, cy, buttons=0)
        mouse(driver, "mousePressed", cx, cy)
        mouse(driver, "mouseReleased", cx, cy, buttons=0)
        wait_for(driver, "window.rayViewer.selected && window.rayViewer.selected.worlds")
        centre = driver.execute_script(
            "const s = window.rayViewer.selected.worlds[0]; return [s[0][3], s[1][3], s[2][3]]")
        px = driver.execute_script("return window.rayViewer.project(arguments[0])", centre)
        start = (rect["left"] + px["x"], rect["top"] + px["y"])
        began, ended = drag(driver, start, lambda t: (start[0] + 60 * math.sin(t * 3), start[1]))
        edits = driver.execute_script("return window.rayViewer.edits")
        rates["gizmo"] = report(driver, "gizmo", began, ended)
        moves, sent, edit_ms = driver.execute_script(
            "const r = window.rayViewer; return [r.dragMoves, r.dragEdits, r.dragEditMs]")
        print(f"  the gizmo moved the object {moves} times; {sent} edits sent (one in flight at a time), "
              f"{edit_ms / max(sent, 1):.0f} ms each from sending to the answer")
        assert edits > 0, "the gizmo drag made no edit"
finally:
    driver.quit()
    viewer.close()
print("preview rate while dragging: " + ", ".join(f"{k} {v:.1f}/s" for k, v in rates.items()))
