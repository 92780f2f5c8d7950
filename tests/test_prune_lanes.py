"""The pruned clearance of the SIMD path in the plane (issue 17 item 1) equals the unpruned one.

From ``PRUNE_LANES[0]`` to ``PRUNE_LANES[1]`` points in the plane, :func:`_certify_lanes` takes
the clearance from :func:`pmplan.kernels.obstacle_line._prune_plane`: every pair is tested on
float32 centres of its projections, and only the pairs that may reach the minimum are
evaluated, lane by lane. It must return *bitwise* the minimum of the brute-force pass (every
pair with a moving point, every piece) in every lane -- whatever the guess it starts from (the
column-class test's gap: exact, too small, zero, huge, NaN; a poor guess takes the second
pass) -- on random, exactly degenerate (integer), clustered and scaled waypoints, and on the
planner's own paths; and end to end ``plan_batch`` with numba equals the numpy reference.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import SHARING
from test_certificate_sweep import FAMILIES, _points  # (the same waypoint families)

import pmplan
from pmplan.certify import clearance as reference_clearance
from pmplan.configuration import coincident_pairs
from pmplan.kernels import obstacle_line as kernels_line

GUESSES = ("gap", "small", "zero", "huge", "nan", "random")
# the rows of T that _prune_plane reads and writes (as _plan_lanes lays them out)
BAD, NORM, THR2, MX, MN, GAP = 3, 4, 10, 11, 13, 16


def _stationary(w: np.ndarray, m: int) -> np.ndarray:
    """Waypoints (kk, p, 2) shaped as the planner's: obstacles fixed, and the pieces
    7k -> 7k + 1 and 7k + 6 -> 7k + 7 of every segment stationary (the SIMD path takes them as
    the distance at their start)."""
    w = w.copy()
    w[:, :m] = w[0, :m]
    for k in range((w.shape[0] - 1) // 7):
        w[7 * k + 1] = w[7 * k]
        w[7 * k + 6] = w[7 * k + 7]
    return w


def _unpruned(w: np.ndarray, m: int) -> float:
    """The minimum over every piece and every pair with a moving point (the loop of
    :func:`_clearance_exact`, which the brute-force pass equals on such waypoints)."""
    kk, p, d = w.shape
    flat = np.ascontiguousarray(w, dtype=float).reshape(1, -1)
    return kernels_line._clearance_exact(flat, 0, kk, p, m, d, -np.inf)[0]


def _guess(rng, mode: str, w: np.ndarray, m: int) -> tuple[float, float]:
    """(GAP, NORM) rows of one lane: the column-class test's smallest gap over |w| or a poor
    guess."""
    o1, o2 = w[0, 0], w[0, 1]
    vec = o2 - o1
    norm = float(np.sqrt(vec @ vec)) or 1.0
    cols = np.sort(np.concatenate([(w[0] - o1) @ vec, (w[-1] - o1) @ vec]))
    gap = float(np.diff(cols).min()) if cols.size > 1 else 0.0
    return {"gap": (gap, norm), "small": (gap * 1e-3, norm), "zero": (0.0, norm),
            "huge": (1e300, 1e-300), "nan": (np.nan, norm),
            "random": (float(rng.uniform(0, 2)), float(rng.uniform(0.5, 2)))}[mode]


def _prune(ws: np.ndarray, m: int, gaps, norms, estimate: bool, shared: int = 0
           ) -> np.ndarray:
    """_prune_plane on lanes of waypoints ``ws`` (L, kk, p, 2): every lane's minimum (its guess
    from the rows GAP, NORM, or with ``estimate`` from the waypoints, :func:`_guess_plane`;
    with ``shared`` the slide's test of the shared lanes too)."""
    lanes, kk, p, d = ws.shape
    wf = np.ascontiguousarray(ws, dtype=float).reshape(lanes, -1)
    s = np.ascontiguousarray(wf.T)
    t = np.zeros((17, lanes))
    amax = np.abs(wf).max(axis=1)
    t[MX] = amax
    with np.errstate(over="ignore"):
        t[THR2] = np.where((amax > 1e-130) & (amax < 1e130), (kernels_line.SURE * amax) ** 2,
                           np.inf)
    t[GAP] = gaps
    t[NORM] = norms
    r = (kk - 1) // 7 + 1
    row = kernels_line._prune_plane(s, t, wf, 0, r, m, p, p * d, kk, MX, np.int64(MN), BAD,
                                    THR2, GAP, NORM, estimate, shared)
    return t[row]


def _check_lanes(rng, ws: np.ndarray, m: int, modes, estimate: bool,
                 shared: int = 0) -> None:
    gaps, norms = zip(*(_guess(rng, mode, w, m) for w, mode in zip(ws, modes)))
    got = _prune(ws, m, np.array(gaps), np.array(norms), estimate, shared)
    for lane, w in enumerate(ws):
        amax = float(np.abs(w).max())
        if 1e-130 < amax < 1e130:  # (other lanes go to the scalar kernel)
            want = _unpruned(w, m)
            assert got[lane] == want, (lane, modes[lane], got[lane], want)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3, 5]),
       st.sampled_from([14, 16, 30, 62, 120]), st.sampled_from([2, 3]),
       st.sampled_from(FAMILIES), st.sampled_from([1, 5, 16]), st.booleans(),
       st.sampled_from([0, 2]))
def test_prune_equals_every_pair_on_arbitrary_waypoints(seed, m, n, r, family, lanes, estimate,
                                                        shared):
    """Waypoints that are no planner's path (the directions are then arbitrary: the bound must
    hold for any), every guess mode across the lanes, the estimate of the compact lanes, with
    and without the slide's test of the shared lanes."""
    rng = np.random.default_rng(seed)
    kk, p = 7 * (r - 1) + 1, m + n
    ws = np.stack([_stationary(_points(rng, family, (kk, p, 2)), m) for _ in range(lanes)])
    if family != "integer":  # and some exact coincidences of points and of projections
        for w in ws:
            t, i = rng.integers(0, kk), rng.integers(m, p)
            w[t, i] = w[rng.integers(0, kk), rng.integers(0, p)]
        ws = np.stack([_stationary(w, m) for w in ws])
    _check_lanes(rng, ws, m, [GUESSES[rng.integers(len(GUESSES))] for _ in range(lanes)],
                 estimate, shared)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3]), st.sampled_from([14, 16, 40, 100]),
       st.sampled_from(FAMILIES), st.sampled_from(GUESSES + ("estimate", "shared", "oneside")))
def test_prune_equals_every_pair_on_planned_paths(seed, m, n, family, mode):
    """Paths of the obstacle-line planners (the directions the pruning is made for): the
    paper's lanes with every guess, the compact lanes' direct lift with its estimate, the
    shared lanes, on two sides or one (robots of one lane at one height through the slide) with
    the slide's test."""
    rng = np.random.default_rng(seed)
    o, s, g = (_points(rng, family, (8, k, 2)) for k in (m, n, n))
    ok = ~(coincident_pairs(np.concatenate([o, s], 1)) | coincident_pairs(np.concatenate([o, g],
                                                                                        1)))
    ok &= ~coincident_pairs(o)
    if not ok.any():
        return
    try:
        planner = {"estimate": "obstacle_line_compact", "shared": "obstacle_line_shared",
                   "oneside": "obstacle_line_oneside"}.get(mode, "obstacle_line")
        wp = pmplan.plan_batch(o[ok], s[ok], g[ok], planner=planner).waypoints
    except pmplan.errors.PmplanError:
        return  # (a path whose certificate fails is not returned)
    _check_lanes(rng, wp, m, [mode if mode in GUESSES else "nan"] * len(wp),
                 mode in ("estimate", "shared", "oneside"), SHARING.get(planner, 0))


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([(2, 16, 2), (2, 14, 3), (2, 30, 2),
                                                   (2, 64, 2), (2, 100, 5), (2, 130, 2)]),
       st.sampled_from(["random", "clustered", "integer"]), st.sampled_from([2, 3]),
       st.sampled_from([None, "obstacle_line_shared", "obstacle_line_oneside"]))
def test_plan_batch_with_the_pruning_equals_the_reference(seed, dims, family, r, planner):
    """From ``PRUNE_LANES[0]`` points in the plane, plan_batch and plan_sequence_batch (the
    SIMD kernel's pruned pass, from ``PRUNE_LANES[1]`` its sweep lane by lane, the scalar
    kernel for the rest of the batch) equal the numpy reference bit for bit."""
    d, n, m = dims
    assert kernels_line.PRUNE_LANES[0] <= m + n
    rng = np.random.default_rng(seed)
    b = kernels_line.lanes(r, m, n, d) + 3
    o = _points(rng, family, (b, m, d))
    cs = [_points(rng, family, (b, n, d)) for _ in range(r)]
    ok = ~coincident_pairs(o)
    for c in cs:
        ok &= ~coincident_pairs(np.concatenate([o, c], 1))
    o, cs = o[ok], [c[ok] for c in cs]
    if len(o) == 0:
        return
    try:
        fast = pmplan.plan_sequence_batch(o, cs, backend="numba", planner=planner)
    except pmplan.errors.PmplanError as exc:
        try:
            pmplan.plan_sequence_batch(o, cs, backend="numpy", planner=planner)
        except pmplan.errors.PmplanError as ref:
            assert (type(exc), str(exc)) == (type(ref), str(ref))
            return
        raise
    ref = pmplan.plan_sequence_batch(o, cs, backend="numpy", planner=planner)
    assert np.array_equal(fast.waypoints, ref.waypoints)
    assert np.array_equal(fast.clearance, ref.clearance)
    assert np.array_equal(fast.clearance, reference_clearance(fast.waypoints, m))


@pytest.mark.parametrize(("planner", "bound"), [("obstacle_line", 12),
                                                ("obstacle_line_compact", 6),
                                                ("obstacle_line_shared", 6),
                                                ("obstacle_line_oneside", 6)])
def test_prune_prunes(planner, bound):
    """The pruning really prunes: on random (2, 64, 2) paths the lanes evaluate a few pairs
    each, not the 2,079 pairs with a moving point (counted through the Python version): the
    paper's lanes from the column-class test's gap, the compact lanes (the default) from the
    estimate of :func:`_guess_plane`, the shared lanes too (their robots of one lane, at one
    height through the slide, are passed by the slide's test along the line)."""
    rng = np.random.default_rng(5)
    n, m = 64, 2
    ws = pmplan.plan_batch(*(rng.normal(size=(8, k, 2)) for k in (m, n, n)),
                           planner=planner).waypoints
    gaps, norms = zip(*(_guess(rng, "gap", w, m) for w in ws))
    count = [0]
    fn = kernels_line._prune_pass.py_func
    names = fn.__globals__
    saved = {k: names[k] for k in ("_pair_lane", "_lane_thresholds", "_prune_pass")}

    def counted(*args):
        count[0] += 1
        return saved["_pair_lane"].py_func(*args)

    plane = kernels_line._prune_plane.py_func
    try:
        names.update({"_pair_lane": counted, "_lane_thresholds": saved["_lane_thresholds"].py_func,
                      "_prune_pass": fn})
        lanes = ws.shape[0]
        wf = np.ascontiguousarray(ws).reshape(lanes, -1)
        s = np.ascontiguousarray(wf.T)
        t = np.zeros((17, lanes))
        t[MX] = np.abs(wf).max(axis=1)
        t[THR2] = (kernels_line.SURE * t[MX]) ** 2
        t[GAP] = gaps
        t[NORM] = norms
        row = plane(s, t, wf, 0, 2, m, n + m, 2 * (n + m), 8, MX, MN, BAD, THR2, GAP, NORM,
                    planner != "obstacle_line", SHARING.get(planner, 0))
    finally:
        names.update(saved)
    for lane, w in enumerate(ws):
        assert t[row, lane] == _unpruned(w, m)
    # (every pair: 2,079 per lane; measured: 7.75 on the paper's lanes, 2.9 on the compact
    # lanes -- about 16 from the gap there, whose direct lift keeps the robots of the closest
    # columns apart, Mathematics §4.4, and the gap below the minimum)
    assert count[0] <= bound * lanes, count[0]


def test_compact_guess_is_the_minimum_from_above():
    """:func:`_guess_plane` on the default planner's paths (the direct lift, Mathematics §4.4):
    never below a lane's minimum (no second pass); within rounding of the float64 value it
    estimates, the least distance of the pairs that cross on the start side's lift piece, in
    every lane; and that value is the lane's minimum where the minimum lies on that piece."""
    rng = np.random.default_rng(11)
    n, m = 16, 2
    ws = pmplan.plan_batch(*(rng.normal(size=(64, k, 2)) for k in (m, n, n))).waypoints
    lanes, kk, p, d = ws.shape
    wf = np.ascontiguousarray(ws).reshape(lanes, -1)
    s = np.ascontiguousarray(wf.T)
    t = np.zeros((17, lanes))
    t[MX] = np.abs(wf).max(axis=1)
    dd = np.zeros((11, lanes))
    aux = np.empty(8)
    for lane in range(lanes):
        kernels_line._directions(wf[lane], p, m, 2, t[MX, lane], aux)
        dd[:8, lane] = aux
    kernels_line._guess_plane(s, dd, t, MX, 2, m, p, p * d)
    guess = dd[kernels_line._GUESS]
    want = np.array([_unpruned(w, m) for w in ws])
    assert np.all(guess >= want)
    # the float64 value: pieces 7k + 1 -> 7k + 2 (here k = 0), in the frame of u0
    u = dd[:2].T
    a = np.einsum("lpd,ld->lp", ws[:, 1], u)
    b0 = ws[:, 1, :, 1] * u[:, :1] - ws[:, 1, :, 0] * u[:, 1:]
    b1 = ws[:, 2, :, 1] * u[:, :1] - ws[:, 2, :, 0] * u[:, 1:]
    i, j = np.triu_indices(p, 1)
    keep = j >= m
    i, j = i[keep], j[keep]
    cross = (b0[:, j] - b0[:, i]) * (b1[:, j] - b1[:, i]) <= 0
    ref = np.where(cross, np.abs(a[:, j] - a[:, i]), np.inf).min(axis=1) / dd[kernels_line._WN0]
    assert np.all(np.isfinite(ref))
    # (its slack for the float32 rounding: 2**-20 times the largest |coordinate|)
    slack = 2.0**-19 * t[MX] / dd[kernels_line._WN0]
    assert np.all(np.abs(np.sqrt(guess) - ref) <= slack + 2.0**-19 * ref)
    near = guess <= (np.sqrt(want) * (1 + 2.0**-19) + 2.0**-19 * t[MX]) ** 2
    # (measured: the minimum lies on that piece in 23 of these 64 lanes, mostly on the goal
    # side's lift in the others)
    assert np.mean(near) >= 0.3
