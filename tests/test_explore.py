"""``pmplan explore``: the server's JSON API against a real uvicorn server, and the CLI command.

The browser tests of the page are in ``test_explore_browser.py``.
"""

from __future__ import annotations

import http.client
import json
import os
import re
import signal
import socket
import subprocess
import sys
import urllib.parse
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from explore_server import need_extra, request, running_server
from pmplan.cli import main
from pmplan.io import parse_query, plan_to_dict, with_defaults
from strategies import queries

SRC = Path(__file__).resolve().parents[1] / "src"


@pytest.fixture(scope="module")
def base():
    with running_server() as url:
        yield url


def _library(obj, samples=None):
    """(status, body) the library gives for a decoded query: the dict, or 422 and the text."""
    try:
        return 200, plan_to_dict(pmplan.plan_query(parse_query(obj)), samples=samples)
    except (pmplan.InputError, pmplan.CertificationError) as exc:
        return 422, {"error": str(exc), "type": type(exc).__name__}


def _roundtrip(d):
    return json.loads(json.dumps(d))


# ------------------------------------------------------------------------------ the page
def test_page_and_assets_are_served_and_offline(base):
    status, html = request(base, "/")
    assert status == 200 and "<svg" in html and "/static/explore.js" in html
    for name in ("explore.js", "explore.css"):
        status, text = request(base, f"/static/{name}")
        assert status == 200 and len(text) > 500
        # no CDN, no remote font or script: every address the page loads is this server's
        assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", text + html)
        assert not re.search(r"""(fetch|import)\s*\(\s*["'](https?:)?//""", text)
        assert "cdn" not in text.lower()
    status, body = request(base, "/static/../server.py")
    assert status == 404
    status, body = request(base, "/static/nothing.js")
    assert status == 404 and body["type"] == "NotFound"


def test_assets_are_package_data():
    root = resources.files("pmplan.web") / "static"
    assert {p.name for p in root.iterdir()} >= {"index.html", "explore.js", "explore.css"}
    pyproject = (SRC.parent / "pyproject.toml").read_text()
    for pattern in ("web/static/*.html", "web/static/*.js", "web/static/*.css"):
        assert pattern in pyproject


# ------------------------------------------------------------------------------ POST /api/plan
def test_plan_is_pmplan_plans_output(base, tmp_path, capsys):
    q = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1], [2, 3]], "goal": [[3, -1], [0, 2]]}
    path = tmp_path / "q.json"
    path.write_text(json.dumps(q))
    for args, suffix in (([], ""), (["--samples", "7"], "?samples=7")):
        assert main(["plan", str(path), *args]) == 0
        cli = json.loads(capsys.readouterr().out)
        status, body = request(base, "/api/plan" + suffix, q)
        assert status == 200
        assert body == cli


REFINE_Q = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1], [2, 3]], "goal": [[3, -1], [0, 2]]}


@pytest.mark.parametrize("radius", [0.0, 0.2])
def test_refined_plan_is_pmplan_plan_refine_output(base, tmp_path, capsys, radius):
    path = tmp_path / "q.json"
    path.write_text(json.dumps(REFINE_Q))
    assert main(["plan", str(path), "--refine", "--radius", str(radius), "--obstacle-radius",
                 str(radius)]) == 0
    cli = json.loads(capsys.readouterr().out)
    status, body = request(
        base, f"/api/plan?refine=true&radius={radius}&obstacle_radius={radius}", REFINE_Q)
    assert status == 200, body
    raw = body.pop("raw")
    assert body == cli and body["refined"] is True and body["radius"] == radius
    unrefined = pmplan.plan_query(with_defaults(parse_query(REFINE_Q),
                                            {"radius": radius, "obstacle_radius": radius}))
    assert raw == _roundtrip({"times": unrefined.path.times.tolist(),
                              "waypoints": unrefined.path.waypoints.tolist()})
    assert (body["domain"], body["stratum"]) == (unrefined.domain, unrefined.stratum)
    assert body["respects_radius"] is True
    status, plain = request(base, "/api/plan?refine=false", REFINE_Q)
    assert status == 200 and "raw" not in plain and plain["refined"] is False


REFINE_BAD = [
    ("refine=yes", "`refine` must be True or False, got 'yes'"),
    ("refine=true&radius=abc", "`radius` must be a finite real number >= 0"),
    ("refine=true&radius=-1", "`radius` must be a finite real number >= 0"),
    ("refine=true&obstacle_radius=nan", "`obstacle_radius` must be a finite real number >= 0"),
    ("radius=0.1", "apply to refined motions"),
    ("refine=true&radius=1.2", "closer than 2 * radius"),
]


@pytest.mark.parametrize("params,words", REFINE_BAD, ids=[p for p, _ in REFINE_BAD])
def test_bad_refine_parameters_get_a_422_with_the_librarys_message(base, params, words):
    status, body = request(base, "/api/plan?" + params, REFINE_Q)
    assert status == 422, body
    assert words in body["error"] and "Traceback" not in body["error"]


def test_examples_cover_every_stratum_and_every_demo_domain(base):
    status, exs = request(base, "/api/examples")
    assert status == 200
    seen_strata, demo = set(), {}
    for ex in exs:
        status, body = request(base, "/api/plan", ex["query"])
        assert status == 200, body
        assert body == _roundtrip(_library(ex["query"])[1])
        if ex["group"].startswith("Section 4"):
            name = ex["name"].split()[0]
            assert ex["name"].endswith(f"(W_{body['domain']})")
            seen_strata.add(name)
        else:
            demo.setdefault(body["planner"], set()).add(body["domain"])
            assert ex["name"].lstrip("W_") == str(body["domain"])
    assert seen_strata == set(pmplan.planners.planar_three.STRATA)
    assert demo == {"obstacle_line_compact": set(range(4, 11)), "planar_three": {1, 2, 3, 4}}


@settings(max_examples=25)
@given(q=st.one_of(queries(2, 2, 2, degenerate=True), queries(2, 3, 1, degenerate=True),
                   queries(2, 3, 3)),
       collide=st.booleans())
def test_plan_agrees_with_the_library_on_any_query(base, q, collide):
    o, s, g = (a.tolist() for a in q)
    if collide:  # an invalid query: the server says what the library says, with 422
        g[0] = o[-1]
    obj = {"obstacles": o, "start": s, "goal": g}
    status, body = request(base, "/api/plan", obj)
    expect_status, expect = _library(obj)
    assert (status, body) == (expect_status, _roundtrip(expect))
    if collide:
        assert status == 422 and "coincide" in body["error"]


BAD = [
    # (raw body, status, words in the message)
    (b"{not json", 400, "not valid JSON"),
    (b"", 400, "not valid JSON"),
    (b"\xff\xfe\x00garbage", 400, "not valid JSON"),
    (b"[" * 100_000 + b"]" * 100_000, 400, "nested too deeply"),
    (b"[1, 2]", 422, "must be a JSON object"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[1,1]]}', 422, "missing key"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [["1",1]], "goal": [[3,1]]}', 422, "str"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[true,1]], "goal": [[3,1]]}', 422, "bool"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[NaN,1]], "goal": [[3,1]]}', 422, "finite"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[1e400,1]], "goal": [[3,1]]}', 422, "finite"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[9007199254740993,1]], "goal": [[3,1]]}',
     422, "exactly"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[1' + b"0" * 5000 + b',1]], "goal": [[3,1]]}',
     422, "too large"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[1,1]], "goal": [[3,1]], "lift": -1}', 422,
     "lift"),
    (b'{"obstacles": [[0,0],[4,0]], "start": [[1,1]], "goal": [[3,1]], "x": 1}', 422,
     "unknown key"),
    (b'{"obstacles": [[0,0],[0,0]], "start": [[1,1]], "goal": [[3,1]]}', 422, "coincide"),
]


@pytest.mark.parametrize("raw,status,words", BAD, ids=[f"bad{k}" for k in range(len(BAD))])
def test_bad_requests_get_a_4xx_with_the_message(base, raw, status, words):
    got, body = request(base, "/api/plan", raw=raw)
    assert got == status, body
    assert words in body["error"] and "Traceback" not in body["error"]
    if status == 422 and raw.startswith(b"{"):  # the library's own text, word for word
        try:
            obj = json.loads(raw)
        except (ValueError, RecursionError):
            return
        if not any(len(str(v)) > 1000 for v in obj.values()):
            assert body == _roundtrip(_library(obj)[1])


def test_bounded_bodies_and_points(base):
    big = b'{"obstacles": [' + b"[0.5, 0.5]," * 100_000 + b"[0,0]]}"
    status, body = request(base, "/api/plan", raw=big)
    assert status == 413 and "1,000,000 bytes" in body["error"]
    # a chunked body (no Content-Length) is bounded as well
    host, port = urllib.parse.urlsplit(base).netloc.split(":")
    conn = http.client.HTTPConnection(host, int(port), timeout=60)
    conn.request("POST", "/api/plan", body=iter([b"[" + b"0," * 300_000] * 2),
                 encode_chunked=True, headers={"Content-Type": "application/json"})
    resp = conn.getresponse()
    assert resp.status == 413 and b"larger than" in resp.read()
    conn.close()
    rng = np.random.default_rng(0)
    q = {"obstacles": rng.normal(size=(2, 2)).tolist(), "start": rng.normal(size=(70, 2)).tolist(),
         "goal": rng.normal(size=(70, 2)).tolist()}
    status, body = request(base, "/api/plan", q)
    assert status == 422 and "72 points" in body["error"] and "at most 64" in body["error"]
    status, body = request(base, "/api/plan?samples=1", {**q, "start": q["start"][:1],
                                                         "goal": q["goal"][:1]})
    assert status == 422 and "--samples must be an integer from 2" in body["error"]
    status, body = request(base, "/api/plan?samples=x", q)
    assert status == 422 and "`samples` must be an integer" in body["error"]
    # ... and the server still answers
    assert request(base, "/api/plan", {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1]],
                                       "goal": [[3, -1]]})[0] == 200


def test_wrong_method_and_address(base):
    assert request(base, "/api/plan")[0] == 405
    assert request(base, "/api/nothing", {})[0] == 404
    assert request(base, "/api/examples", {}, method="POST")[0] == 405


# ------------------------------------------------------------------------------ domain map
Q2 = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1], [2, 3]], "goal": [[3, -1], [1, 2]]}


@pytest.mark.parametrize("which", ["goal", "start"])
def test_domain_map_is_plan_at_every_pixel(base, which):
    req = {"query": Q2, "which": which, "robot": 1, "origin": [-1, -1.5], "step": 0.5,
           "size": [13, 9]}
    status, body = request(base, "/api/domain-map", req)
    assert status == 200, body
    lab = np.array(body["domain"])
    assert lab.shape == (9, 13) and body["planner"] == "obstacle_line_compact"
    counts = {}
    for j in range(9):
        for i in range(13):
            p = [-1 + 0.5 * i, -1.5 + 0.5 * j]
            q = json.loads(json.dumps(Q2))
            q[which][0] = p
            try:
                plan = pmplan.plan(q["obstacles"], q["start"], q["goal"])
            except pmplan.CollisionError:
                assert lab[j, i] == -1
                continue
            assert lab[j, i] == plan.domain
            counts.setdefault(plan.domain, set()).add(plan.stratum)
    # the boundaries are visible: the columns x = 0, 1 (robot 2's column) and 4 of the other
    # points carry a lower label than the rest of the plane
    generic = lab[0, 1]
    for x in (0, 4, 1 if which == "goal" else 2):
        col = lab[:, int((x + 1) / 0.5)]
        assert ((col == generic - 1) | (col == -1)).all()
    assert {e["domain"]: set(e["strata"]) for e in body["legend"]} == counts
    assert sum(e["count"] for e in body["legend"]) + body["invalid"] == lab.size
    assert body["invalid"] == int((lab == -1).sum()) == (3 if which == "goal" else 2)


def test_domain_map_planar_three_and_limits(base, monkeypatch):
    from pmplan.web import server

    o, s, g = pmplan.examples.planar_three_examples()[3]
    q = {"obstacles": o.tolist(), "start": s.tolist(), "goal": g.tolist()}
    req = {"query": q, "origin": [-2, -3], "step": 0.25, "size": [400, 400]}
    status, body = request(base, "/api/domain-map", req)
    assert status == 200 and body["planner"] == "planar_three"
    lab = np.array(body["domain"])
    assert lab.shape == (400, 400) and set(np.unique(lab)) <= {-1, 1, 2, 3, 4}
    # robot 1's start (0, -2) is on o1's column: the goal on an obstacle column is T23_33 (W3),
    # off every column T23_34 (W4)
    assert lab[int((1 + 3) / 0.25), int((6 + 2) / 0.25)] == 4
    assert (lab[:, int((2.5 + 2) / 0.25)][lab[:, int((2.5 + 2) / 0.25)] >= 0] == 3).all()
    for size, words in (([401, 10], "size[0]"), ([10, 0], "size[1]"), ([10], "size"),
                        ([10.5, 10], "size[0]")):
        status, body = request(base, "/api/domain-map", {**req, "size": size})
        assert status == 422 and words in body["error"]
    for bad, words in (({"step": 0}, "step"), ({"step": True}, "step"),
                       ({"origin": [0, float("nan")]}, "finite"), ({"which": "via"}, "which"),
                       ({"robot": 2}, "robot"), ({"extra": 1}, "keys"),
                       ({"step": 1e306, "origin": [1.7e308, 0]}, "finite numbers"),
                       ({"step": 1e200, "origin": [1e300, 0]}, "within 2**-430"),
                       ({"query": {**q, "start": [[0, 0]]}}, "coincide")):
        status, body = request(base, "/api/domain-map", {**req, **bad})
        assert status == 422 and words in body["error"], (bad, body)
    # a map that outlives its time budget says which pixels it did not compute
    monkeypatch.setattr(server, "MAP_BUDGET", 0.0)
    status, body = request(base, "/api/domain-map", req)
    lab = np.array(body["domain"])
    assert status == 200 and body["unfinished"] == int((lab == -3).sum()) > 0
    assert (lab.ravel()[:server.MAP_CHUNK] != -3).all()
    counted = sum(e["count"] for e in body["legend"])
    assert body["unfinished"] + body["invalid"] + counted == lab.size
    status, body = request(base, "/api/domain-map",
                           {**req, "query": {"obstacles": [[0, 0, 0], [1, 0, 0]],
                                             "start": [[1, 1, 1]], "goal": [[2, 2, 2]]}})
    assert status == 422 and "d = 2" in body["error"]


JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.integers(-10**400, 10**400)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=5), inner,
                                                                max_size=3),
    max_leaves=12)
MAP_KEYS = ["query", "which", "robot", "origin", "step", "size", "obstacles", "start", "goal",
            "lift", "planner", "extra"]


@settings(max_examples=60)
@given(key=st.sampled_from(MAP_KEYS), value=JSON, where=st.sampled_from(["map", "query"]))
def test_any_json_in_any_field_gets_an_answer_never_a_5xx(base, key, value, where):
    """Fuzz: one field of a valid request replaced by any JSON value (huge integers too)."""
    q = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1]], "goal": [[3, -1]]}
    req = {"query": q, "which": "goal", "robot": 1, "origin": [-1, -1], "step": 0.5,
           "size": [6, 4]}
    if where == "map":
        req = {**req, key: value}
    else:
        req = {**req, "query": {**q, key: value}}
    for path, body in (("/api/domain-map", req), ("/api/plan", req["query"])):
        status, answer = request(base, path, raw=json.dumps(body).encode())
        assert status in (200, 400, 422), (path, body, answer)
        if status != 200:
            assert answer["error"] and "Traceback" not in answer["error"]
        if path == "/api/plan":
            try:
                lib = _library(req["query"])
            except Exception as exc:  # noqa: BLE001 -- the library's own answer is the oracle
                raise AssertionError(f"the library raised {exc!r}") from exc
            if not isinstance(req["query"], dict) or "query" in key:
                continue
            assert (status, answer) == (lib[0], _roundtrip(lib[1]))


# ------------------------------------------------------------------------------ the command
def test_explore_help_lists_its_options(capsys):
    assert main(["explore", "--help"]) == 0
    out = capsys.readouterr().out
    for opt in ("--port", "--host", "--no-browser"):
        assert opt in out
    assert main(["explore", "--port", "70000"]) == 2
    assert "between 0 and 65,535" in capsys.readouterr().err


def test_missing_extra_is_one_line_with_the_fix(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "starlette", None)
    assert main(["explore", "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "pmplan[explore]"' in err


def test_port_in_use_is_one_line(capsys):
    need_extra()
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        assert main(["explore", "--no-browser", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pmplan explore: error:") and err.count("\n") == 1


def test_opens_the_browser_and_stops_on_ctrl_c(monkeypatch, capsys):
    need_extra()
    import uvicorn
    import webbrowser

    opened = []
    monkeypatch.setattr(webbrowser, "open", opened.append)

    def interrupted(self, sockets=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(uvicorn.Server, "run", interrupted)
    assert main(["explore", "--port", "0"]) == 0
    out = capsys.readouterr().out
    url = re.search(r"serving on (http://127\.0\.0\.1:\d+/)", out).group(1)
    assert opened == [url] and "stopped" in out


def test_warns_when_not_loopback(monkeypatch, capsys):
    need_extra()
    from pmplan.web import server

    assert server.is_loopback("127.0.0.1") and server.is_loopback("::1")
    assert server.is_loopback("localhost") and server.is_loopback("127.8.0.1")
    assert not server.is_loopback("0.0.0.0") and not server.is_loopback("192.0.2.1")
    assert not server.is_loopback("example.invalid")

    def refuse(host, port):
        raise OSError("not binding in a test")

    monkeypatch.setattr(server, "bind", refuse)
    with pytest.raises(OSError):
        server.serve("0.0.0.0", 0, open_browser=False)
    assert "warning: serving on 0.0.0.0, which is not the loopback" in capsys.readouterr().err


def test_explore_subprocess_serves_then_ctrl_c_stops_cleanly():
    need_extra()
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    proc = subprocess.Popen([sys.executable, "-m", "pmplan", "explore", "--no-browser",
                             "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=env, text=True)
    try:
        line = proc.stdout.readline()
        url = re.search(r"serving on (http://127\.0\.0\.1:\d+/)", line).group(1)
        status, html = request(url.rstrip("/"), "/")
        assert status == 200 and "pmplan explore" in html
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "stopped" in out and "Traceback" not in err


@pytest.mark.parametrize("which", ["goal", "start"])
def test_domain_map_names_its_boundaries_and_they_are_where_the_label_changes(base, which):
    """``boundaries``: the columns of the other points (tilted line o1o2), or the line o1o2 for
    the Section 4 planner with o3 on it; a point exactly on a boundary gets another label than
    points just beside it."""
    q = {"obstacles": [[0, 0], [4, 1]], "start": [[1, 1], [2, -1]], "goal": [[3, -1], [1, 2.5]]}
    status, body = request(base, "/api/domain-map", {
        "query": q, "which": which, "robot": 1, "origin": [-2, -2], "step": 0.5, "size": [8, 8]})
    assert status == 200
    e = np.array([4.0, 1.0]) / np.hypot(4, 1)
    others = [[0, 0], [4, 1], q[which][1]]
    assert len(body["boundaries"]) == 3
    for line, p in zip(body["boundaries"], others):
        assert line["point"] == p and abs(np.dot(line["direction"], e)) < 1e-15
        assert abs(np.hypot(*line["direction"]) - 1) < 1e-15
    # on robot 2's column the label differs from beside it: (1, 2.5) + 4 k (-1, 4) is on it
    # exactly (dyadic coordinates)
    on = np.array(q[which][1]) + 0.25 * np.array([-1.0, 4.0])
    moved = {k: [list(map(float, v)) for v in q[k]] for k in q}
    labels = []
    for point in (on, on + [0.25, 0.0]):
        moved[which][0] = point.tolist()
        labels.append(pmplan.plan_query(moved).domain)
    assert labels[0] != labels[1]
    status, body = request(base, "/api/domain-map", {
        "query": {"obstacles": [[0, 0], [4, 0], [2.5, 0]], "start": [[0, -2]], "goal": [[6, 2.5]]},
        "which": which, "robot": 1, "origin": [-2, -2], "step": 0.5, "size": [4, 4]})
    assert status == 200 and body["planner"] == "planar_three"
    assert body["boundaries"] == [{"point": [0.0, 0.0], "direction": [1.0, 0.0]}]
