"""ray view as a modeler, in headless Chromium (Selenium) as a user uses it: a click selects
the object under the pointer and marks it; its color input set to red turns the view's centre
red within seconds; a bad value is refused with the server's message and changes nothing;
undo and redo; "save scene" writes the file it opened (the page names it) and `ray` renders
that file red there; save as writes another; without the token nothing can be edited.
Usage: python3 test_browser_modeler.py RAY_BINARY SCENE (scenes/shadows.xml)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import json
import os
import subprocess
import sys
import tempfile
import time

from viewer_harness import Viewer, headless_chromium_or_skip, read_ppm, wait_for

ray, scene = sys.argv[1], sys.argv[2]
WIDTH, HEIGHT = 640, 480  # the viewer's default size
CX, CY = WIDTH // 2, HEIGHT // 2


def pixel(driver, x, y, canvas_id="view"):
    return driver.execute_script(
        f"return Array.from(document.getElementById('{canvas_id}').getContext('2d').getImageData({x}, {y}, 1, 1).data)")


def red(rgb):
    """Red, not the grey it was: the floor at the centre is half lit (about 110, 12, 12)."""
    return rgb[0] >= 80 and rgb[0] >= 4 * max(rgb[1], rgb[2])


def rendered_centre(path):
    """The centre pixel of `ray FILE 640 480 --device cpu`."""
    ppm = os.path.join(tempfile.mkdtemp(), "saved.ppm")
    subprocess.run([ray, path, str(WIDTH), str(HEIGHT), "--device", "cpu", "-o", ppm, "--quiet"], check=True)
    w, h, data = read_ppm(ppm)
    i = 3 * (CY * w + CX)
    return list(data[i:i + 3])


def set_input(driver, selector, value):
    """What the browser does when the user enters a value: the input's value, then its input
    and change events. `selector`: an id, or a CSS selector such as [data-field=diffuse]."""
    driver.execute_script(
        "const e = document.getElementById(arguments[0]) || document.querySelector(arguments[0]);"
        "e.value = arguments[1];"
        "e.dispatchEvent(new Event('input', { bubbles: true })); e.dispatchEvent(new Event('change', { bubbles: true }));",
        selector, value)


def field_value(driver, selector):
    return driver.execute_script("return document.querySelector(arguments[0]).value", selector)


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402 (Selenium is known present)
from selenium.webdriver.common.by import By  # noqa: E402
# A size given on the command line: the view keeps it (it would otherwise fill the window).
viewer = Viewer(ray, scene, "--device", "cpu", "--width", str(WIDTH), "--height", str(HEIGHT))
try:
    driver.get(viewer.url)
    wait_for(driver, "window.rayViewer.restFrame")
    before = pixel(driver, CX, CY)
    assert not red(before), before
    file_shown = driver.find_element(By.ID, "file").text
    assert file_shown == os.path.realpath(viewer.scene) or file_shown == os.path.abspath(viewer.scene), file_shown
    print(f"page: the scene file is named ({file_shown}); centre pixel {before[:3]}")

    # A click selects the object under the pointer and marks it.
    canvas = driver.find_element(By.ID, "view")
    rect = driver.execute_script("return document.getElementById('view').getBoundingClientRect().toJSON()")
    ActionChains(driver).move_to_element_with_offset(canvas, int(CX + 0.5 - rect["width"] / 2),
                                                     int(CY + 0.5 - rect["height"] / 2)).click().perform()
    selected = wait_for(driver, "window.rayViewer.selected")
    assert selected["pixel"] == [CX, CY], selected
    assert "selected:" in driver.find_element(By.ID, "selection").text
    marker = driver.execute_script(
        "return Array.from(document.getElementById('marker').getContext('2d').getImageData(0, 0, 640, 480).data)")
    near = [marker[4 * (j * WIDTH + i) + 3] for j in range(CY - 9, CY + 10) for i in range(CX - 9, CX + 10)]
    assert sum(1 for a in near if a > 0) >= 20, "the selected object is not marked"
    assert driver.find_element(By.CSS_SELECTOR, "[data-field=diffuse]").get_attribute("type") == "color"
    print(f"click: selected {selected['type']} {selected['path']} (object {selected['object']}), marked")

    # Its color set to red: the view's centre turns red within seconds.
    version = driver.execute_script("return window.rayViewer.sceneVersion")
    start = time.time()
    set_input(driver, "[data-field=diffuse]", "#ff0000")
    wait_for(driver, f"window.rayViewer.sceneVersion > {version}", timeout=30)
    deadline = start + 20
    while not red(pixel(driver, CX, CY)):
        assert time.time() < deadline, f"the centre is not red after 20 s: {pixel(driver, CX, CY)}"
        time.sleep(0.05)
    turned = time.time() - start
    print(f"color input set to #ff0000: the centre turned red in {turned:.2f} s ({pixel(driver, CX, CY)[:3]})")

    # A bad value: the server's message in the page, nothing changed.
    errors = driver.execute_script("return window.rayViewer.editErrors.length")
    shininess = field_value(driver, "[data-field=shininess]")
    set_input(driver, "[data-field=shininess]", "-5")
    wait_for(driver, f"window.rayViewer.editErrors.length > {errors}", timeout=30)
    error = driver.execute_script("return window.rayViewer.editErrors.at(-1)")
    assert error["status"] == 400 and "shininess" in error["error"], error
    # Its error beside the field, and the field back to the value the scene holds.
    beside = driver.execute_script(
        "return document.querySelector('[data-field=shininess]').closest('.field').querySelector('.field-error').textContent")
    assert "shininess" in beside, beside
    assert field_value(driver, "[data-field=shininess]") == shininess, field_value(driver, "[data-field=shininess]")
    status, current = viewer.json("GET", f"/object?id={selected['object']}")
    assert status == 200 and current["material"]["shininess"] == selected["material"]["shininess"], current
    assert current["material"]["diffuse"] == [1, 0, 0], current
    print(f"bad value: HTTP 400 '{error['error']}', shown beside the field, which went back to {shininess}; "
          "the object unchanged")

    # The refused value blocks nothing: the next edit of another field is made.
    edits = driver.execute_script("return window.rayViewer.edits")
    set_input(driver, "[data-field=ior]", "1.25")
    wait_for(driver, f"window.rayViewer.edits > {edits}", timeout=30)
    status, current = viewer.json("GET", f"/object?id={selected['object']}")
    assert current["material"]["ior"] == 1.25, current["material"]
    driver.find_element(By.ID, "undo").click()
    wait_for(driver, "document.querySelector('[data-field=ior]') && "
                     f"Number(document.querySelector('[data-field=ior]').value) === {selected['material']['ior']}", timeout=30)
    print("after the refusal: ior 1.25 accepted (nothing blocked), then undone")

    # Undo brings the color back, redo makes it red again.
    driver.find_element(By.ID, "undo").click()
    deadline = time.time() + 20
    while red(pixel(driver, CX, CY)):
        assert time.time() < deadline, "undo did not bring the color back"
        time.sleep(0.05)
    driver.find_element(By.ID, "redo").click()
    deadline = time.time() + 20
    while not red(pixel(driver, CX, CY)):
        assert time.time() < deadline, "redo did not make it red again"
        time.sleep(0.05)
    print("undo: the old color back; redo: red again")

    # Save scene: the file it opened, which `ray` then renders red at the centre.
    original = open(viewer.scene).read()
    driver.find_element(By.ID, "save-scene").click()
    saved = wait_for(driver, "window.rayViewer.saved", timeout=30)
    assert os.path.samefile(saved, viewer.scene), (saved, viewer.scene)
    assert "saved to" in driver.find_element(By.ID, "saved").text
    written = open(viewer.scene).read()
    assert written != original and 'r="1" g="0" b="0"' in written
    centre = rendered_centre(viewer.scene)
    assert red(centre), centre
    print(f"save scene: {saved} written; ray renders it with the centre {centre}")
    # Its own save is not taken for a change on disk: the history stays (undo is still there).
    time.sleep(1.0)
    assert driver.execute_script("return !document.getElementById('undo').disabled")

    # Save as: another file beside it.
    set_input(driver, "save-as-name", "copy.xml")
    driver.find_element(By.ID, "save-as").click()
    wait_for(driver, "window.rayViewer.saved && window.rayViewer.saved.endsWith('copy.xml')", timeout=30)
    copy = os.path.join(os.path.dirname(viewer.scene), "copy.xml")
    assert open(copy).read() == written
    print("save as: copy.xml written beside it")

    # A light and a transform edited in the panel change the view; undone, the view is back.
    saved_centre = pixel(driver, CX, CY)
    driver.find_element(By.CSS_SELECTOR, "#outline [data-node=light-0]").click()
    wait_for(driver, "document.querySelector('#fields [data-field=color]')")
    set_input(driver, "#fields [data-field=color]", "#000000")  # the only light off: ambient alone
    deadline = time.time() + 20
    while pixel(driver, CX, CY)[0] >= saved_centre[0] - 20:
        assert time.time() < deadline, f"the light edit did not darken the centre: {pixel(driver, CX, CY)}"
        time.sleep(0.05)
    driver.find_element(By.ID, "undo").click()
    wait_for(driver, f"(() => {{ const p = document.getElementById('view').getContext('2d').getImageData({CX}, {CY}, 1, 1).data;"
                 f" return p[0] === {saved_centre[0]} && p[1] === {saved_centre[1]}; }})()", timeout=20)
    status, state = viewer.json("GET", "/state")
    assert state["lights"][0]["color"] == [1.0, 1.0, 1.0], state["lights"]
    # The floor (the selected cube) lowered by 0.5 along its transblock's translate's y.
    driver.find_element(By.CSS_SELECTOR, f"#outline [data-node=object-{selected['object']}]").click()
    translate = "[data-field=translate][data-component='1']"
    wait_for(driver, f"document.querySelector(\"{translate}\")")
    translate_y = float(field_value(driver, translate))
    edits = driver.execute_script("return window.rayViewer.edits")
    set_input(driver, translate, str(translate_y - 0.5))
    wait_for(driver, f"window.rayViewer.edits > {edits}", timeout=20)
    status, current = viewer.json("GET", f"/object?id={selected['object']}")
    assert current["transform"][0]["v"][1] == translate_y - 0.5, current["transform"]
    deadline = time.time() + 20
    while pixel(driver, CX, CY)[:3] == saved_centre[:3]:
        assert time.time() < deadline, "the transform edit did not change the view"
        time.sleep(0.05)
    driver.find_element(By.ID, "undo").click()
    wait_for(driver, f"(() => {{ const p = document.getElementById('view').getContext('2d').getImageData({CX}, {CY}, 1, 1).data;"
                 f" return p[0] === {saved_centre[0]} && p[1] === {saved_centre[1]}; }})()", timeout=20)
    print("panel: the light switched off darkened the view, the floor lowered changed it; each undone")

    # Without the token nothing is edited.
    body = json.dumps({"object": selected["object"], "material": {"diffuse": [0, 0, 1]}}).encode()
    status, _ = viewer.request("POST", "/edit", body, headers={})
    assert status == 403, status
    status, current = viewer.json("GET", f"/object?id={selected['object']}")
    assert current["material"]["diffuse"] == [1, 0, 0]
    print("without the token: POST /edit is 403, nothing changed")
finally:
    driver.quit()
    viewer.close()

# A viewer started open (--no-token) shows the scene and edits nothing.
open_viewer = Viewer(ray, scene, "--device", "cpu", "--no-token", "--width", "64", "--height", "48")
try:
    status, answer = open_viewer.json("POST", "/edit", json.dumps({"light": 0, "color": [1, 0, 0]}).encode())
    assert status == 403 and "token" in answer["error"], (status, answer)
    status, answer = open_viewer.json("POST", "/save", b"{}")
    assert status == 403, status
    print("--no-token: editing and saving refused (403)")
finally:
    open_viewer.close()
print("modeler browser test passed")
