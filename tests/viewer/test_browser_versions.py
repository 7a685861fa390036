"""The page and issue 49's versions, in headless Chromium (Selenium): a colour picked in many
moves is one undo step; an edit the page makes against a revision it has not caught up with is
refused (409), the page says so and shows the scene as it is; "save" over a change another
program made on disk asks, and overwrites only when the user says so.
Usage: python3 test_browser_versions.py RAY_BINARY SCENE (scenes/shadows.xml)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import os
import sys
import time

from viewer_harness import Viewer, headless_chromium_or_skip, wait_for

ray, scene = sys.argv[1], sys.argv[2]


def node_field(viewer, node, name):
    status, answer = viewer.json("GET", f"/node?id={node}")
    assert status == 200, answer
    return next(f["value"] for f in answer["fields"] if f["name"] == name)


def state(viewer):
    status, answer = viewer.json("GET", "/state")
    assert status == 200, answer
    return answer


def fire(driver, selector, value, event):
    driver.execute_script(
        "const e = document.querySelector(arguments[0]); e.value = arguments[1];"
        "e.dispatchEvent(new Event(arguments[2], { bubbles: true }));", selector, value, event)


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.by import By  # noqa: E402 (Selenium is known present)

viewer = Viewer(ray, scene, "--device", "cpu", "--width", "64", "--height", "48")
try:
    driver.get(viewer.url)
    wait_for(driver, "window.rayViewer.restFrame")
    # The sphere, selected in the outline.
    driver.find_element(By.CSS_SELECTOR, "#outline [data-node='object-2']").click()
    wait_for(driver, "window.rayViewer.selected && window.rayViewer.selected.node === 'object-2'")
    original = node_field(viewer, "object-2", "diffuse")

    # A colour picked in twelve moves, then the picker closed: one undo step.
    for k in range(12):
        fire(driver, "[data-field=diffuse]", "#%02x0000" % (20 * k + 15), "input")
    fire(driver, "[data-field=diffuse]", "#ff0000", "change")
    deadline = time.time() + 30
    while node_field(viewer, "object-2", "diffuse") != [1, 0, 0]:
        assert time.time() < deadline, node_field(viewer, "object-2", "diffuse")
        time.sleep(0.1)
    now = state(viewer)
    assert now["history"]["steps"] == 1 and now["can_undo"], now["history"]
    driver.find_element(By.ID, "undo").click()
    deadline = time.time() + 30
    while node_field(viewer, "object-2", "diffuse") != original:
        assert time.time() < deadline, "one undo did not bring the colour back"
        time.sleep(0.1)
    print(f"a colour picked in 13 moves: one step ({now['history']['bytes']} bytes of history); one undo restores it")

    # The page has not caught up with another page's edit: its edit is refused, it says so
    # and reads the scene again.
    wait_for(driver, f"window.rayViewer.revision === {state(viewer)['revision']}")
    driver.execute_script("window.rayViewer.revision -= 1")
    shininess = node_field(viewer, "object-2", "shininess")
    fire(driver, "[data-field=shininess]", str(shininess + 5), "change")
    wait_for(driver, "window.rayViewer.staleEdits === 1")
    wait_for(driver, f"window.rayViewer.revision === {state(viewer)['revision']}")
    wait_for(driver, "document.getElementById('edit-error').textContent.includes('scene changed')")
    assert node_field(viewer, "object-2", "shininess") == shininess
    print(f"a stale edit: 409, nothing changed; the page says '{driver.find_element(By.ID, 'edit-error').text[:70]}...'")

    # Save over another program's change: asked; "Cancel" twice keeps their file; "OK" overwrites.
    fire(driver, "[data-field=shininess]", str(shininess + 5), "change")
    deadline = time.time() + 30
    while node_field(viewer, "object-2", "shininess") != shininess + 5:
        assert time.time() < deadline, "the edit was not made"
        time.sleep(0.1)
    before = os.stat(viewer.scene)
    with open(viewer.scene) as f:
        ours_before = f.read()
    # Their change keeps the file's size and time, so that the watch (which compares them)
    # cannot see it: only the save's own check of the bytes finds it.
    comment = ours_before[:ours_before.index("-->")]
    theirs = ours_before.replace(comment, ("<!-- another program" + " " * len(comment))[:len(comment)], 1)
    assert len(theirs) == len(ours_before)
    with open(viewer.scene, "w") as f:
        f.write(theirs)
    os.utime(viewer.scene, ns=(before.st_atime_ns, before.st_mtime_ns))
    driver.execute_script("window.asked = []; window.confirm = m => { window.asked.push(m); return false; }")
    driver.find_element(By.ID, "save-scene").click()
    wait_for(driver, "window.asked.length === 2")
    asked = driver.execute_script("return window.asked")
    assert "changed on disk" in asked[0] and "overwrite" in asked[0], asked
    with open(viewer.scene) as f:
        assert f.read() == theirs
    driver.execute_script("window.asked = []; window.confirm = m => { window.asked.push(m); return true; }")
    driver.find_element(By.ID, "save-scene").click()
    wait_for(driver, "window.rayViewer.saved !== null")
    with open(viewer.scene) as f:
        ours = f.read()
    assert "another program" not in ours and '<shininess v="%g"/>' % (shininess + 5) in ours, ours
    print("save over a change on disk: asked; Cancel kept their file, OK overwrote it")
finally:
    viewer.close()
    driver.quit()
print("browser versions test passed")
