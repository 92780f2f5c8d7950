"""The certificate is complete and cannot be fooled (issue 12, item 1).

Every path an entry point returns has finite breakpoints from exactly 0 to exactly 1 that never
decrease, finite waypoints beginning exactly at the start and ending exactly at the goal
(through every intermediate configuration of a sequence), fixed obstacles and a positive
clearance (:data:`pmplan.certify.CLAUSES`). What is tested:

* :func:`pmplan.certify.certificate` names the first failing clause, for a path built to break
  each clause (and every clause is reachable);
* each route by which a path reaches the caller -- the generic run loop (a planner without a
  fused kernel), the numpy references of both planners (``backend="numpy"``), the numba kernel
  of the planar planner (per-query breakpoints), the shared breakpoints of the obstacle-line
  planner (batch, sequence and single-query fast paths) and the power-of-two scaled route of
  extreme magnitudes -- is fed a planner output corrupted to break each clause, and the entry
  point raises :class:`CertificationError` naming that clause, never returning the path;
* the queries of the issue that used to return a wrong "certified" path (the planar planner at
  scale 1e200, whose breakpoints were NaN and whose path ended at the start);
* property tests: every path every entry point returns passes every clause, on random and
  exactly degenerate queries.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import running, single
from pmplan.certify import CLAUSES, certificate, check_paths, check_times, describe
from pmplan.errors import CertificationError
from pmplan.kernels import planar as kernels_planar
from pmplan.path import PiecewiseLinearPath
from pmplan.planners import obstacle_line, planar_three
from pmplan.planners.base import REGISTRY, Planner, RawPlan

# --------------------------------------------------------------------------------------------
# corruptions: each breaks exactly one clause of a valid path (times (B, K), waypoints
# (B, K, P, d), m obstacles); applied to every query of the batch
# --------------------------------------------------------------------------------------------


def _nan_time(t, w, m):
    t[:, t.shape[1] // 2] = np.nan


def _start_time(t, w, m):
    t[:, 0] = np.nextafter(0.0, 1.0)


def _end_time(t, w, m):
    t[:, -1] = np.nextafter(1.0, 0.0)


def _decreasing(t, w, m):
    k = t.shape[1] // 2
    t[:, k], t[:, k + 1] = t[:, k + 1], t[:, k].copy()
    assert (t[:, k] > t[:, k + 1]).all()


def _nonfinite_waypoint(t, w, m):
    w[:, w.shape[1] // 2, m, 0] = np.inf


def _start_ulp(t, w, m):
    w[:, 0, m, 0] = np.nextafter(w[:, 0, m, 0], np.inf)


def _goal_ulp(t, w, m):
    w[:, -1, -1, -1] = np.nextafter(w[:, -1, -1, -1], -np.inf)


def _obstacle_moves(t, w, m):
    w[:, 2, 0, 0] = np.nextafter(w[:, 2, 0, 0], np.inf)


def _collision(t, w, m):
    """A robot's interior waypoint put exactly on obstacle o1 (clearance 0)."""
    w[:, 2, m] = w[:, 2, 0]


CORRUPT = {
    1: _nan_time,
    2: _start_time,
    3: _end_time,
    4: _decreasing,
    5: _nonfinite_waypoint,
    6: _start_ulp,
    7: _goal_ulp,
    9: _obstacle_moves,
    10: _collision,
}
TIME_CLAUSES = (1, 2, 3, 4)
WAYPOINT_CLAUSES = (5, 6, 7, 9, 10)

O2 = np.array([[0.0, 0.0], [2.0, 0.0]])
S2 = np.array([[0.0, 1.0], [3.0, 2.0]])
G2 = np.array([[1.0, -1.0], [-2.0, 0.5]])
VIA = np.array([[5.0, 5.0], [-3.0, -3.0]])
O3 = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 3.0]])
S3 = np.array([[1.0, -1.0]])
G3 = np.array([[3.0, 1.0]])


def _raises_clause(clause: int, fn, *args, **kwargs):
    with pytest.raises(CertificationError) as info:
        fn(*args, **kwargs)
    assert CLAUSES[clause] in str(info.value), str(info.value)
    return info.value


# --------------------------------------------------------------------------------------------
# the certificate itself
# --------------------------------------------------------------------------------------------


def _valid_batch():
    raw = obstacle_line.OBSTACLE_LINE.plan_sequence(O2[None], [S2[None], VIA[None], G2[None]],
                                         backend="numpy")
    t = np.array(raw.path.times)[None].copy()
    w = raw.path.waypoints.copy()
    full = [np.concatenate([O2, c])[None] for c in (S2, VIA, G2)]
    return t, w, full


def test_the_valid_path_passes_every_clause():
    t, w, full = _valid_batch()
    clr, clause = certificate(w, full[0], full[2], 2, times=t, via=[(0.5, full[1])])
    assert clause.tolist() == [0] and clr[0] > 0
    assert describe(0) == "certified"


@pytest.mark.parametrize("clause", sorted(CORRUPT))
def test_certificate_names_each_broken_clause(clause):
    t, w, full = _valid_batch()
    CORRUPT[clause](t, w, 2)
    clr, got = certificate(w, full[0], full[2], 2, times=t, via=[(0.5, full[1])])
    assert got.tolist() == [clause], describe(got[0])
    if clause <= 4:
        assert check_times(t).tolist() == [clause]
    if clause == 5:
        assert np.isnan(clr[0])


def test_certificate_names_a_missed_intermediate_configuration():
    t, w, full = _valid_batch()
    w[:, 7, 2, 0] = np.nextafter(w[:, 7, 2, 0], np.inf)  # C_2 at tau = 1/2 is waypoint 7
    _, got = certificate(w, full[0], full[2], 2, times=t, via=[(0.5, full[1])])
    assert got.tolist() == [8]
    # the same path without the via requirement: only the clearance could fail
    assert check_paths(t, w, full[0], full[2], 2).tolist() == [0]


def test_every_clause_has_a_text_and_the_order_is_the_documented_one():
    assert sorted(CLAUSES) == list(range(1, 11))
    t, w, full = _valid_batch()
    _nan_time(t, w, 2)
    _start_ulp(t, w, 2)  # two clauses broken: the first one is reported
    assert check_paths(t, w, full[0], full[2], 2).tolist() == [1]


@pytest.mark.parametrize("row", [0, 3, 6])
@pytest.mark.parametrize("clause", TIME_CLAUSES)
def test_time_clauses_find_the_one_broken_row_of_a_batch(row, clause):
    t = np.tile(obstacle_line.path_times(2), (7, 1))
    CORRUPT[clause](t[row : row + 1], np.zeros((1, t.shape[1], 3, 2)), 2)
    want = [clause if i == row else 0 for i in range(7)]
    assert check_times(t).tolist() == want
    assert check_times(t[row]) == clause
    assert check_times(np.delete(t, row, axis=0)).tolist() == [0] * 6


def test_times_without_breakpoints_fail():
    assert check_times(np.empty((1, 0))).tolist() == [1]


# --------------------------------------------------------------------------------------------
# route 1: the generic run loop (a planner without a fused kernel), every entry point
# --------------------------------------------------------------------------------------------


class _Corrupting(Planner):
    """The obstacle-line reference as a plain planner (no kernel, no fast path: only the
    required members of the protocol) whose output is corrupted by ``fn(times, waypoints, m)``
    (per-query breakpoints)."""

    name = "obstacle_line_compact"  # (the default planner, of its priority)
    summary = "test double"
    priority = 1

    def __init__(self, fn):
        self.fn = fn

    def supports(self, d, n, m):
        return obstacle_line.OBSTACLE_LINE.supports(d, n, m)

    def domain_labels(self, d, n, m):
        return obstacle_line.OBSTACLE_LINE.domain_labels(d, n, m)

    def stratum_name(self, row, d, n, m):
        return obstacle_line.OBSTACLE_LINE.stratum_name(row, d, n, m)

    sequential = True

    def allocate(self, b, r, m, n, d):
        out = obstacle_line.OBSTACLE_LINE.allocate(b, r, m, n, d)
        out["times"] = np.empty((b, out["times"].shape[0]))
        return out

    def reference(self, obstacles, configs, lift):
        raw = obstacle_line.OBSTACLE_LINE_COMPACT.reference(obstacles, configs, lift)
        b, k = raw.path.waypoints.shape[:2]
        t = np.broadcast_to(raw.path.times, (b, k)).copy()
        w = raw.path.waypoints.copy()
        self.fn(t, w, obstacles.shape[1])
        return RawPlan(raw.domain, raw.strata, PiecewiseLinearPath(t, w))


def _generic_entry_points():
    b2 = (O2[None], S2[None], G2[None])
    return {
        "plan": lambda: pmplan.plan(O2, S2, G2),
        "plan_batch": lambda: pmplan.plan_batch(*b2),
        "plan_sequence": lambda: pmplan.plan_sequence(O2, [S2, VIA, G2]),
        "plan_sequence_batch": lambda: pmplan.plan_sequence_batch(
            O2[None], [S2[None], VIA[None], G2[None]]),
    }


@pytest.fixture
def fresh_fast_paths(monkeypatch):
    """Empty caches of the fast paths, restored afterwards."""
    monkeypatch.setattr(single, "_FAST", {})
    monkeypatch.setattr(single, "_FAST_SEQUENCE", {})


@pytest.mark.parametrize("entry", sorted(_generic_entry_points()))
@pytest.mark.parametrize("clause", sorted(CORRUPT))
def test_generic_run_loop_never_returns_a_broken_path(monkeypatch, fresh_fast_paths, entry,
                                                      clause):
    monkeypatch.setitem(REGISTRY, "obstacle_line_compact", _Corrupting(CORRUPT[clause]))
    _raises_clause(clause, _generic_entry_points()[entry])


def test_generic_run_loop_checks_the_intermediate_configurations(monkeypatch, fresh_fast_paths):
    def miss_via(t, w, m):
        w[:, 7, m, 0] = np.nextafter(w[:, 7, m, 0], np.inf)

    monkeypatch.setitem(REGISTRY, "obstacle_line_compact", _Corrupting(miss_via))
    for name in ("plan_sequence", "plan_sequence_batch"):
        _raises_clause(8, _generic_entry_points()[name])


def test_generic_run_loop_returns_what_it_certified(monkeypatch, fresh_fast_paths):
    """The test double itself is sound: uncorrupted, every entry point answers."""
    monkeypatch.setitem(REGISTRY, "obstacle_line_compact", _Corrupting(lambda t, w, m: None))
    for name, fn in _generic_entry_points().items():
        assert fn() is not None, name


# --------------------------------------------------------------------------------------------
# route 2: the numpy references (backend="numpy"), both planners
# --------------------------------------------------------------------------------------------


def _corrupt_reference(monkeypatch, planner_cls, method, fn, m):
    original = getattr(planner_cls, method)

    def corrupted(self, *args, **kwargs):
        raw = original(self, *args, **kwargs)
        b, k = raw.path.waypoints.shape[:2]
        t = np.broadcast_to(raw.path.times, (b, k)).copy()
        w = raw.path.waypoints.copy()
        fn(t, w, m)
        return RawPlan(raw.domain, raw.strata, PiecewiseLinearPath(t, w))

    monkeypatch.setattr(planner_cls, method, corrupted)


@pytest.mark.parametrize("clause", WAYPOINT_CLAUSES)
def test_obstacle_line_reference_never_returns_a_broken_path(monkeypatch, clause):
    _corrupt_reference(monkeypatch, obstacle_line.ObstacleLinePlanner, "reference", CORRUPT[clause],
                       2)
    b2 = (O2[None], S2[None], G2[None])
    _raises_clause(clause, pmplan.plan, O2, S2, G2, backend="numpy")
    _raises_clause(clause, pmplan.plan_batch, *b2, backend="numpy")
    _raises_clause(clause, pmplan.plan_sequence, O2, [S2, VIA, G2], backend="numpy")
    _raises_clause(clause, pmplan.plan_sequence_batch, O2[None],
                   [S2[None], VIA[None], G2[None]], backend="numpy")


@pytest.mark.parametrize("clause", sorted(CORRUPT))
def test_planar_reference_never_returns_a_broken_path(monkeypatch, clause):
    _corrupt_reference(monkeypatch, planar_three.PlanarThreePlanner, "reference", CORRUPT[clause],
                       3)
    _raises_clause(clause, pmplan.plan, O3, S3, G3, backend="numpy")
    batch = pmplan.plan_batch  # PlanBatch[i] only exists if the batch was returned
    _raises_clause(clause, batch, O3[None], S3[None], G3[None], backend="numpy")


# --------------------------------------------------------------------------------------------
# route 3: the kernels' breakpoints (per query: planar; shared: obstacle line)
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("clause", TIME_CLAUSES)
def test_planar_kernel_breakpoints_are_checked(monkeypatch, clause):
    original = kernels_planar.plan_planar

    def corrupted(obstacles, start, goal, even, lift, validate, times, wp, *rest):
        original(obstacles, start, goal, even, lift, validate, times, wp, *rest)
        CORRUPT[clause](times, wp, 3)

    monkeypatch.setattr(kernels_planar, "plan_planar", corrupted)
    batch = (np.repeat(O3[None], 5, axis=0), np.repeat(S3[None], 5, axis=0),
             np.repeat(G3[None], 5, axis=0))
    _raises_clause(clause, pmplan.plan_batch, *batch)
    _raises_clause(clause, pmplan.plan_batch, *batch, workers=2)


@pytest.mark.parametrize("clause", TIME_CLAUSES)
def test_obstacle_line_shared_breakpoints_are_checked(monkeypatch, fresh_fast_paths, clause):
    def bad_times(r):
        t = obstacle_line.path_times(r)[None].copy()
        CORRUPT[clause](t, np.zeros((1, t.shape[1], 3, 2)), 2)
        return t[0]

    original = obstacle_line.ObstacleLinePlanner.allocate

    def allocate(self, b, r, m, n, d):
        out = original(self, b, r, m, n, d)
        out["times"] = bad_times(r)
        return out

    monkeypatch.setattr(obstacle_line.ObstacleLinePlanner, "allocate", allocate)
    monkeypatch.setattr(obstacle_line.ObstacleLinePlanner, "path_times", lambda self, r: bad_times(r))
    for name, fn in _generic_entry_points().items():
        _raises_clause(clause, fn)


# --------------------------------------------------------------------------------------------
# route 4: queries at extreme magnitudes (planned scaled by a power of two, scaled back)
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("clause", WAYPOINT_CLAUSES)
def test_scaled_route_certifies_what_it_returns(monkeypatch, clause):
    original = running._fused_call

    def fused_call(*args):
        call = original(*args)

        def corrupted(idx, obstacles, configs, lift):
            arrays, ok = call(idx, obstacles, configs, lift)
            t = np.broadcast_to(arrays["times"], arrays["waypoints"].shape[:2]).copy()
            CORRUPT[clause](t, arrays["waypoints"], obstacles.shape[1])
            return arrays, ok

        return corrupted

    monkeypatch.setattr(running, "_fused_call", fused_call)
    big = 2.0**900
    _raises_clause(clause, pmplan.plan, O2 * big, S2 * big, G2 * big, lift=big)
    _raises_clause(clause, pmplan.plan_batch, O2[None] * big, S2[None] * big, G2[None] * big,
                   lift=big)
    _raises_clause(clause, pmplan.plan_sequence, O2 * big, [S2 * big, VIA * big, G2 * big],
                   lift=big)


# --------------------------------------------------------------------------------------------
# the queries of the issue
# --------------------------------------------------------------------------------------------


def _assert_certified(plan, obstacles, configs, m):
    """``plan`` (Plan or PlanBatch) passes every clause for its queries."""
    if isinstance(plan, pmplan.PlanBatch):
        times, wp = plan.times, plan.waypoints
        obs = np.asarray(obstacles, dtype=float)
        cfg = [np.asarray(c, dtype=float) for c in configs]
    else:
        times, wp = plan.path.times, plan.path.waypoints[None]
        obs = np.asarray(obstacles, dtype=float)[None]
        cfg = [np.asarray(c, dtype=float)[None] for c in configs]
    r = len(cfg)
    full = [np.concatenate([obs, c], axis=1) for c in cfg]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    clr, clause = certificate(wp, full[0], full[-1], m, times=times, via=via)
    assert (clause == 0).all(), [describe(c) for c in clause]
    assert (clr > 0).all()
    got = plan.clearance if isinstance(plan, pmplan.PlanBatch) else np.array([plan.clearance])
    np.testing.assert_array_equal(got, clr)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_issue_planar_query_at_1e200_is_certified_or_refused(backend):
    o = [[0, 0], [4e200, 0], [1e200, 3e200]]
    s, g = [[1e200, -1e200]], [[3e200, 1e200]]
    p = pmplan.plan(o, s, g, backend=backend)
    _assert_certified(p, o, [s, g], 3)
    np.testing.assert_array_equal(p.path(1.0)[3], g[0])
    b = pmplan.plan_batch([o], [s], [g], backend=backend)
    assert np.isfinite(b.times).all()
    _assert_certified(b, [o], [[s], [g]], 3)
    _assert_certified(b[0], o, [s, g], 3)


@pytest.mark.parametrize("scale", [2.0**k for k in (154, 200, 300, 400, 500, 700, 900, 1000)])
def test_planar_scaled_queries_never_return_a_broken_path(scale):
    o = np.array([[0, 0], [4, 0], [1, 3]], dtype=float) * scale
    s, g = np.array([[1.0, -1.0]]) * scale, np.array([[3.0, 1.0]]) * scale
    for backend in ("numba", "numpy"):
        try:
            p = pmplan.plan(o, s, g, backend=backend)
        except CertificationError:
            continue
        _assert_certified(p, o, [s, g], 3)


# --------------------------------------------------------------------------------------------
# property tests: whatever an entry point returns passes every clause
# --------------------------------------------------------------------------------------------

SHAPES = [(2, 1, 2), (2, 3, 2), (3, 2, 2), (2, 2, 4), (2, 1, 3)]


@given(data=st.data(), shape=st.sampled_from(SHAPES), degenerate=st.booleans(),
       backend=st.sampled_from(["numba", "numpy"]))
def test_every_returned_path_passes_every_clause(data, shape, degenerate, backend):
    d, n, m = shape
    o, s, g = data.draw(queries(d, m, n, degenerate=degenerate))
    try:
        p = pmplan.plan(o, s, g, backend=backend)
    except CertificationError:
        return
    _assert_certified(p, o, [s, g], m)
    b = pmplan.plan_batch(o[None], s[None], g[None], backend=backend)
    _assert_certified(b, o[None], [s[None], g[None]], m)
    _assert_certified(b[0], o, [s, g], m)
    if (d, n, m) != (2, 1, 3):
        _, v, _ = data.draw(queries(d, m, n, degenerate=degenerate))
        if any(np.array_equal(x, y) for x in v for y in o):
            return
        try:
            q = pmplan.plan_sequence(o, [s, v, g], backend=backend)
        except CertificationError:
            return
        _assert_certified(q, o, [s, v, g], m)
