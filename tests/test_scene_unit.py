"""The unit of the planners: ``lift`` (paper: 1) and the scale-equivariant ``lift="scene"``.

Issue 12, item 4. ``lift`` is the unit of both planners: the height scale of the lift in the
obstacle-line planner (``lambda = lift + max_k |r(o_k)|``), the 1 of ``H = 1 + max(0, h3)``
(W1, Figure 6) and ``s3 = c3 + 1`` (T23, Figure 10) in the planar one.
``lift="scene"`` makes it ``u(O) = max_{k>=2} |o_k - o_1|`` of each query. What is checked, and
how it could fail:

* default ``lift`` = 1 is the paper's: the planar W1 height and the third solid vertical are
  exactly ``1 + max(0, h3)`` and ``c3 + 1`` (independently recomputed), and ``lift`` is no longer
  ignored there (``lift=2`` moves exactly those legs);
* ``lift="scene"`` uses u(O), computed independently here;
* equivariance: a query scaled by a power of two gets the scaled plan *bit for bit* (labels,
  strata, times, waypoints, clearance), on random and exactly degenerate integer queries, both
  planners, single / batch / sequence entry points; other scalings, translations and
  rotations (d = 2; by 90 degrees exactly, by any angle to a relative tolerance) give the
  transformed plan up to rounding, with the same labels;
* the numba kernels equal the numpy references bit for bit with ``"scene"`` and with a
  non-default lift (batches large enough for the SIMD lanes and small ones), fast paths and
  ``out=`` included;
* the issue's measurement: a (2,3,2) query scaled by 1e-6 and 1e6 keeps its clearance as a
  fixed fraction of the scene's size with ``"scene"`` (with ``lift=1`` it does not).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import planar_strata
from pmplan import single
from pmplan.generators import planar_stratum_queries as stratum_queries
from pmplan.planners import planar_three
from pmplan.planners.base import SCENE_CODE, scene_unit
from pmplan.planners.planar_three import STRATA


def _bits(a) -> tuple:
    a = np.asarray(a)
    return a.shape, a.dtype, (a + 0.0).tobytes() if a.dtype.kind == "f" else a.tobytes()


def _same_plan(p, q):
    """Equal field by field, bit for bit (up to the sign of zeros)."""
    assert (p.domain, p.stratum, p.planner, p.dims) == (q.domain, q.stratum, q.planner, q.dims)
    assert _bits(p.clearance) == _bits(q.clearance)
    assert _bits(p.path.times) == _bits(q.path.times)
    assert _bits(p.path.waypoints) == _bits(q.path.waypoints)


def _same_batch(p, q):
    for k in ("domain", "strata", "clearance", "times", "waypoints"):
        assert _bits(getattr(p, k)) == _bits(getattr(q, k)), k


def _planar_kernel(o, s, g, lift):
    """The planar kernel alone on a batch: (flags, outputs)."""
    from pmplan.kernels import planar as kernels_planar

    b = o.shape[0]
    out = planar_three.PLANAR_THREE.allocate(b, 2, 3, 1, 2)
    flags = np.empty(b, np.uint8)
    kernels_planar.plan_chunk(o, s, g, planar_strata.EVEN, float(lift), False, out["times"],
                              out["waypoints"], out["domain"], out["strata"], out["clearance"],
                              flags)
    return flags, out


def _u(obstacles) -> float:
    """u(O) recomputed independently (math.dist, exact to within an ulp or two)."""
    o = np.asarray(obstacles, dtype=float)
    return max(math.dist(o[k], o[0]) for k in range(1, len(o)))


# --- the unit itself --------------------------------------------------------------------------
def test_scene_unit_values():
    o = np.array([[[1.0, 1.0], [4.0, 5.0], [1.0, -1.0]], [[0.0, 0.0], [0.0, 2.0], [-3.0, 0.0]]])
    assert scene_unit(o).tolist() == [5.0, 3.0]
    assert scene_unit(o[:, :2]).tolist() == [5.0, 2.0]


@settings(max_examples=40)
@given(st.integers(2, 5), st.integers(2, 4), st.integers(0, 2**32 - 1))
def test_scene_unit_matches_distance(m, d, seed):
    scales = 10.0 ** np.arange(-3, 6, 4)[:, None, None]
    o = np.random.default_rng(seed).normal(size=(3, m, d)) * scales
    got = scene_unit(o)
    want = [_u(q) for q in o]
    np.testing.assert_allclose(got, want, rtol=4e-16)
    assert (got > 0).all()


# --- lift is the planar planner's unit ----------------------------------------------------------
@pytest.mark.parametrize("name", STRATA)
def test_planar_default_lift_is_the_papers_one(name):
    """The W1 height and the solid vertical s3 are exactly 1 + max(0, h3) and c3 + 1 (lift=1)."""
    rng = np.random.default_rng(sum(map(ord, name)))
    o, s, g = stratum_queries(rng, name, 30)
    default = pmplan.plan_batch(o, s, g)
    _same_batch(default, pmplan.plan_batch(o, s, g, lift=1))
    _same_batch(default, pmplan.plan_batch(o, s, g, lift=1.0, backend="numpy"))
    for lift in (1.0, 2.5, "scene"):
        st_ = planar_three.classify(o, s, g)
        sc = planar_three._scene(o, s, g, st_, lift)
        unit = np.full(30, lift) if lift != "scene" else np.array([_u(q) for q in o])
        np.testing.assert_allclose(sc.unit, unit, rtol=4e-16)
        if name in ("T1_11", "T22_33", "T23_44"):
            poly = planar_three.frame_polyline_W1(sc)
            assert _bits(poly[:, 1, 1]) == _bits(sc.unit + np.maximum(0.0, sc.h[:, 2]))
        if name.startswith("T23"):
            assert _bits(planar_three._solid_verticals(sc)[:, 2]) == _bits(sc.cols[:, 2] + sc.unit)
        # the kernel (batch and single-query fast path) is the reference, bit for bit
        ref = pmplan.plan_batch(o, s, g, lift=lift, backend="numpy")
        _same_batch(pmplan.plan_batch(o, s, g, lift=lift), ref)
        flags, _ = _planar_kernel(o, s, g, SCENE_CODE if lift == "scene" else lift)
        assert not flags.any()  # the kernel decided every exact construction alone
        for i in range(0, 30, 7):
            _same_plan(pmplan.plan(o[i], s[i], g[i], lift=lift), ref[i])
    if name in ("T1_11", "T22_33", "T23_44", "T23_33", "T23_34", "T23_43"):
        # lift is not ignored: another unit moves the legs that use it
        other = pmplan.plan_batch(o, s, g, lift=2.0)
        uses = (default.waypoints != other.waypoints).any(axis=(1, 2, 3))
        if name in ("T1_11", "T22_33", "T23_44"):
            assert uses.all()
        else:
            assert uses.any()
        assert (default.domain == other.domain).all()


# --- equivariance -----------------------------------------------------------------------------
def _scaled(q, factor):
    return tuple(a * factor for a in q)


def _check_power_of_two(q, k, **kw):
    f = 2.0**k
    p = pmplan.plan(*q, lift="scene", **kw)
    ps = pmplan.plan(*_scaled(q, f), lift="scene", **kw)
    assert (p.domain, p.stratum) == (ps.domain, ps.stratum)
    assert _bits(ps.path.times) == _bits(p.path.times)
    assert _bits(ps.path.waypoints) == _bits(p.path.waypoints * f)
    assert _bits(ps.clearance) == _bits(p.clearance * f)


@settings(max_examples=60)
@given(st.sampled_from([(2, 2, 2), (2, 4, 2), (3, 2, 3), (2, 1, 3), (4, 2, 2)]),
       st.data(), st.integers(-60, 60), st.booleans())
def test_power_of_two_scaling_is_exact(dims, data, k, degenerate):
    d, n, m = dims
    q = data.draw(queries(d, m, n, degenerate=degenerate))
    _check_power_of_two(q, k)
    _check_power_of_two(q, k, backend="numpy")
    if m == 3 and d == 2 and n == 1:
        _check_power_of_two(q, k, planner="obstacle_line")


@settings(max_examples=40)
@given(st.sampled_from([(2, 2, 2), (2, 1, 3), (3, 2, 2)]), st.data(), st.integers(-40, 40))
def test_power_of_two_scaling_batch_and_sequence(dims, data, k):
    d, n, m = dims
    qs = [data.draw(queries(d, m, n, degenerate=b)) for b in (True, False) * 10]
    o, s, g = (np.stack(a) for a in zip(*qs))
    f = 2.0**k
    b = pmplan.plan_batch(o, s, g, lift="scene")
    bs = pmplan.plan_batch(o * f, s * f, g * f, lift="scene")
    assert _bits(bs.domain) == _bits(b.domain) and _bits(bs.strata) == _bits(b.strata)
    assert _bits(bs.times) == _bits(b.times)
    assert _bits(bs.waypoints) == _bits(b.waypoints * f)
    assert _bits(bs.clearance) == _bits(b.clearance * f)
    seq = pmplan.plan_sequence_batch(o, [s, g, s], lift="scene")
    seqs = pmplan.plan_sequence_batch(o * f, [s * f, g * f, s * f], lift="scene")
    assert _bits(seqs.domain) == _bits(seq.domain)
    assert _bits(seqs.waypoints) == _bits(seq.waypoints * f)
    one = pmplan.plan_sequence(o[0], [s[0], g[0], s[0]], lift="scene")
    ones = pmplan.plan_sequence(o[0] * f, [s[0] * f, g[0] * f, s[0] * f], lift="scene")
    assert _bits(ones.path.waypoints) == _bits(one.path.waypoints * f)


def _rot(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


@settings(max_examples=60)
@given(st.sampled_from([(2, 2, 2), (2, 3, 2), (2, 1, 3), (2, 2, 4)]), st.data(),
       st.integers(0, 3), st.integers(-8, 8), st.booleans())
def test_rotation_by_quarter_turns_and_integer_translation(dims, data, quarter, shift, degenerate):
    """Exact transformations of exact (integer/dyadic) queries: same labels, transformed path."""
    d, n, m = dims
    q = data.draw(queries(d, m, n, degenerate=degenerate))
    rot = np.linalg.matrix_power(np.array([[0.0, -1.0], [1.0, 0.0]]), quarter)
    t = np.array([shift, -3 * shift], dtype=float)
    qt = tuple(a @ rot.T + t for a in q)
    p, pt = pmplan.plan(*q, lift="scene"), pmplan.plan(*qt, lift="scene")
    size = np.abs(np.concatenate(q)).max() + abs(shift) * 4
    assert (p.domain, p.stratum) == (pt.domain, pt.stratum)
    np.testing.assert_allclose(pt.path.times, p.path.times, rtol=0, atol=1e-12)
    assert np.abs(pt.path.waypoints - (p.path.waypoints @ rot.T + t)).max() <= 1e-12 * size
    assert abs(pt.clearance - p.clearance) <= 1e-12 * size


@settings(max_examples=60)
@given(st.sampled_from([(2, 2, 2), (2, 3, 2), (2, 1, 3)]), st.integers(0, 2**32 - 1),
       st.floats(-math.pi, math.pi), st.sampled_from([1e-6, 0.3, 7.0, 1e6]))
def test_similarity_of_generic_queries(dims, seed, theta, factor):
    """Rotation by any angle, translation, any scaling: the transformed plan, to rounding."""
    d, n, m = dims
    rng = np.random.default_rng(seed)
    q = (rng.normal(size=(m, d)), rng.normal(size=(n, d)), rng.normal(size=(n, d)))
    t = rng.normal(size=d) * 5
    r = _rot(theta)
    qt = tuple((a @ r.T) * factor + t * factor for a in q)
    p, pt = pmplan.plan(*q, lift="scene"), pmplan.plan(*qt, lift="scene")
    want_wp = (p.path.waypoints @ r.T) * factor + t * factor
    assert (p.domain, p.stratum) == (pt.domain, pt.stratum)
    scale = factor * (np.abs(np.concatenate(q)).max() + np.abs(t).max())
    np.testing.assert_allclose(pt.path.times, p.path.times, rtol=0, atol=1e-8)
    assert np.abs(pt.path.waypoints - want_wp).max() <= 1e-8 * scale
    assert abs(pt.clearance - p.clearance * factor) <= 1e-8 * scale


# --- kernels == references ----------------------------------------------------------------------
@settings(max_examples=30)
@given(st.sampled_from([(2, 2, 2), (2, 4, 2), (3, 2, 3), (2, 1, 3), (5, 1, 4), (2, 2, 5)]),
       st.data(), st.sampled_from(["scene", 0.37, 3]), st.sampled_from([3, 150]),
       st.integers(0, 2**32 - 1))
def test_kernels_equal_references(dims, data, lift, b, seed):
    """Bit for bit, with "scene" and a non-default lift: small chunks (the scalar kernel) and
    chunks of 150 mostly generic queries (the SIMD lanes of the obstacle-line kernel take
    blocks of 64), with exactly degenerate ones among them."""
    d, n, m = dims
    qs = [data.draw(queries(d, m, n, degenerate=True)) for k in range(3)]
    rng = np.random.default_rng(seed)
    gen = [(rng.normal(size=(m, d)), rng.normal(size=(n, d)), rng.normal(size=(n, d)))
           for _ in range(b - 3)]
    qs = [qs[0], *gen[: b // 2], qs[1], *gen[b // 2:], qs[2]][:b]
    o, s, g = (np.stack(a) for a in zip(*qs))
    for planner in (None, "obstacle_line"):
        if planner is None and (d, n, m) != (2, 1, 3):
            continue
        fast = pmplan.plan_batch(o, s, g, lift=lift, planner=planner)
        ref = pmplan.plan_batch(o, s, g, lift=lift, planner=planner, backend="numpy")
        _same_batch(fast, ref)
        _same_plan(pmplan.plan(o[0], s[0], g[0], lift=lift, planner=planner), ref[0])
        out = pmplan.plan_batch(o, s, g, lift=1.0, planner=planner)
        assert pmplan.plan_batch(o, s, g, lift=lift, planner=planner, out=out) is out
        _same_batch(out, ref)
    seq = pmplan.plan_sequence_batch(o, [s, g, s], lift=lift)
    seq_ref = pmplan.plan_sequence_batch(o, [s, g, s], lift=lift, backend="numpy")
    _same_batch(seq, seq_ref)
    _same_plan(pmplan.plan_sequence(o[0], [s[0], g[0], s[0]], lift=lift), seq_ref[0])


def test_fast_paths_take_scene():
    """The single-query fast paths answer lift="scene" (the comparisons above are not vacuous)."""
    rng = np.random.default_rng(3)
    for o, s, g in ((rng.normal(size=(2, 2)), rng.normal(size=(3, 2)), rng.normal(size=(3, 2))),
                    (rng.normal(size=(3, 2)), rng.normal(size=(1, 2)), rng.normal(size=(1, 2)))):
        assert single._plan_fast(o, s, g, None, "scene") is not None
        assert single._plan_sequence_fast(o, [s, g], "scene") is not None
        assert single._fast_lift("scene") == SCENE_CODE
    assert single._plan_fast(o, s, g, None, 0.0) is None  # a zero lift is an error, not "scene"


# --- the measurement --------------------------------------------------------------------
def test_clearance_is_a_fixed_fraction_of_the_scene():
    """A (2,3,2) query scaled by 1e-6 and 1e6: with "scene", clearance / scene size is fixed."""
    o = np.array([[0.0, 0.0], [1.0, 0.3]])
    s = np.array([[0.2, 1.0], [-1.0, 0.4], [0.5, -0.7]])
    g = np.array([[1.5, 0.1], [0.3, 0.9], [-0.6, -1.2]])
    base = pmplan.plan(o, s, g, lift="scene")
    size = np.ptp(np.concatenate([o, s, g]), axis=0).max()
    frac = base.clearance / size
    for factor in (1e-6, 1e6):
        p = pmplan.plan(o * factor, s * factor, g * factor, lift="scene")
        assert p.domain == base.domain
        assert math.isclose(p.clearance / (size * factor), frac, rel_tol=1e-9)
        motion = np.abs(np.diff(p.path.waypoints, axis=0)).sum() / (size * factor)
        base_motion = np.abs(np.diff(base.path.waypoints, axis=0)).sum() / size
        assert math.isclose(motion, base_motion, rel_tol=1e-9)
    # the absolute unit (lift=1) does not scale: at 1e6 its clearance is a far smaller fraction
    # (the issue measured 3.7e-7 of the scene), at 1e-6 its motion dwarfs the scene
    big = pmplan.plan(o * 1e6, s * 1e6, g * 1e6)
    assert big.clearance / (size * 1e6) < 1e-4 * frac
    small = pmplan.plan(o * 1e-6, s * 1e-6, g * 1e-6)
    assert np.abs(small.path.waypoints).max() / (size * 1e-6) > 1e5
