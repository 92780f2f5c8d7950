"""Every finite input gets a certified answer or a specific pmplan error (issue 12, item 2).

From the smallest subnormal (5e-324) to the largest double (1.7976931348623157e308), for both
planners, batch, single and sequence, both backends, with every warning turned into an error:
the result is a plan that passes the whole certificate, or an :class:`InputError` /
:class:`CertificationError` -- never a ValueError, OverflowError, ZeroDivisionError or a numpy
RuntimeWarning. Queries at extreme magnitudes are planned scaled by a power of two
(:mod:`pmplan.magnitude`), so for the obstacle-line planner an exactly degenerate integer query
scaled by ``2**k`` (with ``lift = 2**k``) has the same label and exactly the ``2**k``-scaled
path, for every k where the scaled path is representable.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import assume, event, given
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import magnitude
from pmplan.certify import CLAUSES, certificate, describe
from pmplan.errors import CertificationError, InputError

MAXF = 1.7976931348623157e308
FACTORS = [5e-324, 1e-320, 1e-310, 1e-300, 1e-200, 1e-150, 1e150, 1e200, 1e300, 1e307, 1e308,
           MAXF]


def _certified(plan, obstacles, configs, m):
    """Whether ``plan`` (a Plan) passes every clause of the certificate for its query."""
    obs = np.asarray(obstacles, dtype=float)[None]
    full = [np.concatenate([obs, np.asarray(c, dtype=float)[None]], axis=1) for c in configs]
    r = len(full)
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    clr, clause = certificate(plan.path.waypoints[None], full[0], full[-1], m,
                              times=plan.path.times, via=via)
    assert clause[0] == 0, describe(clause[0])
    assert clr[0] > 0
    if plan.planner == "planar_three":
        # the planar clearance is certified on the padded path (repeated last waypoints, see
        # PlanBatch); the compacted path of a Plan measures its last moving piece at t = 1 as
        # r0 + v instead of r1, which may differ in the last bits
        assert plan.clearance == pytest.approx(clr[0], rel=1e-12, abs=0)
    else:
        assert plan.clearance == clr[0]
    return True


def _outcome(fn, *args, **kwargs):
    """``fn(...)`` with warnings as errors: the result, or the pmplan error it raised (any
    other exception fails the test)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return fn(*args, **kwargs)
        except (InputError, CertificationError) as exc:
            return exc


def _scaled(a, factor):
    with np.errstate(over="ignore", under="ignore"):
        return np.asarray(a, dtype=float) * factor


SHAPES = [(2, 1, 2), (2, 3, 2), (3, 2, 2), (2, 2, 4), (4, 2, 3), (2, 1, 3)]


@given(data=st.data(), shape=st.sampled_from(SHAPES), factor=st.sampled_from(FACTORS),
       lift=st.sampled_from(["one", "scale"]), degenerate=st.booleans())
def test_every_magnitude_gets_a_certified_answer_or_a_pmplan_error(data, shape, factor, lift,
                                                                   degenerate):
    d, n, m = shape
    o, s, g = data.draw(queries(d, m, n, degenerate=degenerate))
    o, s, g = (_scaled(a, factor) for a in (o, s, g))
    lift_value = 1.0 if lift == "one" else factor
    for backend in ("numba", "numpy"):
        single = _outcome(pmplan.plan, o, s, g, lift=lift_value, backend=backend)
        if isinstance(single, pmplan.Plan):
            assert _certified(single, o, [s, g], m)
        batch = _outcome(pmplan.plan_batch, o[None], s[None], g[None], lift=lift_value,
                         backend=backend)
        assert isinstance(batch, pmplan.PlanBatch) == isinstance(single, pmplan.Plan)
        if isinstance(batch, pmplan.PlanBatch):
            assert _certified(batch[0], o, [s, g], m)
        if (d, n, m) != (2, 1, 3):
            seq = _outcome(pmplan.plan_sequence, o, [s, g, s], lift=lift_value, backend=backend)
            if isinstance(seq, pmplan.Plan):
                assert _certified(seq, o, [s, g, s], m)
            seqs = _outcome(pmplan.plan_sequence_batch, o[None], [s[None], g[None], s[None]],
                            lift=lift_value, backend=backend)
            assert isinstance(seqs, pmplan.PlanBatch) == isinstance(seq, pmplan.Plan)
            if isinstance(seqs, pmplan.PlanBatch):
                np.testing.assert_array_equal(seqs.waypoints[0], seq.path.waypoints)


@given(data=st.data(), shape=st.sampled_from(SHAPES[:5]), k=st.integers(-1074, 1023))
def test_power_of_two_scaling_is_exact(data, shape, k):
    """An exactly degenerate integer query scaled by 2**k with lift 2**k: the same label and
    exactly the 2**k-scaled path, wherever that path is representable; otherwise a
    CertificationError."""
    d, n, m = shape
    o, s, g = data.draw(queries(d, m, n, degenerate=True, grid="int"))
    base = pmplan.plan(o, s, g)
    with np.errstate(over="ignore", under="ignore"):
        want = np.ldexp(base.path.waypoints, k)
        exact = np.isfinite(want).all() and np.array_equal(np.ldexp(want, -k),
                                                           base.path.waypoints)
    with np.errstate(over="ignore", under="ignore"):
        q = [np.ldexp(a, k) for a in (o, s, g)]
    assume(all(np.array_equal(np.ldexp(a, -k), b) for a, b in zip(q, (o, s, g))))
    lift = float(np.ldexp(1.0, k))
    event(f"the scaled path is representable: {exact}")
    for backend in ("numba", "numpy"):
        for p in (_outcome(pmplan.plan, *q, lift=lift, backend=backend),
                  _outcome(lambda: pmplan.plan_batch(*(a[None] for a in q), lift=lift,
                                                     backend=backend)[0])):
            if not exact:
                if isinstance(p, pmplan.Plan):
                    assert _certified(p, q[0], q[1:], m)
                    assert p.domain == base.domain
                continue
            assert isinstance(p, pmplan.Plan), p
            assert (p.domain, p.stratum) == (base.domain, base.stratum)
            np.testing.assert_array_equal(p.path.times, base.path.times)
            np.testing.assert_array_equal(p.path.waypoints, want)
            assert _certified(p, q[0], q[1:], m)


@pytest.mark.parametrize("k", [-1074, -1000, -700, -431, 431, 600, 900, 1000, 1020])
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_sequences_scale_exactly(k, backend):
    o = np.array([[0.0, 0.0], [2.0, 0.0]])
    cs = [np.array([[0.0, 1.0], [2.0, 3.0]]), np.array([[1.0, -1.0], [4.0, 4.0]]),
          np.array([[3.0, 3.0], [-1.0, 2.0]])]
    base = pmplan.plan_sequence(o, cs, backend=backend)
    with np.errstate(over="ignore", under="ignore"):
        want = np.ldexp(base.path.waypoints, k)
        exact = np.isfinite(want).all() and np.array_equal(np.ldexp(want, -k),
                                                           base.path.waypoints)
    lift = float(np.ldexp(1.0, k))
    p = _outcome(pmplan.plan_sequence, np.ldexp(o, k), [np.ldexp(c, k) for c in cs], lift=lift,
                 backend=backend)
    b = _outcome(pmplan.plan_sequence_batch, np.ldexp(o, k)[None],
                 [np.ldexp(c, k)[None] for c in cs], lift=lift, backend=backend)
    if exact:
        assert p.domain == base.domain
        np.testing.assert_array_equal(p.path.waypoints, want)
        np.testing.assert_array_equal(b.waypoints[0], want)
    else:
        assert isinstance(p, (pmplan.Plan, CertificationError))


# --------------------------------------------------------------------------------------------
# the failures of the issue
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_issue_query_at_1e308_is_certified(backend):
    o, s, g = [[0, 0], [1e308, 0]], [[5e307, 1e308]], [[1e308, -1e308]]
    p = _outcome(pmplan.plan, o, s, g, backend=backend)
    assert isinstance(p, pmplan.Plan), p
    assert _certified(p, o, [s, g], 2)
    # lift = 1 is exact at 2**-1024 times the scene: the robot is lifted by exactly 1
    assert p.path.waypoints[:, 2, 1].max() == 1e308


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("factor", [1e300, 1e308, MAXF / 2])
def test_issue_random_queries_at_the_top_of_the_range(seed, factor):
    rng = np.random.default_rng(seed)
    for d, n, m in SHAPES:
        o, s, g = (rng.uniform(-1, 1, size=(k, d)) * factor for k in (m, n, n))
        for backend in ("numba", "numpy"):
            p = _outcome(pmplan.plan, o, s, g, lift=factor, backend=backend)
            assert isinstance(p, (pmplan.Plan, CertificationError)), p
            if isinstance(p, pmplan.Plan):
                assert _certified(p, o, [s, g], m)
            b = _outcome(pmplan.plan_batch, o[None], s[None], g[None], lift=factor,
                         backend=backend)
            assert isinstance(b, (pmplan.PlanBatch, CertificationError)), b


def test_lift_below_the_resolution_says_what_to_do():
    """Two robots swap places along the diagonal line o1 o2 of a scene of size 2**702: the lift
    1 is below the resolution of the coordinates, the lifted robots stay on the line and meet."""
    big = 2.0**700
    o = [[0.0, 0.0], [4 * big, 4 * big]]
    s, g = [[big, big], [2 * big, 2 * big]], [[2 * big, 2 * big], [big, big]]
    for backend in ("numba", "numpy"):
        with pytest.raises(CertificationError, match="below the resolution") as info:
            pmplan.plan(o, s, g, backend=backend)
        assert "larger `lift`" in str(info.value) and 'lift="scene"' in str(info.value)
        assert CLAUSES[10] in str(info.value)
        p = pmplan.plan(o, s, g, lift=big, backend=backend)  # a lift of the scene's size
        assert _certified(p, o, [s, g], 2)


def test_a_lift_far_above_the_scene_is_planned():
    o, s, g = [[0.0, 0.0], [2.0, 0.0]], [[0.0, 1.0]], [[1.0, -1.0]]
    for lift in (1e300, 1e307):
        p = pmplan.plan(o, s, g, lift=lift)
        assert _certified(p, o, [s, g], 2)
        assert p.path.waypoints[:, 2, 1].max() == lift  # lifted by exactly lift


def test_a_tiny_scene_with_the_default_lift_is_planned():
    t = 2.0**-1000
    o, s = [[0.0, 0.0], [4 * t, 4 * t]], [[t, t], [2 * t, 2 * t]]
    for lift in (1.0, t):
        p = pmplan.plan(o, s, s[::-1], lift=lift)
        assert _certified(p, o, [s, s[::-1]], 2)


def test_overflowing_path_says_so():
    """Robot 2 is lifted by 2 lift = 2 MAXF: the path leaves the doubles."""
    o, s, g = [[0, 0], [MAXF, 0]], [[MAXF / 2, 0], [MAXF / 4, 0]], [[MAXF / 4, 0], [MAXF / 2, 0]]
    with pytest.raises(CertificationError, match="range of double precision") as info:
        pmplan.plan(o, s, g, lift=MAXF, planner="obstacle_line")
    assert CLAUSES[5] in str(info.value)


# --------------------------------------------------------------------------------------------
# B = 0
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("shape", [(2, 3, 2), (2, 1, 3), (3, 2, 2), (9, 1, 2)])
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_an_empty_batch_is_valid_everywhere(shape, backend):
    d, n, m = shape
    o, s = np.zeros((0, m, d)), np.zeros((0, n, d))
    b = pmplan.plan_batch(o, s, s, backend=backend)
    assert len(b) == 0 and b.waypoints.shape[0] == 0 and list(b) == []
    assert b.stratum.shape == (0,) and b.path.shape == (0,)
    assert pmplan.plan_batch(o, s, s, backend=backend, out=b) is b
    assert len(pmplan.plan_batch(o, s, s, backend=backend, workers=2)) == 0
    if shape != (2, 1, 3):
        sb = pmplan.plan_sequence_batch(o, [s, s, s], backend=backend)
        assert len(sb) == 0 and sb.times.shape == (15,)
        assert pmplan.plan_sequence_batch(o, [s, s, s], backend=backend, out=sb) is sb


# --------------------------------------------------------------------------------------------
# the scaling itself
# --------------------------------------------------------------------------------------------


def test_exponents_scale_only_what_needs_it_and_only_exactly():
    q = np.array([[[1e300, 0.0]], [[1.0, 2.0]], [[1e-300, 0.0]], [[1e300, 1e-320]]])
    k = magnitude.exponents([q], 1.0)
    assert k.tolist() == [1024, 0, 0, 0]  # the last one does not survive 2**-1024 exactly
    assert magnitude.exponents([q], 1e-300).tolist()[2] == -960
    # a lift 1e300 times the scene: the coordinates stay in [2**-430, 2**430), not subnormal
    assert magnitude.exponents([q], 1e300).tolist() == [1024, 384, 0, 0]
    assert not magnitude.needs_scaling([q[1:2]], 1.0)
    assert magnitude.needs_scaling([q[:1]], 1.0)
    assert magnitude.needs_scaling([q[1:2]], 1e-200)
    assert magnitude.needs_scaling([q[1:2]], 1e200)
    assert magnitude.needs_scaling([q[1:2]], np.array([1.0, 1e200]))  # a per-query lift


@given(data=st.data(), k=st.integers(-1074, 1023))
def test_planar_labels_do_not_change_under_power_of_two_scaling(data, k):
    """The planar planner's classification is exact, so a degenerate integer query scaled by
    2**k keeps its domain and stratum whenever a certified path is returned (its unit is
    absolute, so the path itself is the scaled one only for strata that do not use it)."""
    o, s, g = data.draw(queries(2, 3, 1, degenerate=True, grid="int"))
    base = pmplan.plan(o, s, g)
    with np.errstate(over="ignore", under="ignore"):
        q = [np.ldexp(a, k) for a in (o, s, g)]
    assume(all(np.array_equal(np.ldexp(a, -k), b) for a, b in zip(q, (o, s, g))))
    for backend in ("numba", "numpy"):
        p = _outcome(pmplan.plan, *q, backend=backend)
        assert isinstance(p, (pmplan.Plan, CertificationError)), p
        if isinstance(p, pmplan.Plan):
            assert (p.domain, p.stratum) == (base.domain, base.stratum)
            assert _certified(p, q[0], q[1:], 3)
            event("certified")
        else:
            event("refused")


def test_paths_at_the_top_of_the_range_evaluate_without_overflow():
    """Sampling, resampling and the length of a certified path whose waypoints are ~1e308
    apart: exact at the breakpoints, finite in between, no warning."""
    p = _outcome(pmplan.plan, [[0, 0], [1e308, 0]], [[5e307, 1e308]], [[1e308, -1e308]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        at = p.path(p.path.times)
        np.testing.assert_array_equal(at, p.path.waypoints)
        mid = p.path(np.linspace(0.0, 1.0, 33))
        assert np.isfinite(mid).all()
        assert np.isfinite(p.path.resample(9).waypoints).all()
        legs = p.path.leg_lengths()
        assert np.isfinite(legs).all() and (legs >= 0).all()
        assert p.path.length() == np.inf or np.isfinite(p.path.length())
        # times proportional to length, computed without overflow
        t = p.path.arc_length_reparametrised().times
        assert np.isfinite(t).all() and t[0] == 0.0 and t[-1] == 1.0 and (np.diff(t) >= 0).all()


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_planar_unit_below_the_resolution_says_so(backend):
    """T1_11 on the diagonal at scale 2**702: the W1 path runs one unit above L_C, which is
    below the resolution of the coordinates, so it would pass through o3."""
    sc = 2.0**700
    o = np.array([[0, 0], [4, 4], [2, 2]]) * sc
    s, g = np.array([[1.0, 1.0]]) * sc, np.array([[3.0, 3.0]]) * sc
    with pytest.raises(CertificationError, match="below the resolution") as info:
        pmplan.plan(o, s, g, backend=backend)
    assert CLAUSES[10] in str(info.value)
    p = pmplan.plan(o / sc, s / sc, g / sc, backend=backend)  # the same query at scale 4
    assert _certified(p, o / sc, [s / sc, g / sc], 3)


@pytest.mark.parametrize("factor", [2.0**-1050, 1e-310, 1e-300, 1e-200, 1e200, 1e300, 2.0**1020])
def test_scene_unit_at_every_magnitude(factor):
    """With lift="scene" the unit scales with the scene, so a query has a certified plan at
    every magnitude where it is representable, with the clearance a fixed fraction of the
    scene (both planners, single and batch, both backends; warnings are errors)."""
    cases = [([[0, 0], [4, 0], [1, 3]], [[1, -1]], [[3, 1]]),
             ([[0, 0], [1, 0]], [[0.5, 1], [0.3, -1]], [[0.5, -1], [2, 2]])]
    for q in cases:
        base = pmplan.plan(*q, lift="scene")
        o, s, g = (_scaled(a, factor) for a in q)
        for backend in ("numba", "numpy"):
            p = _outcome(pmplan.plan, o, s, g, lift="scene", backend=backend)
            assert isinstance(p, pmplan.Plan), p
            assert _certified(p, o, [s, g], len(q[0]))
            assert (p.domain, p.stratum) == (base.domain, base.stratum)
            assert p.clearance / factor == pytest.approx(base.clearance, rel=1e-5)
            b = _outcome(pmplan.plan_batch, o[None], s[None], g[None], lift="scene",
                         backend=backend)
            assert isinstance(b, pmplan.PlanBatch), b
            assert b.clearance[0] == p.clearance
