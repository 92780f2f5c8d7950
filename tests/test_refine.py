"""Refined motions (pmplan.refine, issue 14): certified, same domains and strata, endpoints and
intermediate configurations exact, radii reported truthfully, continuous inside a stratum,
equivariant, kernel == numpy reference, parameters validated."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan.certify import exact_segment_dist2, certificate
from pmplan.errors import CollisionError, InputError
from pmplan.refine.kernel import refine_batch
from pmplan.planners.base import REGISTRY
from pmplan.strata import spec_for
from pmplan.refine import (
    DEFAULT_STEPS,
    DEFAULT_WAYPOINTS,
    check_parameters,
    grid,
    radius_report,
    reference,
    refine_paths,
    schedule,
)
from pmplan.refine.grid import WALL_SLIDE, pairs, piece_minima, raw_positions
from pmplan.refine.reference import _wall_scale

R = reference  # the map's reference (its substeps; the grid's constants through it)
OMPL_OBSTACLES = np.array([[0.35, 0.5], [0.65, 0.5]])

DIMS = [(2, 1, 2), (2, 3, 2), (3, 2, 2), (2, 2, 3), (4, 1, 3), (2, 1, 3)]


def _full(obstacles, conf):
    return np.concatenate([obstacles, conf], axis=0)


def _exact_min2(wp: np.ndarray, pa, pb) -> Fraction | None:
    """The exact squared minimum over the pieces of a path (K, P, d) of the pairs (pa, pb)."""
    best = None
    for j in range(wp.shape[0] - 1):
        for a, b in zip(pa, pb):
            v = exact_segment_dist2(wp[j, a], wp[j, b], wp[j + 1, a], wp[j + 1, b])
            best = v if best is None or v < best else best
    return best


def _check_refined(raw: pmplan.Plan, ref: pmplan.Plan, configs, radius=0.0, obstacle_radius=0.0):
    """Everything a refined plan promises, checked independently."""
    _d, n, m = raw.dims
    obstacles = raw.obstacles
    assert ref.refined and not raw.refined
    assert ref.domain == raw.domain and ref.stratum == raw.stratum
    assert ref.planner == raw.planner and ref.dims == raw.dims
    assert ref.radius == radius and ref.obstacle_radius == obstacle_radius
    wp, times = ref.path.waypoints, ref.path.times
    # the whole certificate, on the returned path
    r = len(configs)
    full = [_full(obstacles, c)[None] for c in configs]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    clr, clause = certificate(wp[None], full[0], full[-1], m, times=times, via=via)
    assert clause[0] == 0 and clr[0] > 0
    assert clr[0] == ref.clearance
    assert np.array_equal(wp[0], full[0][0]) and np.array_equal(wp[-1], full[-1][0])
    for tau, c in via:
        assert np.array_equal(ref.path(tau), c[0])
    assert (wp[:, :m] == obstacles).all()
    # the exact minima and respects_radius, against the exact arithmetic
    a, b, _ = pairs(m + n, m)
    rr = a >= m
    ro2 = _exact_min2(wp, a[~rr], b[~rr])
    assert ref.obstacle_distance == pytest.approx(float(ro2) ** 0.5, rel=1e-12)
    if n > 1:
        rr2 = _exact_min2(wp, a[rr], b[rr])
        assert ref.robot_distance == pytest.approx(float(rr2) ** 0.5, rel=1e-12)
        ok_rr = rr2 >= (2 * Fraction(radius)) ** 2
    else:
        assert ref.robot_distance == np.inf
        ok_rr = True
    ok_ro = ro2 >= (Fraction(radius) + Fraction(obstacle_radius)) ** 2
    assert ref.respects_radius == (ok_rr and ok_ro)
    oo = min(np.linalg.norm(obstacles[i] - obstacles[j]) for i in range(m)
             for j in range(i + 1, m))
    assert ref.clearance == pytest.approx(min(ref.robot_distance, ref.obstacle_distance, oo),
                                          rel=1e-12)


# --- property tests: every planner, random and exactly degenerate queries ------------------

@pytest.mark.parametrize("dims", DIMS)
@pytest.mark.parametrize("degenerate", [False, True])
@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_refined_plan_certified_same_domain(dims, degenerate, data):
    d, n, m = dims
    o, s, g = data.draw(queries(d, m, n, degenerate=degenerate))
    raw = pmplan.plan(o, s, g)
    ref = pmplan.refine(raw)
    _check_refined(raw, ref, [s, g])
    assert ref.path.length() <= raw.path.length() * (1 + 1e-12)
    assert ref.clearance > 0


def _assert_fixed_waypoints(planner, raw_times, raw_wp, ref_times, ref_wp, fixed, full):
    """The fixed waypoints ``fixed`` of one raw path are its r = len(full) configurations at the
    times k / (r - 1), and the refined path keeps each exactly where its raw waypoint is in
    the refined grid (``raw_positions``: ``fixed[k] S`` less ``S - 1`` per still piece
    before it)."""
    r, k = len(full), raw_times.shape[-1]
    at = raw_positions(k, DEFAULT_WAYPOINTS, planner.still_for(raw_times))
    assert ref_times.shape[-1] == at[-1] + 1 and fixed.shape == (r,)
    assert np.array_equal(ref_times[..., at], raw_times)
    for j, (kj, conf) in enumerate(zip(fixed.tolist(), full)):
        assert raw_times[kj] == j / (r - 1) == ref_times[at[kj]]
        assert np.array_equal(raw_wp[kj], conf) and np.array_equal(ref_wp[at[kj]], conf)


@pytest.mark.parametrize("degenerate", [False, True])
@settings(max_examples=10, deadline=None)
@given(data=st.data(), r=st.integers(2, 5), dims=st.sampled_from([(2, 2, 2), (3, 1, 3)]))
def test_refined_sequence_keeps_vias(degenerate, data, r, dims):
    """r = 2..5 configurations, single and batch: the planner's fixed waypoints
    (``Planner.fixed_waypoints``) are the configurations, and the refined path keeps them."""
    d, n, m = dims
    o, s, g = data.draw(queries(d, m, n, degenerate=degenerate))
    # intermediate configurations: the robots of the query in another order (distinct from
    # each other and from the obstacles)
    v = [g[::-1].copy(), s[::-1].copy(), g.copy()][:r - 2]
    configs = [s, *v, g]
    raw = pmplan.plan_sequence(o, configs)
    ref = pmplan.refine(raw)
    _check_refined(raw, ref, configs)
    again = pmplan.plan_sequence(o, configs, refine=True)
    assert np.array_equal(again.path.waypoints, ref.path.waypoints)
    full = [_full(o, c) for c in configs]
    planner = REGISTRY[raw.planner]
    fixed = planner.fixed_waypoints(raw.path.times)
    _assert_fixed_waypoints(planner, raw.path.times, raw.path.waypoints, ref.path.times,
                            ref.path.waypoints, fixed, full)
    raw_b = pmplan.plan_sequence_batch(np.stack([o, o]), [np.stack([c, c]) for c in configs])
    ref_b = pmplan.refine(raw_b)
    assert np.array_equal(planner.fixed_waypoints(raw_b.times), fixed)
    for i in range(2):
        _assert_fixed_waypoints(planner, raw_b.times, raw_b.waypoints[i], ref_b.times,
                                ref_b.waypoints[i], fixed, full)
        assert np.array_equal(ref_b.waypoints[i], ref.path.waypoints)


@settings(max_examples=10, deadline=None)
@given(data=st.data(), degenerate=st.booleans())
def test_planar_fixed_waypoints_first_and_last(data, degenerate):
    """The planar planner (per-query breakpoints in a batch): r = 2, the first and the last
    waypoint, single and batch."""
    o, s, g = data.draw(queries(2, 3, 1, degenerate=degenerate))
    raw = pmplan.plan(o, s, g)
    assert raw.planner == "planar_three"
    planner = REGISTRY[raw.planner]
    full = [_full(o, s), _full(o, g)]
    ref = pmplan.refine(raw)
    k = raw.path.times.shape[0]
    fixed = planner.fixed_waypoints(raw.path.times)
    assert fixed.tolist() == [0, k - 1]
    _assert_fixed_waypoints(planner, raw.path.times, raw.path.waypoints, ref.path.times,
                            ref.path.waypoints, fixed, full)
    raw_b = pmplan.plan_batch(o[None], s[None], g[None])
    assert raw_b.times.ndim == 2
    fixed_b = planner.fixed_waypoints(raw_b.times)
    assert fixed_b.tolist() == [0, raw_b.times.shape[1] - 1]
    ref_b = pmplan.refine(raw_b)
    _assert_fixed_waypoints(planner, raw_b.times[0], raw_b.waypoints[0], ref_b.times[0],
                            ref_b.waypoints[0], fixed_b, full)


@settings(max_examples=15, deadline=None)
@given(data=st.data(), radius=st.sampled_from([0.0, 0.25, 0.5, 1.0]),
       obstacle_radius=st.sampled_from([0.0, 0.25, 1.0]))
def test_respects_radius_truthful_integer_queries(data, radius, obstacle_radius):
    """Exactly degenerate integer queries with radii: the report is the exact arithmetic's, and a
    start or goal violating the radii is refused with the pair named."""
    o, s, g = data.draw(queries(2, 2, 2, degenerate=True, grid="int"))
    raw = pmplan.plan(o, s, g)
    try:
        ref = pmplan.refine(raw, radius=radius, obstacle_radius=obstacle_radius)
    except CollisionError as e:
        conf = s if e.which == "start" else g
        full = _full(o, conf)
        names = [f"o{k + 1}" for k in range(2)] + ["x1", "x2"]
        i, j = names.index(e.pair[0]), names.index(e.pair[1])
        need = 2 * Fraction(radius) if i >= 2 else Fraction(radius) + Fraction(obstacle_radius)
        assert exact_segment_dist2(full[i], full[j], full[i], full[j]) < need**2
        assert "move them apart or use smaller radii" in str(e)
        return
    _check_refined(raw, ref, [s, g], radius, obstacle_radius)


@pytest.mark.parametrize("dims", [(2, 3, 2), (3, 2, 3), (2, 1, 3)])
@settings(max_examples=12, deadline=None)
@given(data=st.data(), frac=st.sampled_from([0.1, 0.45, 0.5]))
def test_respects_radius_truthful_random_queries(dims, data, frac):
    """Random queries with radii a fraction of the starts' and goals' smallest distance (so
    they are valid; 0.5 of it is exactly reachable at the endpoints): the report is exact."""
    d, n, m = dims
    o, s, g = data.draw(queries(d, m, n))
    gap = min(float(np.linalg.norm(c[:, None] - c[None], axis=-1)[np.triu_indices(m + n, 1)]
                    .min()) for c in (_full(o, s), _full(o, g)))
    radius = obstacle_radius = frac * gap
    raw = pmplan.plan(o, s, g)
    try:
        ref = pmplan.refine(raw, radius=radius, obstacle_radius=obstacle_radius)
    except CollisionError:
        assert frac == 0.5  # 2 * radius == gap may round above the float distance
        return
    _check_refined(raw, ref, [s, g], radius, obstacle_radius)


def test_radius_zero_still_shortens_and_clears():
    o = OMPL_OBSTACLES
    raw = pmplan.plan(o, [[0.1, 0.5], [0.2, 0.2]], [[0.9, 0.5], [0.8, 0.8]], lift=0.1,
                      planner="obstacle_line")
    ref = pmplan.refine(raw)
    assert ref.path.length() < 0.7 * raw.path.length()
    assert ref.clearance > 0.4 * raw.clearance  # KAPPA of the raw clearance, kept
    assert ref.respects_radius  # radii 0


def _ompl_refined(s, g):
    """The refined plan of the OMPL scene (radius = obstacle_radius = 0.025), or None when
    the start or goal violates the radii."""
    try:
        return pmplan.plan(OMPL_OBSTACLES, s, g, lift=0.1, refine=True, radius=0.025,
                           obstacle_radius=0.025)
    except CollisionError:
        return None


def test_radius_reached_on_the_ompl_scene():
    rng = np.random.default_rng(5)
    for _ in range(5):
        s = rng.uniform(0.05, 0.95, (2, 2))
        g = rng.uniform(0.05, 0.95, (2, 2))
        ref = _ompl_refined(s, g)
        if ref is None:
            continue
        _check_refined(pmplan.plan(OMPL_OBSTACLES, s, g, lift=0.1), ref, [s, g], 0.025, 0.025)
        assert ref.respects_radius and ref.robot_distance >= 0.05
        assert ref.obstacle_distance >= 0.05


def test_unreachable_radius_reported_false_still_certified():
    """Obstacles of radius 0.3 one apart make a wall the raw path passes through (between them,
    0.5 from each): no continuous deformation that keeps the endpoints reaches 0.6 there. The
    plan says so and is still certified."""
    o = np.array([[0.0, 0.0], [1.0, 0.0]])
    s, g = np.array([[0.5, 1.0]]), np.array([[0.5, -1.0]])
    raw = pmplan.plan(o, s, g, lift=0.01)
    ref = pmplan.refine(raw, radius=0.3, obstacle_radius=0.3)
    _check_refined(raw, ref, [s, g], 0.3, 0.3)
    assert not ref.respects_radius and 0 < ref.obstacle_distance < 0.6


# --- continuity inside a stratum ---------------------------------------------------------

@pytest.mark.parametrize("dims", [(2, 2, 2), (3, 2, 2), (2, 1, 3)])
def test_continuity_within_stratum(dims):
    d, n, m = dims
    rng = np.random.default_rng(11)
    p = REGISTRY[pmplan.choose_planner(d, n, m).name]
    done = 0
    for _ in range(40):
        q = (rng.normal(size=(m, d)), rng.normal(size=(n, d)), rng.normal(size=(n, d)))
        moved = spec_for(p).perturb_within_stratum(rng, q, 1e-7)
        if moved is None:
            continue
        a, b = pmplan.plan(*q), pmplan.plan(*moved)
        if a.domain != b.domain:
            continue
        ra, rb = pmplan.refine(a), pmplan.refine(b)
        assert ra.domain == rb.domain
        ts = np.linspace(0, 1, 257)
        sup = np.abs(ra.path(ts) - rb.path(ts)).max()
        assert sup < 1e-4, sup  # a discontinuity would move the path by O(1)
        done += 1
    assert done >= 10


def test_continuity_probe_ompl_scene():
    """The probe of benchmarks/refine_bench.py: 1e-6 moves of the starts move the refined path
    by O(1e-6)."""
    rng = np.random.default_rng(2)
    sups = []
    for _ in range(12):
        s = rng.uniform(0.1, 0.9, (2, 2))
        g = rng.uniform(0.1, 0.9, (2, 2))
        a = _ompl_refined(s, g)
        b = _ompl_refined(s + 1e-6 * rng.normal(size=s.shape), g)
        if a is not None and b is not None and a.domain == b.domain:
            ts = np.linspace(0, 1, 201)
            sups.append(np.abs(a.path(ts) - b.path(ts)).max())
    assert sups and max(sups) < 1e-4


# --- equivariance -----------------------------------------------------------------------

@settings(max_examples=20, deadline=None)
@given(data=st.data(), k=st.integers(-40, 40))
def test_power_of_two_scaling_bitwise(data, k):
    o, s, g = data.draw(queries(2, 2, 2))
    f = 2.0**k
    a = pmplan.plan(o, s, g, lift="scene", refine=True, radius=0.01, obstacle_radius=0.0)
    b = pmplan.plan(o * f, s * f, g * f, lift="scene", refine=True, radius=0.01 * f,
                    obstacle_radius=0.0)
    assert np.array_equal(a.path.waypoints * f, b.path.waypoints)
    assert a.respects_radius == b.respects_radius and a.clearance * f == b.clearance


def test_translation_rotation_scaling_to_tolerance():
    rng = np.random.default_rng(7)
    for _ in range(10):
        o, s, g = rng.normal(size=(2, 2)), rng.normal(size=(2, 2)), rng.normal(size=(2, 2))
        a = pmplan.plan(o, s, g, lift="scene", refine=True)
        th = rng.uniform(0, 2 * np.pi)
        rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        shift, scale = rng.normal(size=2), 3.7

        def tf(x, rot=rot, shift=shift, scale=scale):
            return scale * x @ rot.T + shift

        b = pmplan.plan(tf(o), tf(s), tf(g), lift="scene", refine=True)
        if a.domain != b.domain:
            continue  # the rotation moved the query across a stratum (the frame uses e_d)
        assert np.allclose(tf(a.path.waypoints), b.path.waypoints, atol=1e-7 * scale)


# --- kernel == reference ------------------------------------------------------------------

@pytest.mark.parametrize("dims", [(2, 4, 2), (3, 2, 3), (2, 1, 3), (8, 2, 2), (5, 3, 2)])
@pytest.mark.parametrize("wp,steps", [(1, 3), (2, 10), (4, 7)])
@pytest.mark.parametrize("still", [False, True])
def test_kernel_equals_reference_bitwise(dims, wp, steps, still):
    """With every piece cut, and with the planner's still pieces kept one piece
    (Planner.still_pieces): the kernel is the reference, bit for bit."""
    d, n, m = dims
    rng = np.random.default_rng(sum(dims) + wp)
    b = pmplan.plan_batch(rng.normal(size=(5, m, d)), rng.normal(size=(5, n, d)),
                          rng.normal(size=(5, n, d)))
    target = np.stack([b.clearance * 0.7, b.clearance * 1.5], axis=1)
    keep = REGISTRY[b.planner].still_for(b.times) if still else None
    assert (keep is not None) == (still and b.times.ndim == 1)  # (planar_three: per query)
    t1, x1 = refine_paths(b.times, b.waypoints, m, 2, target, wp, steps, None, keep)
    t2, x2 = refine_batch(b.times, b.waypoints, m, 2, target, wp, steps, None, keep)
    assert np.array_equal(t1, t2) and np.array_equal(x1, x2)
    assert x1.shape[1] == (b.times.shape[-1] - 1) * wp + 1 - (wp - 1) * sum(keep or ())


@pytest.mark.parametrize("dims", [(2, 4, 2), (3, 3, 3), (2, 8, 4)])
@pytest.mark.parametrize("wp,steps", [(1, 3), (2, 10)])
def test_kernel_equals_reference_bitwise_with_walls(dims, wp, steps):
    """With a workspace's walls (limits that cut through the raw paths, so that both the walls'
    pushes and their holds act) the kernel is the reference, bit for bit."""
    d, n, m = dims
    rng = np.random.default_rng(10 * sum(dims) + wp)
    b = pmplan.plan_batch(rng.normal(size=(5, m, d)), rng.normal(size=(5, n, d)),
                          rng.normal(size=(5, n, d)))
    target = np.stack([b.clearance * 0.7, b.clearance * 1.5], axis=1)
    lo = b.waypoints.min(axis=(1, 2))
    hi = b.waypoints.max(axis=(1, 2))
    walls = np.stack([lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo)], axis=1)  # (5, 2, d)
    t1, x1 = refine_paths(b.times, b.waypoints, m, 2, target, wp, steps, walls)
    t2, x2 = refine_batch(b.times, b.waypoints, m, 2, target, wp, steps, walls)
    assert np.array_equal(t1, t2) and np.array_equal(x1, x2)
    _, free = refine_paths(b.times, b.waypoints, m, 2, target, wp, steps)
    assert not np.array_equal(free, x1)  # (the walls acted)


@pytest.mark.parametrize("walled", [False, True])
def test_kernel_equals_reference_bitwise_for_a_crowd_in_the_plane(walled):
    """More than CROWD robots in the plane: the crowd's clearing-only steps (CROWD_FINAL of
    the steps, grid.final_steps) are the same in the kernel and the reference, bit for bit."""
    from pmplan.refine.grid import CROWD, final_steps

    n, m = CROWD + 1, 2
    assert final_steps(4, n, 2) > final_steps(4, n, 3)  # (the crowd's, not the default's)
    rng = np.random.default_rng(CROWD + walled)
    b = pmplan.plan_batch(rng.normal(size=(2, m, 2)), rng.normal(size=(2, n, 2)),
                          rng.normal(size=(2, n, 2)))
    target = np.stack([b.clearance * 0.7, b.clearance * 1.5], axis=1)
    walls = None
    if walled:
        lo, hi = b.waypoints.min(axis=(1, 2)), b.waypoints.max(axis=(1, 2))
        walls = np.stack([lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo)], axis=1)
    t1, x1 = refine_paths(b.times, b.waypoints, m, 2, target, 2, 4, walls)
    t2, x2 = refine_batch(b.times, b.waypoints, m, 2, target, 2, 4, walls)
    assert np.array_equal(t1, t2) and np.array_equal(x1, x2)


@pytest.mark.parametrize("c", [1e-3, 1e-6, 1e-9, 1e-12])
@pytest.mark.parametrize("shift", [0.0, 0.1])
def test_a_pair_that_nearly_touches_mid_piece_is_pushed_out(c, shift):
    """Two robots that pass each other head-on, ``c`` apart in the middle of long pieces (0.5
    apart at the pieces' ends), are pushed out to their target by both backends at the default
    effort: the push of a piece goes along its push point, the closest point to within
    LAMBDA h^2 / |v|^2 here, outward along the piece. (Along the soft closest point, a few per cent of the piece away, the push was
    nearly along the piece and the pair's own directional budget held it at c for c <= 1e-6.)"""
    wp = np.zeros((1, 4, 4, 2))
    wp[0, :, 0], wp[0, :, 1] = [0.0, 0.9], [0.0, -0.9]  # two obstacles far off
    wp[0, :, 2] = [[-0.5, 0.0], [-0.25, 0.0], [0.25, 0.0], [0.5, 0.0]]
    mid = np.array([shift, c])
    wp[0, :, 3] = [mid + [0.9, 0.0], mid + [0.45, 0.0], mid - [0.3, 0.0], mid - [0.6, 0.0]]
    times = np.array([0.0, 1 / 3, 2 / 3, 1.0])
    a, b, _ = pairs(4, 2)
    assert piece_minima(wp, a, b).min(axis=1)[0, -1] == pytest.approx(c, rel=0.02)
    target = np.array([[0.1, 0.05]])
    _, x1 = refine_paths(times, wp, 2, 2, target, DEFAULT_WAYPOINTS, DEFAULT_STEPS)
    _, x2 = refine_batch(times, wp, 2, 2, target, DEFAULT_WAYPOINTS, DEFAULT_STEPS)
    assert np.array_equal(x1, x2)
    dmin = piece_minima(x1, a, b).min(axis=1)[0]
    assert dmin[-1] >= 0.1 and dmin[:-1].min() >= 0.05


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-4, 4), dx=st.floats(-4, 4), other=st.floats(-4, 4),
       lo=st.floats(-3, 0), width=st.floats(0.5, 6), e=st.sampled_from([1e-6, 1e-9, 1e-12]))
def test_the_walls_hold_is_a_continuous_scale_that_keeps_a_share_of_the_room(x, dx, other, lo,
                                                                              width, e):
    """The walls' scale of a clearing move: in [WALL_SLIDE, 1]; the held move goes toward a
    limit at most the room it has there plus WALL_SLIDE times its largest coordinate (no
    underflow for a tiny move); and it is Lipschitz
    (a move of the point or of its push by e changes the held move by O(e), at every size)."""
    walls = np.array([[[lo, -10.0], [lo + width, 10.0]]])  # (1, 2, d)

    def held(px, pdx):
        xx = np.array([[[0.0, 0.0], [px, 0.0]]])[None]  # (B, W, P, d): one obstacle, one robot
        delta = np.array([[[0.0, 0.0], [pdx, other]]])[None]
        sc = _wall_scale(xx, delta, 1, walls)[0, 0, 0]
        return sc, sc * np.array([pdx, other])

    sc, move = held(x, dx)
    assert WALL_SLIDE <= sc <= 1.0
    slide = WALL_SLIDE * max(abs(dx), abs(other))
    assert -move[0] <= max(x - lo, 0.0) + slide + 1e-12
    assert move[0] <= max(lo + width - x, 0.0) + slide + 1e-12
    for px, pdx in ((x + e, dx), (x, dx + e)):
        assert np.abs(held(px, pdx)[1] - move).max() <= 20.0 * e + 1e-15


@settings(max_examples=10, deadline=None)
@given(data=st.data())
def test_kernel_equals_reference_degenerate_sequences(data):
    o, s, g = data.draw(queries(2, 2, 2, degenerate=True))
    raw = pmplan.plan_sequence_batch(o[None], [s[None], g[None], s[None]])
    a = pmplan.refine(raw, radius=0.0)
    b = pmplan.refine(raw, radius=0.0, backend="numpy")
    assert np.array_equal(a.waypoints, b.waypoints) and np.array_equal(a.clearance, b.clearance)
    assert np.array_equal(a.respects_radius, b.respects_radius)


# --- batches ------------------------------------------------------------------------------

def test_batch_matches_single_and_slices():
    rng = np.random.default_rng(3)
    o, s, g = rng.normal(size=(6, 2, 2)), rng.normal(size=(6, 3, 2)), rng.normal(size=(6, 3, 2))
    batch = pmplan.plan_batch(o, s, g, refine=True, radius=0.001, workers=2)
    assert batch.refined.all() and (batch.radius == 0.001).all()
    for i in range(6):
        one = pmplan.plan(o[i], s[i], g[i], refine=True, radius=0.001)
        assert np.array_equal(batch[i].path.waypoints, one.path.waypoints)
        assert batch[i].respects_radius == one.respects_radius
        assert batch[i].robot_distance == one.robot_distance
    sub = batch[1:4]
    assert isinstance(sub, pmplan.PlanBatch) and len(sub) == 3
    assert np.array_equal(sub.robot_distance, batch.robot_distance[1:4])
    assert sub.refined.all() and sub[0].refined
    mask = batch[batch.domain == batch.domain[0]]
    assert mask.refined.all()
    # unrefined batches report the same quantities, with radii 0
    raw = pmplan.plan_batch(o, s, g)
    assert not raw.refined.any() and (raw.radius == 0).all() and raw.respects_radius.all()
    assert np.all(raw.clearance <= np.minimum(raw.robot_distance, raw.obstacle_distance))


@pytest.mark.parametrize("dims", [(8, 2, 2), (9, 1, 3)])
def test_high_dimension_numpy_planner(dims):
    """d >= 8: the planner's numpy path, the kernel's refinement, the numpy measurement."""
    d, n, m = dims
    rng = np.random.default_rng(d)
    o, s, g = rng.normal(size=(m, d)), rng.normal(size=(n, d)), rng.normal(size=(n, d))
    raw = pmplan.plan(o, s, g)
    ref = pmplan.refine(raw, radius=0.01)
    _check_refined(raw, ref, [s, g], 0.01)
    assert np.array_equal(ref.path.waypoints,
                          pmplan.refine(raw, radius=0.01, backend="numpy").path.waypoints)


def test_empty_batch():
    e = pmplan.plan_batch(np.zeros((0, 2, 2)), np.zeros((0, 2, 2)), np.zeros((0, 2, 2)),
                          refine=True, radius=0.1)
    assert len(e) == 0 and e.waypoints.shape[0] == 0 and e.respects_radius.shape == (0,)
    assert len(pmplan.refine(pmplan.plan_batch(np.zeros((0, 2, 3)), np.zeros((0, 1, 3)),
                                               np.zeros((0, 1, 3))))) == 0


def test_planar_three_batch_per_query_times():
    rng = np.random.default_rng(4)
    o, s, g = rng.normal(size=(8, 3, 2)), rng.normal(size=(8, 1, 2)), rng.normal(size=(8, 1, 2))
    raw = pmplan.plan_batch(o, s, g)
    ref = pmplan.refine(raw)
    assert raw.planner == ref.planner == "planar_three" and ref.times.ndim == 2
    for i in range(8):
        _check_refined(raw[i], ref[i], [s[i], g[i]])


def test_extreme_magnitudes_refined_scaled():
    o = np.array([[0.0, 0.0], [2.0, 0.0]]) * 2.0**600
    s, g = np.array([[0.0, 1.0]]) * 2.0**600, np.array([[1.0, -1.0]]) * 2.0**600
    ref = pmplan.plan(o, s, g, lift="scene", refine=True)
    small = pmplan.plan(o * 2.0**-600, s * 2.0**-600, g * 2.0**-600, lift="scene", refine=True)
    assert np.array_equal(ref.path.waypoints, small.path.waypoints * 2.0**600)
    assert ref.clearance > 0


# --- parameters ---------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs,match", [
    ({"radius": -1.0}, "radius"), ({"radius": True}, "radius"),
    ({"radius": float("nan")}, "radius"), ({"radius": float("inf")}, "radius"),
    ({"radius": "1"}, "radius"), ({"obstacle_radius": -0.5}, "obstacle_radius"),
    ({"steps": 0}, "steps"), ({"steps": 2.0}, "steps"), ({"steps": True}, "steps"),
    ({"waypoints": 3}, "waypoints"), ({"waypoints": 0}, "waypoints"),
    ({"waypoints": 128}, "waypoints"), ({"workers": 0}, "workers"),
    ({"progress": "yes"}, "progress"), ({"backend": "gpu"}, "backend"),
])
def test_bad_parameters(kwargs, match):
    raw = pmplan.plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    with pytest.raises(InputError, match=match):
        pmplan.refine(raw, **kwargs)


def test_bad_flags_and_arguments():
    q = ([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    with pytest.raises(InputError, match="refine=True"):
        pmplan.plan(*q, radius=0.1)  # radii without refine: refused, not ignored
    with pytest.raises(InputError, match="refine"):
        pmplan.plan(*q, refine=1)
    raw = pmplan.plan_batch(*(np.asarray(x, dtype=float)[None] for x in q))
    with pytest.raises(InputError, match="out="):
        pmplan.plan_batch(*(np.asarray(x, dtype=float)[None] for x in q), refine=True, out=raw)
    with pytest.raises(InputError, match="already refined"):
        pmplan.refine(pmplan.plan(*q, refine=True))
    with pytest.raises(InputError, match="Plan or a PlanBatch"):
        pmplan.refine(np.zeros((3, 3, 2)))
    with pytest.raises(CollisionError, match="x1 and x2 .* 2 \\* radius"):
        pmplan.plan([[0, 0], [2, 0]], [[0, 1], [0, 1.5]], [[1, -1], [3, 3]], refine=True,
                    radius=0.3)
    with pytest.raises(CollisionError, match="configuration 2: points o1 and x1"):
        pmplan.plan_sequence([[0, 0], [2, 0]], [[[0, 1]], [[0.1, 0.1]], [[1, -1]]],
                             refine=True, radius=0.1, obstacle_radius=0.1)


def test_defaults_documented_and_schedule():
    assert check_parameters(0, 0, None, None) == (0.0, 0.0, DEFAULT_WAYPOINTS, DEFAULT_STEPS)
    assert sum(k for _, k in schedule(8, 50)) == 50
    assert [s for s, _ in schedule(8, 50)] == [1, 2, 4, 8]
    assert f"= {DEFAULT_WAYPOINTS}" in pmplan.refine.__doc__
    assert f"= {DEFAULT_STEPS}" in pmplan.refine.__doc__


def test_radius_report_exact_at_ties():
    """A robot passing an obstacle at exactly distance 1: respected at 1, not at 1 + ulp."""
    wp = np.array([[[0.0, 0.0], [-1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0]]])[None]
    _rd, od, ok = radius_report(wp, 1, 0.5, 0.5)
    assert od[0] == 1.0 and ok[0]
    _, _, ok = radius_report(wp, 1, 0.5, np.nextafter(0.5, 1))
    assert not ok[0]
    assert grid.KAPPA > 0 and 0 < R.PHI < 1


def _pieces_exact(wp: np.ndarray, a, b) -> np.ndarray:
    """The exact squared minimum of every pair on every piece of paths (B, W, P, d), as floats
    rounded from rationals (B, W-1, pairs)."""
    out = np.empty((wp.shape[0], wp.shape[1] - 1, len(a)))
    for i in range(wp.shape[0]):
        for j in range(wp.shape[1] - 1):
            for q, (pa, pb) in enumerate(zip(a, b)):
                out[i, j, q] = float(exact_segment_dist2(wp[i, j, pa], wp[i, j, pb],
                                                          wp[i, j + 1, pa], wp[i, j + 1, pb]))
    return out


@settings(max_examples=60, deadline=None)
@given(data=st.data(), integer=st.booleans(), d=st.sampled_from([2, 3]),
       robots=st.integers(1, 3), w=st.integers(3, 6), phi=st.sampled_from([0.0, 0.25, 0.9]),
       gain=st.sampled_from([0.3, 3.0, 30.0]))
def test_clearing_scale_keeps_every_floor(data, integer, d, robots, w, phi, gain):
    """A clearing move scaled by ``_clear_scale`` (isotropic or directional allowance) keeps
    every pair above its floor F on every piece, exactly (rational distances), for random and
    integer (degenerate: collinear, head-on, zero-length pieces) paths and moves of any size."""
    m, p = 2, 2 + robots
    if integer:
        coords = st.integers(-3, 3).map(float)
    else:
        coords = st.floats(-1, 1, allow_nan=False, allow_subnormal=False)
    x = np.array(data.draw(st.lists(coords, min_size=w * p * d, max_size=w * p * d)))
    x = x.reshape(1, w, p, d)
    x[:, :, :m] = x[:, :1, :m]  # the obstacles stay fixed
    a, b, c = pairs(p, m)
    d0 = R.piece_minima(x, a, b)
    if not (d0 > 1e-6).all():
        return  # a colliding "path": not an input of the refinement
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    delta = gain * rng.normal(size=x.shape)
    delta[:, :, :m] = 0.0
    floor = phi * d0
    gap = np.maximum(d0 - floor, 0.0)
    cap = R._caps(x, a, b, c, (R.SHARE * c) * gap)
    s = R._clear_scale(x, delta, m, a, b, c, d0, gap, cap)
    assert ((s >= 0) & (s <= 1)).all()
    moved = x.copy()
    moved[:, :, m:] = x[:, :, m:] + delta[:, :, m:] * s[:, :, m:, None]
    after2 = _pieces_exact(moved, a, b)
    # the floor, up to the rounding of the float move (relative 1e-9 of the distances)
    assert (after2 >= (floor * floor) * (1 - 1e-9) - 1e-12 * d0 * d0).all()


def test_clearing_directional_allowance_pushes_a_near_contact_out():
    """A robot whose path nearly touches an obstacle head-on at a waypoint (distance 1e-4) is
    pushed out, along the path's turn, by far more than its isotropic cap, and stays clear.
    (Below about 1e-5 of the path's extent the room above F' is within the budget's rounding
    slack, and the allowance is off: tests/test_refine_exact.py.)"""
    c_near = 1e-4
    x = np.zeros((1, 3, 3, 2))
    x[:, :, 1] = [5.0, 5.0]  # the second obstacle, far away
    x[0, :, 2] = [[1.0, 0.0], [c_near, 0.0], [1.0, 0.5]]  # in, nearly touching 0, out
    a, b, c = pairs(3, 2)
    d0 = R.piece_minima(x, a, b)
    floor = R.PHI * d0
    gap = np.maximum(d0 - floor, 0.0)
    cap = R._caps(x, a, b, c, (R.SHARE * c) * gap)
    delta = np.zeros(x.shape)
    delta[0, 1, 2] = [0.1, 0.025]  # outward, between the two pieces
    s = R._clear_scale(x, delta, 2, a, b, c, d0, gap, cap)
    moved = x.copy()
    moved[:, :, 2:] += delta[:, :, 2:] * s[:, :, 2:, None]
    step = np.hypot(*(moved[0, 1, 2] - x[0, 1, 2]))
    assert step > 1e3 * cap[0, 1, 2] and step > 0.05
    assert (R.piece_minima(moved, a, b) >= floor).all()


@settings(max_examples=200, deadline=None)
@given(data=st.data(), d=st.sampled_from([2, 3]), start=st.booleans())
def test_directional_budget_is_the_exact_minimum(data, d, start):
    """``_budget`` is ``min(1, min over t of h(t) / g(t))`` (g > 0): never above the ratio at
    any of 20,001 sampled t (safe), and within 1e-3 of the sampled minimum (tight), for random
    and integer pieces and moves; the kernel's version gives the same bits."""
    from pmplan.refine.kernel import _budget as kernel_budget

    f = data.draw(st.sampled_from([st.floats(-1, 1, allow_subnormal=False),
                                   st.integers(-3, 3).map(float)]))
    r0 = np.array(data.draw(st.lists(f, min_size=d, max_size=d)))
    v = np.array(data.draw(st.lists(f, min_size=d, max_size=d)))
    al, be = data.draw(f), data.draw(f)
    ts = np.linspace(0.0, 1.0, 20001)
    rt = r0[None] + ts[:, None] * v[None]
    dist = np.sqrt((rt * rt).sum(-1))
    if not dist.min() > 1e-3:
        return  # the pair touches: not a path the refinement moves
    f2 = data.draw(st.floats(0.0, 0.99)) * dist.min() * 0.999
    nterms = data.draw(st.sampled_from([2.0, 4.0]))
    got = R._budget(r0[None], v[None], np.array([f2]), nterms, np.array([al]), np.array([be]),
                    start)[0]
    assert got == kernel_budget(r0, v, f2, nterms, al, be, start)
    g = ((1.0 - ts) if start else ts) * (al + ts * be)
    h = (dist * dist - f2 * f2) / (2.0 * nterms)
    pos = g > 0
    brute = min(1.0, (h[pos] / g[pos]).min()) if pos.any() else 1.0
    assert got <= brute * (1 + 1e-9)
    assert got >= brute * (1 - 1e-3) - 1e-12


def test_the_raw_clearance_is_reported_beside_the_refined_one():
    """Issue 24 item 2: a refined plan (single, batch, row of a batch) carries the clearance
    of the plan it refined; an unrefined plan's is its own clearance."""
    o, s, g = OMPL_OBSTACLES, np.array([[0.1, 0.5], [0.5, 0.2]]), np.array([[0.9, 0.5], [0.5, 0.8]])
    raw = pmplan.plan(o, s, g, lift=0.1)
    assert raw.raw_clearance == raw.clearance
    ref = pmplan.refine(raw, radius=0.02)
    assert ref.raw_clearance == raw.clearance and ref.clearance != raw.clearance
    rng = np.random.default_rng(3)
    ob, sb, gb = (rng.uniform(0, 1, (6, k, 2)) for k in (2, 3, 3))
    rawb = pmplan.plan_batch(ob, sb, gb, lift=0.1)
    assert np.array_equal(rawb.raw_clearance, rawb.clearance)
    refb = pmplan.refine(rawb)
    assert np.array_equal(refb.raw_clearance, rawb.clearance)
    assert refb[2].raw_clearance == rawb.clearance[2]
    assert np.array_equal(refb[1:4].raw_clearance, rawb.clearance[1:4])


@pytest.mark.parametrize("n, d", [(8, 2), (9, 2), (16, 2), (9, 3)])
def test_a_crowd_gets_the_crowds_default_effort(n, d, monkeypatch):
    """More than CROWD robots: the defaults are (CROWD_WAYPOINTS, CROWD_STEPS) in the plane and
    (CROWD_WAYPOINTS, SPACE_CROWD_STEPS) in d >= 3, bit for bit the same refinement as asking
    for them (in space not the plane's); up to CROWD, DEFAULT_WAYPOINTS and PLANE_STEPS in the
    plane (more than SETTLE robots). The batch, the single plan and the refine() call agree."""
    from pmplan.refine import (CROWD, CROWD_STEPS, CROWD_WAYPOINTS, DEFAULT_STEPS,
                               DEFAULT_WAYPOINTS, PLANE_STEPS, SETTLE, SPACE_CROWD_STEPS,
                               default_effort)

    crowd = n > CROWD
    steps = CROWD_STEPS if d == 2 else SPACE_CROWD_STEPS
    assert SETTLE < 8 <= CROWD and PLANE_STEPS != DEFAULT_STEPS
    s, k = (CROWD_WAYPOINTS, steps) if crowd else (DEFAULT_WAYPOINTS, PLANE_STEPS)
    assert default_effort(n, d) == (s, k) and (s, k) != (DEFAULT_WAYPOINTS // 2, DEFAULT_STEPS)
    rng = np.random.default_rng(n)
    o, x, y = (rng.uniform(0, 10, size=(3, 6, d)), rng.uniform(0, 10, size=(3, n, d)),
               rng.uniform(0, 10, size=(3, n, d)))
    kw = dict(radius=1e-3, obstacle_radius=1e-3)
    # the refined plans' default unit and planner
    planner = pmplan.choose_planner(d, n, 6, refining=True).name
    raw = pmplan.plan_batch(o, x, y, lift=2e-3, planner=planner)
    default = pmplan.refine(raw, **kw)
    asked = pmplan.refine(raw, waypoints=s, steps=k, **kw)
    other = pmplan.refine(raw, waypoints=2 * s, steps=k, **kw)
    still = REGISTRY[planner].still_for(raw.times)
    assert default.waypoints.shape[1] == raw_positions(raw.times.shape[-1], s, still)[-1] + 1
    assert default.waypoints.tobytes() == asked.waypoints.tobytes()
    assert default.waypoints.shape != other.waypoints.shape
    if crowd and d > 2:  # a crowd in space does not get the plane's steps (both 112 today)
        import importlib

        grid = importlib.import_module("pmplan.refine.grid")
        monkeypatch.setattr(grid, "CROWD_STEPS", CROWD_STEPS + 8)
        assert default_effort(n, d) == (s, SPACE_CROWD_STEPS) != default_effort(n, 2)
        assert pmplan.refine(raw, **kw).waypoints.tobytes() == default.waypoints.tobytes()
        monkeypatch.undo()
    full = pmplan.plan_batch(o, x, y, refine=True, **kw)
    assert full.waypoints.tobytes() == default.waypoints.tobytes()
    one = pmplan.plan(o[0], x[0], y[0], refine=True, **kw)
    asked_one = pmplan.refine(pmplan.plan(o[0], x[0], y[0], lift=2e-3, planner=planner),
                              waypoints=s, steps=k, **kw)
    assert one.path.waypoints.tobytes() == asked_one.path.waypoints.tobytes()
    # a steps-only request keeps the crowd's waypoints, and the reverse
    assert pmplan.refine(raw, steps=3, **kw).waypoints.shape == default.waypoints.shape


@pytest.mark.parametrize("d", [2, 3, 4, 5])
def test_the_kernels_piece_minima_are_the_references(d):
    """``kernels.measure.minima`` (one loop over every piece of every pair, d = 2 and 3 written
    out) gives :func:`~pmplan.refine.grid.piece_minima` bit for bit: random paths, a pair at
    rest (v = 0), a piece through contact, integer paths (exact ties) and tiny and huge
    magnitudes."""
    from pmplan.kernels.measure import minima, minima_scratch

    rng = np.random.default_rng(d)
    for w, p, m in ((2, 3, 1), (8, 14, 6), (15, 9, 4)):
        a, b, _ = pairs(p, m)
        for scale in (1.0, 1e-150, 1e150):
            x = rng.normal(size=(w, p, d)) * scale
            x[:, 1] = x[0, 1]  # a point at rest
            x[:, 2] = x[:, 0] if p > 2 else x[:, 2]  # a pair at rest, touching
            xi = rng.integers(-2, 3, size=(w, p, d)).astype(float)
            for path in (x, xi):
                got = np.empty((w - 1, a.shape[0]))
                minima(path, a, b, got, minima_scratch(w, d, a.shape[0]))
                want = piece_minima(path[None], a, b)[0]
                assert np.array_equal(got.view(np.int64), want.view(np.int64))
        with pytest.raises(ValueError, match="scratch"):  # (not a write beyond it)
            minima(x, a, b, got, np.empty((d, w)))


# --- the still pieces ----------------------------------------------------------------------

@pytest.mark.parametrize("name", ["obstacle_line", "obstacle_line_compact",
                                  "obstacle_line_oneside"])
@pytest.mark.parametrize("r", [2, 3])
def test_still_pieces_are_still_for_generic_queries_and_refined_whole(name, r):
    """What the obstacle-line planners declare still (Planner.still_pieces: the
    desingularization and its reverse, the first and last piece of every leg) moves no point
    for a generic query and moves robots of a query where two share a column; either way the
    refined path keeps each still piece one piece, passes its configurations where the raw
    waypoints are in its grid, and is certified (the degenerate one too)."""
    planner = REGISTRY[name]
    still = planner.still_pieces(r)
    times = planner.path_times(r)
    assert still.shape == (times.shape[0] - 1,) and still.sum() == 2 * (r - 1)
    assert planner.still_for(times) == tuple(still.tolist())
    assert planner.still_for(pmplan.path.cut_along(times, 2)) == tuple(np.repeat(still, 2))
    rng = np.random.default_rng(r)
    o = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 2.0]])
    generic = [rng.normal(size=(3, 2)) * 3 for _ in range(r)]
    shared = [np.array([[0.25, 1.0], [0.25, -1.0], [0.0, 1.5]]), *generic[1:]]  # one column
    for configs, moves in ((generic, False), (shared, True)):
        raw = pmplan.plan_sequence(o, configs, planner=name)
        wp = raw.path.waypoints
        moved = [not np.array_equal(wp[j], wp[j + 1]) for j in np.flatnonzero(still)]
        assert any(moved) == moves
        ref = pmplan.refine(raw, radius=0.01)
        at = raw_positions(times.shape[0], DEFAULT_WAYPOINTS, tuple(still))
        assert ref.path.times.shape[0] == at[-1] + 1 < (times.shape[0] - 1) * DEFAULT_WAYPOINTS + 1
        assert np.array_equal(ref.path.times[at], times)
        assert (np.diff(at)[still] == 1).all() and (np.diff(at)[~still] == DEFAULT_WAYPOINTS).all()
        for kj, conf in zip(planner.fixed_waypoints(times).tolist(), configs):
            assert np.array_equal(ref.path.waypoints[at[kj], 3:], conf)
        _check_refined(raw, ref, configs, radius=0.01)
