"""ray view on a course JSON scene (issue 50), in headless Chromium (Selenium) as a user uses
it: a click selects the cylinder at the centre, its diffuse colour set to red in the panel
turns the view red; an emissive colour, which a JSON scene cannot hold, is refused with the
reason beside the field and changes nothing; "save scene" writes the JSON file with that one
line changed, the numbers that changed alone (the rest byte for byte) and `ray` renders it red. Then through the page's
routes (docs/modeler-protocol.md): a point light moved (its group holds it alone: the group's
translate is written), a primitive deleted (its lines go), undo of the delete, save: the
file loads, and differs from the course's in those lines alone.
Usage: python3 test_browser_json.py RAY_BINARY SCENE (../shared/cs1230/.../phong_total.json)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing, or the scene is absent."""
import difflib
import json
import os
import subprocess
import sys
import tempfile
import time

from viewer_harness import Viewer, headless_chromium_or_skip, read_ppm, wait_for

ray, scene = sys.argv[1], sys.argv[2]
if not os.path.exists(scene):
    print(f"SKIPPED: {scene} is absent (../shared/cs1230: the course's JSON scenes)")
    sys.exit(0)
WIDTH, HEIGHT = 320, 240
CX, CY = WIDTH // 2, HEIGHT // 2


def pixel(driver, x, y):
    return driver.execute_script(
        f"return Array.from(document.getElementById('view').getContext('2d').getImageData({x}, {y}, 1, 1).data)")


def set_input(driver, selector, value):
    """What the browser does when the user enters a value: the value, then input and change."""
    driver.execute_script(
        "const e = document.querySelector(arguments[0]);"
        "e.value = arguments[1];"
        "e.dispatchEvent(new Event('input', { bubbles: true })); e.dispatchEvent(new Event('change', { bubbles: true }));",
        selector, value)


def changed_lines(before, after):
    """The lines a line diff removes and adds."""
    diff = list(difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0))
    return [line for line in diff if line[:1] in "+-" and not line.startswith(("+++", "---"))]


def rendered_centre(path):
    ppm = os.path.join(tempfile.mkdtemp(), "saved.ppm")
    subprocess.run([ray, path, str(WIDTH), str(HEIGHT), "--device", "cpu", "-o", ppm, "--quiet"], check=True)
    w, h, data = read_ppm(ppm)
    i = 3 * (CY * w + CX)
    return list(data[i:i + 3])


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402 (Selenium is known present)
from selenium.webdriver.common.by import By  # noqa: E402
viewer = Viewer(ray, scene, "--device", "cpu", "--width", str(WIDTH), "--height", str(HEIGHT))
try:
    os.chmod(viewer.scene, 0o644)  # the course's files are read-only; a student's copy is not
    course = open(viewer.scene).read()
    driver.get(viewer.url)
    wait_for(driver, "window.rayViewer.restFrame")
    before = pixel(driver, CX, CY)
    assert before[1] > before[0] + 40, f"the centre is not the green cylinder: {before}"

    # A click selects the cylinder; its colour set to red turns the view red.
    canvas = driver.find_element(By.ID, "view")
    rect = driver.execute_script("return document.getElementById('view').getBoundingClientRect().toJSON()")
    ActionChains(driver).move_to_element_with_offset(canvas, int(CX + 0.5 - rect["width"] / 2),
                                                     int(CY + 0.5 - rect["height"] / 2)).click().perform()
    selected = wait_for(driver, "window.rayViewer.selected")
    node = selected["node"]
    assert selected["type"] == "cylinder", selected
    print(f"click: selected {selected['type']} ({node})")
    set_input(driver, "[data-field=diffuse]", "#ff0000")
    deadline = time.time() + 30
    while pixel(driver, CX, CY)[0] < before[0] + 60:
        assert time.time() < deadline, f"the centre did not turn red: {pixel(driver, CX, CY)}"
        time.sleep(0.05)
    print(f"diffuse #ff0000: the centre {before[:3]} -> {pixel(driver, CX, CY)[:3]}")

    # Emissive: refused with the reason, beside the field; nothing changed.
    errors = driver.execute_script("return window.rayViewer.editErrors.length")
    version = driver.execute_script("return window.rayViewer.sceneVersion")
    set_input(driver, "[data-field=emissive]", "#ffffff")
    wait_for(driver, f"window.rayViewer.editErrors.length > {errors}", timeout=30)
    error = driver.execute_script("return window.rayViewer.editErrors.at(-1)")
    assert error["status"] == 400 and "JSON scene" in error["error"] and "emissive" in error["error"], error
    assert driver.execute_script("return window.rayViewer.sceneVersion") == version
    status, view = viewer.json("GET", f"/node?id={node}")
    assert next(f["value"] for f in view["fields"] if f["name"] == "emissive") == [0, 0, 0], view
    print(f"emissive: HTTP 400 '{error['error']}'; the scene unchanged")

    # Save scene: the JSON file, one line changed; ray renders it red.
    driver.find_element(By.ID, "save-scene").click()
    saved = wait_for(driver, "window.rayViewer.saved", timeout=30)
    assert os.path.samefile(saved, viewer.scene), (saved, viewer.scene)
    written = open(viewer.scene).read()
    lines = changed_lines(course, written)
    assert lines == ['-              "diffuse": [0.0, 1.0, 0.0],', '+              "diffuse": [1, 0, 0.0],'], lines
    centre = rendered_centre(viewer.scene)
    assert centre[0] > centre[2] + 60, centre
    print(f"save scene: {saved}: {lines}; ray renders the centre {centre}")

    # Through the page's routes: a light moved, a primitive deleted and undone, another deleted.
    def op(body):
        status, answer = viewer.json("POST", "/op", json.dumps(body).encode())
        assert status == 200, (body, answer)
        return answer

    status, outline = viewer.json("GET", "/outline")
    lights = [entry["node"] for entry in outline["nodes"] if entry["kind"] == "light"]
    objects = [entry["node"] for entry in outline["nodes"] if entry["kind"] == "object"]
    op({"op": "set", "node": lights[1], "fields": {"position": [8, -2, 1]}})
    op({"op": "delete", "nodes": [objects[-1]]})
    status, answer = viewer.json("POST", "/undo", b"{}")
    assert status == 200, answer
    op({"op": "delete", "nodes": [objects[1]]})
    status, answer = viewer.json("POST", "/save", b"{}")
    assert status == 200, answer
    written = open(viewer.scene).read()
    lines = changed_lines(course, written)
    removed = [line for line in lines if line.startswith("-")]
    assert '+      "translate": [8, -2, 1],' in lines, lines
    assert '+              "diffuse": [1, 0, 0.0],' in lines, lines
    added = [line for line in lines if line.startswith("+")]
    # Besides those two, at most a line that lost its comma, where what followed it went.
    assert len(added) <= 3 and all(line[1:] + "," in course for line in added[2:]), lines
    assert all(line[1:] in course for line in removed), lines
    assert '-                  "type": "sphere",' in removed, lines
    assert not any(line.strip() == '+"primitives": []' for line in added), lines
    assert json.loads(written)["groups"][1]["translate"] == [8, -2, 1]
    subprocess.run([ray, viewer.scene, "16", "12", "--device", "cpu", "-o",
                    os.path.join(viewer.folder, "check.ppm"), "--quiet"], check=True)
    print(f"light moved, a primitive deleted (another deleted and undone), saved: {len(lines)} lines changed, "
          "the file loads")
finally:
    viewer.close()
    driver.quit()
print("JSON scene in the browser test passed")
