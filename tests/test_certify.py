"""The certificate of a piecewise-linear motion (Mathematics §6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.certify import certify, clearance, segment_clearance

seeds = st.integers(0, 2**32 - 1)


def random_waypoints(rng, b, k, p, d, m):
    wp = rng.normal(size=(b, k, p, d)) * 3
    wp[:, :, :m] = wp[:, :1, :m]  # obstacles fixed
    return wp


def sampled_min_distance(wp, m, samples=400):
    """min over dense samples (each piece, both ends included) of pairwise distances."""
    b, k, p, d = wp.shape
    s = np.linspace(0, 1, samples)
    best = np.full(b, np.inf)
    lip = np.zeros(b)  # bound on the speed of a relative position, for the upper check
    for i in range(k - 1):
        a, c = wp[:, i], wp[:, i + 1]
        pts = a[:, None] + s[None, :, None, None] * (c - a)[:, None]  # (b, S, p, d)
        diff = pts[:, :, :, None] - pts[:, :, None, :]
        dist = np.linalg.norm(diff, axis=-1)
        iu = np.triu_indices(p, 1)
        keep = iu[1] >= m
        dd = dist[:, :, iu[0][keep], iu[1][keep]]
        best = np.minimum(best, dd.min(axis=(1, 2)))
        vel = (c - a)[:, :, None] - (c - a)[:, None, :]
        lip = np.maximum(lip, np.linalg.norm(vel, axis=-1).max(axis=(1, 2)))
    if m >= 2:
        o = wp[:, 0, :m]
        od = np.linalg.norm(o[:, :, None] - o[:, None, :], axis=-1)
        od[:, np.arange(m), np.arange(m)] = np.inf
        best = np.minimum(best, od.min(axis=(1, 2)))
    return best, lip / (samples - 1)


@settings(max_examples=25)
@given(seed=seeds, k=st.integers(2, 5), p=st.integers(2, 5), d=st.integers(2, 3),
       m=st.integers(0, 2))
def test_clearance_matches_dense_sampling(seed, k, p, d, m):
    rng = np.random.default_rng(seed)
    m = min(m, p - 1)
    wp = random_waypoints(rng, 6, k, p, d, m)
    clr = clearance(wp, m)
    sampled, step = sampled_min_distance(wp, m)
    # a lower bound on every sample ...
    assert np.all(sampled >= clr - 1e-12)
    # ... attained: some sample is within half a step of relative motion of the minimum
    assert np.all(sampled <= clr + step / 2 + 1e-12)


@settings(max_examples=25)
@given(seed=seeds)
def test_clearance_near_collision_paths(seed):
    """Robots aimed at a point (grazing it by a tiny offset) are still measured right."""
    rng = np.random.default_rng(seed)
    target = rng.normal(size=2)
    off = rng.choice([1e-3, 1e-8, 1e-12]) * rng.normal(size=2)
    a, c = target - rng.normal(size=2), None
    c = 2 * target - a + off  # passes within about |off| of target
    wp = np.array([[[target, a], [target, c]]])
    clr = clearance(wp, 1)[0]
    # exact distance from target to the segment [a, c]
    v = c - a
    t = np.clip(np.dot(target - a, v) / np.dot(v, v), 0, 1)
    want = np.linalg.norm(a + t * v - target)
    assert clr == pytest.approx(want, rel=1e-6, abs=1e-15)


def test_exact_zero_through_an_obstacle():
    # robot from (-1, 0) to (1, 0) through the obstacle at the origin, at t = 1/2
    wp = np.array([[[[0, 0], [5, 5], [-1, 0]], [[0, 0], [5, 5], [1, 0]]]], dtype=float)
    assert clearance(wp, 2)[0] == 0.0


@pytest.mark.parametrize("scale", [1.0, 3.0, 2.0**-20, 1e5, 2.0**40])  # exact scalings
def test_exact_zero_at_non_dyadic_times(scale):
    """Meetings at t = 1/3 and t = 2/7 (not representable as floats) are exact zeros."""
    # robot through obstacle (0, 0) at t = 1/3
    a = np.array([[[[0, 0], [-1, 0]], [[0, 0], [2, 0]]]], dtype=float) * scale
    # two robots meeting at (1, 0) at t = 1/3: x1 (0,0)->(3,0), x2 (1,1)->(1,-2)
    b = np.array([[[[9, 9], [0, 0], [1, 1]], [[9, 9], [3, 0], [1, -2]]]], dtype=float) * scale
    # a robot meeting a point at t = 2/7 on a diagonal
    c = np.array([[[[2, 2], [0, 0]], [[2, 2], [7, 7]]]], dtype=float) * scale
    assert clearance(a, 1)[0] == 0.0
    assert clearance(b, 1)[0] == 0.0
    assert clearance(c, 1)[0] == 0.0
    for wp, m in ((a, 1), (b, 1), (c, 1)):
        _, ok = certify(wp, wp[:, 0], wp[:, -1], m)
        assert not ok[0]


@pytest.mark.parametrize("offset", [1e-300, 1e-310, 5e-324, 1e-17, 2.0**-60])
def test_tiny_positive_clearance_is_positive(offset):
    wp = np.array([[[[0, 0], [-1, offset]], [[0, 0], [3, offset]]]], dtype=float)
    clr = clearance(wp, 1)[0]
    assert clr > 0
    assert clr == pytest.approx(offset, rel=1e-9)
    _, ok = certify(wp, wp[:, 0], wp[:, -1], 1)
    assert ok[0]


def test_tiny_offset_between_moving_robots():
    # two robots crossing, offset by 1e-300 in y, meeting x = 1 at t = 1/3 both
    wp = np.array([[[[9, 9], [0, 0], [1, 1]], [[9, 9], [3, 0], [1, -2]]]], dtype=float)
    wp[:, :, 1, 1] += 1e-300  # x1 at height 1e-300
    clr = clearance(wp, 1)[0]
    assert 0 < clr <= 1e-300


def test_obstacle_pairs_count():
    wp = np.array([[[[0, 0], [1e-3, 0], [5, 5]], [[0, 0], [1e-3, 0], [6, 5]]]])
    assert clearance(wp, 2)[0] == pytest.approx(1e-3, rel=1e-12)
    assert clearance(wp[:, :, 2:], 0)[0] == np.inf  # a single point never collides


def test_certify_checks_endpoints_and_fixed_obstacles():
    rng = np.random.default_rng(7)
    wp = random_waypoints(rng, 4, 4, 4, 2, 2)
    start, goal = wp[:, 0].copy(), wp[:, -1].copy()
    clr, ok = certify(wp, start, goal, 2)
    np.testing.assert_array_equal(clr, clearance(wp, 2))
    np.testing.assert_array_equal(ok, clr > 0)
    # endpoint mismatch by one bit
    bad_goal = goal.copy()
    bad_goal[1, 3, 0] = np.nextafter(bad_goal[1, 3, 0], np.inf)
    bad_start = start.copy()
    bad_start[2, 2, 1] = np.nextafter(bad_start[2, 2, 1], -np.inf)
    _, ok2 = certify(wp, bad_start, bad_goal, 2)
    np.testing.assert_array_equal(ok2, ok & np.array([True, False, False, True]))
    # a moving obstacle (changes in an interior waypoint only)
    moved = wp.copy()
    moved[3, 2, 1, 0] += 1e-9
    _, ok3 = certify(moved, start, goal, 2)
    assert not ok3[3]
    np.testing.assert_array_equal(ok3[:3], ok[:3])


def test_certify_rejects_non_finite_waypoints():
    wp = np.array([[[[0, 0], [-1, 1]], [[0, 0], [np.nan, 1]], [[0, 0], [1, 1]]]], dtype=float)
    _, ok = certify(wp, wp[:, 0], wp[:, -1], 1)
    assert not ok[0]


@settings(max_examples=20)
@given(seed=seeds, b=st.integers(1, 6))
def test_batch_equals_loop(seed, b):
    rng = np.random.default_rng(seed)
    wp = random_waypoints(rng, b, 4, 4, 2, 2)
    wp[0, 2, 3] = wp[0, 2, 2]  # a collision at a waypoint in query 0
    clr = clearance(wp, 2)
    assert clr[0] == 0.0
    for i in range(b):
        assert clearance(wp[i:i + 1], 2)[0] == clr[i]


def test_segment_clearance_closed_form():
    r0 = np.array([[1.0, 1.0], [1.0, 1.0], [2.0, 0.0]])
    r1 = np.array([[-1.0, 1.0], [3.0, 1.0], [2.0, 0.0]])
    np.testing.assert_allclose(segment_clearance(r0, r1), [1.0, np.sqrt(2), 2.0])


def test_huge_coordinates_do_not_crash():
    wp = np.array([[[[0, 0], [-1e200, 1e200]], [[0, 0], [1e200, 1e200]]]], dtype=float)
    assert clearance(wp, 1)[0] == pytest.approx(1e200)
