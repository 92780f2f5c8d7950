"""The default planner of a refined crowd (Mathematics §8, "Crowds"): a plan to be refined of
at least ``CROWD_LANES`` robots in the plane takes ``obstacle_line_oneside`` by default, a raw
plan, a smaller crowd or a crowd in space ``obstacle_line_compact``, at every entry point (the
library's functions, dask arrays, the command line, a query file's faces); a named planner is
always the one used. The refined plan is then exactly the refinement of the one-side raw plan
at the refined plan's unit."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pmplan
from pmplan import io
from pmplan.cli import main
from pmplan.planners.base import CROWD_LANES, WALL_LANES, default_planner

ONESIDE, COMPACT = "obstacle_line_oneside", "obstacle_line_compact"
WALLS = "obstacle_line_walls"
RADIUS = 0.01


def _query(n: int, seed: int = 0, d: int = 2, m: int = 3):
    rng = np.random.default_rng([seed, n, d, m])
    return (rng.uniform(0, 10, (m, d)), rng.uniform(0, 10, (n, d)),
            rng.uniform(0, 10, (n, d)))


@pytest.mark.parametrize("d", [2, 3, 4])
@pytest.mark.parametrize("m", [2, 3, 6])
def test_default_planner_by_robot_count_and_refinement(d, m):
    for n in (1, CROWD_LANES - 1, CROWD_LANES, CROWD_LANES + 5):
        for sequential in (False, True):
            raw = default_planner(d, n, m, sequential)
            refined = default_planner(d, n, m, sequential, refining=True)
            assert raw == ("planar_three" if (d, n, m) == (2, 1, 3) and not sequential
                           else COMPACT)
            assert refined == (ONESIDE if n >= CROWD_LANES and d == 2 else raw)
            chosen = pmplan.choose_planner(d, n, m, sequential=sequential, refining=True)
            assert chosen.name == refined
            # in a box (Mathematics §8, "The side of the lanes"): the wall side from WALL_LANES
            boxed = default_planner(d, n, m, sequential, refining=True, bounded=True)
            assert boxed == (WALLS if n >= WALL_LANES and d == 2 else refined)
            assert default_planner(d, n, m, sequential, bounded=True) == raw
            assert pmplan.choose_planner(d, n, m, COMPACT, refining=True).name == COMPACT


@pytest.mark.parametrize("bounds", [None, (-1.0, 11.0)])
def test_every_function_refines_a_crowd_with_the_one_side_lanes(bounds):
    """plan, plan_batch, plan_sequence and plan_sequence_batch (in R^d and in a box): refined,
    a crowd gets the one-side lanes (in a box in the plane on the wall side) -- the refinement
    of that raw plan at the refined plan's unit (the robots' diameter), bit for bit; raw, or
    fewer robots (in R^d), or a named planner: as before."""
    o, s, g = _query(CROWD_LANES)
    kw = dict(refine=True, radius=RADIUS, bounds=bounds)
    lanes = ONESIDE if bounds is None else WALLS
    got = pmplan.plan(o, s, g, **kw)
    want = pmplan.refine(pmplan.plan(o, s, g, planner=lanes, lift=2 * RADIUS, bounds=bounds),
                         radius=RADIUS)
    assert got.planner == lanes and got.domain == want.domain
    np.testing.assert_array_equal(got.path.waypoints, want.path.waypoints)
    assert pmplan.plan(o, s, g, bounds=bounds).planner == COMPACT
    assert pmplan.plan(o, s, g, planner=COMPACT, **kw).planner == COMPACT
    fewer = COMPACT if bounds is None else WALLS  # CROWD_LANES - 1 robots
    assert pmplan.plan(o, s[1:], g[1:], **kw).planner == fewer
    o3, s3, g3 = _query(CROWD_LANES, d=3)
    space = None if bounds is None else (-1.0, 11.0)
    assert pmplan.plan(o3, s3, g3, refine=True, radius=RADIUS, bounds=space).planner == COMPACT
    batch = pmplan.plan_batch(o[None], s[None], g[None], **kw)
    assert batch.planner == lanes
    np.testing.assert_array_equal(batch.waypoints[0], got.path.waypoints)
    seq = pmplan.plan_sequence(o, [s, g, s], **kw)
    seqs = pmplan.plan_sequence_batch(o[None], [s[None], g[None], s[None]], **kw)
    assert seq.planner == seqs.planner == lanes
    np.testing.assert_array_equal(seqs.waypoints[0], seq.path.waypoints)
    assert pmplan.plan_sequence(o, [s, g, s], bounds=bounds).planner == COMPACT


def test_a_lazy_refined_crowd_takes_the_one_side_lanes():
    """Dask arrays (pmplan.scale) choose the planner as the eager call does."""
    da = pytest.importorskip("dask.array")
    o, s, g = (np.stack([a, a]) for a in _query(CROWD_LANES, seed=1))
    lazy = pmplan.plan_batch(*(da.from_array(a, chunks=(1, *a.shape[1:])) for a in (o, s, g)),
                             refine=True, radius=RADIUS)
    eager = pmplan.plan_batch(o, s, g, refine=True, radius=RADIUS)
    assert lazy.planner == eager.planner == ONESIDE
    np.testing.assert_array_equal(np.asarray(lazy.waypoints), eager.waypoints)


def test_the_faces_plan_a_refined_crowd_as_the_library_does(tmp_path, capsys):
    """``pmplan plan --refine`` and ``pmplan batch --refine`` (and every face through
    :func:`pmplan.io.with_defaults`) give the plan ``pmplan.plan(..., refine=True)`` gives."""
    o, s, g = _query(CROWD_LANES, seed=2)
    query = {"obstacles": o.tolist(), "start": s.tolist(), "goal": g.tolist()}
    path = tmp_path / "q.json"
    path.write_text(json.dumps(query))
    assert main(["plan", str(path), "--refine", "--radius", str(RADIUS)]) == 0
    res = json.loads(capsys.readouterr().out)
    want = pmplan.plan(o, s, g, refine=True, radius=RADIUS)
    assert res["planner"] == ONESIDE
    np.testing.assert_array_equal(np.array(res["waypoints"]), want.path.waypoints)
    # a batch file of two queries
    batch = tmp_path / "b.json"
    batch.write_text(json.dumps([query, query]))
    out = tmp_path / "out.npz"
    assert main(["batch", str(batch), "--out", str(out), "--refine", "--radius",
                 str(RADIUS)]) == 0
    assert f"with {ONESIDE}" in capsys.readouterr().out
    # the query's own planner wins; a raw plan keeps the compact lanes
    parsed = io.parse_query(query)
    assert io.with_defaults(parsed, {"radius": RADIUS})["planner"] == ONESIDE
    assert io.with_defaults(dict(parsed, planner=COMPACT), {"radius": RADIUS})["planner"] \
        == COMPACT
    assert "planner" not in io.with_defaults(parsed, None)
    # a query with a box: the wall side, as pmplan.plan(..., bounds=, refine=True) takes it
    boxed = dict(parsed, bounds=np.array([-1.0, 11.0]))
    assert io.with_defaults(boxed, {"radius": RADIUS})["planner"] == WALLS
