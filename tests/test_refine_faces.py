"""What a user meets of refined motions (issue 14) outside the library call: the command line
(``--refine``, ``--radius``, ``--obstacle-radius``, ``--waypoints``, ``--steps`` on plan, batch,
animate, verify, demo), the JSON and npz outputs, ``pmplan verify --refine``, the demo picture
(raw and refined side by side) and the animation of a refined motion (robots as discs)."""

from __future__ import annotations

import json

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from PIL import Image  # noqa: E402

import pmplan  # noqa: E402
from pmplan import io  # noqa: E402
from pmplan.animation import REFINED_PHASE, draw_frame, phase_at  # noqa: E402
from pmplan.cli import main  # noqa: E402
from pmplan.plotting import plan_grid, plan_title  # noqa: E402

# the scene of the OMPL comparison: unit square, two obstacles; robots 0.1 and more apart
OBSTACLES = [[0.35, 0.5], [0.65, 0.5]]
QUERY = {"obstacles": OBSTACLES, "start": [[0.1, 0.5], [0.5, 0.8]],
         "goal": [[0.9, 0.5], [0.5, 0.2]]}
SEQUENCE = dict(QUERY, via=[[[0.2, 0.2], [0.8, 0.8]]])


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def write_json(tmp_path, obj, name="q.json"):
    path = tmp_path / name
    path.write_text(json.dumps(obj))
    return str(path)


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def assert_one_line_error(status, out, err, match):
    assert status == 2 and out == ""
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("pmplan") and "error:" in lines[0]
    assert match in lines[0], lines[0]


# --------------------------------------------------------------------------------------------
# pmplan plan --refine


@pytest.mark.parametrize("query", [QUERY, SEQUENCE], ids=["two configurations", "via"])
def test_plan_refine_radius_is_the_refined_plan(tmp_path, capsys, query):
    status, out, err = run(capsys, "plan", write_json(tmp_path, query), "--refine",
                           "--radius", "0.05")
    assert status == 0 and err == ""
    res = json.loads(out)
    raw = pmplan.plan_query(io.with_defaults(io.parse_query(query), {"radius": 0.05}))
    assert raw.path.waypoints.max() < 3.0  # (lanes 0.1 apart: the default unit, 2 radius)
    ref = pmplan.refine(raw, radius=0.05)
    # the same domain and stratum as the raw plan; the refined path, bit for bit
    assert (res["domain"], res["stratum"]) == (raw.domain, raw.stratum)
    assert res["refined"] is True and res["radius"] == 0.05 and res["obstacle_radius"] == 0.0
    np.testing.assert_array_equal(np.array(res["waypoints"]), ref.path.waypoints)
    np.testing.assert_array_equal(np.array(res["times"]), ref.path.times)
    assert res["clearance"] == ref.clearance > 0
    assert (res["robot_distance"], res["obstacle_distance"], res["respects_radius"]) == (
        ref.robot_distance, ref.obstacle_distance, ref.respects_radius)
    # what it claims holds: the exact minima against the radii
    if res["respects_radius"]:
        assert res["robot_distance"] >= 0.1 and res["obstacle_distance"] >= 0.05
    # endpoints exact, obstacles fixed
    wp = np.array(res["waypoints"])
    np.testing.assert_array_equal(wp[0], np.array(OBSTACLES + query["start"]))
    np.testing.assert_array_equal(wp[-1], np.array(OBSTACLES + query["goal"]))
    assert (wp[:, :2] == np.array(OBSTACLES)).all()
    # shorter than the raw path
    assert ref.path.length() < raw.path.length()


def test_plan_output_has_the_refinement_fields_unrefined_too(tmp_path, capsys):
    one = {"obstacles": OBSTACLES, "start": [[0.1, 0.5]], "goal": [[0.9, 0.5]]}
    status, out, _ = run(capsys, "plan", write_json(tmp_path, one))
    assert status == 0
    res = json.loads(out)
    assert set(io.REFINE_FIELDS) <= set(res)
    assert res["refined"] is False and res["radius"] == 0.0
    assert res["robot_distance"] is None  # one robot: no pair (inf in Python, null in JSON)
    assert res["obstacle_distance"] == pmplan.plan(OBSTACLES, [[0.1, 0.5]],
                                                   [[0.9, 0.5]]).obstacle_distance > 0
    json.dumps(res, allow_nan=False)  # strict JSON


def test_plan_refine_tuning_options_reach_refine(tmp_path, capsys):
    q = write_json(tmp_path, QUERY)
    status, out, _ = run(capsys, "plan", q, "--refine", "--waypoints", "8", "--steps", "5",
                         "--obstacle-radius", "0.01")
    assert status == 0
    res = json.loads(out)
    raw = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"], lift=0.01)  # (default)
    ref = pmplan.refine(raw, waypoints=8, steps=5, obstacle_radius=0.01)
    np.testing.assert_array_equal(np.array(res["waypoints"]), ref.path.waypoints)
    assert res["obstacle_radius"] == 0.01
    assert len(res["times"]) == 5 * 8 + 2 + 1  # 7 raw pieces, each cut in 8 but the 2 still


REFINE_ERRORS = [
    (["plan", "Q", "--radius", "0.05"], "--radius applies to a refined motion: add --refine"),
    (["plan", "Q", "--steps", "3"], "--steps applies to a refined motion: add --refine"),
    (["animate", "Q", "--obstacle-radius", "0.1"],
     "--obstacle-radius applies to a refined motion: add --refine"),
    (["batch", "Q", "--out", "p.npz", "--waypoints", "2"],
     "--waypoints applies to a refined motion: add --refine"),
    (["plan", "Q", "--refine", "--radius", "wide"], "argument --radius: expected a number"),
    (["plan", "Q", "--refine", "--steps", "many"], "argument --steps: expected an integer"),
    (["plan", "Q", "--refine", "--radius", "-1"], "`radius` must be a finite real number >= 0"),
    (["plan", "Q", "--refine", "--radius", "nan"], "`radius` must be a finite real number >= 0"),
    (["plan", "Q", "--refine", "--obstacle-radius", "inf"], "`obstacle_radius` must be"),
    (["plan", "Q", "--refine", "--waypoints", "3"], "`waypoints` must be a power of two"),
    (["plan", "Q", "--refine", "--steps", "0"], "`steps` must be an int from 1"),
    # robot 1 starts 0.25 from o1: it cannot be a disc of radius 0.3
    (["plan", "Q", "--refine", "--radius", "0.3"], "closer than"),
    # the same check chunk by chunk when streaming into a Zarr store
    (["batch", "Q", "--out", "p.zarr", "--refine", "--radius", "0.3", "--no-progress"],
     "closer than"),
    (["verify", "--refine", "--radius", "0.1"], "unrecognized arguments: --radius"),
]


@pytest.mark.parametrize("argv, match", REFINE_ERRORS, ids=lambda v: " ".join(v)
                         if isinstance(v, list) else None)
def test_refine_option_errors_are_one_line(tmp_path, capsys, argv, match):
    q = write_json(tmp_path, QUERY)
    status, out, err = run(capsys, *[q if a == "Q" else
                                     str(tmp_path / a) if a.startswith("p.") else a
                                     for a in argv])
    assert_one_line_error(status, out, err, match)


def test_refine_options_wherever_a_motion_is_planned():
    import argparse

    from pmplan.cli import build_parser

    parser = build_parser()
    commands = next(a for a in parser._actions
                    if isinstance(a, argparse._SubParsersAction)).choices
    for name in ("plan", "batch", "animate"):
        for opt in ("--refine", "--radius", "--obstacle-radius", "--waypoints", "--steps"):
            assert opt in commands[name]._option_string_actions, (name, opt)
    assert "--refine" in commands["verify"]._option_string_actions
    for opt in ("--radius", "--obstacle-radius"):
        assert opt in commands["demo"]._option_string_actions


# --------------------------------------------------------------------------------------------
# pmplan batch --refine


@pytest.mark.parametrize("via", [False, True])
def test_batch_refine_writes_the_refined_batch(tmp_path, capsys, via):
    rng = np.random.default_rng(5)
    b = 12
    obstacles = np.tile(np.array(OBSTACLES), (b, 1, 1))
    # robots 0.3 apart, starts above the obstacles' line y = 0.5, goals below it
    start = np.stack([rng.uniform(0, 0.7, b), rng.uniform(0.7, 1.0, b)], -1)[:, None]
    start = np.concatenate([start, start + [0.3, 0.0]], axis=1)
    goal = np.stack([rng.uniform(0, 0.7, b), rng.uniform(0.0, 0.3, b)], -1)[:, None]
    goal = np.concatenate([goal + [0.3, 0.0], goal], axis=1)  # and they swap sides
    arrays = dict(obstacles=obstacles, start=start, goal=goal)
    if via:  # robots 0.3 apart on the line y = 1.2, well above the obstacles
        mid = (start + goal) / 2 + [[-0.15, 0.0], [0.15, 0.0]]
        mid[:, :, 1] = 1.2
        arrays["via"] = mid[:, None]
    np.savez(tmp_path / "q.npz", **arrays)
    status, out, err = run(capsys, "batch", tmp_path / "q.npz", "--out", tmp_path / "p.npz",
                           "--no-progress", "--refine", "--radius", "0.02",
                           "--obstacle-radius", "0.02")
    assert status == 0, err
    if via:
        configs = [start, *np.moveaxis(arrays["via"], 1, 0), goal]
        raw = pmplan.plan_sequence_batch(obstacles, configs, lift=0.04)  # (the default unit)
    else:
        raw = pmplan.plan_batch(obstacles, start, goal, lift=0.04)
    ref = pmplan.refine(raw, radius=0.02, obstacle_radius=0.02)
    with np.load(tmp_path / "p.npz") as res:
        np.testing.assert_array_equal(res["domain"], raw.domain)
        np.testing.assert_array_equal(res["waypoints"], ref.waypoints)
        assert res["refined"].all() and (res["radius"] == 0.02).all()
        for key in ("robot_distance", "obstacle_distance", "respects_radius", "clearance"):
            np.testing.assert_array_equal(res[key], getattr(ref, key))
        kept = res["respects_radius"]
        assert (res["robot_distance"][kept] >= 0.04).all()
        assert (res["obstacle_distance"][kept] >= 0.04).all()
    assert f"radii respected by {int(ref.respects_radius.sum())} of {b}" in out


def test_batch_unrefined_npz_has_the_fields(tmp_path, capsys):
    np.savez(tmp_path / "q.npz", obstacles=np.array([OBSTACLES]), start=np.array([[[0.1, 0.5]]]),
             goal=np.array([[[0.9, 0.5]]]))
    assert run(capsys, "batch", tmp_path / "q.npz", "--out", tmp_path / "p.npz",
               "--no-progress")[0] == 0
    with np.load(tmp_path / "p.npz") as res:
        assert not res["refined"].any() and res["radius"].tolist() == [0.0]
        assert res["obstacle_radius"].tolist() == [0.0]
        # the minima apart are measured for refined batches only (a pass over all pairs)
        assert not set(io.REFINE_FIELDS[3:]) & set(res.files)


# --------------------------------------------------------------------------------------------
# pmplan verify --refine


@pytest.fixture(scope="module")
def refined_report():
    from pmplan.verify import verify

    return verify(d=2, n=2, m=2, queries=60, seed=3, progress=False, refine=True)


def test_verify_refine_reports_refined_moduli_beside_the_raw_ones(refined_report):
    r = refined_report
    assert r.ok and r.refine, r.problems
    realised = [d for d in r.domains if d.queries]
    assert [d.label for d in realised] == r.labels
    for d in realised:
        # every raw plan was refined and certified, in the same domain
        assert d.refined_queries == d.queries and d.refined_min_clearance > 0
    moduli = [d for d in realised if d.modulus is not None]
    assert moduli
    for d in moduli:
        assert d.refined_modulus is not None and d.refined_perturbations > 0
        # continuous inside the domain: far below the jumps across domains (~1/delta)
        low_jump = min(x.jump for x in r.domains if x.jump is not None)
        assert d.refined_modulus < 1e-3 * low_jump, (d.label, d.refined_modulus, low_jump)
    fams = r.families
    for name in ("exact", "random", "near-degenerate"):
        assert fams["refined " + name]["queries"] == fams[name]["planned"]
        assert fams["refined " + name]["failed"] == 0


def test_verify_refine_text_and_json(refined_report, capsys):
    from pmplan.verify import Report

    text = refined_report.to_text()
    head = text.splitlines()[3]
    assert head.split()[:6] == ["domain", "queries", "strata", "min", "clearance", "continuity"]
    assert "refined" in head and text.index("continuity") < text.index("refined  ")
    assert "refined certificates:" in text and "refined continuity:" in text
    again = Report.from_json(refined_report.to_json())
    assert again == refined_report
    # the command line prints the same report
    status, out, _ = run(capsys, "verify", "--d", "2", "--n", "2", "--m", "2", "--queries", "60",
                         "--seed", "3", "--no-progress", "--refine", "--json")
    assert status == 0 and Report.from_json(out) == refined_report


def test_verify_refine_probes_three_sizes_and_scales(refined_report):
    """The refined modulus is measured at every size of REFINE_DELTAS on the same base queries,
    and it scales linearly in every domain of this case."""
    from pmplan.verify import REFINE_DELTAS

    measured = [d for d in refined_report.domains if d.refined_modulus is not None]
    assert measured
    for d in measured:
        assert len(d.refined_moduli) == len(REFINE_DELTAS)
        assert d.refined_modulus == max(v for v in d.refined_moduli if v is not None)
        assert d.refined_linear is True
    text = refined_report.to_text()
    assert all(f"{dl:g}:" in text for dl in REFINE_DELTAS) and "scales linearly" in text


def test_verify_refine_fails_a_domain_whose_modulus_does_not_scale(monkeypatch, capsys):
    """A refined path that jumps by a fixed amount inside a domain (planted: the probe's change
    made independent of the perturbation size) is a failure, in the text and the exit status."""
    import pmplan.verify as V

    real = V._refined_probe

    def jumping(name, lift, b0, k0, r0, k0r, moved, dist):
        out = real(name, lift, b0, k0, r0, k0r, moved, dist)
        size = float(np.median(dist[dist > 0])) if (dist > 0).any() else 1.0
        return [(label, r + 1e-3 / size) for label, r in out]  # a jump of 1e-3 at every size

    monkeypatch.setattr(V, "_refined_probe", jumping)
    r = V.verify(d=2, n=1, m=2, queries=20, seed=1, progress=False, refine=True)
    assert not r.ok
    assert any("does not scale linearly" in p for p in r.problems)
    assert any(d.refined_linear is False for d in r.domains)
    assert "does NOT scale linearly" in r.to_text() and r.to_text().endswith("NOT OK")
    status, out, _ = run(capsys, "verify", "--d", "2", "--n", "1", "--m", "2", "--queries",
                         "20", "--seed", "1", "--no-progress", "--refine")
    assert status == 1 and "does not scale linearly" in out


def test_verify_without_refine_is_unchanged():
    from pmplan.verify import verify

    r = verify(d=2, n=1, m=2, queries=20, progress=False)
    assert not r.refine and all(d.refined_modulus is None for d in r.domains)
    assert "refined" not in r.to_text() and not any(k.startswith("refined") for k in r.families)
    with pytest.raises(pmplan.InputError, match="`refine` must be True or False"):
        verify(d=2, n=1, m=2, queries=20, progress=False, refine="yes")


# --------------------------------------------------------------------------------------------
# the demo: every domain's query raw and refined, side by side


def test_demo_draws_raw_and_refined_side_by_side(tmp_path, capsys, monkeypatch):
    import pmplan.plotting

    drawn = []

    def grid(plans, *args, **kwargs):
        drawn.extend(plans)
        return plan_grid(plans, *args, **kwargs)

    monkeypatch.setattr(pmplan.plotting, "plan_grid", grid)
    out_png = tmp_path / "demo.png"
    status, out, _ = run(capsys, "demo", "--n", "2", "--out", out_png)
    assert status == 0
    # every domain's query, raw then refined (and the crowded room, in its box): the same
    # domain, stratum and endpoints
    assert len(drawn) == 2 * (len(pmplan.info(2, 2, 2).labels) + 4 + 1)
    assert drawn[-2].bounds is not None and drawn[-1].bounds is not None
    for raw, ref in zip(drawn[::2], drawn[1::2]):
        assert not raw.refined and ref.refined
        assert (ref.planner, ref.domain, ref.stratum) == (raw.planner, raw.domain, raw.stratum)
        np.testing.assert_array_equal(ref.path.waypoints[[0, -1]], raw.path.waypoints[[0, -1]])
    rows = [line.split() for line in out.splitlines()
            if line.startswith(("obstacle_line", "planar_three"))]
    labels = pmplan.info(2, 2, 2).labels
    assert [int(r[1].removeprefix("W_")) for r in rows if r[0] == "obstacle_line_compact"] \
        == list(labels)
    # the crowded room, last: the plan pmplan.plan(..., refine=True) returns for 8 robots in the
    # plane in its box (the one-side lanes on the wall side) and the raw plan it refines
    assert rows[-1][0] == "obstacle_line_walls" == drawn[-1].planner == drawn[-2].planner
    from pmplan.examples import ROOM_GAP, crowded_room

    o, s, g, bounds = crowded_room()
    radii = {"radius": ROOM_GAP / 2, "obstacle_radius": ROOM_GAP / 2}
    direct = pmplan.plan(o, s, g, bounds=bounds, refine=True, **radii)
    np.testing.assert_array_equal(drawn[-1].path.waypoints, direct.path.waypoints)
    np.testing.assert_array_equal(pmplan.refine(drawn[-2], **radii).path.waypoints,
                                  direct.path.waypoints)
    assert len(rows) == len(drawn) // 2
    for r, raw in zip(rows, drawn[::2]):  # raw length, clearance; refined length, clearance
        raw_len, raw_clr, ref_len, ref_clr = map(float, r[-4:])
        assert raw_clr > 0 and ref_clr > 0 and ref_len <= raw_len, r
        # shorter, unless the raw motion is already straight (the direct lift's W_8 query):
        # its length the lower bound, the sum of the robots' start-goal distances
        ends = raw.path.waypoints[[0, -1]]
        bound = float(np.linalg.norm(ends[1] - ends[0], axis=-1).sum())
        assert ref_len < raw_len or abs(raw_len - bound) <= 1e-3, r
    with Image.open(out_png) as im:
        assert im.size[0] > 1200 and im.size[1] > 1500


def test_demo_pairs_share_the_domain_label_in_their_titles():
    from pmplan.examples import obstacle_line_examples

    raw = list(pmplan.plan_batch(*[np.stack(a) for a in zip(*obstacle_line_examples(3))]))
    pairs = [q for p in raw for q in (p, pmplan.refine(p))]
    fig = plan_grid(pairs, ncols=4)
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert len(panels) == 2 * len(raw)
    for k in range(0, len(panels), 2):
        left, right = panels[k].get_title(), panels[k + 1].get_title()
        assert left == plan_title(pairs[k]) and right == plan_title(pairs[k + 1])
        assert "refined" not in left and " refined  " in right
        assert left.split("  ")[1] == right.split("  ")[1]  # "$W_l$: $stratum$"
    from test_faces import _assert_labels_apart_and_inside

    _assert_labels_apart_and_inside(fig, pairs)


def test_refined_plan_with_radius_draws_discs():
    from matplotlib.collections import EllipseCollection

    from pmplan.plotting import draw_plan

    p = pmplan.refine(pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"]),
                      radius=0.05, obstacle_radius=0.02)
    ax = draw_plan(p)
    discs = [c for c in ax.collections if isinstance(c, EllipseCollection)]
    # robots at start, obstacles once, robots at goal
    assert [len(c.get_offsets()) for c in discs] == [2, 2, 2]
    unrefined = draw_plan(pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"]))
    assert not [c for c in unrefined.collections if isinstance(c, EllipseCollection)]


# --------------------------------------------------------------------------------------------
# pmplan animate --refine


def test_animate_refine_writes_a_gif_of_the_refined_motion(tmp_path, capsys):
    out = tmp_path / "m.gif"
    status, printed, err = run(capsys, "animate", write_json(tmp_path, QUERY), "--out", out,
                               "--frames", "6", "--refine", "--radius", "0.05")
    assert status == 0, err
    assert f"wrote {out.resolve()}" in printed
    with Image.open(out) as im:
        assert im.n_frames == 6 and im.size[0] > 200


def test_refined_frame_shows_discs_and_no_phase_of_the_construction():
    from matplotlib.collections import EllipseCollection

    raw = pmplan.plan(QUERY["obstacles"], QUERY["start"], QUERY["goal"])
    p = pmplan.refine(raw, radius=0.05)
    ph = phase_at(p, 0.5)
    pieces = p.path.times.size - 1
    assert ph.name == REFINED_PHASE and ph.count == pieces
    assert ph.label() == f"{REFINED_PHASE}, piece {ph.index} of {pieces}"
    ax = draw_frame(p, 0.5)
    (discs,) = [c for c in ax.collections if isinstance(c, EllipseCollection)]
    # the discs sit on the robots at t = 0.5
    np.testing.assert_allclose(discs.get_offsets(), p.path(0.5)[2:])
    assert "refined, radius 0.05" in ax.get_title()
    assert phase_at(raw, 0.5).name == "slide"  # the raw plan keeps its phases
