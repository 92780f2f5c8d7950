"""The pruned clearance of the obstacle-line kernels (issue 17 item 1) equals the unpruned one.

:func:`pmplan.kernels.obstacle_line._sweep_min` skips the pairs whose gap along a direction
proves them farther than the minimum found so far; it must return *bitwise* the minimum over
every piece and pair of the float squared distance, and, with a cap, decide the small minima
exactly as the unpruned loop :func:`~pmplan.kernels.obstacle_line._clearance_exact`. Checked
(hypothesis) on paths of the planner and on arbitrary waypoints -- random, exactly degenerate
(integer coordinates: ties, collinear points, equal columns, equal keys), clustered (many
near pairs) and scaled far from 1 -- for d = 2, 3, 4, 7 and up to 256 robots; and end to end:
``plan_batch`` with numba (from ``SWEEP_MIN`` points on the sweep, in the SIMD kernel lane by
lane) equals the numpy reference (:func:`pmplan.certify.clearance`).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan import certify
from pmplan.certify import clearance as reference_clearance
from pmplan.configuration import coincident_pairs
from pmplan.kernels import obstacle_line as kernels_line

FAMILIES = ("random", "integer", "clustered", "scaled")


def _points(rng, family: str, shape) -> np.ndarray:
    if family == "integer":  # exact ties everywhere: equal columns, collinear triples
        return rng.integers(-3, 4, size=shape).astype(float)
    if family == "clustered":  # many near pairs (and some exactly equal coordinates)
        centres = rng.normal(size=(3,) + shape[-1:])
        pts = centres[rng.integers(0, 3, size=shape[:-1])]
        return pts + rng.normal(size=shape) * 10.0 ** rng.integers(-12, -3)
    pts = rng.normal(size=shape)
    return pts * 10.0 ** rng.integers(-90, 90) if family == "scaled" else pts


def _sweep(w, kk, p, m, d, cap):
    amax = float(np.abs(w).max())
    nlo, naux = kernels_line._sweep_sizes(p, d)
    return kernels_line._sweep_min(w, kk, p, m, d, amax, np.empty(nlo), np.empty(nlo),
                                   np.empty(4 * p + 1, np.int64), np.empty(naux), cap)


def _unpruned(w, kk, p, m, d, thr2):
    return kernels_line._clearance_exact(w.reshape(1, -1), 0, kk, p, m, d, thr2)


def _check(w, kk, p, m, d):
    """The sweep equals the loop over every pair: the minimum, and with a cap (at the
    minimum, above it, the kernels' threshold) the suspect decision too."""
    w = np.ascontiguousarray(w, dtype=float).reshape(-1)
    amax = float(np.abs(w).max())
    if not 1e-130 < amax < 1e130:
        return
    full, _ = _unpruned(w, kk, p, m, d, -np.inf)
    best, suspect = _sweep(w, kk, p, m, d, -np.inf)
    assert best == full and not suspect
    for cap in (full, 4.0 * full + 1e-300, (kernels_line.SURE * amax) ** 2):
        assert _sweep(w, kk, p, m, d, cap) == _unpruned(w, kk, p, m, d, cap)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3, 4, 7]), st.sampled_from([2, 3, 5]),
       st.sampled_from([1, 3, 22, 40, 100, 256]), st.sampled_from([2, 3]),
       st.sampled_from(FAMILIES))
def test_sweep_equals_every_pair_on_arbitrary_waypoints(seed, d, m, n, r, family):
    """Waypoints that are no planner's path (the sweep's directions are then arbitrary: its
    bound must hold for any)."""
    rng = np.random.default_rng(seed)
    kk = 7 * (r - 1) + 1
    p = m + n
    w = _points(rng, family, (kk, p, d))
    w[:, :m] = w[0, :m]  # obstacles fixed
    if family != "integer":  # and some exact coincidences of points and of keys
        w[rng.integers(0, kk), rng.integers(m, p)] = w[rng.integers(0, kk), rng.integers(0, p)]
    _check(w, kk, p, m, d)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3, 4, 7]), st.sampled_from([2, 3]),
       st.sampled_from([1, 8, 30, 64, 256]), st.sampled_from(FAMILIES))
def test_sweep_equals_every_pair_on_planned_paths(seed, d, m, n, family):
    """Paths of the obstacle-line planner (the directions the sweep is made for), from
    random, exactly degenerate integer, clustered and scaled queries."""
    rng = np.random.default_rng(seed)
    o = _points(rng, family, (1, m, d))
    s = _points(rng, family, (1, n, d))
    g = _points(rng, family, (1, n, d))
    if family == "integer":  # distinct integer points of a grid: ties in every direction
        dd = min(d, 3)
        side = int(np.ceil((m + 2 * n) ** (1 / dd))) + 1
        axes = np.meshgrid(*[np.arange(side) - side // 2] * dd)
        grid = np.stack(axes, -1).reshape(-1, dd)
        grid = np.concatenate([grid, np.zeros((len(grid), d - dd))], 1)
        pick = grid[rng.permutation(len(grid))[: m + 2 * n]]
        o, s, g = pick[None, :m], pick[None, m:m + n], pick[None, m + n:]
    if coincident_pairs(o).any():
        return
    try:
        wp = pmplan.plan_batch(o, s, g).waypoints[0]
    except pmplan.errors.PmplanError:
        return  # (a path whose certificate fails is not returned)
    _check(wp, wp.shape[0], m + n, m, d)


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([(2, 40, 2), (2, 64, 3), (3, 40, 2),
                                                   (4, 25, 2), (7, 24, 2)]),
       st.sampled_from(["random", "clustered", "integer"]))
def test_plan_batch_with_the_sweep_equals_the_reference(seed, dims, family):
    """From ``SWEEP_MIN`` points on, plan_batch (the SIMD kernel's sweep lane by lane, the
    scalar kernel's for the rest of the batch) equals the numpy reference bit for bit."""
    d, n, m = dims
    assert kernels_line._sweeps(m + n, d)
    rng = np.random.default_rng(seed)
    b = kernels_line.lanes(2, m, n, d) + 3
    o, s, g = (_points(rng, family, (b, k, d)) for k in (m, n, n))
    ok = ~(coincident_pairs(np.concatenate([o, s], 1)) | coincident_pairs(np.concatenate([o, g],
                                                                                        1)))
    if family == "integer":
        ok &= ~coincident_pairs(o)
    o, s, g = o[ok], s[ok], g[ok]
    if len(o) == 0:
        return
    try:
        fast = pmplan.plan_batch(o, s, g, backend="numba")
    except pmplan.errors.PmplanError as exc:
        try:
            pmplan.plan_batch(o, s, g, backend="numpy")
        except pmplan.errors.PmplanError as ref:
            assert (type(exc), str(exc)) == (type(ref), str(ref))
            return
        raise
    ref = pmplan.plan_batch(o, s, g, backend="numpy")
    assert np.array_equal(fast.waypoints, ref.waypoints)
    assert np.array_equal(fast.clearance, ref.clearance)
    assert np.array_equal(fast.clearance, reference_clearance(fast.waypoints, m))


@pytest.mark.parametrize(("d", "n", "factor"), [(2, 256, 2), (3, 64, 2), (4, 30, 4)])
def test_sweep_prunes(d, n, factor):
    """The sweep really prunes: on a random path it computes far fewer pieces than the 7
    of every pair (2, 256, 2: 7 * 33,000), counted through the Python version of the sweep. In
    space the compact lanes keep the robots' offsets (Mathematics §4.4), so the closest pairs
    are not those of close columns: the direction of the offsets prunes there (without it
    (3, 64, 2) computes 187-574 pieces, (4, 30, 2) 157-616 on seeds 4-8; with it 4-22 and
    7-163)."""
    rng = np.random.default_rng(4)
    m = 2
    p = n + m
    wp = pmplan.plan_batch(*(rng.normal(size=(1, k, d)) for k in (m, n, n))).waypoints[0]
    w = np.ascontiguousarray(wp).reshape(-1)
    count = [0]
    sweep = kernels_line._sweep_min.py_func
    names = sweep.__globals__
    saved = {k: names[k] for k in ("_piece_dist2", "_directions", "_sort_by", "_bucket_sort")}

    def counted(*args):
        count[0] += 1
        return saved["_piece_dist2"].py_func(*args)

    nlo, naux = kernels_line._sweep_sizes(p, d)
    try:
        names.update({"_piece_dist2": counted, "_directions": saved["_directions"].py_func,
                      "_sort_by": saved["_sort_by"].py_func,
                      "_bucket_sort": saved["_bucket_sort"].py_func})
        best, _ = sweep(w, 8, p, m, d, float(np.abs(w).max()), np.empty(nlo), np.empty(nlo),
                        np.empty(4 * p + 1, np.int64), np.empty(naux), -np.inf)
    finally:
        names.update(saved)
    assert best == _unpruned(w, 8, p, m, d, -np.inf)[0]
    assert count[0] < factor * p


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3, 4, 7]), st.sampled_from([2, 3]),
       st.sampled_from([62, 100, 256]), st.sampled_from(FAMILIES + ("planned",)))
def test_reference_sweep_equals_every_pair(seed, d, m, n, family):
    """The numpy reference :func:`pmplan.certify.clearance` from ``_SWEEP_MIN`` points on
    evaluates only the pairs its sweep cannot exclude: the same clearances as every pair, on
    planned paths and on arbitrary (random, integer, clustered, scaled) waypoints."""
    rng = np.random.default_rng(seed)
    if family == "planned":
        o, s, g = (rng.normal(size=(2, k, d)) for k in (m, n, n))
        w = pmplan.plan_batch(o, s, g).waypoints
    else:
        w = _points(rng, family, (2, 8, m + n, d))
        w[:, :, :m] = w[:, :1, :m]
        w[1, 3] = np.nan if seed % 5 == 0 else w[1, 3]  # (a row the sweep leaves to the loop)
    assert m + n >= certify._SWEEP_MIN
    assert np.array_equal(certify.clearance(w, m), certify.clearance(w, m, sweep=False),
                          equal_nan=True)


@pytest.mark.parametrize("d", [3, 4, 7])
def test_the_direction_of_the_offsets_is_taken_only_from_offsets(d):
    """The sweep prunes along the robots' offsets only where the compact lanes keep them: on
    paths of the paper's projection (every robot on the obstacle line at waypoint 2, up to
    rounding) it finds none, so it spends nothing on projections that prune nothing (the
    offset's norm taken as a difference of squares found one in the rounding of 167 of 200
    such (7, 24, 2) paths)."""
    rng = np.random.default_rng(d)
    n, m = 24, 2
    p = n + m
    o, s, g = (rng.normal(size=(20, k, d)) for k in (m, n, n))
    aux = np.empty(kernels_line._sweep_sizes(p, d)[1])
    for planner, expected in (("obstacle_line", False), ("obstacle_line_compact", True)):
        wp = pmplan.plan_batch(o, s, g, planner=planner).waypoints
        for w in np.ascontiguousarray(wp).reshape(len(wp), -1):
            amax = float(np.abs(w).max())
            kernels_line._directions(w, p, m, d, amax, aux)
            assert kernels_line._offset_direction(w, p, m, d, amax, aux) == expected
