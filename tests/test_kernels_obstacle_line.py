"""The fused numba kernel of the obstacle-line planner against its numpy reference.

``backend="numba"`` (:mod:`pmplan.kernels.obstacle_line`) must reproduce ``backend="numpy"``
(the reference code of :mod:`pmplan.predicates`, :mod:`pmplan.frame`,
:mod:`pmplan.planners.obstacle_line`, :mod:`pmplan.certify`) exactly. What is checked, and why
it can fail:

* waypoints, breakpoints, labels, stratum records and certified clearances are *equal* (``==``,
  no tolerance) for generic and exactly degenerate queries (hypothesis: d in {2, 3, 4},
  m in {2, 3, 5}, n in {1, 2, 4, 8}; sequential r in {3, 4}; the odd-d pole e == N) -- and the
  kernel really decided them itself (no flag: otherwise the comparison would be vacuous);
* each re-decision route is taken where it must be: an exact tie only fractions can see
  (``FALLBACK``), a clearance ~1e-11 of the scene (``SUSPECT``), overflow, d > MAX_D;
* the same queries fail their certificate, with the same indices;
* validation: every error of the fast single-query path has the reference path's type and
  message; the kernel's coincidence test agrees with ``coincident_pairs``;
* chunked planning equals unchunked planning;
* the SIMD path (:func:`pmplan.kernels.obstacle_line._plan_lanes`, generic queries 64 at a
  time) gives the scalar kernel's outputs bit for bit on batches that mix generic queries with
  every kind it must hand over (lattice ties, coincident points, NaN, the pole, tiny gaps, huge scales), it
  decides only top-stratum queries, and all of those in a random batch;
* the kernel's shortcuts are exact: the generic column test (all projections pairwise farther
  apart than the filter bound, no sort) against near-ties just above / below the bound, the
  one-pass NaN detection on waypoints, and the one-pass validation of
  :func:`pmplan.configuration.check_query` (:func:`pmplan.kernels.validation.valid_queries`),
  which must accept exactly the queries the reference checks accept, and leave the errors to them.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import configuration, running
from pmplan.configuration import coincident_pairs
from pmplan.errors import CertificationError, InputError, PmplanError
from pmplan.kernels import obstacle_line as kernels_line
from pmplan.kernels import validation as kernels_validation
from pmplan.planners.obstacle_line import OBSTACLE_LINE, path_times


def _stack(qs):
    return tuple(np.stack(a) for a in zip(*qs))


def _kernel_flags(obstacles, configs, lift=1.0):
    """Run the kernel alone on a batch; return its flags (B,)."""
    obstacles = np.ascontiguousarray(obstacles, dtype=float)
    configs = [np.ascontiguousarray(c, dtype=float) for c in configs]
    b, m, d = obstacles.shape
    n = configs[0].shape[1]
    r = len(configs)
    middle = np.stack(configs[1:-1]) if r > 2 else np.empty((0, b, n, d))
    wp = np.empty((b, 7 * (r - 1) + 1, m + n, d))
    flags = np.empty(b, np.uint8)
    kernels_line.plan_chunk(obstacles, configs[0], configs[-1], middle, float(lift), False, wp,
                 np.empty(b, np.int64), np.empty((b, r + 2), np.int64), np.empty(b), flags,
                 kernels_line.tables(r, m, n, d))
    return flags


def _outcome(fn, *args, **kwargs):
    """The PlanBatch, or the (type, message, indices) of the pmplan error raised."""
    try:
        return fn(*args, **kwargs)
    except PmplanError as exc:
        idx = getattr(exc, "indices", None)
        return type(exc), str(exc), None if idx is None else tuple(np.asarray(idx).tolist())


def assert_same_batch(a, b):
    if isinstance(a, tuple) or isinstance(b, tuple):
        assert a == b
        return
    assert a.waypoints.shape == b.waypoints.shape
    assert np.array_equal(a.waypoints, b.waypoints)
    assert np.array_equal(a.times, b.times)
    assert np.array_equal(a.domain, b.domain)
    assert np.array_equal(a.strata, b.strata)
    assert np.array_equal(a.clearance, b.clearance)
    assert (a.planner, a.dims) == (b.planner, b.dims)


@st.composite
def batches(draw, r: int = 2, ds=(2, 3, 4), ms=(2, 3, 5), ns=(1, 2, 4, 8)):
    """A batch of 1..5 queries with the same (d, m, n), generic or exactly degenerate, and
    r - 2 extra intermediate robot configurations (for r > 2) drawn like the goals."""
    d = draw(st.sampled_from(ds))
    m = draw(st.sampled_from(ms))
    n = draw(st.sampled_from(ns))
    degenerate = draw(st.booleans())
    qs = draw(st.lists(queries(d, m, n, degenerate=degenerate), min_size=1, max_size=5))
    obstacles, start, goal = _stack(qs)
    configs = [start]
    for _ in range(r - 2):
        mids = draw(st.lists(queries(d, m, n, degenerate=degenerate), min_size=len(qs),
                             max_size=len(qs)))
        # keep each query's obstacles: use the drawn robots only where they avoid them
        mid = np.stack([q[2] for q in mids])
        clash = coincident_pairs(np.concatenate([obstacles, mid], axis=1))
        mid[clash] = goal[clash]
        configs.append(mid)
    configs.append(goal)
    return degenerate, obstacles, configs


@settings(max_examples=50)
@given(batches(), st.sampled_from([1.0, 0.25, 3.0]))
def test_batch_equals_reference(case, lift):
    degenerate, obstacles, (start, goal) = case
    fast = _outcome(pmplan.plan_batch, obstacles, start, goal, planner="obstacle_line",
                    lift=lift, backend="numba")
    ref = _outcome(pmplan.plan_batch, obstacles, start, goal, planner="obstacle_line",
                   lift=lift, backend="numpy")
    assert_same_batch(fast, ref)
    flags = _kernel_flags(obstacles, [start, goal], lift)
    if not degenerate:  # generic queries are decided by the kernel alone
        assert not (flags & kernels_line.FALLBACK).any()


@settings(max_examples=25)
@given(batches(r=3) | batches(r=4, ns=(1, 2, 3)))
def test_sequence_equals_reference(case):
    _, obstacles, configs = case
    fast = _outcome(pmplan.plan_sequence_batch, obstacles, configs, backend="numba")
    ref = _outcome(pmplan.plan_sequence_batch, obstacles, configs, backend="numpy")
    assert_same_batch(fast, ref)
    if not isinstance(fast, tuple):
        r = len(configs)
        assert fast.waypoints.shape[1] == 7 * (r - 1) + 1
        for k in range(r):  # passes through C_k at tau = k / (r - 1), exactly
            assert fast.times[7 * k] == k / (r - 1)
            assert np.array_equal(fast.waypoints[:, 7 * k, obstacles.shape[1]:], configs[k])


@settings(max_examples=40)
@given(batches() | batches(r=3) | batches(r=4, ns=(1, 2, 3)),
       st.sampled_from(["obstacle_line_shared", "obstacle_line_oneside"]))
def test_shared_lanes_equal_reference(case, planner):
    """The shared lanes (Mathematics §4.4), on two sides or one: the kernels' chains (ranks by
    the exact classes and by index, or in the lanes by the projections) are the reference's,
    on random and exactly degenerate batches through 2 to 4 configurations, bit for bit."""
    _, obstacles, configs = case
    fast = _outcome(pmplan.plan_sequence_batch, obstacles, configs, backend="numba",
                    planner=planner)
    ref = _outcome(pmplan.plan_sequence_batch, obstacles, configs, backend="numpy",
                   planner=planner)
    assert_same_batch(fast, ref)


def test_integer_grid_queries_are_decided_by_the_kernel():
    """Exact degeneracies on small integers are settled by the error-free stage, in-kernel."""
    rng = np.random.default_rng(7)
    for d, m, n in [(2, 2, 4), (3, 3, 2), (4, 2, 3), (2, 5, 8)]:
        o = rng.integers(-3, 4, size=(400, m, d)).astype(float)
        s = rng.integers(-3, 4, size=(400, n, d)).astype(float)
        g = rng.integers(-3, 4, size=(400, n, d)).astype(float)
        keep = ~coincident_pairs(np.concatenate([o, s], 1)) & ~coincident_pairs(
            np.concatenate([o, g], 1))
        o, s, g = o[keep], s[keep], g[keep]
        flags = _kernel_flags(o, [s, g])
        assert not (flags & kernels_line.FALLBACK).any()
        labels, _ = OBSTACLE_LINE.plan(o, s, g, backend="numba").strata, None
        ref = OBSTACLE_LINE.plan(o, s, g, backend="numpy")
        assert np.array_equal(labels, ref.strata)
        # ties do occur: some configuration has fewer distinct columns than points
        assert (labels[:, 0] < m + n).any()


def test_odd_d_pole():
    """e == N exactly (Mathematics §4.1): nu = e_1, label one lower; both backends agree."""
    o = np.array([[[1.0, 2.0, 0.0], [1.0, 2.0, 3.0]]])
    s = np.array([[[0.0, 0.0, 1.0], [2.0, 2.0, 1.0]]])  # two robots share a column
    g = np.array([[[5.0, 1.0, -1.0], [0.0, 1.0, 7.0]]])
    for planner, lanes in (("obstacle_line", [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),  # i lambda nu
                           ("obstacle_line_compact", [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])):  # +-k
        fast = pmplan.plan_batch(o, s, g, backend="numba", planner=planner)
        assert_same_batch(fast, pmplan.plan_batch(o, s, g, backend="numpy", planner=planner))
        assert fast.strata[0].tolist() == [3, 4, 2, 1]
        assert fast.domain[0] == 3 + 4 - 2 + 2 - 1
        lifted = fast.waypoints[0, 3, 2:] - fast.waypoints[0, 2, 2:]
        assert np.array_equal(lifted, lanes)  # nu = e_1


def test_exact_tie_only_fractions_see_goes_to_the_reference():
    """(0.3, -0.1) . (0.1, 0.3) == 0 exactly, but its products are inexact: the error-free
    stage cannot decide, the kernel flags FALLBACK and the numpy reference decides."""
    o = np.array([[[0.0, 0.0], [0.1, 0.3]]])
    s = np.array([[[0.3, -0.1], [1.0, 1.0]]])
    g = np.array([[[1.0, -1.0], [2.0, 2.0]]])
    assert _kernel_flags(o, [s, g])[0] & kernels_line.FALLBACK
    fast = pmplan.plan_batch(o, s, g, backend="numba")
    assert_same_batch(fast, pmplan.plan_batch(o, s, g, backend="numpy"))
    assert fast.strata[0, 0] == 3  # x1 shares the column of o1: cp(C) = 3, not 4


@pytest.mark.parametrize("scale", [1.0, 2.0**-440, 2.0**450])
def test_tiny_clearance_is_decided_exactly(scale):
    """Columns 1e-10 apart in a scene of size ~5: the clearance (2.5e-11, robot 1 crossing the
    line from below to its lane above, next to o1) is below certify's float threshold, the
    kernel flags SUSPECT and certify.clearance decides it exactly -- also at scales where the
    kernel's squared-distance shortcut is off (|coordinates| < 1e-130 or > 1e130) and every
    small minimum is tested as certify tests it."""
    o = np.array([[[0.0, 0.0], [1.0, 0.0]]]) * scale
    s = np.array([[[0.0, -1.0], [1e-10, 5.0]]]) * scale
    g = np.array([[[0.5, -1.0], [2.0, 2.0]]]) * scale
    lift = 1.0 * scale
    assert _kernel_flags(o, [s, g], lift)[0] & kernels_line.SUSPECT
    fast = pmplan.plan_batch(o, s, g, lift=lift, backend="numba")
    assert_same_batch(fast, pmplan.plan_batch(o, s, g, lift=lift, backend="numpy"))
    assert 0 < fast.clearance[0] < 1e-10 * scale


def test_certificate_failures_agree():
    """Overflow (w = o2 - o1 is infinite) and sub-resolution eps fail in both backends, with
    the same batch indices; the good queries around them do not matter."""
    o = np.array([[[0.0, 0.0], [2.0, 0.0]], [[-1e308, 0.0], [1e308, 0.0]],
                  [[0.0, 0.0], [1.0, 2.0]], [[0.0, 0.0], [2.0, 0.0]]])
    s = np.array([[[0.0, 1.0], [1.0, 1.0]], [[0.0, 1.0], [1.0, 1.0]],
                  [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]], [[0.5, 1.0], [1.0, 1.0]]])
    g = np.array([[[1.0, -1.0], [3.0, 3.0]]] * 4)
    with np.errstate(all="ignore"):
        fast = _outcome(pmplan.plan_batch, o, s, g, backend="numba", planner="obstacle_line")
        ref = _outcome(pmplan.plan_batch, o, s, g, backend="numpy", planner="obstacle_line")
    assert fast[0] is CertificationError
    assert fast == ref
    assert fast[2] == (1, 2)


def test_large_d_uses_the_reference():
    rng = np.random.default_rng(3)
    d = kernels_line.MAX_D + 2
    o, s, g = rng.normal(size=(3, 2, d)), rng.normal(size=(3, 2, d)), rng.normal(size=(3, 2, d))
    assert_same_batch(pmplan.plan_batch(o, s, g, backend="numba"),
                      pmplan.plan_batch(o, s, g, backend="numpy"))


def test_chunks(monkeypatch):
    """Chunk boundaries change nothing (CHUNK = 3 on a batch of 10, r = 2 and r = 3)."""
    rng = np.random.default_rng(11)
    o, s, g, h = (rng.normal(size=(10, k, 2)) for k in (3, 2, 2, 2))
    whole = pmplan.plan_batch(o, s, g)
    whole_seq = pmplan.plan_sequence_batch(o, [s, h, g])
    monkeypatch.setattr(running, "CHUNK", 3)
    assert_same_batch(pmplan.plan_batch(o, s, g), whole)
    assert_same_batch(pmplan.plan_sequence_batch(o, [s, h, g]), whole_seq)
    assert_same_batch(pmplan.plan_batch(o, s, g, backend="numpy"), whole)


def test_chunk_size_gives_every_worker_work_and_changes_nothing(monkeypatch):
    """Large queries come in smaller chunks, and with workers > 1 a batch is cut into at least
    CHUNKS_PER_WORKER chunks per worker where the chunks stay above MIN_CHUNK: so (2, 64, 2) with
    B = 300 is planned in 5 chunks of 64 by 2 threads, bit for bit as in one chunk by one."""
    for b, row, w in [(10**6, 768, 1), (10**6, 768, 2), (300, 8 * 66 * 2 * 8, 2), (5, 100, 8),
                      (1000, 10**9, 1), (0, 768, 2)]:
        c = running.chunk_size(b, row, w)
        assert 1 <= c <= running.CHUNK and (c >= running.MIN_CHUNK or c == running.CHUNK)
        assert c * row <= max(running.CHUNK_BYTES, running.MIN_CHUNK * row)
        if w > 1 and b >= 2 * running.CHUNKS_PER_WORKER * w * running.MIN_CHUNK:
            assert -(-b // c) >= running.CHUNKS_PER_WORKER * w
    rng = np.random.default_rng(12)
    o, s, g = rng.normal(size=(300, 2, 2)), rng.normal(size=(300, 64, 2)), \
        rng.normal(size=(300, 64, 2))
    one = pmplan.plan_batch(o, s, g)
    starts = []
    each = running._each_chunk
    monkeypatch.setattr(running, "_each_chunk",
                        lambda chunk, st_, *a, **k: (starts.append(list(st_)), each(chunk, st_, *a, **k)))
    assert_same_batch(pmplan.plan_batch(o, s, g, workers=2), one)
    assert starts[-1] == list(range(0, 300, 64))
    monkeypatch.setattr(running, "CHUNK", 3)  # a smaller CHUNK still wins
    assert running.chunk_size(300, 768, 2) == 3


@settings(max_examples=40)
@given(st.sampled_from([(2, 2, 1), (2, 2, 4), (3, 3, 2), (4, 5, 1), (2, 3, 1)]).flatmap(
    lambda dmn: queries(*dmn, degenerate=True) | queries(*dmn)))
def test_single_plan_equals_reference(q):
    """The lean single-query path gives the reference Plan (for (2, 1, 3): planar_three)."""
    fast = pmplan.plan(*q)
    ref = pmplan.plan(*q, backend="numpy")
    assert (fast.domain, fast.stratum, fast.clearance, fast.planner, fast.dims) == (
        ref.domain, ref.stratum, ref.clearance, ref.planner, ref.dims)
    assert np.array_equal(fast.path.times, ref.path.times)
    assert np.array_equal(fast.path.waypoints, ref.path.waypoints)
    seq = pmplan.plan_sequence(q[0], [q[1], q[2]])
    assert np.array_equal(seq.path.waypoints,
                          pmplan.plan(*q, planner="obstacle_line_compact").waypoints)


O = [[0.0, 0.0], [2.0, 0.0]]
S = [[1.0, 1.0], [0.0, 1.0]]
G = [[1.0, -1.0], [3.0, 3.0]]


@pytest.mark.parametrize("args, kwargs", [
    ((O, S, G), {"planner": "nope"}),
    ((O, S, G), {"planner": "planar_three"}),
    ((O, S, G), {"lift": 0.0}),
    ((O, S, G), {"lift": np.nan}),
    ((O, S, G), {"lift": "x"}),
    ((O, S, G), {"backend": "cuda"}),
    ((O, [[1.0, 1.0], [0.0, np.nan]], G), {}),
    ((O, S, [[1.0, -1.0], [np.inf, 3.0]]), {}),
    (([[0.0, 0.0], [0.0, 0.0]], S, G), {}),
    ((O, [[1.0, 1.0], [1.0, 1.0]], G), {}),
    ((O, S, [[1.0, -1.0], [2.0, 0.0]]), {}),
    ((O, [[1.0, 1.0]], G), {}),
    ((O, [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], G), {}),
    (([0.0, 0.0], S, G), {}),
    ((O, [["a", 1.0], [0.0, 1.0]], G), {}),
    (([[0.0, 0.0]], S, G), {}),
    (([[0.0], [1.0]], [[2.0]], [[3.0]]), {}),
    (([[0.0, 0.0], [1.0, 2.0]], [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]], G),
     {"planner": "obstacle_line"}),  # (Mathematics §6.2: the paper's projection)
])
def test_fast_path_errors_are_the_reference_errors(args, kwargs):
    fast = _outcome(pmplan.plan, *args, **kwargs)
    ref = _outcome(pmplan.plan, *args, **{**kwargs, "backend": "numpy"}) \
        if kwargs.get("backend") is None else fast
    assert isinstance(fast, tuple) and issubclass(fast[0], PmplanError)
    if kwargs.get("backend") is None:
        assert fast == ref
    if fast[0] is not CertificationError:
        assert issubclass(fast[0], ValueError)


@settings(max_examples=30)
@given(st.integers(0, 2**32 - 1), st.integers(1, 4), st.integers(2, 4))
def test_first_coincident_agrees_with_coincident_pairs(seed, n, d):
    rng = np.random.default_rng(seed)
    o = rng.integers(-1, 2, size=(20, 2, d)).astype(float)
    x = rng.integers(-1, 2, size=(20, n, d)).astype(float)
    bad = coincident_pairs(np.concatenate([o, x], axis=1))
    want = int(np.flatnonzero(bad)[0]) if bad.any() else -1
    assert kernels_validation.first_coincident(o, x) == want


@pytest.mark.parametrize("r", [2, 3, 5])
def test_path_times(r):
    """The shared breakpoints: strictly increasing, C_k at k/(r-1), the paper's eight for r = 2."""
    t = path_times(r)
    assert t.shape == (7 * (r - 1) + 1,) and t[0] == 0.0 and t[-1] == 1.0
    assert (np.diff(t) > 0).all()
    assert [t[7 * k] for k in range(r)] == [k / (r - 1) for k in range(r)]
    if r == 2:
        want = [0, 1 / 6, 1 / 3, 4 / 9, 5 / 9, 2 / 3, 5 / 6, 1]
        assert np.allclose(t, want, rtol=0, atol=2.0**-52)


def test_non_finite_waypoints_are_flagged_wherever_they_are():
    """An (unvalidated) query with o1 == o2 has w = 0: eps(C) = gap / |w| is not finite and so
    are the middle waypoints, while the first and last rows are the (finite) input. The kernel
    must flag NONFINITE (the certificate fails), whatever the order of the rows."""
    o = np.array([[[-2.0, 0.0], [-2.0, 0.0]]])
    s = np.array([[[0.0, 2.0], [0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]])
    g = np.array([[[1.0, 1.0], [-1.0, 1.0], [1.0, 0.0], [1.0, -1.0]]])
    wp = np.empty((1, 8, 6, 2))
    flags = np.empty(1, np.uint8)
    clr = np.empty(1)
    with np.errstate(all="ignore"):
        kernels_line.plan_chunk(o, s, g, np.empty((0, 1, 4, 2)), 1.0, False, wp,
                                np.empty(1, np.int64), np.empty((1, 4), np.int64), clr, flags,
                                kernels_line.tables(2, 2, 4, 2))
    assert np.isfinite(wp[0, -1]).all() and not np.isfinite(wp).all()
    assert flags[0] & kernels_line.NONFINITE
    assert np.isnan(clr[0])


@pytest.mark.parametrize("k", [-3, -1, 0, 1, 3, 64])
def test_near_ties_around_the_filter_bound(k):
    """Robots whose columns differ by k ulps of a coordinate ~1 (k <= 0: tie or swapped
    order): near the filter bound the kernel takes its sorted path, far from it the generic
    path; labels, waypoints and clearances equal the reference's either way."""
    x = 1.0 + 2.0**-30
    o = np.array([[[0.0, 0.0], [1.0, 0.0]]] * 2)
    s = np.array([[[x, 1.0], [np.nextafter(x, 3.0 if k > 0 else -3.0) if k else x, -2.0]],
                  [[x, 1.0], [x + k * 2.0**-52, 3.0]]])
    g = np.array([[[-1.0, 1.0], [2.5, -1.5]]] * 2)
    fast = _outcome(pmplan.plan_batch, o, s, g, backend="numba")
    ref = _outcome(pmplan.plan_batch, o, s, g, backend="numpy")
    assert_same_batch(fast, ref)
    if not isinstance(fast, tuple):
        # equal columns (k = 0) leave fewer classes than points; distinct ones do not
        assert (fast.strata[:, 0] < 4).tolist() == [k == 0, k == 0]


def _reference_valid(o, s, g):
    fin = np.isfinite(o).all() and np.isfinite(s).all() and np.isfinite(g).all()
    return bool(fin and not coincident_pairs(np.concatenate([o, s], 1)).any()
                and not coincident_pairs(np.concatenate([o, g], 1)).any())


@settings(max_examples=40)
@given(st.integers(0, 2**32 - 1), st.integers(1, 5), st.integers(2, 4), st.integers(2, 4),
       st.sampled_from([0.0, np.nan, np.inf, 1e308]))
def test_valid_queries_agrees_with_the_reference_checks(seed, n, m, d, special):
    """valid_queries accepts exactly the batches with finite coordinates and no coincident
    points (small integer grids: coincidences and equal keys are frequent); 1e308 makes the
    keys overflow to inf, so equal keys of distinct points are compared exactly."""
    rng = np.random.default_rng(seed)
    o, s, g = (rng.integers(-2, 3, size=(6, k, d)).astype(float) for k in (m, n, n))
    if special == 1e308:  # coordinates up to 1e308: keys x0 + 0.57 x1 + ... overflow to inf
        o, s, g = o * 5e307, s * 5e307, g * 5e307
    elif special != 0.0:
        (o, s, g)[seed % 3][seed % 6, 0, seed % d] = special
    want = _reference_valid(o, s, g)
    assert kernels_validation.valid_queries(o, s, g) == want
    for b in range(6):  # and query by query
        one = (o[b:b + 1], s[b:b + 1], g[b:b + 1])
        assert kernels_validation.valid_queries(*one) == _reference_valid(*one)


@settings(max_examples=30)
@given(st.integers(0, 2**32 - 1), st.booleans(), st.sampled_from(["ok", "nan", "shape", "list"]))
def test_check_query_fast_path_is_the_reference(seed, batched, kind):
    """check_query with its one-pass fast path returns what the reference checks return, and
    raises the same error (type and message) where they raise."""
    rng = np.random.default_rng(seed)
    shape = (3,) if batched else ()
    o = rng.integers(-2, 3, size=shape + (2, 2)).astype(float)
    s = rng.integers(-2, 3, size=shape + (2, 2)).astype(float)
    g = rng.integers(-2, 3, size=shape + (2, 2)).astype(float)
    if kind == "nan":
        s[..., 0, 1] = np.nan
    elif kind == "shape":
        g = g[..., :1, :]
    elif kind == "list":
        o, s, g = o.tolist(), s.tolist(), g.tolist()

    def outcome(fast):
        saved = configuration._valid_fast
        if not fast:
            configuration._valid_fast = lambda *a: None
        try:
            return configuration.check_query(o, s, g, batched=batched)
        except PmplanError as exc:
            return type(exc), str(exc)
        finally:
            configuration._valid_fast = saved

    got, want = outcome(True), outcome(False)
    if isinstance(want, tuple) and isinstance(want[0], type):
        assert got == want
    else:
        assert all(np.array_equal(a, b) and a.shape == b.shape for a, b in zip(got, want))


# --- the SIMD path: _plan_lanes (generic queries, L at a time) against the scalar _plan -------


def _mixed_batch(rng, b, d, m, n, r, special):
    """A batch of b queries through r configurations: mostly generic normal queries, with
    ``special`` queries at random positions replaced by one that the lanes must hand to the
    scalar kernel (exact lattice ties, coincident points, NaN, the odd-d pole, a tiny robot
    gap, a huge scale, finite obstacles whose difference w overflows: e is NaN)."""
    o = rng.normal(size=(b, m, d))
    cs = [rng.normal(size=(b, n, d)) for _ in range(r)]
    kinds = ["lattice", "coincident", "nan", "pole", "tiny", "huge", "zero_w", "overflow_w"]
    for i in rng.choice(b, size=min(special, b), replace=False):
        kind = kinds[rng.integers(len(kinds))]
        if kind == "lattice":
            o[i] = rng.integers(-2, 3, size=(m, d))
            for c in cs:
                c[i] = rng.integers(-2, 3, size=(n, d))
        elif kind == "coincident":
            cs[rng.integers(r)][i, 0] = o[i, rng.integers(m)]
        elif kind == "nan":
            cs[rng.integers(r)][i, 0, 0] = np.nan
        elif kind == "pole":
            o[i, 1] = o[i, 0]
            o[i, 1, d - 1] += 1.5
        elif kind == "tiny" and n > 1:
            cs[0][i, 1] = cs[0][i, 0] + 1e-12
        elif kind == "huge":
            o[i] *= 1e200
            for c in cs:
                c[i] *= 1e200
        elif kind == "overflow_w":
            o[i, 0, 0] = -1.5e308
            o[i, 1, 0] = 1.5e308
        elif kind == "zero_w":
            o[i, 1] = o[i, 0]
    return o, cs


def _run_chunk(o, cs, lift, scalar_only, compact=False, shared=0):
    b, m, d = o.shape
    n, r = cs[0].shape[1], len(cs)
    middle = np.stack(cs[1:-1]) if r > 2 else np.empty((0, b, n, d))
    kk = 7 * (r - 1) + 1
    out = (np.full((b, kk, m + n, d), 7.0), np.full(b, -1, np.int64),
           np.full((b, r + 2), -1, np.int64), np.full(b, -1.0), np.full(b, 99, np.uint8))
    tab = kernels_line.tables(r, m, n, d)
    with np.errstate(all="ignore"):
        if scalar_only:
            kernels_line.plan_queries(o, cs[0], cs[-1], middle, lift, True, *out, tab,
                                      np.arange(b), b, compact, shared)
        else:
            kernels_line.plan_chunk(o, cs[0], cs[-1], middle, lift, True, *out, tab, compact,
                                    shared)
    return out


@settings(max_examples=30)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3, 4, 5]), st.sampled_from([2, 3, 5]),
       st.sampled_from([1, 2, 4, 9]), st.sampled_from([2, 2, 3]), st.integers(0, 40),
       st.sampled_from([1.0, 0.25]), st.sampled_from([(False, 0), (True, 0), (True, 2), (True, 1)]))
def test_lanes_equal_the_scalar_kernel(seed, d, m, n, r, special, lift, sections):
    """The SIMD path decides the generic queries of a chunk and hands every other one to the
    scalar kernel: the outputs (waypoints, labels, strata, clearances, flags -- also of invalid
    queries, validated) are identical to the scalar kernel's on every query, the lanes really
    decide the generic ones, and they never decide a query that is not generic."""
    rng = np.random.default_rng(seed)
    b = int(rng.integers(kernels_line.LANES_MIN, 3 * kernels_line.lanes(r, m, n, d) + 7))
    compact, shared = sections  # the paper's lanes, the compact ones, the shared ones (2 sides, 1)
    o, cs = _mixed_batch(rng, b, d, m, n, r, special)
    lanes = _run_chunk(o, cs, lift, scalar_only=False, compact=compact, shared=shared)
    scalar = _run_chunk(o, cs, lift, scalar_only=True, compact=compact, shared=shared)
    flags = scalar[4]
    assert np.array_equal(lanes[4], flags)
    for a, z in zip(lanes[1:4], scalar[1:4]):
        assert np.array_equal(a, z, equal_nan=True)
    # (the waypoints of a query flagged INVALID or FALLBACK are left unspecified: the caller
    # raises, or recomputes the query with the numpy reference)
    kept = (flags & (kernels_line.INVALID | kernels_line.FALLBACK)) == 0
    assert np.array_equal(lanes[0][kept], scalar[0][kept], equal_nan=True)
    # which queries did the lanes decide?
    middle = np.stack(cs[1:-1]) if r > 2 else np.empty((0, b, n, d))
    todo = np.empty(b, np.int64)
    out = [np.empty_like(x) for x in lanes]
    with np.errstate(all="ignore"):
        nt = kernels_line._plan_lanes(o, cs[0], cs[-1], middle, lift, *out, todo,
                                      kernels_line.lanes(r, m, n, d), compact, shared)
    decided = np.ones(b, bool)
    decided[todo[:nt]] = False
    strata = scalar[2]
    generic = (strata[:, :r] == m + n).all(axis=1) & (strata[:, r] == m) & (flags == 0)
    if d % 2:
        generic &= strata[:, r + 1] == 0
    assert not (decided & ~generic).any()  # the lanes only decide top-stratum queries...
    full = (b // kernels_line.lanes(r, m, n, d)) * kernels_line.lanes(r, m, n, d)
    if special == 0:  # ...and decide all of those in full blocks of a random batch
        assert decided[:full].all()



@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([(2, 4, 2), (2, 2, 3), (3, 3, 2)]),
       st.sampled_from([2, 3]))
def test_closest_pair_at_a_configuration(seed, dims, r):
    """Generic queries whose closest pair sits in a configuration C_k (two points 1e-4..1e-2
    apart, robot-robot or robot-obstacle): the clearance is then the distance at C_k, which
    the SIMD path takes from the configurations themselves; numba equals the numpy reference."""
    d, n, m = dims
    rng = np.random.default_rng(seed)
    b = 3 * kernels_line.lanes(r, m, n, d) + 3
    o = rng.normal(size=(b, m, d))
    cs = [rng.normal(size=(b, n, d)) for _ in range(r)]
    k = rng.integers(0, r, size=b)  # the configuration with the close pair
    near = rng.integers(0, m + n - 1, size=b)  # the point the last robot comes close to
    gap = 10.0 ** rng.uniform(-4, -2, size=b)
    u = rng.normal(size=(b, d))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    for i in range(b):
        c = cs[k[i]]
        pts = np.concatenate([o[i], c[i]])
        c[i, -1] = pts[near[i]] + gap[i] * u[i]
    if r == 2:
        fast = pmplan.plan_batch(o, cs[0], cs[1], backend="numba")
        ref = pmplan.plan_batch(o, cs[0], cs[1], backend="numpy")
    else:
        fast = pmplan.plan_sequence_batch(o, cs, backend="numba")
        ref = pmplan.plan_sequence_batch(o, cs, backend="numpy")
    assert_same_batch(fast, ref)
    assert (fast.clearance < 1.01e-2).all()  # the close pair decides the clearance


@pytest.mark.parametrize("planner, dims", [("obstacle_line", (2, 3, 2)),
                                           ("obstacle_line", (3, 2, 4)),
                                           ("planar_three", (2, 1, 3))])
def test_workers_change_nothing(monkeypatch, planner, dims):
    """Threads plan the chunks of a batch in parallel: the result is the one-thread result, and
    a failing certificate is reported with the same indices (also from a later chunk)."""
    d, n, m = dims
    rng = np.random.default_rng(5)
    o, s, g = (rng.normal(size=(300, k, d)) for k in (m, n, n))
    monkeypatch.setattr(running, "CHUNK", 64)
    one = pmplan.plan_batch(o, s, g, planner=planner)
    for workers in (2, 3, -1):
        assert_same_batch(pmplan.plan_batch(o, s, g, planner=planner, workers=workers), one)
    if planner == "obstacle_line":
        h = rng.normal(size=s.shape)
        seq = pmplan.plan_sequence_batch(o, [s, h, g])
        assert_same_batch(pmplan.plan_sequence_batch(o, [s, h, g], workers=2), seq)
    if planner == "obstacle_line" and dims == (2, 3, 2):
        # the precision case of Mathematics §6.2 (see test_configuration) in chunks 2 and 4
        o[[150, 270]] = [[0.0, 0.0], [1.0, 2.0]]
        s[[150, 270], :2] = [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]]
        g[[150, 270], :2] = [[5.0, 5.0], [6.0, -7.0]]
        s[[150, 270], 2] = g[[150, 270], 2] = [-4.0, 7.0]
        single = _outcome(pmplan.plan_batch, o, s, g, planner=planner)
        # (the error names the failing queries of the first chunk that has any)
        assert single[0] is CertificationError and single[2] == (150,)
        assert _outcome(pmplan.plan_batch, o, s, g, planner=planner, workers=2) == single


@pytest.mark.parametrize("workers", [0, -2, 1.5, True, "2", None])
def test_workers_must_be_a_thread_count(workers):
    o, s, g = np.zeros((1, 2, 2)), np.ones((1, 1, 2)), np.ones((1, 1, 2))
    o[0, 1] = 1.0
    with pytest.raises(InputError, match="workers"):
        pmplan.plan_batch(o, s, g, workers=workers)


def test_one_specialisation():
    """Read-only, Fortran-ordered, strided, float32 and list inputs reuse the one compiled
    kernel (a new array type would make numba compile every kernel again, for seconds)."""
    rng = np.random.default_rng(3)
    o, s, g = (rng.normal(size=(40, k, 2)) for k in (2, 3, 3))
    frozen = [a.copy() for a in (o, s, g)]
    for a in frozen:
        a.flags.writeable = False
    want = pmplan.plan_batch(o, s, g)
    assert_same_batch(pmplan.plan_batch(*frozen), want)
    assert_same_batch(pmplan.plan_sequence_batch(frozen[0], [frozen[1], frozen[2]]), want)
    assert_same_batch(pmplan.plan_batch(np.asfortranarray(o), s[:, ::-1][:, ::-1], g.tolist()),
                      want)
    pmplan.plan_batch(o.astype(np.float32), s, g)  # (other values: planned, not compared)
    for kernel in (kernels_line.plan_queries, kernels_validation.valid_queries, kernels_line._plan_lanes):
        assert len(kernel.signatures) == 1, kernel
    # compiled with _plan_lanes only on a cold cache (else loaded with it): never twice
    assert len(kernels_line._pair_plane.signatures) <= 1


@pytest.mark.parametrize("bad", ["nan", "inf", "coincident_start", "coincident_goal",
                                 "obstacles_equal"])
@pytest.mark.parametrize("where", [3, 150, 299])
def test_validation_in_the_kernel_raises_the_reference_error(monkeypatch, bad, where):
    """plan_batch lets the kernel validate the queries in its own pass: an invalid query
    anywhere (any chunk, in the SIMD blocks or the tail) raises exactly the error of the
    reference checks -- also when an earlier chunk holds a query whose certificate fails."""
    rng = np.random.default_rng(17)
    o, s, g = (rng.normal(size=(300, k, 2)) for k in (2, 3, 3))
    if bad == "nan":
        s[where, 1, 0] = np.nan
    elif bad == "inf":
        g[where, 2, 1] = -np.inf
    elif bad == "coincident_start":
        s[where, 2] = o[where, 1]
    elif bad == "coincident_goal":
        g[where, 0] = g[where, 2]
    else:
        o[where, 1] = o[where, 0]
    want = _outcome(configuration.check_query, o, s, g, batched=True)
    assert isinstance(want, tuple) and issubclass(want[0], PmplanError)
    monkeypatch.setattr(running, "CHUNK", 100)
    assert _outcome(pmplan.plan_batch, o, s, g) == want
    assert _outcome(pmplan.plan_batch, o, s, g, workers=2) == want
    # the precision case of Mathematics §6.2 (a failing certificate) in the first chunk changes nothing
    o[1] = [[0.0, 0.0], [1.0, 2.0]]
    s[1, :2] = [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]]
    g[1, :2] = [[5.0, 5.0], [6.0, -7.0]]
    s[1, 2] = g[1, 2] = [-4.0, 7.0]
    assert _outcome(pmplan.plan_batch, o, s, g, planner="obstacle_line") == want


def test_plan_batch_validates_in_one_pass(monkeypatch):
    """For the obstacle-line and the planar kernels the separate validation pass is skipped
    (the kernel validates); for the numpy backend it runs first."""
    calls = []
    real = kernels_validation.valid_queries
    monkeypatch.setattr(kernels_validation, "valid_queries", lambda *a: calls.append(1) or real(*a))
    rng = np.random.default_rng(2)
    o, s, g = (rng.normal(size=(50, k, 2)) for k in (2, 3, 3))
    pmplan.plan_batch(o, s, g)
    assert calls == []
    pmplan.plan_batch(o, s, g, backend="numpy")
    assert calls == [1]
    o3, s1, g1 = (rng.normal(size=(50, k, 2)) for k in (3, 1, 1))
    pmplan.plan_batch(o3, s1, g1)
    assert calls == [1]


def test_large_batch_equals_reference():
    """A batch large enough for several SIMD blocks, generic and exactly degenerate queries
    mixed, through the public API: numba equals the numpy reference."""
    rng = np.random.default_rng(7)
    for d, n, m in [(2, 4, 2), (3, 2, 3), (4, 3, 2)]:
        b = 2 * kernels_line.lanes(2, m, n, d) + 5
        o, (s, g) = _mixed_batch(rng, b, d, m, n, 2, 0)
        lat = rng.choice(b, size=b // 4, replace=False)
        for a in (o, s, g):
            a[lat] = rng.integers(-2, 3, size=a[lat].shape)
        ok = ~(coincident_pairs(np.concatenate([o, s], 1))
               | coincident_pairs(np.concatenate([o, g], 1)))
        o, s, g = o[ok], s[ok], g[ok]
        fast = pmplan.plan_batch(o, s, g, backend="numba")
        assert_same_batch(fast, pmplan.plan_batch(o, s, g, backend="numpy"))
