"""The page of ``pmplan explore`` in a real browser: headless Chromium driven by Selenium.

A real server (uvicorn, a free loopback port), Debian's ``chromium`` and ``chromium-driver``
(nothing is downloaded at run time), and real pointer drags (ActionChains). In CI these tests
fail, rather than skip, when the browser is missing (.ci/run installs it). Locally::

    apt-get install -y chromium chromium-driver && pip install -e ".[test]"
    python -m pytest tests/test_explore_browser.py

Screenshots of every step are saved under pytest's temporary folder (printed at the end of
each test with ``-s``).
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import pmplan

from explore_server import chromium, need_browser, running_server


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    need_browser()
    from selenium.webdriver.support.ui import WebDriverWait

    shots = tmp_path_factory.mktemp("explore-screenshots")
    with running_server() as base:
        driver = chromium(tmp_path_factory.mktemp("chromium-profile"))
        try:
            driver.get(base + "/")
            WebDriverWait(driver, 60).until(
                lambda d: d.find_element("tag name", "body").get_attribute("data-state")
                in ("ready", "error"))
            yield driver, shots
        finally:
            driver.quit()


def _wait_ready(driver, state="ready"):
    """Wait until the page has planned its current query; check that it shows ``state``."""
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(driver, 60).until(lambda d: d.execute_script(
        "return document.body.dataset.state !== 'planning' && !pmplanExplore.pending()"))
    assert driver.find_element("tag name", "body").get_attribute("data-state") == state


def _shown(driver) -> dict:
    """What the page shows: the label, stratum, clearance, and robot 1's drawn path (units)."""
    get = driver.find_element
    out = {k: get("id", k).text for k in ("planner", "domain", "stratum", "clearance")}
    out["label"] = get("id", "domain").get_attribute("data-label")
    out["error"] = get("id", "error").text if get("id", "error").is_displayed() else ""
    paths = driver.find_elements("id", "path-1")
    if paths:
        scale = driver.execute_script("return pmplanExplore.state.view.scale")
        pts = [tuple(map(float, p.split(","))) for p in paths[0].get_attribute("points").split()]
        times = json.loads(paths[0].get_attribute("data-times"))
        out["path"] = (np.array(times), np.array(pts) / scale)  # screen px -> units
    return out


def _sup(a, b) -> float:
    """Sup distance (units) between two drawn paths, sampled at 1001 times."""
    ts = np.linspace(0, 1, 1001)

    def at(p):
        t, xy = p
        return np.stack([np.interp(ts, t, xy[:, 0]), np.interp(ts, t, xy[:, 1])], axis=1)
    return float(np.abs(at(a) - at(b)).max())


def _drag(driver, element_id, dx_units, dy_units, steps=5, state="ready"):
    """Drag a marker by (dx, dy) units with real pointer actions, in a few moves."""
    from selenium.webdriver.common.action_chains import ActionChains

    # units -> the plane's 800 x 600 user units -> CSS pixels (the SVG is scaled to the page)
    scale = driver.execute_script(
        "return pmplanExplore.state.view.scale"
        " * document.getElementById('plane').getBoundingClientRect().width / 800")
    el = driver.find_element("id", element_id)
    total = (round(dx_units * scale), round(-dy_units * scale))
    chain = ActionChains(driver).click_and_hold(el)
    done = (0, 0)
    for k in range(1, steps + 1):
        nxt = (round(total[0] * k / steps), round(total[1] * k / steps))
        chain.move_by_offset(nxt[0] - done[0], nxt[1] - done[1]).pause(0.05)
        done = nxt
    chain.release().perform()
    _wait_ready(driver, state)


DEFAULT = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1]], "goal": [[3, -1]]}


def _reset(driver, query=DEFAULT):
    """Set up a scene (as loading an example does); the tests then drag with the pointer."""
    driver.execute_script("pmplanExplore.setQuery(arguments[0])", query)
    _wait_ready(driver)


def _point(driver, kind, i=0):
    return driver.execute_script(f"return pmplanExplore.state.{kind}[{i}]")


def test_drag_across_a_domain_boundary_jumps_and_inside_stays_close(page):
    driver, shots = page
    # the page opens on o1 = (0, 0), o2 = (4, 0), x1 = (1, 1), x'1 = (3, -1): W_6, T_{3,3}
    _wait_ready(driver)
    first = _shown(driver)
    assert first["planner"] == "obstacle_line_compact" and first["label"] == "6"
    assert first["stratum"] == "T3,3" and float(first["clearance"]) > 0
    driver.save_screenshot(str(shots / "0-start.png"))

    _drag(driver, "goal-1", 0.25, 0)  # a little, inside the domain
    assert _point(driver, "goal") == [3.25, -1]
    inside = _shown(driver)
    assert inside["label"] == "6" and not inside["error"]
    assert 0 < _sup(first["path"], inside["path"]) <= 0.3  # it follows: moved by 0.25
    driver.save_screenshot(str(shots / "1-inside.png"))

    _drag(driver, "goal-1", 0.75, 0)  # onto o2's column x = 4: the domain W_5
    assert _point(driver, "goal") == [4, -1]
    boundary = _shown(driver)
    assert boundary["label"] == "5" and boundary["stratum"] == "T3,2"
    assert _sup(inside["path"], boundary["path"]) > 1.0  # it jumps
    driver.save_screenshot(str(shots / "2-boundary.png"))

    _drag(driver, "goal-1", 0.25, 0)  # off the column again: back in W_6, close to before
    beyond = _shown(driver)
    assert beyond["label"] == "6"
    assert _sup(inside["path"], beyond["path"]) <= 1.0 + 1e-9  # moved by 1 unit, no jump
    assert _sup(boundary["path"], beyond["path"]) > 1.0
    driver.save_screenshot(str(shots / "3-beyond.png"))
    print("screenshots in", shots)


def test_invalid_position_shows_the_librarys_message(page):
    driver, shots = page
    _reset(driver)
    goal = _point(driver, "goal")
    # drag the goal onto o2 = (4, 0): coincident points
    _drag(driver, "goal-1", 4 - goal[0], 0 - goal[1], state="error")
    shown = _shown(driver)
    assert "coincide" in shown["error"] and "o2" in shown["error"] and "x1" in shown["error"]
    assert shown["label"] == "" and "path" not in shown  # no broken drawing
    assert "invalid" in driver.find_element("id", "points").get_attribute("class")
    driver.save_screenshot(str(shots / "4-invalid.png"))
    _drag(driver, "goal-1", 0, -1)  # to (4, -1): valid again, on o2's column
    assert _point(driver, "goal") == [4, -1]
    assert _shown(driver)["error"] == "" and _shown(driver)["label"] == "5"


def test_domain_map_of_the_goal_and_of_the_start(page):
    from selenium.webdriver.support.ui import Select, WebDriverWait

    driver, shots = page
    _reset(driver)
    for mode in ("goal", "start"):
        Select(driver.find_element("id", "map-mode")).select_by_value(mode)
        WebDriverWait(driver, 60).until(
            lambda d: d.execute_script("return document.body.dataset.map") == "ready"
            and d.execute_script("return pmplanExplore.state.map.which") == mode)
        legend = driver.find_element("id", "legend").text
        # the goal's (start's) own column x = 1 and the obstacles' columns are W_5: lines
        assert "W5" in legend and "W6" in legend and "T3,3" in legend
        colours = driver.execute_script("""
            const c = document.getElementById('map').getContext('2d');
            const d = c.getImageData(0, 0, 800, 600).data, seen = new Set();
            for (let k = 0; k < d.length; k += 4 * 97) seen.add(d[k] + ',' + d[k+1] + ',' + d[k+2]);
            return seen.size;""")
        assert colours >= 2
        # the pixel on o1's column (x = 0) has W_5's colour, one beside it W_6's
        sx, sy = (driver.execute_script(f"return pmplanExplore.{f}({v})")
                  for f, v in (("sx", 0), ("sy", 2.5)))
        a, b = (driver.execute_script(
            f"const p = document.getElementById('map').getContext('2d')"
            f".getImageData({round(x)}, {round(sy)}, 1, 1).data; return [p[0], p[1], p[2]]")
            for x in (sx, sx + 20))
        assert a != b
        driver.save_screenshot(str(shots / f"5-map-{mode}.png"))
    Select(driver.find_element("id", "map-mode")).select_by_value("off")


def test_examples_buttons_and_animation(page):
    from selenium.webdriver.support.ui import Select, WebDriverWait

    driver, shots = page
    Select(driver.find_element("id", "examples")).select_by_visible_text("T23_34 (W_4)")
    _wait_ready(driver)
    shown = _shown(driver)
    assert shown["planner"] == "planar_three" and shown["label"] == "4"
    assert shown["stratum"] == "T2,33,4"  # T^{2,3}_{3,4}, as sup/sub text
    Select(driver.find_element("id", "examples")).select_by_visible_text("W_10")
    _wait_ready(driver)
    assert _shown(driver)["label"] == "10" and len(driver.find_elements("css selector",
                                                                     ".robot-path")) == 3
    driver.find_element("id", "add-robot").click()
    _wait_ready(driver)
    assert len(driver.find_elements("css selector", ".robot-path")) == 4
    driver.find_element("id", "remove-robot").click()
    driver.find_element("id", "add-obstacle").click()
    _wait_ready(driver)
    assert len(driver.find_elements("css selector", ".obstacle")) == 3
    assert _shown(driver)["planner"] == "obstacle_line_compact"
    driver.find_element("id", "remove-obstacle").click()
    _wait_ready(driver)
    # play moves the robots along the motion; pause stops them
    driver.find_element("id", "play").click()
    WebDriverWait(driver, 30).until(
        lambda d: int(d.find_element("id", "time").get_attribute("value")) > 100)
    driver.find_element("id", "play").click()
    t = int(driver.find_element("id", "time").get_attribute("value"))
    assert int(driver.find_element("id", "time").get_attribute("value")) == t
    # the mover of robot 1 is drawn where the plan puts it at that time
    pos = driver.execute_script(
        "const m = document.getElementById('mover-1');"
        "return [Number(m.getAttribute('cx')), Number(m.getAttribute('cy'))]")
    p = _shown(driver)["path"]
    scale = driver.execute_script("return pmplanExplore.state.view.scale")
    tt = driver.execute_script("return pmplanExplore.state.t")
    want = [np.interp(tt, p[0], p[1][:, 0]), np.interp(tt, p[0], p[1][:, 1])]
    assert np.allclose(np.array(pos) / scale, want, atol=0.02)
    driver.find_element("id", "discs-toggle").click()
    assert len(driver.find_elements("css selector", ".disc")) == 2 + 3
    driver.save_screenshot(str(shots / "6-example.png"))


def test_section_4_planner_jumps_from_W4_to_W3_on_an_obstacle_column(page):
    driver, shots = page
    # the demo's W4 query of paper Section 4: o3 = (2.5, 1.5), x = (0, -2) on o1's column,
    # x' = (6, 2.5) on its own column: T^{2,3}_{3,4}
    _reset(driver, {"obstacles": [[0, 0], [4, 0], [2.5, 1.5]], "start": [[0, -2]],
                    "goal": [[6, 2.5]]})
    before = _shown(driver)
    assert before["planner"] == "planar_three" and before["label"] == "4"
    _drag(driver, "goal-1", -0.25, 0)  # inside W4
    inside = _shown(driver)
    assert inside["label"] == "4" and 0 < _sup(before["path"], inside["path"]) <= 0.3
    _drag(driver, "goal-1", -1.75, 0)  # onto o2's column u = 4: T^{2,3}_{3,3}, W3
    assert _point(driver, "goal") == [4, 2.5]
    on = _shown(driver)
    assert on["label"] == "3" and on["stratum"] == "T2,33,3"
    assert _sup(inside["path"], on["path"]) > 1.0
    driver.save_screenshot(str(shots / "7-section4-W3.png"))
    # obstacles are draggable too: o3 onto the line o1o2 gives the family T^1 (here T^1_{2,2})
    _drag(driver, "obstacle-3", 0, -1.5)
    assert driver.execute_script("return pmplanExplore.state.obstacles[2]") == [2.5, 0]
    moved = _shown(driver)
    assert moved["label"] == "2" and moved["stratum"] == "T12,2"


def _polyline_length(driver, element_id) -> float:
    pts = driver.find_element("id", element_id).get_attribute("points").split()
    xy = np.array([tuple(map(float, p.split(","))) for p in pts])
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def test_refined_motion_toggle_keeps_the_domain_and_draws_the_radii(page):
    driver, shots = page
    q = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1], [2, 3]], "goal": [[3, -1], [0, 2]]}
    _reset(driver, q)
    raw = _shown(driver)
    assert not driver.find_elements("css selector", ".raw-path")
    assert driver.find_element("id", "radii").text == "-"
    radius = driver.find_element("id", "radius")
    radius.clear()
    radius.send_keys("0.2")
    driver.find_element("id", "refine-toggle").click()
    _wait_ready(driver)
    refined = _shown(driver)
    # the same domain and stratum; the raw motion dashed underneath, the refined one shorter
    assert (refined["label"], refined["stratum"]) == (raw["label"], raw["stratum"])
    assert len(driver.find_elements("css selector", ".raw-path")) == 2
    for i in (1, 2):
        assert _polyline_length(driver, f"path-{i}") < _polyline_length(driver, f"raw-{i}")
    want = pmplan.plan(q["obstacles"], q["start"], q["goal"], refine=True, radius=0.2,
                       obstacle_radius=0.2)  # (the default unit of a refined plan: 0.4)
    world = json.loads(driver.find_element("id", "path-1").get_attribute("data-world"))
    assert np.array_equal(np.array(world), want.path.waypoints[:, 2])  # what pmplan.plan gives
    radii = driver.find_element("id", "radii")
    assert radii.get_attribute("data-kept") == "true" and radii.text.startswith("kept")
    # robots and obstacles drawn as discs of the radius (screen pixels = units * scale)
    scale = driver.execute_script("return pmplanExplore.state.view.scale")
    bodies = driver.find_elements("css selector", ".body")
    assert len(bodies) == 4
    assert all(abs(float(b.get_attribute("r")) - 0.2 * scale) < 1e-6 for b in bodies)
    driver.save_screenshot(str(shots / "8-refined.png"))
    # a radius the start violates: the library's message, one line, and no motion
    radius.clear()
    radius.send_keys("1.2")
    radius.send_keys("\t")  # change event
    _wait_ready(driver, "error")
    assert "closer than radius + obstacle_radius = 2.4" in _shown(driver)["error"]
    driver.find_element("id", "refine-toggle").click()
    _wait_ready(driver)
    assert not driver.find_elements("css selector", ".raw-path, .body")
    assert _shown(driver)["label"] == raw["label"]


def test_a_refined_motion_that_misses_its_radii_says_why(page):
    driver, shots = page
    # a robot's path crosses the gap between o3 and o2, narrower than a robot of radius 0.45
    q = {"obstacles": [[2, -1], [-2, 1], [-3, 2]], "start": [[-1, 3], [-2, -1]],
         "goal": [[3, 1], [-3, -1]]}
    _reset(driver, q)
    why = driver.find_element("id", "radii-why")
    assert not why.is_displayed()
    radius = driver.find_element("id", "radius")
    radius.clear()
    radius.send_keys("0.45")
    driver.find_element("id", "refine-toggle").click()
    _wait_ready(driver)
    want = pmplan.plan(q["obstacles"], q["start"], q["goal"], refine=True, radius=0.45,
                       obstacle_radius=0.45)
    assert not want.respects_radius
    assert driver.find_element("id", "radii").get_attribute("data-kept") == "false"
    assert why.is_displayed() and why.text == want.radius_reason
    assert re.search(r"crosses the gap between obstacles (o3 and o2|o2 and o3)", why.text)
    driver.save_screenshot(str(shots / "8b-radii-why.png"))
    driver.find_element("id", "refine-toggle").click()  # unrefined: nothing to explain
    _wait_ready(driver)
    assert not why.is_displayed()


# --------------------------------------------------------------------------------------------
# the domain map: on when the page opens, its boundaries continuous lines; a phone's width


TILTED = {"obstacles": [[0, 0], [4, 1]], "start": [[1, 1], [2, -1]], "goal": [[3, -1], [1, 2.5]]}


def _wait_map(driver, which="goal"):
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(driver, 60).until(lambda d: d.execute_script(
        "return document.body.dataset.map === 'ready' && !pmplanExplore.pending()"
        " && pmplanExplore.state.map && pmplanExplore.state.map.which === arguments[0]", which))


def _boundaries(driver) -> list[dict]:
    return driver.execute_script("""
        return [...document.querySelectorAll('#boundaries line')].map((l) => {
          const s = getComputedStyle(l);
          return {x1: +l.getAttribute('x1'), y1: +l.getAttribute('y1'),
                  x2: +l.getAttribute('x2'), y2: +l.getAttribute('y2'),
                  width: parseFloat(s.strokeWidth), color: s.stroke};
        });""")


def _grid_colours(driver) -> set:
    return set(driver.execute_script(
        "return [...document.querySelectorAll('#grid line')].map((l) => getComputedStyle(l).stroke)"))


def test_domain_boundaries_are_wide_continuous_lines_when_the_line_tilts(page):
    """With o1o2 tilted, the goal's label changes on the columns of o1, o2 and the other goal:
    three straight lines perpendicular to o1o2 through those points, one SVG line each (not
    scattered pixels), wider than the grid lines and in a colour the grid does not use."""
    from selenium.webdriver.support.ui import Select

    driver, shots = page
    Select(driver.find_element("id", "map-mode")).select_by_value("goal")
    _reset(driver, TILTED)
    _wait_map(driver)
    lines = _boundaries(driver)
    assert len(lines) == 3
    e = np.array([4.0, 1.0]) / np.hypot(4, 1)
    through = [[0, 0], [4, 1], [1, 2.5]]  # o1, o2, robot 2's goal
    sx = lambda p: driver.execute_script(  # noqa: E731
        "return [pmplanExplore.sx(arguments[0]), pmplanExplore.sy(arguments[1])]", *p)
    for line, p in zip(lines, through):
        a, b = np.array([line["x1"], line["y1"]]), np.array([line["x2"], line["y2"]])
        d = (b - a) / np.hypot(*(b - a))
        # perpendicular to o1o2 (screen y points down: e becomes (e_x, -e_y))
        assert abs(d @ np.array([e[0], -e[1]])) < 1e-3
        # through the point, and long enough to cross the whole plane
        q = np.array(sx(p))
        assert abs(d[0] * (q - a)[1] - d[1] * (q - a)[0]) < 1.0
        assert np.hypot(*(b - a)) >= 1000
        assert line["width"] >= 2.5 and line["color"] not in _grid_colours(driver)
    assert "domain boundaries" in driver.find_element("id", "legend").text
    driver.save_screenshot(str(shots / "9-boundaries-tilted.png"))
    # the paper's Section 4 planner with o3 on the line o1o2: the height decides, one boundary
    _reset(driver, {"obstacles": [[0, 0], [4, 0], [2.5, 0]], "start": [[0, -2]],
                    "goal": [[6, 2.5]]})
    _wait_map(driver)
    (line,) = _boundaries(driver)
    assert abs(line["y1"] - line["y2"]) < 1e-6  # along L_C (horizontal here)
    Select(driver.find_element("id", "map-mode")).select_by_value("off")
    assert _boundaries(driver) == []


def test_phone_width_every_control_clicks_and_the_map_is_on_by_default(page):
    """At 360 px the plane scales to the width, the panel stacks below it, nothing overflows
    sideways, and every control takes a real click (no element paints over another); the
    domain map is on when the page opens; a drag moves a point by what the finger moved."""
    from selenium.common.exceptions import ElementClickInterceptedException
    from selenium.webdriver.support.ui import Select, WebDriverWait

    driver, shots = page
    base = driver.current_url.split("#")[0]
    driver.set_window_size(360, 780)
    try:
        driver.get(base)
        WebDriverWait(driver, 60).until(lambda d: d.execute_script(
            "return document.body.dataset.state") == "ready")
        # the map is on from the start, with its boundaries
        assert driver.find_element("id", "map-mode").get_attribute("value") == "goal"
        _wait_map(driver)
        assert len(_boundaries(driver)) >= 1
        box = driver.execute_script("""
            const r = (id) => document.getElementById(id).getBoundingClientRect();
            return {inner: window.innerWidth, scroll: document.documentElement.scrollWidth,
                    stage: r('stage'), plane: r('plane'), aside: document.querySelector('aside')
                    .getBoundingClientRect()};""")
        assert box["scroll"] <= box["inner"], "the page scrolls sideways"
        assert 300 <= box["plane"]["width"] <= box["inner"]
        assert abs(box["plane"]["height"] / box["plane"]["width"] - 0.75) < 0.01
        assert box["aside"]["top"] >= box["stage"]["bottom"]  # stacked below the plane
        assert box["aside"]["right"] <= box["inner"]
        driver.save_screenshot(str(shots / "10-phone.png"))

        def click(element_id):
            el = driver.find_element("id", element_id)
            driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", el)
            try:
                el.click()
            except ElementClickInterceptedException as exc:  # pragma: no cover - the defect
                raise AssertionError(f"#{element_id} is covered: {exc.msg}") from None

        # each button adds or removes one robot path / obstacle marker
        for button, selector, change in (("add-robot", ".robot-path", 1),
                                         ("remove-robot", ".robot-path", -1),
                                         ("add-obstacle", ".obstacle", 1),
                                         ("remove-obstacle", ".obstacle", -1)):
            before = len(driver.find_elements("css selector", selector))
            click(button)
            _wait_ready(driver)
            assert len(driver.find_elements("css selector", selector)) == before + change, button
        click("play")
        WebDriverWait(driver, 30).until(
            lambda d: int(d.find_element("id", "time").get_attribute("value")) > 50)
        click("play")
        assert driver.find_element("id", "play").text == "play"
        click("time")  # the slider takes a click: the time jumps to about its middle
        assert 300 <= int(driver.find_element("id", "time").get_attribute("value")) <= 700
        click("discs-toggle")
        assert driver.find_elements("css selector", ".disc")
        click("discs-toggle")
        click("snap")
        assert not driver.find_element("id", "snap").is_selected()
        click("snap")
        assert driver.find_element("id", "snap").is_selected()
        click("radius")
        click("refine-toggle")
        _wait_ready(driver)
        assert driver.find_elements("css selector", ".raw-path")
        click("refine-toggle")
        _wait_ready(driver)
        click("examples")
        Select(driver.find_element("id", "examples")).select_by_visible_text("W_5")
        _wait_ready(driver)
        assert _shown(driver)["label"] == "5"
        click("map-mode")
        Select(driver.find_element("id", "map-mode")).select_by_value("start")
        _wait_map(driver, "start")
        # a real drag on the scaled plane moves the point by the units the finger moved
        _reset(driver)
        before = _point(driver, "goal")
        _drag(driver, "goal-1", 0.5, 0)
        assert _point(driver, "goal") == [before[0] + 0.5, before[1]]
        driver.save_screenshot(str(shots / "11-phone-after.png"))
    finally:
        driver.set_window_size(1200, 700)
        driver.get(base)
        WebDriverWait(driver, 60).until(lambda d: d.execute_script(
            "return document.body.dataset.state") == "ready")


# --------------------------------------------------------------------------------------------
# the workspace box (issue 25): drawn, its corners dragged, every motion inside it


def test_workspace_box_keeps_the_motion_inside_and_its_corners_drag(page):
    driver, shots = page
    q = {"obstacles": [[0, 0], [4, 0], [2, 2]], "start": [[1, 1], [3, 2]],
         "goal": [[3, -1], [-0.5, 1]]}
    _reset(driver, q)
    free = pmplan.plan(q["obstacles"], q["start"], q["goal"])
    assert free.waypoints[:, :, 1].max() >= 3  # the free motion reaches the top wall (y = 3)
    driver.find_element("id", "box-toggle").click()
    _wait_ready(driver)
    box = driver.execute_script("return pmplanExplore.state.box")
    assert box == [[-1.5, -2], [5, 3]]  # every point, one unit of margin
    assert driver.find_element("id", "box").is_displayed()
    m = 3
    world = np.array(json.loads(driver.find_element("id", "path-2").get_attribute("data-world")))
    want = pmplan.plan(q["obstacles"], q["start"], q["goal"], bounds=([-1.5, -2], [5, 3]))
    assert np.array_equal(world, want.path.waypoints[:, m + 1])
    assert (world >= [-1.5, -2]).all() and (world <= [5, 3]).all()
    # drag the upper corner up by one unit: the box follows, the motion stays inside it
    _drag(driver, "box-corner-2", 0, 1)
    box = driver.execute_script("return pmplanExplore.state.box")
    assert box[0] == [-1.5, -2] and box[1] == [5, 4]
    for i in (1, 2):
        w = np.array(json.loads(driver.find_element("id", f"path-{i}").get_attribute("data-world")))
        assert (w >= [-1.5, -2]).all() and (w <= [5, 4]).all()
    driver.save_screenshot(str(shots / "9-box.png"))
    # the refined motion keeps its radius off the walls
    radius = driver.find_element("id", "radius")
    radius.clear()
    radius.send_keys("0.2")
    driver.find_element("id", "refine-toggle").click()
    _wait_ready(driver)
    for i in (1, 2):
        w = np.array(json.loads(driver.find_element("id", f"path-{i}").get_attribute("data-world")))
        assert (w >= np.array([-1.5, -2]) + 0.2).all() and (w <= np.array([5, 4]) - 0.2).all()
    assert driver.find_element("id", "radii").get_attribute("data-kept") == "true"
    # a corner dragged past a start: the library's message, in one line
    _drag(driver, "box-corner-2", -4.5, 0, state="error")
    assert "outside the workspace box" in _shown(driver)["error"]
    _drag(driver, "box-corner-2", 4.5, 0)
    # the domain map marks the outside of the box
    _wait_map(driver)
    mp = driver.execute_script("return pmplanExplore.state.map")
    assert mp["outside"] > 0 and mp["boundaries"] == []
    driver.find_element("id", "refine-toggle").click()
    driver.find_element("id", "box-toggle").click()
    _wait_ready(driver)
    assert not driver.find_elements("id", "box")
