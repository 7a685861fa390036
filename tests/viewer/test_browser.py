"""ray view in headless Chromium (Selenium): the first full frame equals the CLI's render of the
same view, a drag orbits and a new frame arrives, a click shows the pixel's explanation.
Usage: python3 test_browser.py RAY_BINARY SCENE [SCREENSHOT.png]
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import os
import shutil
import subprocess
import sys
import tempfile
import time

try:
    from selenium import webdriver
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
except ImportError:
    print("SKIPPED: python3-selenium is not installed")
    sys.exit(0)
if not shutil.which("chromedriver") or not (shutil.which("chromium") or shutil.which("chromium-browser")):
    print("SKIPPED: chromium or chromium-driver is not installed")
    sys.exit(0)

from viewer_harness import Viewer

ray, scene = sys.argv[1], sys.argv[2]
screenshot = sys.argv[3] if len(sys.argv) > 3 else None
WIDTH, HEIGHT = 160, 120


def read_ppm(path):
    data = open(path, "rb").read()
    parts = data.split(maxsplit=4)
    assert parts[0] == b"P6" and int(parts[3]) == 255
    return int(parts[1]), int(parts[2]), parts[4]


def wait(driver, condition, timeout=180):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = driver.execute_script("return " + condition)
        if value:
            return value
        time.sleep(0.2)
    raise TimeoutError(condition)


viewer = Viewer(ray, scene, "--width", str(WIDTH), "--height", str(HEIGHT), "--device", "cpu")
options = webdriver.ChromeOptions()
for flag in ["--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,900", "--disable-dev-shm-usage"]:
    options.add_argument(flag)
driver = webdriver.Chrome(options=options)
try:
    driver.get(viewer.url)
    wait(driver, "window.rayViewer.completeFrame > 0")

    # The canvas (PoCL, through the engine) against `ray` with --device cpu --aa off at the
    # same size: the same kernel and pixel numbering, so byte-identical.
    folder = tempfile.mkdtemp()
    ppm = os.path.join(folder, "cli.ppm")
    subprocess.run([ray, viewer.scene, str(WIDTH), str(HEIGHT), "--device", "cpu", "--aa", "off", "-o", ppm, "--quiet"],
                   check=True)
    w, h, expected = read_ppm(ppm)
    pixels = driver.execute_script(
        "const c = document.getElementById('view');"
        "return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);")
    assert len(pixels) == w * h * 4, (len(pixels), w, h)
    differing = sum(1 for i in range(w * h) if tuple(pixels[4 * i:4 * i + 3]) != tuple(expected[3 * i:3 * i + 3]))
    assert differing == 0, f"{differing} pixels differ from the CLI's render"
    print(f"first frame: {w}x{h}, identical to ray --device cpu --aa off")

    # Drag to orbit: a new frame arrives and completes.
    frames = driver.execute_script("return window.rayViewer.frames")
    done = driver.execute_script("return window.rayViewer.completeFrame")
    canvas = driver.find_element(By.ID, "view")
    ActionChains(driver).move_to_element(canvas).click_and_hold().move_by_offset(40, 10).release().perform()
    wait(driver, f"window.rayViewer.frames > {frames} && window.rayViewer.completeFrame > {done}")
    after = driver.execute_script(
        "const c = document.getElementById('view');"
        "return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);")
    assert after != pixels, "the orbit did not change the image"
    print("drag: a new frame arrived")

    # Click a pixel: its explanation appears beside the image.
    ActionChains(driver).move_to_element_with_offset(canvas, 0, 0).click().perform()
    wait(driver, "window.rayViewer.lastExplain !== null")
    text = driver.find_element(By.ID, "explain").text
    assert "pixel (" in text and "camera ray" in text, text[:300]
    print("click: explanation shown:", text.splitlines()[0])
    if screenshot:
        driver.save_screenshot(screenshot)
finally:
    driver.quit()
    viewer.close()
print("browser test passed")
