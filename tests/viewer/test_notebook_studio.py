"""cs123ray.view in a browser as a notebook shows it (issue 52), in headless Chromium
(Selenium): a page on another port of 127.0.0.1, as Jupyter's is, holds the studio's HTML
(Studio._repr_html_: an IFrame on the URL cs123ray.view returned); the viewer's page opens
inside it and draws its frame. An edit made in that page (the page's own request) is then
what the notebook's scene holds, and the notebook's edit is what the page reads back.
Usage: python3 test_notebook_studio.py RAY_BINARY MODULE_DIR SCENE (scenes/shadows.xml)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import functools
import http.server
import os
import sys
import tempfile
import threading
import time

from viewer_harness import headless_chromium_or_skip, wait_for

ray, module_dir, scene_file = sys.argv[1:4]
os.environ["RAY_BINARY"] = ray
sys.path.insert(0, module_dir)
import cs123ray  # noqa: E402 (from the build folder given)


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def page_request(driver, method, path, body=None):
    """A request made by the viewer's page inside the frame, with its token, as it makes them."""
    return driver.execute_async_script("""
        const [method, path, body, done] = arguments;
        const token = document.querySelector('meta[name="ray-token"]').content;
        const headers = {Authorization: 'token ' + token};
        if (body !== null) headers['Content-Type'] = 'application/json';
        fetch(path, {method, headers, body: body === null ? undefined : JSON.stringify(body)})
            .then(r => r.json().then(j => done({status: r.status, json: j})))
            .catch(e => done({status: 0, json: String(e)}));""", method, path, body)


def check(condition, message):
    if not condition:
        print("FAIL:", message)
        sys.exit(1)


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.by import By  # noqa: E402 (Selenium is known present)

scene = cs123ray.load_scene(scene_file)
studio = cs123ray.view(scene, device="cpu", width=160, height=120)
site = tempfile.mkdtemp(prefix="ray_notebook_page_")
with open(os.path.join(site, "notebook.html"), "w") as page:
    page.write("<!DOCTYPE html><html><body><h1>a notebook</h1>" + studio._repr_html_() + "</body></html>")
notebook = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(QuietHandler, directory=site))
threading.Thread(target=notebook.serve_forever, daemon=True).start()
try:
    driver.set_script_timeout(60)
    driver.get(f"http://127.0.0.1:{notebook.server_address[1]}/notebook.html")
    frame = driver.find_element(By.TAG_NAME, "iframe")
    check(frame.get_attribute("src") == studio.url and "?token=" in studio.url,
          f"the IFrame opens {frame.get_attribute('src')}, not the studio's URL {studio.url}")
    driver.switch_to.frame(frame)
    wait_for(driver, "window.rayViewer && window.rayViewer.restFrame", timeout=300)
    check(driver.execute_script("return location.origin") == f"http://127.0.0.1:{studio.port}",
          "the frame does not show the viewer's page")
    print(f"the viewer's page opened inside the notebook's page and drew its frame ({studio.url.split('?')[0]})")

    # The page edits: the notebook's scene holds it.
    light = next(entry["node"] for entry in scene.outline() if entry["kind"] == "light")
    answer = page_request(driver, "POST", "/op", {"op": "set", "node": light, "fields": {"color": [0, 1, 0]}})
    check(answer["status"] == 200, f"the page's edit was refused: {answer}")
    color = scene.lights[0]["color"]
    check(tuple(color) == (0.0, 1.0, 0.0), f"the notebook's scene did not take the page's edit: {color}")
    print("an edit made in the page is the notebook's scene's:", color)

    # The notebook edits: the page reads it back once the studio has reloaded the file.
    light = next(entry["node"] for entry in scene.outline() if entry["kind"] == "light")
    scene.set(light, color=(1, 0, 0))
    deadline = time.time() + 30
    shown = None
    while time.time() < deadline:
        answer = page_request(driver, "GET", "/node?id=" + light)
        shown = next((f["value"] for f in answer["json"].get("fields", []) if f["name"] == "color"), None)
        if shown == [1, 0, 0]:
            break
        time.sleep(0.2)
    check(shown == [1, 0, 0], f"the page did not get the notebook's edit: {shown}")
    print("an edit made in the notebook is the page's:", shown)
finally:
    driver.quit()
    notebook.shutdown()
    studio.stop()
check(not studio.running, "the studio still runs after stop()")
print("test_notebook_studio: all passed")
