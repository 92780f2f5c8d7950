"""The workspace box (pmplan.workspace, issue 25 item 1): the map into the box and out of it,
plans that stay inside it with their endpoints, vias and obstacles exact, certified and
continuous, refined plans inside the box shrunk by the radius with the walls in
``respects_radius``, and the errors for a bad box or a point outside it."""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import spaced_points

import pmplan
from pmplan import workspace as W
from pmplan.certify import clearance, radius_report
from pmplan.io import parse_query
from pmplan.path import PiecewiseLinearPath, cut_along
from pmplan.refine.grid import DEFAULT_WAYPOINTS, raw_positions

BOX = np.array([[0.0, 0.0], [10.0, 10.0]])


# --- the map ----------------------------------------------------------------------------------

def test_check_bounds_forms_and_refusals():
    assert W.check_bounds((0, 10), 2).tolist() == BOX.tolist()
    assert W.check_bounds(([0, -1, 2], [1, 1, 3]), 3).tolist() == [[0, -1, 2], [1, 1, 3]]
    for bad in [(10, 0), (0, 0), (0, np.inf), (0, np.nan), "ab", (0,), (0, 1, 2), (True, 2),
                (0, [1, 2, 3]), ([0, 0], [[1, 1]]), ("0", 1), None]:
        with pytest.raises(pmplan.InputError, match="`bounds` must be a pair"):
            W.check_bounds(bad, 2)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-1e6, 1e6), lo=st.floats(-100, 100), width=st.floats(1e-3, 1e3))
def test_the_map_is_a_monotone_bijection_onto_the_box_and_the_identity_inside(x, lo, width):
    box = np.array([[lo], [lo + width]])
    y = float(W.into_box(np.array([x]), box)[0])
    assert lo <= y <= lo + width
    mu = W.BAND * width
    if lo + mu <= x <= lo + width - mu:
        assert y == x  # bit for bit
    if lo < y < lo + width:  # (far out, y rounds to the wall)
        back = float(W.from_box(np.array([y]), box)[0])
        assert abs(back - x) <= 1e-9 * max(1.0, abs(x - lo), width) * (1 + (abs(x - lo) / mu) ** 2)
    # monotone and continuous across the band's edges (value and slope match: C^1)
    xs = np.array([x, x + 1e-7 * width])
    ys = W.into_box(xs, box)
    assert ys[1] >= ys[0] and ys[1] - ys[0] <= 1e-7 * width * (1 + 1e-6)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-1e3, 1e3), lo=st.floats(-100, 100), width=st.floats(1e-2, 1e3))
def test_the_slope_is_the_derivative_of_the_map(x, lo, width):
    """into_box_slope is phi's derivative: a central difference of into_box agrees with it to
    the difference's own error, it is exactly 1 on the inner box, and the tails' slope is
    (mu / (mu + t))^2 at a distance t beyond the inner box (exact at the box's wall: 1/4)."""
    box = np.array([[lo], [lo + width]])
    mu = W.BAND * width
    slope = float(W.into_box_slope(np.array([x]), box)[0])
    h = 1e-4 * (mu + abs(x - lo) + abs(x - lo - width))
    fd = float(np.diff(W.into_box(np.array([x - h, x + h]), box))[0]) / (2 * h)
    # the second derivative is at most 2 / mu times the slope's scale: a central difference's
    # error is O(h^2 / mu^2); rounding adds eps * width / h
    assert abs(fd - slope) <= 1e-6 + 4e-7 * (1 + (h / mu) ** 2) + 1e-12 * width / h
    assert 0.0 < slope <= 1.0
    if lo + mu <= x <= lo + width - mu:
        assert slope == 1.0
    wall = W.into_box_slope(np.array([[lo, lo + width]]).T, box)[:, 0]
    assert np.allclose(wall, 0.25, rtol=1e-12)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-1e3, 1e3), lo=st.floats(-100, 100), width=st.floats(1e-2, 1e3))
def test_the_slope_of_the_linear_map_is_its_derivative(x, lo, width):
    """into_box_linear_slope is the slope of into_box_linear's cell at x: a one-sided
    difference inside the cell agrees with it, it is 1 on the inner box and 2^(-2k-1) (a power
    of two) beyond it."""
    box = np.array([[lo], [lo + width]])
    slope = float(W.into_box_linear_slope(np.array([x]), box)[0])
    assert 0.0 < slope <= 1.0 and np.frexp(slope)[0] == 0.5
    inner = lo + W.BAND * width <= x <= lo + width - W.BAND * width
    assert (slope == 1.0) == inner or slope == 0.5  # (the first cell beyond: 1/2)
    side = 1.0 if x >= lo + width / 2 else -1.0  # (into the cell, away from the inner box)
    h = 1e-6 * W.BAND * width * slope ** -0.5
    y = W.into_box_linear(np.array([[x], [x + side * h]]), box)[:, 0]
    fd = side * (y[1] - y[0]) / h
    if W.into_box_linear_slope(np.array([x + side * h]), box)[0] == slope:  # (one cell)
        # (rounding: a few ulps of the values and of the unit coordinates, over h)
        assert abs(fd - slope) <= 1e-6 * slope + 8e-16 * (abs(lo) + width + abs(x)) / h


@pytest.mark.parametrize("k", [-1000, -500, -60, 60, 500, 960])
def test_a_box_at_every_magnitude_is_bitwise_equivariant(k):
    """The maps run in the box's unit coordinates: a query and its box scaled by 2**k give the
    plan scaled by 2**k, bit for bit, refined too (lift="scene": equivariant plans)."""
    rng = np.random.default_rng(7)
    o, s, g = _inside_queries(rng, 12, 4, 3)
    f = 2.0 ** k
    a = pmplan.plan_batch(o, s, g, lift="scene", bounds=(0, 10), refine=True, radius=0.01)
    b = pmplan.plan_batch(o * f, s * f, g * f, lift="scene", bounds=(0, 10 * f), refine=True,
                          radius=0.01 * f)
    assert np.array_equal(b.domain, a.domain)
    assert np.array_equal(b.waypoints, a.waypoints * f)
    assert np.array_equal(b.respects_radius, a.respects_radius) and a.respects_radius.sum() >= 10


@pytest.mark.parametrize("band", [W.BAND, 3 / 16, 5 / 16])
@pytest.mark.parametrize("w", [0.5, 0.1, 1e-3])
def test_the_map_out_of_the_box_stretches_by_mu_over_w_squared(band, w):
    """Mathematics §8: at a distance ``w`` (a fraction of the band) from a wall, ``phi^-1``
    stretches by ``(mu / w)^2``, so an obstacle near a wall moves that much more in R^d: the
    difference quotient over a step of 1e-6 w, against the closed form in exact arithmetic."""
    box = np.array([[0.0], [10.0]])
    mu = band * 10.0
    y = 10.0 - w * mu
    h = 1e-6 * w * mu
    x = W.from_box(np.array([y, y + h]), box, band)
    quotient = (x[1] - x[0]) / h
    # the closed form, exactly: (psi^-1)'(y) = mu^2 / (hi - y)^2, and the secant's own error
    # (the second derivative is 2 mu^2 / (hi - y)^3) is below h / (hi - y - h) of it
    exact = Fraction(mu) ** 2 / (Fraction(10.0) - Fraction(y)) ** 2
    assert abs(Fraction(quotient) / exact - 1) < 1e-5
    assert float(exact) == pytest.approx((1.0 / w) ** 2, rel=1e-9)  # (y = hi - w mu, rounded)


def test_far_points_stay_apart():
    """The algebraic tail: points 100 and 101 band widths beyond the wall stay distinct (an
    exponential tail rounds both to the wall)."""
    box = np.array([[0.0], [10.0]])
    mu = W.BAND * 10
    y = W.into_box(np.array([10 - mu + 100 * mu, 10 - mu + 101 * mu]), box)
    assert y[0] < y[1] < 10.0


# --- plans in a box ---------------------------------------------------------------------------

def _inside_queries(rng, b, n, m, d=2, size=10.0, margin=0.5, gap=0.6):
    """b queries in [margin, size - margin]^d, the points of a configuration >= gap apart."""
    o, s, g = [], [], []
    for _ in range(b):
        ob = spaced_points(rng, m, d, margin, size - margin, gap)
        pair = [spaced_points(rng, m + n, d, margin, size - margin, gap)[m:] for _ in range(2)]
        while any(np.linalg.norm(c[:, None] - ob[None], axis=-1).min() < gap for c in pair):
            pair = [spaced_points(rng, m + n, d, margin, size - margin, gap)[m:] for _ in range(2)]
        o.append(ob), s.append(pair[0]), g.append(pair[1])
    return np.array(o), np.array(s), np.array(g)


@pytest.mark.parametrize("dims", [(2, 1, 2), (2, 4, 2), (2, 8, 6), (3, 4, 4), (2, 1, 3)])
def test_plans_stay_in_the_box_with_exact_endpoints(dims):
    d, n, m = dims
    rng = np.random.default_rng(sum(dims))
    o, s, g = _inside_queries(rng, 40, n, m, d)
    box = np.array([[0.0] * d, [10.0] * d])
    batch = pmplan.plan_batch(o, s, g, bounds=(0, 10))
    free = pmplan.plan_batch(o, s, g)
    assert W.inside(batch.waypoints, box).all() and not W.inside(free.waypoints, box).all() \
        or n == 1
    assert (batch.clearance > 0).all()
    assert np.array_equal(batch.waypoints[:, 0, m:], s) and np.array_equal(batch.waypoints[:, -1, m:], g)
    assert (batch.waypoints[:, :, :m] == o[:, None]).all()
    plane = pmplan.plan_batch(*(W.from_box_linear(x, box) for x in (o, s, g)))
    assert np.array_equal(batch.domain, plane.domain)
    assert batch.bounds.shape == (40, 2, d) and (batch.bounds == box).all()
    # the conjugated motion at every time (Mathematics §8): phi of the plan of phi^-1(q)
    t = np.random.default_rng(1).uniform(0, 1, 300)
    for q in range(0, 40, 7):
        want = W.into_box_linear(plane[q].path(t), box)
        got = batch[q].path(t)
        assert np.abs(got - want).max() <= 1e-12 * 10
    # one query alone: its row's motion, and (shared raw breakpoints) the raw breakpoints at the
    # same places
    one = pmplan.plan(o[3], s[3], g[3], bounds=(0, 10))
    assert one.domain == batch.domain[3]
    assert np.abs(one.path(t) - batch[3].path(t)).max() <= 1e-12 * 10
    if plane.times.ndim == 2:  # (planar_three: per-query breakpoints, a Plan drops empty pieces)
        return
    k = plane.times.shape[-1]
    c1, c2 = (one.path.times.size - 1) // (k - 1), (batch.times.shape[-1] - 1) // (k - 1)
    assert np.array_equal(one.path.times[::c1], batch.times[3, ::c2])
    assert np.array_equal(one.waypoints[::c1], batch.waypoints[3, ::c2])


def test_a_plan_inside_the_inner_box_is_unchanged():
    """The map is the identity away from the walls: a query whose raw path stays in the inner
    box gets the same path, bit for bit."""
    o, s, g = [[4.5, 5.0], [5.5, 5.0]], [[4.0, 4.0]], [[6.0, 6.0]]
    free = pmplan.plan(o, s, g, lift=0.1)
    boxed = pmplan.plan(o, s, g, lift=0.1, bounds=(0, 10))
    assert np.array_equal(free.waypoints, boxed.waypoints)


@settings(max_examples=30, deadline=None)
@given(pts=st.lists(st.tuples(st.integers(1, 7), st.integers(1, 7)), min_size=6, max_size=6,
                    unique=True), goal=st.lists(st.tuples(st.integers(1, 7), st.integers(1, 7)),
                                                min_size=2, max_size=2, unique=True))
def test_integer_queries_in_a_box(pts, goal):
    """Exactly degenerate queries (integer points on a grid, collinear triples, the obstacle
    line through robots): every path certified and inside [0, 8]^2."""
    o, s = np.array(pts[:2], float), np.array(pts[2:4], float)
    g = np.array(goal, float)
    if {tuple(x) for x in g} & {tuple(x) for x in o}:
        return
    p = pmplan.plan(o, s, g, bounds=(0, 8))
    assert W.inside(p.waypoints[None], np.array([[0.0, 0], [8, 8]]))[0] and p.clearance > 0
    assert np.array_equal(p.waypoints[-1, 2:], g)


def test_sequences_in_a_box():
    rng = np.random.default_rng(5)
    o = rng.uniform(1, 9, (6, 3, 2))
    cs = [rng.uniform(1, 9, (6, 2, 2)) for _ in range(3)]
    b = pmplan.plan_sequence_batch(o, cs, bounds=(0, 10), refine=True, radius=0.05)
    assert W.inside(b.waypoints, BOX, 0.05).all()
    times = b.times if b.times.ndim == 1 else b.times[0]
    k = int(np.flatnonzero(times == 0.5)[0])
    assert np.array_equal(b.waypoints[:, k, 3:], cs[1])
    one = pmplan.plan_sequence(o[0], [c[0] for c in cs], bounds=(0, 10))
    assert W.inside(one.waypoints[None], BOX)[0]


@pytest.mark.parametrize("delta", [1e-6, 1e-9, 1e-12])
def test_plans_in_a_box_are_continuous(delta):
    """The map and its inverse are continuous (C^1 with slopes at most 1 into the box): a
    move of the query moves the boxed path by about what it moves the free one. (The refined
    default of 4 robots in a box in the plane takes a side per robot, Mathematics §8: a move
    that keeps the label keeps the sides; tests/test_sides.py probes the wall side.)"""
    rng = np.random.default_rng(9)
    o, s, g = _inside_queries(rng, 30, 4, 4)
    a = pmplan.plan_batch(o, s, g, bounds=(0, 10), refine=True, radius=0.05)
    assert a.planner == "obstacle_line_robots"
    move = [delta * rng.uniform(-1, 1, x.shape) for x in (o, s, g)]
    b = pmplan.plan_batch(*(x + v for x, v in zip((o, s, g), move)), bounds=(0, 10),
                          refine=True, radius=0.05)
    same = a.domain == b.domain
    assert same.sum() >= 25
    change = np.abs(a.waypoints - b.waypoints).max(axis=(1, 2, 3))[same] / delta
    assert change.max() <= 1e3, change.max()  # (issue 25's continuity goal)


def test_refined_plans_keep_the_radius_from_the_walls():
    rng = np.random.default_rng(2)
    o, s, g = _inside_queries(rng, 40, 4, 6)
    r = 0.2
    b = pmplan.plan_batch(o, s, g, bounds=(0, 10), refine=True, radius=r, obstacle_radius=r)
    ok = W.inside(b.waypoints, BOX, r)
    _, _, kept = radius_report(b.waypoints, 6, r, r)
    assert np.array_equal(b.respects_radius, kept & ok)
    assert b.respects_radius.sum() >= 30
    assert W.inside(b.waypoints, BOX).all()
    # (the default unit and planner, refined)
    raw = pmplan.plan_batch(o, s, g, bounds=(0, 10), lift=2 * r, planner=b.planner)
    again = pmplan.refine(raw, radius=r, obstacle_radius=r)  # the raw batch carries its box
    assert np.array_equal(again.waypoints, b.waypoints) and (again.bounds == BOX).all()


# --- errors -----------------------------------------------------------------------------------

def test_points_outside_the_box_are_named():
    o, s, g = [[3.5, 5], [6.5, 5]], [[1, 5], [5, 2]], [[9, 5], [5, 8]]
    with pytest.raises(pmplan.InputError, match=r"obstacle o1 is at x\[1\] = 5, outside"):
        pmplan.plan(o, s, g, bounds=(0, 4))
    gb = np.array([g] * 3, float)
    gb[:2, 0, 0] = 8.5
    with pytest.raises(pmplan.InputError, match=r"in the goal, robot x1 is at x\[0\] = 9, .*query 2"):
        pmplan.plan_batch(np.array([o] * 3, float), np.array([s] * 3, float), gb, bounds=(0, 9))
    with pytest.raises(pmplan.InputError, match=r"robot x1 is 1 from the wall x\[0\] = 0, closer"):
        pmplan.plan(o, s, g, bounds=(0, 10), refine=True, radius=1.5)
    with pytest.raises(pmplan.InputError, match="cannot be combined with `bounds=`"):
        out = pmplan.plan_batch(*(np.array([v], float) for v in (o, s, g)))
        pmplan.plan_batch(*(np.array([v], float) for v in (o, s, g)), bounds=(0, 10), out=out)


def test_json_and_cli(tmp_path):
    q = {"obstacles": [[3.5, 5], [6.5, 5]], "start": [[1, 5], [5, 2]], "goal": [[9, 5], [5, 8]],
         "bounds": [0, 10]}
    p = pmplan.plan_query(parse_query(q))
    assert p.bounds.tolist() == BOX.tolist()
    f = tmp_path / "q.json"
    f.write_text(json.dumps(q))
    run = [sys.executable, "-m", "pmplan", "plan", str(f), "--refine", "--radius", "0.3"]
    res = subprocess.run(run, capture_output=True, text=True, check=False)
    out = json.loads(res.stdout)
    assert res.returncode == 0 and out["bounds"] == BOX.tolist() and out["respects_radius"]
    res = subprocess.run(run + ["--bounds", "0", "9"], capture_output=True, text=True, check=False)
    assert res.returncode == 2 and res.stdout == "" and len(res.stderr.splitlines()) == 1
    assert '--bounds [0.0, 9.0] contradicts "bounds": [0.0, 10.0]' in res.stderr
    del q["bounds"]
    f.write_text(json.dumps(q))
    res = subprocess.run([sys.executable, "-m", "pmplan", "plan", str(f), "--bounds", "0,0",
                          "10,10"], capture_output=True, text=True, check=False)
    assert res.returncode == 0 and json.loads(res.stdout)["bounds"] == BOX.tolist()
    q["bounds"] = [0, 10, 20]
    f.write_text(json.dumps(q))
    res = subprocess.run([sys.executable, "-m", "pmplan", "plan", str(f)], capture_output=True,
                         text=True, check=False)
    assert res.returncode == 2 and "`bounds` must be a list [lo, hi]" in res.stderr


# --- batches: dask arrays, Zarr stores, pmplan batch ------------------------------------------

def test_dask_arrays_and_stores_in_a_box(tmp_path):
    import dask.array as da

    from pmplan import scale

    rng = np.random.default_rng(4)
    o, s, g = _inside_queries(rng, 30, 3, 2)
    ref = pmplan.plan_batch(o, s, g, bounds=(0, 10), refine=True, radius=0.05)
    lazy = pmplan.plan_batch(*(da.from_array(x, chunks=7) for x in (o, s, g)), bounds=(0, 10),
                             refine=True, radius=0.05)
    got = scale.compute(lazy, scheduler="sync")
    assert np.array_equal(got.waypoints, ref.waypoints) and (got.bounds == BOX).all()
    assert np.array_equal(got.respects_radius, ref.respects_radius)
    with pytest.raises(pmplan.InputError, match="`bounds` must be a pair"):
        pmplan.plan_batch(*(da.from_array(x, chunks=7) for x in (o, s, g)), bounds=(10, 0))
    rep = scale.plan_store({"obstacles": o, "start": s, "goal": g}, tmp_path / "p.zarr",
                           bounds=(0, 10), refine={"radius": 0.05}, chunk=8)
    assert rep.queries == 30
    back = scale.compute(scale.open_plans(tmp_path / "p.zarr"))
    assert np.array_equal(back.waypoints, ref.waypoints) and (back.bounds == BOX).all()
    with pytest.raises(pmplan.InputError, match=r"--bounds \(bounds=\): stored"):
        scale.plan_store({"obstacles": o, "start": s, "goal": g}, tmp_path / "p.zarr",
                         bounds=(0, 11), refine={"radius": 0.05}, chunk=8, resume=True)


def test_a_json_batch_with_one_box(tmp_path):
    q = {"obstacles": [[3.5, 5], [6.5, 5]], "start": [[1, 5], [5, 2]], "goal": [[9, 5], [5, 8]],
         "bounds": [0, 10]}
    f = tmp_path / "qs.json"
    f.write_text(json.dumps([q, q]))
    res = subprocess.run([sys.executable, "-m", "pmplan", "batch", str(f), "--out",
                          str(tmp_path / "p.npz"), "--no-progress"], capture_output=True, text=True,
                         check=False)
    assert res.returncode == 0, res.stderr
    with np.load(tmp_path / "p.npz") as z:
        assert z["bounds"].shape == (2, 2, 2) and (z["bounds"] == BOX).all()
        assert W.inside(z["waypoints"], BOX).all()
    f.write_text(json.dumps([q, {**q, "bounds": [0, 20]}]))
    res = subprocess.run([sys.executable, "-m", "pmplan", "batch", str(f), "--out",
                          str(tmp_path / "p.npz")], capture_output=True, text=True, check=False)
    assert res.returncode == 2 and 'query 1 has "bounds"' in res.stderr


# --- the chords of a plan in the box (Mathematics §8, "What the chords are not") ------------

def _winding(path: np.ndarray, p: np.ndarray) -> int:
    """The winding number around ``p`` of the polyline ``path`` (K, 2) closed by the segment
    from its last point back to its first (``benchmarks/box_chords.py``'s)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from box_chords import windings

    return int(windings(path[:, None], p[None])[0, 0])


def _chord_queries():
    """Two queries of the scene family *swap* (n = 4, seed 5, query 1), consecutive floats
    apart on a move that changes no column in R^2 (every point's distance to the line o1 o2
    scaled by 1 - 2t, t = 0.10764434558745764 and the next float, in the frame of the
    algebraic map, whose chords cross o4 there), and the box."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import scenes
    from length_bound import mirror_move

    o, s, g = scenes.queries("swap", 4, 12, 5)[1]
    move = mirror_move(o, s, g, BOX, t=[0.10764434558745764, 0.10764434558745765],
                       maps=(W.from_box, W.into_box))
    return [(q[:6], q[6:10], q[10:]) for q in move], BOX


def test_the_conjugated_motion_keeps_its_clearance_across_the_chords_wall():
    """In R^2 the raw plans of the two queries (phi^-1 of them) share their label and keep the
    unit from every obstacle; the polyline through the algebraic map of the raw waypoints comes
    within rounding of o4 (the chords' wall), the plan in the box (the map linear on cells,
    exactly) keeps a clearance of the plane's order."""
    (qa, qb), box = _chord_queries()
    for q in (qa, qb):
        plane = pmplan.plan(*(W.from_box(x, box) for x in q), lift=0.3)
        assert plane.clearance == pytest.approx(0.3, rel=1e-9)
        chords = W.into_box(plane.waypoints, box)
        chords[:, :6] = q[0]
        assert clearance(chords[None], 6)[0] < 1e-12
        boxed = pmplan.plan(*q, bounds=(0, 10), lift=0.3)
        assert boxed.domain == plane.domain and boxed.clearance > 0.1


def test_plans_in_the_box_keep_their_class_inside_a_domain():
    """The two queries of one label, consecutive floats apart, where the polyline through the
    algebraic map of the raw waypoints passed o4 on opposite sides: the plans in the box
    follow the conjugated motion, in one class. Their refinements start from the plans at the
    raw breakpoints (chords again, Mathematics §8), which pass o4 on one side for both: the
    refined plans keep the radii and stay together."""
    (qa, qb), _ = _chord_queries()
    a, b = (pmplan.plan(*q, bounds=(0, 10), lift=0.3) for q in (qa, qb))
    assert a.domain == b.domain
    assert _winding(a.path.waypoints[:, 6], qa[0][3]) == _winding(b.path.waypoints[:, 6],
                                                                   qb[0][3])
    ra, rb = (pmplan.refine(p, radius=0.05, obstacle_radius=0.05) for p in (a, b))
    assert ra.respects_radius and rb.respects_radius
    assert np.abs(ra.waypoints - rb.waypoints).max() <= 1e-6
    assert _winding(ra.path.waypoints[:, 6], qa[0][3]) == _winding(rb.path.waypoints[:, 6],
                                                                    qb[0][3])


@pytest.mark.parametrize("cuts", [1, 3])
def test_the_refinement_in_a_box_starts_from_the_plan_at_the_raw_breakpoints(monkeypatch, cuts):
    """The start of the refinement in a box (:func:`pmplan.running.box_start`): the plan at the
    raw planner's breakpoints, bit for bit (RAW_CUTS = 1), and with RAW_CUTS = k points of the
    plan at k - 1 more times in every raw piece; shared breakpoints that do not depend on the
    query, so a query refined alone is its row of the refined batch (bit for bit with RAW_CUTS
    = 1)."""
    from pmplan.planners.base import REGISTRY
    from pmplan.running import box_start

    monkeypatch.setattr(W, "RAW_CUTS", cuts)
    rng = np.random.default_rng(4)
    o, s, g = _inside_queries(rng, 12, 4, 4)
    batch = pmplan.plan_batch(o, s, g, bounds=(0, 10), lift=0.3)
    p = REGISTRY[batch.planner]
    raw_t = p.path_times(2)
    c = (batch.times.shape[1] - 1) // (raw_t.size - 1)
    assert c > 1 and (batch.times[:, ::c] == raw_t).all()  # (the plans cross some nodes)
    t, wp = box_start(p, batch.times, batch.waypoints, batch.dims)
    assert t.ndim == 1 and np.array_equal(t[::cuts], raw_t) and t.size == (raw_t.size - 1) * cuts + 1
    assert np.array_equal(wp[:, ::cuts], batch.waypoints[:, ::c])
    for q in range(12):
        assert np.abs(wp[q] - batch[q].path(t)).max() <= 1e-12 * 10
    refined = pmplan.refine(batch, radius=0.05, obstacle_radius=0.05)
    at = raw_positions(t.size, DEFAULT_WAYPOINTS, p.still_for(t))  # (still pieces: one piece)
    assert refined.times.ndim == 1 and refined.times.size == at[-1] + 1
    assert np.array_equal(refined.times[at], t)
    for q in (0, 5, 11):
        one = pmplan.refine(pmplan.plan(o[q], s[q], g[q], bounds=(0, 10), lift=0.3),
                            radius=0.05, obstacle_radius=0.05)
        if cuts == 1:  # (else points of the plan, whose breakpoints differ alone: to rounding)
            assert np.array_equal(one.waypoints, refined.waypoints[q])
            assert one.raw_clearance == refined.raw_clearance[q]
        else:
            assert np.abs(one.waypoints - refined.waypoints[q]).max() <= 1e-9


@pytest.mark.parametrize("cuts", [1, 2])
@pytest.mark.parametrize("r", [3, 4])
def test_a_sequence_in_a_box_passes_through_its_configurations(monkeypatch, cuts, r):
    """A sequential plan in the box, alone and in a batch (per-query breakpoints): the planner's
    fixed waypoints are found among the breakpoints of the exact image (every configuration at
    its time k / (r - 1)), the plan passes through every configuration exactly, and its
    refinement (with RAW_CUTS = cuts) keeps them."""
    from pmplan.planners.base import REGISTRY

    o = np.array([[2.0, 2.0], [8.0, 3.0], [5.0, 7.0]])
    configs = [np.array([[1.0, 1.0], [9.0, 9.0]]), np.array([[9.0, 1.0], [1.0, 9.0]]),
               np.array([[5.0, 2.0], [3.0, 5.0]]), np.array([[1.0, 8.0], [8.0, 8.5]])][:r]
    monkeypatch.setattr(W, "RAW_CUTS", cuts)
    plan = pmplan.plan_sequence(o, configs, bounds=(0, 10))
    p = REGISTRY[plan.planner]
    shift = np.array([0.0, 0.25])
    batch = pmplan.plan_sequence_batch(np.stack([o, o + shift]),
                                       [np.stack([c, c + shift]) for c in configs], bounds=(0, 10))
    for times, rows in ((plan.path.times, plan.path.waypoints[None]), (batch.times, batch.waypoints)):
        fixed = p.fixed_waypoints(times)
        assert fixed.size == r
        t = np.broadcast_to(times, rows.shape[:2])
        for k, kj in enumerate(fixed):
            assert (t[:, kj] == k / (r - 1)).all()
            for q in range(rows.shape[0]):
                assert np.array_equal(rows[q, kj, 3:], configs[k] + q * shift)
    for ref in (pmplan.refine(plan, radius=0.1, obstacle_radius=0.1),
                pmplan.refine(batch, radius=0.1, obstacle_radius=0.1)[0]):
        for k, c in enumerate(configs):
            j = int(np.searchsorted(ref.path.times, k / (r - 1)))
            assert ref.path.times[j] == k / (r - 1)
            assert np.array_equal(ref.path.waypoints[j, 3:], c)


def test_the_width_of_a_batch_in_a_box():
    """Every piece of every path gets the same number of new breakpoints: the most any piece
    needs (:func:`pmplan.workspace.crossing_width`), or a larger given ``width`` (the same
    motion); a smaller one is refused, in :func:`pmplan.workspace.path_into_box_linear` and,
    as a pmplan error, where a store fixed it first."""
    from pmplan.running import plan_arrays

    rng = np.random.default_rng(6)
    o, s, g = _inside_queries(rng, 10, 4, 4)
    box = BOX
    plane = pmplan.plan_batch(*(W.from_box_linear(x, box) for x in (o, s, g)))
    need = W.crossing_width(plane.times, plane.waypoints, box)
    tt, ww = W.path_into_box_linear(plane.times, plane.waypoints, box)
    assert need >= 1 and tt.shape[1] == (plane.times.size - 1) * (need + 1) + 1
    wide = W.path_into_box_linear(plane.times, plane.waypoints, box, width=need + 3)
    t = rng.uniform(0, 1, 200)
    for q in range(10):
        assert np.abs(PiecewiseLinearPath(wide[0][q], wide[1][q])(t)
                      - PiecewiseLinearPath(tt[q], ww[q])(t)).max() <= 1e-12 * 10
    with pytest.raises(ValueError, match="smaller than"):
        W.path_into_box_linear(plane.times, plane.waypoints, box, width=need - 1)
    with pytest.raises(pmplan.InputError, match="fixed for"):
        plan_arrays(o, [s, g], bounds=(0, 10), width=need - 1)
    assert plan_arrays(o, [s, g], bounds=(0, 10), width=need + 3).times.shape == wide[0].shape


# --- the map linear on cells (Mathematics §8, "The exact image of a path") -----------------------

def test_the_linear_map_sends_the_nodes_to_the_tails_values_exactly():
    """On a box whose band is a power of two the nodes ``b + mu (2^k - 1)`` go to ``hi - mu
    2^-k`` bit for bit (the values of the algebraic tail there), both ways, and the inner box
    is the identity bit for bit."""
    box = np.array([[0.0, -8.0], [8.0, 0.0]])  # mu = 1; x: the upper band, y: the lower
    k = np.arange(12.0)
    nodes = np.stack([7.0 + (2.0 ** k - 1.0), -7.0 - (2.0 ** k - 1.0)], axis=-1)
    values = np.stack([8.0 - 2.0 ** -k, -8.0 + 2.0 ** -k], axis=-1)
    assert (W.into_box_linear(nodes, box) == values).all()
    assert (W.into_box(nodes, box) == values).all()
    assert (W.from_box_linear(values, box) == nodes).all()
    inner = np.random.default_rng(0).uniform([1, -7], [7, -1], (100, 2))
    assert (W.into_box_linear(inner, box) == inner).all()
    assert (W.from_box_linear(inner, box) == inner).all()


@settings(max_examples=60, deadline=None)
@given(k=st.integers(2, 5), p=st.integers(1, 3), d=st.integers(2, 3), seed=st.integers(0, 999),
       far=st.integers(0, 6), batch=st.integers(1, 3))
def test_the_linear_image_is_the_mapped_path_at_every_time(k, p, d, seed, far, batch):
    """The map is increasing, into the box and inverted by its inverse (to rounding, at
    magnitudes up to 1e6 times the box); the polyline through the points where some point
    crosses a node, at the times it does, is the map of the path at every time (to rounding),
    keeps every breakpoint and puts the map of every waypoint there, and a batch padded to its
    longest path is the same motion as each path alone."""
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-5, 5, d)
    box = np.array([lo, lo + rng.uniform(0.5, 20, d)])
    side = (box[1] - lo).max()
    raw = lo + (box[1] - lo) * rng.uniform(-1, 2, (batch, k, p, d)) \
        * 10.0 ** rng.uniform(0, far, (batch, k, p, d))
    times = np.sort(np.concatenate([[0.0, 1.0], rng.uniform(0, 1, k - 2)]))
    tt, ww = W.path_into_box_linear(times, raw, box)
    assert (np.diff(tt, axis=1) > 0).all() and (ww >= box[0]).all() and (ww <= box[1]).all()
    t = rng.uniform(0, 1, 200)
    for q in range(batch):
        assert np.isin(times, tt[q]).all()
        at = np.searchsorted(tt[q], times)
        assert (ww[q, at] == W.into_box_linear(raw[q], box)).all()
        want = W.into_box_linear(PiecewiseLinearPath(times, raw[q])(t), box)
        got = PiecewiseLinearPath(tt[q], ww[q])(t)
        assert np.abs(got - want).max() <= 1e-9 * side
        alone = W.path_into_box_linear(times, raw[q:q + 1], box)
        assert np.abs(PiecewiseLinearPath(alone[0][0], alone[1][0])(t) - got).max() \
            <= 1e-12 * side
    z = np.sort(raw.reshape(-1, d), axis=0)
    y = W.into_box_linear(z, box)
    assert (np.diff(y, axis=0) >= 0).all()
    inner = (z > box[0]) & (z < box[1])
    assert np.abs(W.from_box_linear(y, box) - z)[inner].max(initial=0.0) <= 1e-9 * side


def test_the_linear_image_keeps_the_class_where_the_chords_change_it():
    """On queries of the scene family *room* (n = 4, seed 13) where the polyline through the
    mapped waypoints alone (the chords) passes some obstacle in another class than the
    conjugated motion (the raw path cut into 1024 pieces, then mapped), the exact image passes
    every obstacle in the class of the conjugated motion (``benchmarks/box_exact.py``)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import scenes
    from box_chords import windings

    box = BOX
    seen = 0
    for o, s, g in scenes.queries("room", 4, 24, 13):
        plan = pmplan.plan(*(W.from_box_linear(x, box) for x in (o, s, g)), lift=0.3)
        raw, m = plan.path.waypoints, len(o)
        ref = windings(W.into_box_linear(cut_along(raw, 1024, 0), box)[:, m:], o)
        chord = windings(W.into_box_linear(raw, box)[:, m:], o)
        exact = W.path_into_box_linear(plan.path.times, raw[None], box)[1][0]
        assert (windings(exact[:, m:], o) == ref).all()
        seen += bool((chord != ref).any())
    assert seen >= 2  # (the chords change some class on these queries: 4 of 24 when written)


@pytest.mark.parametrize("lo, hi", [(0.0, 1e-300), (-1e300, 1e300), (1e15, 1e15 + 1.0),
                                    (-3.0, 10.0)])
def test_the_linear_map_at_every_magnitude(lo, hi):
    """Increasing, finite and in the closed box from far below to far beyond it, at boxes of
    every magnitude and offset (computed in the box's unit coordinates); its inverse finite and
    increasing on the open box."""
    box = np.array([[lo], [hi]])
    w = hi - lo
    with np.errstate(over="ignore"):
        z = np.concatenate([lo + w * np.linspace(-3.0, 4.0, 5001),
                            [lo - w * 1e250, hi + w * 1e250, -1.7e308, 1.7e308]])
    z = np.sort(z[np.isfinite(z)])  # (points of a query are finite)
    y = W.into_box_linear(z[:, None], box)[:, 0]
    assert np.isfinite(y).all() and (np.diff(y) >= 0).all()
    assert (y >= lo).all() and (y <= hi).all()
    inside = y[(y > lo) & (y < hi)]
    back = W.from_box_linear(inside[:, None], box)[:, 0]
    assert np.isfinite(back).all() and (np.diff(back) >= 0).all()
