"""Take docs/explore.png and docs/explore_refined.png, the pictures of ``pmplan
explore``, with the real browser.

Starts the server on a free loopback port, opens the page in headless Chromium (Debian's
``chromium`` and ``chromium-driver``, as the browser tests do), loads the demo's W_8 example,
turns the domain map of robot 1's goal on, stops the animation half way and saves the window;
then ticks "refined motion" (radius 0.15) and saves it again: the same domain and map, the
refined motion over the dashed raw one, robots and obstacles as discs.
Run from the repository root: ``python docs/explore_screenshot.py``.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "src")]

from explore_server import chromium, running_server  # noqa: E402


def main(out: Path = ROOT / "docs" / "explore.png",
         refined: Path = ROOT / "docs" / "explore_refined.png") -> Path:
    from selenium.webdriver.support.ui import Select, WebDriverWait

    with running_server() as base, tempfile.TemporaryDirectory() as profile:
        driver = chromium(profile)
        try:
            driver.set_window_size(1180, 790)
            driver.get(base + "/")
            wait = WebDriverWait(driver, 60)
            wait.until(lambda d: d.execute_script("return document.body.dataset.state") == "ready")
            Select(driver.find_element("id", "examples")).select_by_visible_text("W_8")
            wait.until(lambda d: d.execute_script(
                "return document.body.dataset.state === 'ready' && !pmplanExplore.pending()"
                " && document.getElementById('domain').dataset.label === '8'"))
            Select(driver.find_element("id", "map-mode")).select_by_value("goal")
            wait.until(lambda d: d.execute_script("return document.body.dataset.map") == "ready")
            driver.execute_script(
                "const t = document.getElementById('time'); t.value = 560;"
                "t.dispatchEvent(new Event('input'));"
                "document.getElementById('discs-toggle').click();")
            driver.save_screenshot(str(out))
            radius = driver.find_element("id", "radius")
            radius.clear()
            radius.send_keys("0.15")
            driver.find_element("id", "refine-toggle").click()
            wait.until(lambda d: d.execute_script(
                "return document.body.dataset.state === 'ready' && !pmplanExplore.pending()"
                " && pmplanExplore.state.plan.refined"))
            driver.execute_script(
                "const t = document.getElementById('time'); t.value = 560;"
                "t.dispatchEvent(new Event('input'));")
            driver.save_screenshot(str(refined))
        finally:
            driver.quit()
    print(f"wrote {out} and {refined}")
    return out


if __name__ == "__main__":
    main()
