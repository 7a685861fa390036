"""ray view in headless Chromium (Selenium) in a 1280×800 window, as a user meets it: the URL
with its token, the view filling what the window leaves it (and following a resize), the
page without horizontal scrolling and the explanation fully visible, the view at rest
byte-identical to the CLI's render of the same view, a drag that orbits, a
click that explains and marks its pixel, and an explanation that goes stale and is
refreshed after an orbit and a reload; a broken save's error does not squeeze the panel.
Usage: python3 test_browser.py RAY_BINARY SCENE [SCREENSHOT.png]
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import base64
import hashlib
import http.client
import os
import re
import subprocess
import sys
import tempfile
import time

from viewer_harness import Viewer, headless_chromium_or_skip, read_ppm, wait_for

ray, scene = sys.argv[1], sys.argv[2]
screenshot = sys.argv[3] if len(sys.argv) > 3 else None
WINDOW_WIDTH, WINDOW_HEIGHT = 1280, 800


def canvas_pixels(driver, canvas_id="view"):
    return driver.execute_script(
        f"const c = document.getElementById('{canvas_id}');"
        "return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);")


def check_layout(driver, when):
    """No horizontal scrolling; the panel inside the window, the explanation's lines not cut;
    the view takes most of the window."""
    layout = driver.execute_script("""
        const panel = document.getElementById('panel').getBoundingClientRect();
        const view = document.getElementById('viewport').getBoundingClientRect();
        const text = document.getElementById('explain');
        return { inner: window.innerWidth, scroll: document.documentElement.scrollWidth,
                 bodyScroll: document.body.scrollWidth, scrollX: window.scrollX,
                 panelLeft: panel.left, panelRight: panel.right, panelWidth: panel.width,
                 viewWidth: view.width, viewHeight: view.height,
                 textScroll: text.scrollWidth, textClient: text.clientWidth };""")
    assert layout["scroll"] <= layout["inner"] and layout["bodyScroll"] <= layout["inner"], (when, layout)
    assert layout["panelRight"] <= layout["inner"] and layout["panelLeft"] >= 0, (when, layout)
    assert layout["textScroll"] <= layout["textClient"], (when, "explanation lines cut", layout)
    assert layout["panelWidth"] >= 300, (when, "panel squeezed", layout)
    assert layout["viewWidth"] >= layout["inner"] / 2, (when, "the view does not fill the window", layout)
    return layout


def view_fits_window(driver):
    """The view at rest, rendered at the size of the space the window leaves it."""
    return wait_for(driver, "(() => { const v = document.getElementById('viewport'), c = document.getElementById('view');"
                            " const r = window.rayViewer.restFrame;"
                            " return r && c.width === v.clientWidth && c.height === v.clientHeight &&"
                            " window.rayViewer.completeFrame === r.frame && r; })()", timeout=180)


def explain_pixel(driver, canvas, x, y):
    """Clicks pixel (x, y) of the canvas (CSS and canvas pixels are the same size here)."""
    before = driver.execute_script("return window.rayViewer.explains")
    rect = driver.execute_script("return document.getElementById('view').getBoundingClientRect().toJSON()")
    ActionChains(driver).move_to_element_with_offset(canvas, int(x + 0.5 - rect["width"] / 2),
                                                     int(y + 0.5 - rect["height"] / 2)).click().perform()
    wait_for(driver, f"window.rayViewer.explains > {before} && window.rayViewer.explainState === 'fresh'", timeout=180)
    return driver.execute_script("return window.rayViewer.lastExplain")


driver = headless_chromium_or_skip(WINDOW_WIDTH, WINDOW_HEIGHT)
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402 (Selenium is known present)
from selenium.webdriver.common.by import By  # noqa: E402
viewer = Viewer(ray, scene, "--device", "cpu")
try:
    # The viewport, not the window, is 1280 px wide (a window's frame would take from it).
    inner = driver.execute_script("return [window.innerWidth, window.innerHeight]")
    driver.set_window_size(2 * WINDOW_WIDTH - inner[0], 2 * WINDOW_HEIGHT - inner[1])
    driver.get(viewer.url)
    inner = driver.execute_script("return [window.innerWidth, window.innerHeight]")
    assert inner == [WINDOW_WIDTH, WINDOW_HEIGHT], inner

    # The token: the URL's query is traded for an HttpOnly cookie and leaves the address bar.
    assert "token" not in driver.current_url and driver.execute_script("return document.cookie") == "", \
        driver.current_url
    print("token: URL with the token -> cookie, address bar without it")

    # The page's Content-Security-Policy lets its own bundled script alone run (by its hash):
    # the page ran (it asked for its state), and an inline handler slipped into it does not.
    status, page = viewer.request("GET", "/")
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=30)
    connection.request("GET", "/", headers=viewer.auth_headers())
    policy = connection.getresponse().getheader("Content-Security-Policy")
    connection.close()
    script = re.search(rb"<script>(.*?)</script>", page, re.S).group(1)
    digest = base64.b64encode(hashlib.sha256(script).digest()).decode()
    assert f"script-src 'sha256-{digest}'" in policy and "unsafe" not in policy, policy
    driver.execute_script("document.body.insertAdjacentHTML('beforeend',"
                          " '<img id=injected src=data:, onerror=\"window.injectedRan = true\">')")
    time.sleep(0.5)
    assert driver.execute_script("return window.injectedRan === undefined && window.rayViewer.frames > 0")
    print(f"Content-Security-Policy: the page's script alone (sha256-{digest[:12]}...); an injected handler did not run")

    # At rest the view is refined to the CLI's antialiasing: byte-identical to `ray scene W H`
    # on the same device (PoCL, through the engine).
    rest = view_fits_window(driver)
    assert rest["aa"] == "course", rest
    WIDTH, HEIGHT = driver.execute_script("const c = document.getElementById('view'); return [c.width, c.height]")
    folder = tempfile.mkdtemp()
    ppm = os.path.join(folder, "cli.ppm")
    subprocess.run([ray, viewer.scene, str(WIDTH), str(HEIGHT), "--device", "cpu", "-o", ppm, "--quiet"], check=True)
    w, h, expected = read_ppm(ppm)
    pixels = canvas_pixels(driver)
    assert len(pixels) == w * h * 4, (len(pixels), w, h)
    differing = sum(1 for i in range(w * h) if tuple(pixels[4 * i:4 * i + 3]) != tuple(expected[3 * i:3 * i + 3]))
    assert differing == 0, f"{differing} pixels differ from the CLI's render"
    print(f"view at rest (frame {rest['frame']}): {w}x{h}, course AA, identical to ray {WIDTH} {HEIGHT} --device cpu")
    layout = check_layout(driver, "first view")
    print(f"layout at {WINDOW_WIDTH}x{WINDOW_HEIGHT}: no horizontal scroll, panel {layout['panelWidth']:.0f} px wide "
          f"at x {layout['panelLeft']:.0f}..{layout['panelRight']:.0f}")

    # Click a pixel on the floor: its explanation appears, fully visible, and the pixel is
    # marked over the image (the image itself is untouched).
    canvas = driver.find_element(By.ID, "view")
    x, y = 400, 400
    tree = explain_pixel(driver, canvas, x, y)
    assert tree["pixel"] == [x, y], tree["pixel"]
    text = driver.find_element(By.ID, "explain").text
    assert "pixel (" in text and "camera ray" in text and "hits " in text, text[:300]
    check_layout(driver, "explanation shown")
    marker = canvas_pixels(driver, "marker")
    near = [marker[4 * (j * WIDTH + i) + 3] for j in range(y - 9, y + 10) for i in range(x - 9, x + 10)]
    far = [marker[4 * (j * WIDTH + i) + 3] for j in range(0, 40) for i in range(0, 40)]
    assert sum(1 for a in near if a > 0) >= 20 and not any(far), "the explained pixel is not marked"
    assert canvas_pixels(driver) == pixels, "the marker was drawn into the image"
    print(f"click: pixel ({x}, {y}) explained ({len(text.splitlines())} lines, none cut) and marked")

    # Orbit: the explanation goes stale (dimmed) at once and is explained again, for the new
    # view, once the camera rests.
    old_view = tree["view"]
    driver.execute_script("window.rayViewer.explainStates = []")
    ActionChains(driver).move_to_element(canvas).click_and_hold().move_by_offset(40, 10).release().perform()
    wait_for(driver, f"window.rayViewer.restFrame.view > {old_view} && window.rayViewer.explainState === 'fresh' && "
                 f"window.rayViewer.lastExplain.view === window.rayViewer.restFrame.view", timeout=180)
    states = driver.execute_script("return window.rayViewer.explainStates")
    stale = [s for s in states if s["state"] == "stale"]
    assert stale and all(float(s["opacity"]) < 0.6 for s in stale), states
    assert float(states[-1]["opacity"]) == 1.0, states
    assert canvas_pixels(driver) != pixels, "the orbit did not change the image"
    refreshed = driver.execute_script("return window.rayViewer.lastExplain")
    assert refreshed["pixel"] == [x, y] and refreshed["view"] > old_view
    print("orbit: a new view; the explanation was dimmed as stale, then refreshed for it:",
          " -> ".join(s["state"] for s in states))

    # A good save reloads the scene: stale, then refreshed for the new version.
    old_version = refreshed["scene_version"]
    driver.execute_script("window.rayViewer.explainStates = []")
    good = open(viewer.scene).read()
    time.sleep(1.1)  # a new modification time, whatever the file system's resolution
    open(viewer.scene, "w").write(good)
    wait_for(driver, f"window.rayViewer.lastExplain.scene_version > {old_version} && "
                 "window.rayViewer.explainState === 'fresh'", timeout=180)
    states = driver.execute_script("return window.rayViewer.explainStates")
    assert any(s["state"] == "stale" for s in states), states
    print("reload: the explanation was dimmed as stale, then refreshed:", " -> ".join(s["state"] for s in states))

    # A broken save: its error line wraps under the image and leaves the panel as wide.
    width_before = check_layout(driver, "before the broken save")["panelWidth"]
    time.sleep(1.1)
    open(viewer.scene, "w").write(good[:len(good) // 2] + "<unclosed_" + "x" * 200 + "\n")
    wait_for(driver, "document.getElementById('error').textContent.length > 0", timeout=30)
    after = check_layout(driver, "broken save")
    assert after["panelWidth"] == width_before, (width_before, after)
    print(f"broken save: error shown, panel still {after['panelWidth']:.0f} px, no horizontal scroll")

    # A smaller window: the view follows it, rendered again at its new size.
    size = driver.get_window_size()
    driver.set_window_size(size["width"] - 200, size["height"] - 100)
    view_fits_window(driver)
    resized = driver.execute_script("const c = document.getElementById('view'); return [c.width, c.height]")
    assert resized == [WIDTH - 200, HEIGHT - 100], (resized, WIDTH, HEIGHT)
    print(f"window 200x100 px smaller: the view followed, now {resized[0]}x{resized[1]}")
    if screenshot:
        time.sleep(1.1)
        open(viewer.scene, "w").write(good)
        wait_for(driver, "document.getElementById('error').textContent.length === 0", timeout=30)
        wait_for(driver, "window.rayViewer.explainState === 'fresh'", timeout=180)
        driver.save_screenshot(screenshot)
finally:
    driver.quit()
    viewer.close()
print("browser test passed")
