"""Reading queries, writing plans, and the command line (pmplan.io, pmplan.cli)."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import asdict

import numpy as np
import pytest

import pmplan
from pmplan import io
from pmplan.cli import main

QUERY = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1], [0, 2]], "goal": [[3, -1], [2, 2.5]]}


def write_json(tmp_path, obj, name="q.json"):
    path = tmp_path / name
    path.write_text(obj if isinstance(obj, str) else json.dumps(obj))
    return str(path)


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def assert_one_line_error(status, out, err, match):
    assert status == 2
    assert out == ""
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert lines[0].startswith("pmplan") and "error:" in lines[0]
    assert match in lines[0], lines[0]


# --------------------------------------------------------------------------------------------
# pmplan plan


def test_plan_outputs_the_plan(tmp_path, capsys):
    status, out, err = run(capsys, "plan", write_json(tmp_path, QUERY))
    assert status == 0 and err == ""
    res = json.loads(out)
    assert {"domain", "stratum", "clearance", "times", "waypoints", "planner"} <= set(res)
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"])
    assert res["domain"] == ref.domain and res["stratum"] == ref.stratum
    assert res["clearance"] == ref.clearance > 0
    wp = np.array(res["waypoints"])
    times = np.array(res["times"])
    assert wp.shape == (times.size, 4, 2)
    np.testing.assert_array_equal(wp[0], np.array(QUERY["obstacles"] + QUERY["start"]))
    np.testing.assert_array_equal(wp[-1], np.array(QUERY["obstacles"] + QUERY["goal"]))
    assert times[0] == 0.0 and times[-1] == 1.0 and np.all(np.diff(times) > 0)


@pytest.mark.parametrize("k", [2, 7, 50])
def test_plan_samples(tmp_path, capsys, k):
    status, out, _ = run(capsys, "plan", write_json(tmp_path, QUERY), "--samples", str(k))
    assert status == 0
    res = json.loads(out)
    samples = np.array(res["samples"])
    assert samples.shape == (k, 4, 2)
    ts = np.linspace(0.0, 1.0, k)
    np.testing.assert_array_equal(res["times"], ts)
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"])
    np.testing.assert_array_equal(samples, ref.path(ts))


def test_plan_samples_must_be_at_least_two(tmp_path, capsys):
    status, out, err = run(capsys, "plan", write_json(tmp_path, QUERY), "--samples", "1")
    assert_one_line_error(status, out, err, "argument --samples: must be between 2 and 100,000")


def test_plan_from_stdin(monkeypatch, capsys):
    import io as _io

    monkeypatch.setattr(sys, "stdin", _io.StringIO(json.dumps(QUERY)))
    status, out, _ = run(capsys, "plan", "-", "--indent", "2")
    assert status == 0 and json.loads(out)["domain"] == pmplan.plan(
        QUERY["obstacles"], QUERY["start"], QUERY["goal"]).domain


def test_plan_via(tmp_path, capsys):
    via = [[[5, 5], [-1, 3]], [[2, -3], [1, 1]]]
    q = dict(QUERY, via=via)
    status, out, _ = run(capsys, "plan", write_json(tmp_path, q), "--samples", "7")
    assert status == 0
    samples = np.array(json.loads(out)["samples"])
    # r = 4 configurations, visited at tau = 0, 1/3, 2/3, 1: samples 0, 2, 4, 6
    for k, robots in enumerate([QUERY["start"], *via, QUERY["goal"]]):
        np.testing.assert_allclose(samples[2 * k], np.array(QUERY["obstacles"] + robots),
                                   atol=1e-12)
    status, out, _ = run(capsys, "plan", write_json(tmp_path, q))
    res = json.loads(out)
    wp, times = np.array(res["waypoints"]), np.array(res["times"])
    for k, robots in enumerate(via, start=1):
        hit = np.flatnonzero(np.isclose(times, k / 3, rtol=0, atol=1e-15))
        assert hit.size and any(
            np.array_equal(wp[h], np.array(QUERY["obstacles"] + robots)) for h in hit)


def test_plan_options_from_the_query(tmp_path, capsys):
    q = dict(QUERY, lift=2.5, planner="obstacle_line")
    status, out, _ = run(capsys, "plan", write_json(tmp_path, q))
    assert status == 0
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"], lift=2.5)
    np.testing.assert_array_equal(json.loads(out)["waypoints"], ref.path.waypoints)


# --------------------------------------------------------------------------------------------
# bad input: exit status 2, one line on stderr


BAD_QUERIES = {
    "truncated": ('{"obstacles": [[0, 0], [4, 0]], "start": [[1, 1]', "not valid JSON"),
    "not an object": ("[1, 2, 3]", "must be a JSON object"),
    "wrong key": (dict(QUERY, obstacels=[[0, 0]]), "unknown key(s) ['obstacels']"),
    "missing key": ({"obstacles": QUERY["obstacles"], "start": QUERY["start"]},
                    "missing key(s) ['goal']"),
    "ragged": (dict(QUERY, start=[[1, 1], [2]]), "ragged"),
    "strings": (dict(QUERY, goal=[["3", "-1"], [2, 2.5]]), "must hold numbers"),
    "booleans": (dict(QUERY, start=[[True, 1], [0, 2]]), "must hold numbers"),
    "null": (dict(QUERY, start=None), "must be a list"),
    "flat": (dict(QUERY, start=[1, 2]), "must be a list"),
    "lift string": (dict(QUERY, lift="high"), "`lift` must be a number"),
    "lift negative": (dict(QUERY, lift=-1), "`lift` must be a positive finite number"),
    "planner type": (dict(QUERY, planner=3), "`planner` must be a string"),
    "unknown planner": (dict(QUERY, planner="rrt"), "unknown planner 'rrt'"),
    "coincident": (dict(QUERY, start=[[4, 0], [0, 2]]), "points o2 and x1"),
    "shape": (dict(QUERY, goal=[[3, -1, 0], [2, 2.5, 0]]), "d = 2 coordinates"),
    "m = 1": (dict(QUERY, obstacles=[[0, 0]]), "m = 1"),
}


@pytest.mark.parametrize("case", sorted(BAD_QUERIES))
def test_plan_bad_query(tmp_path, capsys, case):
    content, match = BAD_QUERIES[case]
    status, out, err = run(capsys, "plan", write_json(tmp_path, content))
    assert_one_line_error(status, out, err, match)


def test_plan_too_many_points(tmp_path, capsys):
    n = io.MAX_POINTS - 1  # m + n = MAX_POINTS + 1
    start = [[float(i), 1.0] for i in range(n)]
    q = dict(QUERY, start=start, goal=[[float(i), -1.0] for i in range(n)])
    status, out, err = run(capsys, "plan", write_json(tmp_path, q))
    assert_one_line_error(status, out, err, f"the limit is {io.MAX_POINTS}")


def test_plan_nonexistent_file(tmp_path, capsys):
    status, out, err = run(capsys, "plan", str(tmp_path / "nope.json"))
    assert_one_line_error(status, out, err, "cannot read")


def test_plan_certification_error_is_one_line(tmp_path, capsys):
    q = {"obstacles": [[0, 0], [1, 2]], "start": [[-1, 3], [3 + 2**-51, 1]],
         "goal": [[5, 5], [6, -7]]}
    status, out, err = run(capsys, "plan", write_json(tmp_path, q))
    assert_one_line_error(status, out, err, "certificate")


def test_parse_query_directly():
    q = io.parse_query(QUERY)
    assert q["obstacles"].shape == (2, 2) and q["start"].dtype == float
    with pytest.raises(pmplan.InputError, match="nested 2 deep"):
        io.parse_query(dict(QUERY, start=5))


# --------------------------------------------------------------------------------------------
# pmplan batch


def random_batch(b=6, seed=0):
    rng = np.random.default_rng(seed)
    return {"obstacles": rng.normal(size=(b, 2, 2)), "start": rng.normal(size=(b, 3, 2)),
            "goal": rng.normal(size=(b, 3, 2))}


def test_batch_round_trip(tmp_path, capsys):
    q = random_batch()
    src, dst = tmp_path / "q.npz", tmp_path / "plans.npz"
    np.savez(src, **q)
    status, out, err = run(capsys, "batch", str(src), "--out", str(dst), "--no-progress")
    assert status == 0 and "planned 6 queries" in out
    ref = pmplan.plan_batch(q["obstacles"], q["start"], q["goal"])
    with np.load(dst, allow_pickle=False) as res:
        np.testing.assert_array_equal(res["domain"], ref.domain)
        np.testing.assert_array_equal(res["clearance"], ref.clearance)
        np.testing.assert_array_equal(res["waypoints"], ref.waypoints)
        np.testing.assert_array_equal(res["times"], ref.times)
        np.testing.assert_array_equal(res["stratum"], ref.stratum.astype(str))
        wp = res["waypoints"]
        np.testing.assert_array_equal(wp[:, 0], np.concatenate([q["obstacles"], q["start"]], 1))
        np.testing.assert_array_equal(wp[:, -1], np.concatenate([q["obstacles"], q["goal"]], 1))
        assert (res["clearance"] > 0).all()


def test_batch_from_json_list(tmp_path, capsys):
    src = write_json(tmp_path, [QUERY, dict(QUERY, goal=[[3, 1], [5, 5]])], "qs.json")
    dst = tmp_path / "p.npz"
    status, _, _ = run(capsys, "batch", src, "--out", str(dst), "--no-progress")
    assert status == 0
    with np.load(dst) as res:
        assert res["domain"].shape == (2,)


def test_batch_bad_inputs(tmp_path, capsys):
    dst = str(tmp_path / "p.npz")
    notzip = tmp_path / "bad.npz"
    notzip.write_text("this is not an npz file")
    status, out, err = run(capsys, "batch", str(notzip), "--out", dst)
    assert_one_line_error(status, out, err, "as npz")

    q = random_batch()
    lacking = tmp_path / "lacking.npz"
    np.savez(lacking, obstacles=q["obstacles"], start=q["start"])
    status, out, err = run(capsys, "batch", str(lacking), "--out", dst)
    assert_one_line_error(status, out, err, "lacks array(s) ['goal']")

    strings = tmp_path / "strings.npz"
    np.savez(strings, obstacles=q["obstacles"], start=q["start"],
             goal=q["goal"].astype(str))
    status, out, err = run(capsys, "batch", str(strings), "--out", dst)
    assert_one_line_error(status, out, err, "must be numeric")

    coincide = dict(q)
    coincide["start"] = q["start"].copy()
    coincide["start"][4, 2] = q["obstacles"][4, 0]
    path = tmp_path / "coincide.npz"
    np.savez(path, **coincide)
    status, out, err = run(capsys, "batch", str(path), "--out", dst)
    assert_one_line_error(status, out, err, "o1 and x3 of the start configuration of query 4")

    status, out, err = run(capsys, "batch", str(tmp_path / "missing.npz"), "--out", dst)
    assert_one_line_error(status, out, err, "cannot read")

    mixed = write_json(tmp_path, [QUERY, dict(QUERY, start=[[1, 1]], goal=[[2, 2]])], "m.json")
    status, out, err = run(capsys, "batch", mixed, "--out", dst)
    assert_one_line_error(status, out, err, "same (m, n, d)")


# --------------------------------------------------------------------------------------------
# pmplan info, --help, demo


@pytest.mark.parametrize("d, n, m, r", [(2, 3, 2, 2), (3, 2, 4, 2), (2, 2, 2, 3)])
def test_info(capsys, d, n, m, r):
    rec = pmplan.info(d, n, m, r)
    status, out, _ = run(capsys, "info", "--d", str(d), "--n", str(n), "--m", str(m),
                         "--r", str(r), "--json")
    assert status == 0
    got = json.loads(out)
    assert got == json.loads(json.dumps(asdict(rec)))
    # the record is consistent with the mathematics: TC and optimality
    tc = r * n + m - 1 if d % 2 == 0 else r * n + m
    assert got["tc"] == tc and got["domains"] == len(got["labels"])
    assert got["optimal"] == (got["domains"] == tc)
    status, out, _ = run(capsys, "info", "--d", str(d), "--n", str(n), "--m", str(m),
                         "--r", str(r))
    assert status == 0
    assert f"domains:  {rec.domains} (labels {rec.labels[0]}..{rec.labels[-1]})" in out
    assert rec.planner in out and f"TC:       {tc}" in out


@pytest.mark.parametrize("json_flag", [[], ["--json"]])
def test_info_unsupported_is_an_error(capsys, json_flag):
    status, out, err = run(capsys, "info", "--d", "2", "--n", "1", "--m", "1", *json_flag)
    assert_one_line_error(status, out, err, "no planner covers m = 1")


def test_help_lists_every_command_with_an_example(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for cmd in ("plan", "batch", "demo", "info", "figures", "animate", "verify"):
        assert any(line.strip().startswith(f"pmplan {cmd}") for line in out.splitlines()), cmd
    status, out, err = run(capsys)  # no command: one line on stderr, status 2
    assert_one_line_error(status, out, err, "no command given")


def test_demo_writes_png_and_one_row_per_domain(tmp_path, capsys):
    out_png = tmp_path / "demo.png"
    status, out, _ = run(capsys, "demo", "--out", str(out_png))
    assert status == 0
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rec = pmplan.info(2, 3, 2)
    rows = [line.split() for line in out.splitlines() if line.startswith("obstacle_line")]
    assert len(rows) == rec.domains
    assert [int(r[1].removeprefix("W_")) for r in rows] == list(rec.labels)
    for r in rows:  # positive certified clearance on every row
        assert float(r[-1]) > 0


def test_demo_bad_n(tmp_path, capsys):
    status, out, err = run(capsys, "demo", "--n", "0", "--out", str(tmp_path / "x.png"))
    assert_one_line_error(status, out, err, "argument --n: must be between 1 and 8, got 0")


# --------------------------------------------------------------------------------------------
# the installed entry point, once, in a subprocess


def test_subprocess_plan_and_error(tmp_path):
    good = write_json(tmp_path, QUERY)
    res = subprocess.run([sys.executable, "-m", "pmplan", "plan", good, "--samples", "3"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert len(json.loads(res.stdout)["samples"]) == 3
    bad = write_json(tmp_path, '{"obstacles": [[0, 0]', "bad.json")
    res = subprocess.run([sys.executable, "-m", "pmplan", "plan", bad],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 2
    assert res.stdout == "" and len(res.stderr.strip().splitlines()) == 1
    assert "Traceback" not in res.stderr
