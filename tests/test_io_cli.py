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
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"], lift=2.5,
                      planner="obstacle_line")
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
    "strings": (dict(QUERY, goal=[["3", "-1"], [2, 2.5]]), "`goal[0][0]` must hold real numbers"),
    "booleans": (dict(QUERY, start=[[True, 1], [0, 2]]), "`start[0][0]` must hold real numbers"),
    "huge integer": (dict(QUERY, start=[[10**400, 1], [0, 2]]), "too large for a double"),
    "null": (dict(QUERY, start=None), "must be a list"),
    "flat": (dict(QUERY, start=[1, 2]), "must be a list"),
    "lift string": (dict(QUERY, lift="high"), "`lift` must be a positive real number or 'scene'"),
    "lift bool": (dict(QUERY, lift=True), "`lift` must be a positive real number or 'scene'"),
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
         "goal": [[5, 5], [6, -7]], "planner": "obstacle_line"}  # (Mathematics §6.2)
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
    rows, room = rows[:-1], rows[-1]  # the last row: the crowded room, in its box
    assert len(rows) == rec.domains
    assert [int(r[1].removeprefix("W_")) for r in rows] == list(rec.labels)
    assert "8 robots among 6 obstacles in the box [0, 10]^2 (bounds=)" in out
    assert "radii and walls kept" in out and float(room[-1]) > 0.3
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


def test_subprocess_reader_leaves_quietly(tmp_path):
    """``pmplan plan q.json --samples 50000 | head -c 10``: the reader closes the pipe early;
    pmplan stops without an error line (and without a traceback) and reports SIGPIPE's 141."""
    good = write_json(tmp_path, QUERY)
    proc = subprocess.Popen([sys.executable, "-m", "pmplan", "plan", good, "--samples", "50000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout.read(10)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert err == ""


# --------------------------------------------------------------------------------------------
# every option: help text, validation (one line, exit 2), --version, --lift


def _subparsers():
    import argparse

    from pmplan.cli import build_parser

    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return parser, action.choices


def test_every_option_of_every_command_has_help():
    parser, commands = _subparsers()
    assert set(commands) == {"plan", "batch", "demo", "info", "figures", "animate", "verify",
                             "explore"}
    for name, sub in [("pmplan", parser), *commands.items()]:
        for action in sub._actions:
            if action.dest == "command":
                continue
            assert action.help and len(action.help) > 8, (name, action.option_strings, action.dest)


def test_version(capsys):
    from importlib.metadata import version

    assert main(["--version"]) == 0
    out = capsys.readouterr().out.strip()
    assert out == f"pmplan {version('pmplan')}" == f"pmplan {pmplan.__version__}"


def test_lift_is_an_option_wherever_a_planner_runs():
    _, commands = _subparsers()
    for name in ("plan", "batch", "animate", "verify", "demo"):
        assert "--lift" in commands[name]._option_string_actions, name


BAD_OPTIONS = [
    (["plan", "Q", "--samples", "1000000000"], "argument --samples: must be between 2 and 100,000"),
    (["plan", "Q", "--samples", "0"], "argument --samples: must be between 2 and 100,000, got 0"),
    (["plan", "Q", "--samples", "ten"], "argument --samples: expected an integer, got 'ten'"),
    (["plan", "Q", "--indent", "-1"], "argument --indent: must be between 0 and 16"),
    (["plan", "Q", "--lift", "high"], "argument --lift: expected a positive number or the word"),
    (["plan", "Q", "--lift", "-1"], "`lift` must be"),  # the API's message
    (["plan", "Q", "--lift", "nan"], "`lift` must be"),
    (["plan", "Q", "--planner", "rrt"], "argument --planner: invalid choice: 'rrt'"),
    (["plan", "Q", "--bogus"], "unrecognized arguments: --bogus"),
    (["plan"], "the following arguments are required: query"),
    (["batch", "Q"], "the following arguments are required: --out"),
    (["batch", "Q", "--out", "p.npz", "--workers", "0"], "argument --workers: must be at least 1 or -1"),
    (["batch", "Q", "--out", "p.npz", "--workers", "-2"], "must be at least 1 or -1, got -2"),
    (["animate", "Q", "--frames", "1"], "argument --frames: must be between 2 and 1,000, got 1"),
    (["animate", "Q", "--frames", "100000"], "argument --frames: must be between 2 and 1,000"),
    (["animate", "Q", "--fps", "0"], "argument --fps: must be between 1 and 100, got 0"),
    (["verify", "--queries", "-5"], "argument --queries: must be between 10 and 100,000, got -5"),
    (["verify", "--queries", "0"], "argument --queries: must be between 10 and 100,000, got 0"),
    (["verify", "--queries", "1000000000"], "argument --queries: must be between 10 and 100,000"),
    (["verify", "--seed", "-1"], "argument --seed: must be at least 0, got -1"),
    (["verify", "--d", "1"], "argument --d: must be between 2 and 10,000, got 1"),
    (["verify", "--n", "40", "--m", "40", "--d", "40"], "more than 200,000,000: use fewer"),
    (["demo", "--n", "9"], "argument --n: must be between 1 and 8, got 9"),
    (["info", "--d", "2", "--n", "10000000000", "--m", "2"], "argument --n: must be between 0"),
    (["info", "--d", "2", "--n", "1", "--m", "2", "--r", "1"], "r = 1: a motion needs r >= 2"),
    (["info", "--d", "2", "--n", "10000", "--m", "2", "--r", "10000"], "more than pmplan info lists"),
    (["frobnicate"], "argument COMMAND: invalid choice: 'frobnicate'"),
]


@pytest.mark.parametrize("argv, match", BAD_OPTIONS, ids=lambda v: " ".join(v) if isinstance(v, list) else None)
def test_bad_options_are_one_line_errors(tmp_path, capsys, argv, match):
    q = write_json(tmp_path, QUERY)
    status, out, err = run(capsys, *[q if a == "Q" else a for a in argv])
    assert_one_line_error(status, out, err, match)


def test_argparse_errors_in_a_real_process_are_one_line(tmp_path):
    res = subprocess.run([sys.executable, "-m", "pmplan", "verify", "--queries", "-5"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr.strip().splitlines() == [
        "pmplan verify: error: argument --queries: must be between 10 and 100,000, got -5 "
        "(see pmplan verify --help)"]


def test_plan_lift_option(tmp_path, capsys):
    status, out, _ = run(capsys, "plan", write_json(tmp_path, QUERY), "--lift", "2.5")
    assert status == 0
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"], lift=2.5)
    np.testing.assert_array_equal(json.loads(out)["waypoints"], ref.path.waypoints)
    assert not np.array_equal(  # and it is not the default lift
        ref.path.waypoints, pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"]).path.waypoints)


@pytest.mark.parametrize("command", ["plan", "animate"])
def test_lift_scene_is_passed_to_the_api_as_the_string(tmp_path, capsys, monkeypatch, command):
    """``--lift scene`` reaches the API as the string "scene" (the API decides what it means)."""
    from pmplan import api

    seen = []
    real = api.plan_query

    def spy(q, planner=None):
        seen.append(q["lift"])
        return real(dict(q, lift=1.0), planner)

    monkeypatch.setattr(api, "plan_query", spy)
    argv = [command, write_json(tmp_path, QUERY), "--lift", "scene"]
    if command == "animate":
        argv += ["--out", str(tmp_path / "m.gif"), "--frames", "2"]
    status, _, err = run(capsys, *argv)
    assert status == 0, err
    assert seen == ["scene"]


def test_batch_lift_scene_is_passed_to_the_api_as_the_string(tmp_path, capsys, monkeypatch):
    from pmplan import api

    seen = []
    real = api.plan_batch
    monkeypatch.setattr(api, "plan_batch",
                        lambda *a, lift, **k: seen.append(lift) or real(*a, lift=1.0, **k))
    src = tmp_path / "q.npz"
    np.savez(src, **random_batch())
    status, _, err = run(capsys, "batch", str(src), "--out", str(tmp_path / "p"), "--lift",
                         "scene", "--no-progress")
    assert status == 0, err
    assert seen == ["scene"]


def test_option_and_file_must_agree(tmp_path, capsys):
    path = write_json(tmp_path, dict(QUERY, lift=3, planner="obstacle_line"))
    status, out, err = run(capsys, "plan", path, "--lift", "2")
    assert_one_line_error(status, out, err, '--lift 2.0 contradicts "lift": 3')
    status, out, err = run(capsys, "plan", path, "--planner", "planar_three")
    assert_one_line_error(status, out, err, "--planner planar_three contradicts")
    status, out, _ = run(capsys, "plan", path, "--lift", "3", "--planner", "obstacle_line")
    assert status == 0  # the same value twice is fine
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"], lift=3.0,
                      planner="obstacle_line")
    np.testing.assert_array_equal(json.loads(out)["waypoints"], ref.path.waypoints)


def test_plan_to_dict_bounds_the_samples():
    p = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"])
    with pytest.raises(pmplan.InputError, match="from 2 to 100,000"):
        io.plan_to_dict(p, samples=10**9)
    with pytest.raises(pmplan.InputError, match="from 2 to 100,000"):
        io.plan_to_dict(p, samples=True)
    big = pmplan.plan([[0, 0], [1, 0]], [[k, 1.0] for k in range(2, 1000)],
                      [[k, -1.0] for k in range(2, 1000)])
    with pytest.raises(pmplan.InputError, match="ask for at most 5,000 samples"):
        io.plan_to_dict(big, samples=100_000)  # 100,000 x 1000 points x 2 > 10,000,000 numbers
    assert len(io.plan_to_dict(big, samples=5_000)["samples"]) == 5_000


def test_plan_a_single_query_from_npz(tmp_path, capsys):
    src = tmp_path / "q.npz"
    np.savez(src, obstacles=np.array(QUERY["obstacles"]), start=np.array(QUERY["start"]),
             goal=np.array(QUERY["goal"]))
    status, out, err = run(capsys, "plan", str(src), "--samples", "5")
    assert status == 0 and err == ""
    res = json.loads(out)
    ref = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"])
    assert (res["domain"], res["stratum"], res["clearance"]) == (ref.domain, ref.stratum,
                                                                 ref.clearance)
    np.testing.assert_array_equal(res["samples"], ref.path(np.linspace(0, 1, 5)))
    np.savez(src, obstacles=np.array(QUERY["obstacles"]), start=np.array(QUERY["start"]))
    status, out, err = run(capsys, "plan", str(src))
    assert_one_line_error(status, out, err, "missing key(s) ['goal']")


# --------------------------------------------------------------------------------------------
# pmplan batch: the file written, B = 0, per-query options honoured or refused


def test_batch_reports_the_file_it_wrote(tmp_path, capsys):
    src = tmp_path / "q.npz"
    np.savez(src, **random_batch())
    status, out, _ = run(capsys, "batch", str(src), "--out", str(tmp_path / "plans"),
                         "--no-progress")
    assert status == 0
    assert (tmp_path / "plans.npz").is_file() and not (tmp_path / "plans").exists()
    assert out.rstrip().endswith(f"wrote {tmp_path / 'plans.npz'}")


def test_batch_of_zero_queries(tmp_path, capsys):
    src, dst = tmp_path / "empty.npz", tmp_path / "plans.npz"
    np.savez(src, obstacles=np.zeros((0, 2, 2)), start=np.zeros((0, 3, 2)),
             goal=np.zeros((0, 3, 2)))
    status, out, err = run(capsys, "batch", str(src), "--out", str(dst), "--no-progress")
    assert status == 0 and "Traceback" not in err
    assert out.startswith("planned 0 queries with obstacle_line_compact;")
    with np.load(dst) as res:
        assert res["domain"].shape == (0,) and res["clearance"].shape == (0,)
        assert res["waypoints"].shape[0] == 0 and res["waypoints"].shape[2:] == (5, 2)
        assert res["stratum"].shape == (0,)


def _batch_json(tmp_path, capsys, items, *options):
    src = write_json(tmp_path, items, "qs.json")
    dst = tmp_path / "p.npz"
    status, out, err = run(capsys, "batch", src, "--out", str(dst), "--no-progress", *options)
    return status, out, err, dst


QUERY2 = dict(QUERY, goal=[[3, 1], [5, 5]])


def _stack(*qs):
    return [np.array([q[k] for q in qs], dtype=float) for k in ("obstacles", "start", "goal")]


def test_batch_json_common_lift_and_planner_are_honoured(tmp_path, capsys):
    items = [dict(QUERY, lift=2.5, planner="obstacle_line"),
             dict(QUERY2, lift=2.5, planner="obstacle_line")]
    status, _, err, dst = _batch_json(tmp_path, capsys, items)
    assert status == 0, err
    ref = pmplan.plan_batch(*_stack(QUERY, QUERY2), lift=2.5, planner="obstacle_line")
    default = pmplan.plan_batch(*_stack(QUERY, QUERY2))
    assert not np.array_equal(ref.waypoints, default.waypoints)
    with np.load(dst) as res:
        np.testing.assert_array_equal(res["waypoints"], ref.waypoints)


def test_batch_json_common_via_is_a_sequence_batch(tmp_path, capsys):
    items = [dict(QUERY, via=[[[1, 2], [3, 2]]]), dict(QUERY2, via=[[[2, 3], [1, -2]]])]
    status, _, err, dst = _batch_json(tmp_path, capsys, items)
    assert status == 0, err
    o, s, g = _stack(QUERY, QUERY2)
    via = np.array([items[0]["via"][0], items[1]["via"][0]], dtype=float)
    ref = pmplan.plan_sequence_batch(o, [s, via, g])
    with np.load(dst) as res:
        np.testing.assert_array_equal(res["waypoints"], ref.waypoints)
        np.testing.assert_array_equal(res["domain"], ref.domain)


BAD_BATCH_JSON = {
    "lift differs": ([dict(QUERY, lift=2), dict(QUERY2, lift=3)],
                     'query 1 has "lift": 3'),
    "lift missing": ([dict(QUERY, lift=2), QUERY2, dict(QUERY2, lift=2)],
                     'query 0 gives "lift" but query 1 does not'),
    "planner differs": ([dict(QUERY, planner="obstacle_line"),
                         dict(QUERY2, planner="planar_three")],
                        'query 1 has "planner": \'planar_three\''),
    "via missing": ([QUERY, dict(QUERY2, via=[[[2, 3], [1, -2]]])],
                    'query 1 has "via" but query 0 does not'),
    "via count": ([dict(QUERY, via=[[[1, 2], [3, 2]]]),
                   dict(QUERY2, via=[[[1, 2], [3, 2]], [[2, 3], [1, -2]]])],
                  "query 1 has 2 intermediate configuration(s)"),
    "via shape": ([dict(QUERY, via=[[[1, 2], [3, 2]]]), dict(QUERY2, via=[[[1, 2, 0], [3, 2, 0]]])],
                  "query 1 has via[0] of shape (2, 3)"),
    "via planner": ([dict(QUERY, via=[[[1, 2], [3, 2]]], planner="planar_three")] * 2,
                    "planned by the obstacle_line, obstacle_line_compact, obstacle_line_shared, "
                    "obstacle_line_oneside, obstacle_line_walls or obstacle_line_robots planner"),
    "empty list": ([], "holds an empty list"),
}


@pytest.mark.parametrize("case", sorted(BAD_BATCH_JSON))
def test_batch_json_options_that_differ_are_refused(tmp_path, capsys, case):
    items, match = BAD_BATCH_JSON[case]
    status, out, err, dst = _batch_json(tmp_path, capsys, items)
    assert_one_line_error(status, out, err, match)
    assert not dst.exists()


def test_batch_option_conflicting_with_the_file_is_refused(tmp_path, capsys):
    items = [dict(QUERY, lift=2), dict(QUERY2, lift=2)]
    status, out, err, _ = _batch_json(tmp_path, capsys, items, "--lift", "3")
    assert_one_line_error(status, out, err, '--lift 3.0 contradicts "lift": 2')
    status, out, err, _ = _batch_json(tmp_path, capsys, items, "--lift", "2")
    assert status == 0, err


def test_batch_npz_options(tmp_path, capsys):
    o, s, g = _stack(QUERY, QUERY2)
    via = np.array([[[[1, 2], [3, 2]]], [[[2, 3], [1, -2]]]], dtype=float)  # (B, k=1, n, d)
    src, dst = tmp_path / "q.npz", tmp_path / "p.npz"
    np.savez(src, obstacles=o, start=s, goal=g, via=via, lift=2.0)
    status, _, err = run(capsys, "batch", str(src), "--out", str(dst), "--no-progress")
    assert status == 0, err
    ref = pmplan.plan_sequence_batch(o, [s, via[:, 0], g], lift=2.0)
    with np.load(dst) as res:
        np.testing.assert_array_equal(res["waypoints"], ref.waypoints)
    np.savez(src, obstacles=o, start=s, goal=g, planner="planar_three")
    status, out, err = run(capsys, "batch", str(src), "--out", str(dst))
    assert_one_line_error(status, out, err, "planner 'planar_three' does not apply")
    for extra, match in ((dict(lift=np.array([1.0, 2.0])), "`lift` in"),
                         (dict(lift=True), "`lift` in"),
                         (dict(via=via[:, :, :1]), "array `via`"),
                         (dict(weights=np.ones(2)), "unknown array(s) ['weights']")):
        np.savez(src, obstacles=o, start=s, goal=g, **extra)
        status, out, err = run(capsys, "batch", str(src), "--out", str(dst))
        assert_one_line_error(status, out, err, match)


def test_npy_and_bad_list_items_are_one_line_errors(tmp_path, capsys):
    npy = tmp_path / "a.npy"
    np.save(npy, np.zeros(3))
    disguised = tmp_path / "a.npz"
    disguised.write_bytes(npy.read_bytes())
    for command, src in (("batch", npy), ("batch", disguised), ("plan", disguised)):
        extra = ["--out", str(tmp_path / "p")] if command == "batch" else []
        status, out, err = run(capsys, command, str(src), *extra)
        assert_one_line_error(status, out, err, "holds a single array (.npy)")
    src = write_json(tmp_path, [QUERY, 5], "qs.json")
    status, out, err = run(capsys, "batch", src, "--out", str(tmp_path / "p"))
    assert_one_line_error(status, out, err, "qs.json: query 1: a query must be a JSON object")
