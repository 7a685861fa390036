"""ray view against another page in the same browser, in headless Chromium (Selenium): once the
user has opened the viewer (so the browser holds its cookie), a page served from another
port of 127.0.0.1 tries to edit and save through it, by fetch (no-cors, with credentials)
and by auto-submitted text/plain forms; the scene, the viewer's state and the folder stay
as they were. Then the viewer's own page saves as: `..`, an absolute path elsewhere, a NUL
byte, a link out and an existing file are refused (the existing one replaced only once the
user agrees), and a new name is written in the scene's folder.
Usage: python3 test_browser_cross_site.py RAY_BINARY SCENE (scenes/shadows.xml)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import functools
import hashlib
import http.server
import os
import shutil
import sys
import tempfile
import threading
import time

from viewer_harness import Viewer, headless_chromium_or_skip, wait_for

ray, scene = sys.argv[1], sys.argv[2]

HOSTILE_PAGE = """<!DOCTYPE html><html><body>
<iframe name="sink" style="display:none"></iframe>
<form id="save-form" method="POST" enctype="text/plain" target="sink" action="VIEWER/save">
  <input name='{"as": "form.xml", "x": "' value='"}'></form>
<form id="edit-form" method="POST" enctype="text/plain" target="sink" action="VIEWER/edit">
  <input name='{"light": 0, "color": [0, 1, 0], "x": "' value='"}'></form>
<script>
const viewer = "VIEWER";
window.outcomes = [];
async function attempt(name, promise) {
  try { const r = await promise; window.outcomes.push(`${name}: answered (opaque ${r.type})`); }
  catch (e) { window.outcomes.push(`${name}: blocked (${e})`); }
}
async function run() {
  const edit = JSON.stringify({ light: 0, color: [0, 1, 0] });
  await attempt("fetch no-cors /edit", fetch(viewer + "/edit", { method: "POST", mode: "no-cors", credentials: "include", body: edit }));
  await attempt("fetch no-cors /save", fetch(viewer + "/save", { method: "POST", mode: "no-cors", credentials: "include", body: '{"as": "fetched.xml"}' }));
  await attempt("fetch no-cors /view", fetch(viewer + "/view", { method: "POST", mode: "no-cors", credentials: "include", body: '{"position": [40, 40, 40]}' }));
  await attempt("fetch cors /state", fetch(viewer + "/state", { credentials: "include" }));
  await attempt("fetch cors /edit with a JSON type", fetch(viewer + "/edit", { method: "POST", credentials: "include", headers: { "Content-Type": "application/json" }, body: edit }));
  await attempt("fetch no-cors the page", fetch(viewer + "/", { mode: "no-cors", credentials: "include" }));
  document.getElementById("save-form").submit();
  await new Promise(r => setTimeout(r, 500));
  document.getElementById("edit-form").submit();
  await new Promise(r => setTimeout(r, 500));
  window.done = true;
}
run();
</script></body></html>"""




def folder_snapshot(folder):
    """Each file of the folder with a hash of its bytes (links as their target)."""
    snapshot = {}
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if os.path.islink(path):
            snapshot[name] = "-> " + os.readlink(path)
        else:
            snapshot[name] = hashlib.sha256(open(path, "rb").read()).hexdigest()
    return snapshot


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.by import By  # noqa: E402 (Selenium is known present)
viewer = Viewer(ray, scene, "--device", "cpu", "--width", "160", "--height", "120")
site = tempfile.mkdtemp(prefix="ray_hostile_site_")
outside = tempfile.mkdtemp(prefix="ray_view_outside_")
hostile = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(QuietHandler, directory=site))
threading.Thread(target=hostile.serve_forever, daemon=True).start()
try:
    viewer_origin = f"http://127.0.0.1:{viewer.port}"
    with open(os.path.join(site, "index.html"), "w") as f:
        f.write(HOSTILE_PAGE.replace("VIEWER", viewer_origin))
    driver.get(viewer.url)  # the user opens the viewer: the browser now holds its cookie
    wait_for(driver, "window.rayViewer && window.rayViewer.restFrame", timeout=60)
    status, before = viewer.json("GET", "/state")
    files_before = folder_snapshot(viewer.folder)

    driver.get(f"http://127.0.0.1:{hostile.server_address[1]}/index.html")
    wait_for(driver, "window.done === true", timeout=60)
    outcomes = driver.execute_script("return window.outcomes")
    time.sleep(1)  # anything the viewer accepted would be done by now
    status, after = viewer.json("GET", "/state")
    assert status == 200
    assert after["lights"] == before["lights"] and not after["modified"] and not after["can_undo"], after
    assert after["position"] == before["position"], (before["position"], after["position"])
    assert folder_snapshot(viewer.folder) == files_before, (files_before, folder_snapshot(viewer.folder))
    refused_in_log = viewer.log().count("saved ")
    assert refused_in_log == 0, viewer.log()
    for line in outcomes:
        print("  another page:", line)
    print(f"another local port: {len(outcomes)} fetches and 2 text/plain forms; the scene, the view and the folder unchanged")

    # The viewer's own page: save as, through its controls.
    driver.get(viewer.url)
    wait_for(driver, "window.rayViewer && window.rayViewer.restFrame", timeout=60)
    edit_error = driver.find_element(By.ID, "edit-error")
    name_input = driver.find_element(By.ID, "save-as-name")
    os.symlink(os.path.join(outside, "target.xml"), os.path.join(viewer.folder, "link.xml"))
    with open(os.path.join(viewer.folder, "existing.xml"), "w") as f:
        f.write("<!-- the user's own file -->\n")
    files_before = folder_snapshot(viewer.folder)

    def save_as(name):
        errors = driver.execute_script("return window.rayViewer.editErrors.length")
        driver.execute_script("arguments[0].value = arguments[1];", name_input, name)
        driver.find_element(By.ID, "save-as").click()
        return errors

    refused = ["../up.xml", os.path.join(os.path.dirname(viewer.folder), "up.xml"), "/tmp/elsewhere.xml",
               "precious\u0000.xml", "link.xml", "sub/inner.xml"]
    for name in refused:
        errors = save_as(name)
        wait_for(driver, f"window.rayViewer.editErrors.length > {errors}", timeout=60)
        assert edit_error.text, name
        print(f"  save as {name!r}: {edit_error.text}")
    assert folder_snapshot(viewer.folder) == files_before
    assert not os.path.exists(os.path.join(outside, "target.xml"))

    # An existing file: the page asks; "no" leaves it, "yes" replaces it.
    save_as("existing.xml")
    alert = None
    deadline = time.time() + 30
    while time.time() < deadline:
        try:
            alert = driver.switch_to.alert
            break
        except Exception:
            time.sleep(0.05)
    assert alert is not None and "already exists" in alert.text, "no question before replacing a file"
    alert.dismiss()
    time.sleep(0.5)
    assert open(os.path.join(viewer.folder, "existing.xml")).read() == "<!-- the user's own file -->\n"
    save_as("existing.xml")
    deadline = time.time() + 30
    while time.time() < deadline:
        try:
            driver.switch_to.alert.accept()
            break
        except Exception:
            time.sleep(0.05)
    wait_for(driver, "window.rayViewer.saved && window.rayViewer.saved.endsWith('existing.xml')", timeout=60)
    assert open(os.path.join(viewer.folder, "existing.xml")).read().lstrip().startswith("<")
    assert "<scenefile" in open(os.path.join(viewer.folder, "existing.xml")).read()

    save_as("new.xml")
    wait_for(driver, "window.rayViewer.saved && window.rayViewer.saved.endsWith('new.xml')", timeout=60)
    assert os.path.samefile(os.path.dirname(driver.execute_script("return window.rayViewer.saved")), viewer.folder)
    assert "<scenefile" in open(os.path.join(viewer.folder, "new.xml")).read()
    print(f"own page: {len(refused)} names refused with a message; an existing file replaced only after the user "
          "agreed; new.xml written in the scene's folder")
finally:
    driver.quit()
    hostile.shutdown()
    viewer.close()
    shutil.rmtree(site, ignore_errors=True)
    shutil.rmtree(outside, ignore_errors=True)
print("cross-site browser test passed")
