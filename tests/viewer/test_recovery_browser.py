"""The page's side of unsaved work (issue 49), in headless Chromium (Selenium), in a scratch
HOME and XDG_STATE_HOME: a viewer killed (SIGKILL) after an edit leaves a recovery; the next
viewer's page shows the offer (a banner naming the recovery, Restore and Discard); Restore
opens the edit as an unsaved change (the outline shows it, the file is untouched) and the
banner goes; while the scene is modified a `beforeunload` handler asks before the tab closes,
and once saved it does not; the save removes the recovery.
Usage: python3 test_recovery_browser.py RAY_BINARY SCENE (scenes/shadows.xml)
Prints SKIPPED when Selenium, Chromium or chromedriver is missing."""
import signal
import sys

from recovery_harness import Home, ViewerOf
from viewer_harness import headless_chromium_or_skip, wait_for

ray, source = sys.argv[1], sys.argv[2]

# Whether closing the tab now would ask: a beforeunload event the page cancels.
ASKS_BEFORE_CLOSING = ("(() => { const e = new Event('beforeunload', { cancelable: true }); "
                       "window.dispatchEvent(e); return e.defaultPrevented; })()")


def asks_before_closing(driver):
    return driver.execute_script("return " + ASKS_BEFORE_CLOSING)


def outline_text(driver):
    return driver.execute_script("return document.getElementById('outline').textContent")


driver = headless_chromium_or_skip(1280, 900)
from selenium.webdriver.common.by import By  # noqa: E402 (Selenium is known present)

home = Home(source)
try:
    viewer = ViewerOf(ray, home)
    try:
        viewer.op({"op": "add-primitive", "shape": "torus"})
        [kept] = home.wait_recoveries(1, timeout=5)
        viewer.stop(signal.SIGKILL)
    finally:
        viewer.close()
    assert home.scene_untouched()

    viewer = ViewerOf(ray, home)
    try:
        driver.get(viewer.url)
        wait_for(driver, "window.rayViewer.recoveryOffer", timeout=60)
        banner = driver.find_element(By.ID, "recovery")
        assert banner.is_displayed() and kept in banner.text, banner.text
        assert "torus" not in outline_text(driver)
        assert not asks_before_closing(driver), "the page asks before closing with nothing unsaved"
        print(f"page: the offer shown ('{banner.text}'); no question before closing")

        driver.find_element(By.ID, "recovery-restore").click()
        wait_for(driver, "window.rayViewer.restored && window.rayViewer.modified", timeout=60)
        wait_for(driver, "document.getElementById('outline').textContent.includes('torus')", timeout=30)
        wait_for(driver, "document.getElementById('recovery').hidden", timeout=10)
        assert driver.find_element(By.ID, "modified").text == "(modified)"
        assert home.scene_untouched(), "Restore wrote the scene file"
        assert asks_before_closing(driver), "a modified scene's tab closes without asking"
        print("Restore: the torus in the outline, modified, the file untouched; beforeunload asks")

        driver.find_element(By.ID, "save-scene").click()
        wait_for(driver, "window.rayViewer.modified === false", timeout=30)
        assert not home.scene_untouched() and b"torus" in open(home.scene, "rb").read()
        assert not asks_before_closing(driver), "the page still asks once saved"
        home.wait_recoveries(0)
        print("save: written, the recovery removed; beforeunload no longer asks")
    finally:
        viewer.stop()
        viewer.close()

    # Discard in the page removes the recovery and the banner.
    viewer = ViewerOf(ray, home)
    try:
        viewer.op({"op": "add-primitive", "shape": "cone"})
        [kept] = home.wait_recoveries(1, timeout=5)
        viewer.stop(signal.SIGKILL)
    finally:
        viewer.close()
    viewer = ViewerOf(ray, home)
    try:
        driver.get(viewer.url)
        wait_for(driver, "window.rayViewer.recoveryOffer", timeout=60)
        driver.find_element(By.ID, "recovery-discard").click()
        wait_for(driver, "document.getElementById('recovery').hidden && window.rayViewer.recoveryOffer === null",
                 timeout=30)
        home.wait_recoveries(0)
        assert not asks_before_closing(driver)
        print("Discard: the recovery removed, the banner gone")
    finally:
        viewer.stop()
        viewer.close()
finally:
    driver.quit()
    home.close()
print("recovery browser test passed")
