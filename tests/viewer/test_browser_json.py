"""ray view on a course JSON scene (issue 50), in headless Chromium (Selenium) as a user uses
it: a click selects the cylinder at the centre, its diffuse colour set to red in the panel
turns the view red; an emissive colour, which a JSON scene cannot hold, is refused with the
reason beside the field and changes nothing; "save scene" writes the JSON file with that one
line changed, the numbers that changed alone (the rest byte for byte) and `ray` renders it red. Then through the page's
routes (docs/modeler-protocol.md): a point light moved (its group holds it alone: the group's
translate is written), a primitive deleted (its lines go), undo of the delete, save: the
file loads, and differs from the course's in those lines alone.
The outline speaks the JSON format: groups, template groups and template uses (never XML's
"transblock" or "master"), each entry's place in the file as its tooltip (a light's
`groups[1].lights[0]`), and "save as" offers other.json; the same scene converted to XML
(`ray convert`) keeps the XML outline as it was (transblock, tree, placement, "master post")
and offers other.xml. The selection line and the panel's notes say "group", "primitives" and
"template" for the JSON scene, "transblock", "objects" and "master" for the XML one.
Usage: python3 test_browser_json.py RAY_BINARY SCENE (../shared/cs1230/.../phong_total.json)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing, or the scene is absent."""
import difflib
import json
import os
import shutil
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


def shown_outline(driver):
    """The outline as the page shows it, once it is there: [(label, whole text, tooltip)], and
    the save-as box's placeholder."""
    wait_for(driver, "document.querySelectorAll('#outline .node').length > 0", timeout=30)
    entries = driver.execute_script(
        "return Array.from(document.querySelectorAll('#outline .node'), e => "
        "[e.querySelector('.kind').textContent, e.textContent, e.title]);")
    return [tuple(entry) for entry in entries], \
        driver.execute_script("return document.getElementById('save-as-name').placeholder")


# A scene with a template placed twice, whose light the template holds (templateGroups).
TEMPLATE_SCENE = {
    "name": "root",
    "globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
    "cameraData": {"position": [0, 2, 8], "up": [0, 1, 0], "heightAngle": 45, "focus": [0, 0, 0]},
    "templateGroups": [{"name": "post", "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}],
                        "primitives": [{"type": "cylinder", "diffuse": [0.5, 0.5, 0.5]}]}],
    "groups": [{"translate": [0, 4, 0], "lights": [{"type": "directional", "color": [1, 1, 1], "direction": [0, -1, 0]}]},
               {"scale": [2, 1, 2], "primitives": [{"type": "cube", "diffuse": [1, 0, 0]}, {"type": "sphere"}]},
               {"translate": [-2, 0, 0], "groups": [{"name": "post"}]},
               {"translate": [2, 0, 0], "groups": [{"name": "post"}]}],
}


def select_in_outline(driver, path):
    """Clicks the outline's entry of the node at `path` (its tooltip); the selection line and
    the properties panel's notes then."""
    driver.execute_script("Array.from(document.querySelectorAll('#outline .node'))"
                          ".find(e => e.title === arguments[0]).click()", path)
    wait_for(driver, f"window.rayViewer.selected && window.rayViewer.selected.path === {json.dumps(path)}", timeout=30)
    return driver.execute_script(
        "return [document.getElementById('selection').textContent, document.getElementById('fields').textContent]")


def check_outlines():
    """The template scene's outline in JSON words; the same scene as XML, in XML's as before."""
    folder = tempfile.mkdtemp(prefix="ray_json_outline_")
    json_scene, xml_scene = os.path.join(folder, "posts.json"), os.path.join(folder, "posts.xml")
    with open(json_scene, "w") as f:
        json.dump(TEMPLATE_SCENE, f, indent=2)
    converted = subprocess.run([ray, "convert", json_scene, xml_scene], capture_output=True, text=True)
    assert converted.returncode == 0, converted.stderr
    for path in (json_scene, xml_scene):
        page = Viewer(ray, path, "--device", "cpu", "--width", "64", "--height", "48")
        try:
            driver.get(page.url)
            shown, placeholder = shown_outline(driver)
            status, outline = page.json("GET", "/outline")
            nodes = outline["nodes"]
            json_places = path == json_scene
            # The selection line and the panel's notes in the format's words too.
            template_object = "templateGroups[0].primitives[0]" if json_places else "post/transblock[0]/object[0]"
            shared_object = "groups[1].primitives[0]" if json_places else "root/transblock[1]/object[0]"
            group = "groups[1]" if json_places else "root/transblock[1]"
            placed = select_in_outline(driver, template_object)
            shared = select_in_outline(driver, shared_object)
            selected_group = select_in_outline(driver, group)
        finally:
            page.close()
        assert len(shown) == len(nodes), (shown, nodes)
        labels = [label for label, _, _ in shown]
        if path == json_scene:
            assert placeholder == "other.json", placeholder
            assert not any(word in text for _, text, _ in shown for word in ("transblock", "master", "placement")), shown
            assert labels.count("template group") == 1 and labels.count("template use") == 2, shown
            assert labels.count("group") == 7 and "groups" in labels, shown
            assert ("template use", "template usepost", "groups[2].groups[0]") in shown, shown
            assert ("template group", "template grouppost", "templateGroups[0]") in shown, shown
            assert ("", "cylinder", "templateGroups[0].primitives[0]") in shown, shown
            lights = [title for label, _, title in shown if label == "light"]
            assert lights == ["groups[0].lights[0]"] + ["templateGroups[0].lights[0]"] * 2, shown
            assert placed[0].startswith("selected: cylinder templateGroups[0].primitives[0], line "), placed
            assert "placed 2 times (a primitive of a template)" in placed[1], placed
            assert "its group holds other primitives: moving it gives it a group of its own" in shared[1], shared
            assert selected_group[0] == "selected: group groups[1]", selected_group
        else:
            assert placeholder == "other.xml", placeholder
            # As the page showed an XML scene before: the protocol's kind (none for an object),
            # then the text; the place as the tooltip.
            assert shown == [("" if n["kind"] == "object" else n["kind"],
                              ("" if n["kind"] == "object" else n["kind"]) + n["text"], n["path"]) for n in nodes], shown
            assert all(n["label"] == n["kind"] for n in nodes), nodes
            assert {"transblock", "tree", "placement"} <= set(labels), shown
            assert ("placement", "placementmaster post") in [(label, text) for label, text, _ in shown], shown
            assert not any("group" in label or "template" in label for label in labels), shown
            assert "placed 2 times (an object of a master)" in placed[1], placed
            assert "its transblock holds other objects: moving it gives it a transblock of its own" in shared[1], shared
            assert selected_group[0] == "selected: transblock root/transblock[1]", selected_group
        print(f"outline of {os.path.basename(path)}: {len(shown)} entries, "
              f"{sorted(set(labels) - {''})}; save as offers {placeholder}; '{placed[0]}'; '{selected_group[0]}'")
    shutil.rmtree(folder, ignore_errors=True)


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

    # The course's scene in the outline: JSON's words and places; save as offers other.json.
    shown, placeholder = shown_outline(driver)
    assert placeholder == "other.json", placeholder
    assert not any(word in text for _, text, _ in shown for word in ("transblock", "master", "tree")), shown
    assert ("light", "lightpoint light", "groups[1].lights[0]") in shown, shown
    assert ("", "cylinder", "groups[3].groups[0].primitives[0]") in shown, shown
    assert ("group", "group", "groups[3].groups[1].groups[0]") in shown, shown
    print(f"outline: {len(shown)} entries in JSON's words ({sorted(set(l for l, _, _ in shown) - {''})}), "
          f"places as tooltips; save as offers {placeholder}")

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
    viewer.close()
    check_outlines()
finally:
    viewer.close()
    driver.quit()
print("JSON scene in the browser test passed")
