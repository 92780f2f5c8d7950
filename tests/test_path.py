"""The path algebra: piecewise-linear paths [0, 1] -> (R^d)^P (pmplan.path)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.path import PiecewiseLinearPath, compose_via_deformations, join, linear


def random_times(rng, k: int, zero_pieces: bool = False) -> np.ndarray:
    inner = np.sort(rng.uniform(0, 1, size=k - 2))
    t = np.concatenate([[0.0], inner, [1.0]])
    if zero_pieces and k > 3:
        t[2] = t[1]  # one zero-duration piece
    return t


def random_path(rng, k=5, p=3, d=2, batch=None, per_path=False, zero_pieces=False):
    shape = () if batch is None else (batch,)
    wp = rng.normal(size=shape + (k, p, d))
    if per_path:
        times = np.stack([random_times(rng, k, zero_pieces) for _ in range(batch)])
    else:
        times = random_times(rng, k, zero_pieces)
    if zero_pieces and k > 3:
        wp[..., 2, :, :] = wp[..., 1, :, :]  # a zero-duration piece joins equal waypoints
    return PiecewiseLinearPath(times, wp)


def reference_eval(times: np.ndarray, wp: np.ndarray, t: float) -> np.ndarray:
    """Evaluate one path at one t, by the definition (the last piece containing t)."""
    k = len(times)
    for i in range(k - 1):
        t0, t1 = times[i], times[i + 1]
        if t0 <= t <= t1 and t1 > t0:
            if t == t1 and i < k - 2:
                continue  # take the later piece at an interior breakpoint
            return wp[i] + (t - t0) / (t1 - t0) * (wp[i + 1] - wp[i])
    # t sits at a breakpoint followed only by zero-duration pieces
    return wp[np.searchsorted(times, t, side="right") - 1]


seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=30)
@given(seed=seeds, k=st.integers(2, 7), zero=st.booleans())
def test_evaluation_matches_definition(seed, k, zero):
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k, zero_pieces=zero)
    ts = np.concatenate([rng.uniform(0, 1, 20), path.times])
    out = path(ts)
    for j, t in enumerate(ts):
        np.testing.assert_allclose(out[j], reference_eval(path.times, path.waypoints, t),
                                   rtol=1e-12, atol=1e-12)


@settings(max_examples=30)
@given(seed=seeds, k=st.integers(2, 7), zero=st.booleans())
def test_breakpoints_return_waypoints(seed, k, zero):
    """Exactly, at t = 0 and at interior breakpoints."""
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k, zero_pieces=zero)
    inner = path.times[:-1]
    got = path(inner)
    for j, t in enumerate(inner):
        # the waypoint of the last breakpoint equal to t (zero-duration pieces have equal ends)
        last = np.flatnonzero(path.times == t)[-1]
        np.testing.assert_array_equal(got[j], path.waypoints[last])
    np.testing.assert_array_equal(path(0.0), path.waypoints[0])
    np.testing.assert_allclose(path(1.0), path.waypoints[-1], rtol=0, atol=1e-15)


def test_end_of_path_is_exact():
    p = linear(np.array([[-0.7, 0.0]]), np.array([[0.1, 0.0]]))
    np.testing.assert_array_equal(p(1.0), [[0.1, 0.0]])


@settings(max_examples=30)
@given(seed=seeds, k=st.integers(2, 6), lam=st.floats(0, 1))
def test_linear_between_breakpoints(seed, k, lam):
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k)
    for i in range(k - 1):
        t0, t1 = path.times[i], path.times[i + 1]
        if t1 <= t0:
            continue
        a, b = rng.uniform(t0, t1, size=2)
        mid = a + lam * (b - a)
        np.testing.assert_allclose(path(mid), path(a) + lam * (path(b) - path(a)), atol=1e-11)


def test_linear_is_straight_motion():
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(2, 4, 3))
    p = linear(a, b)
    for t in (0.0, 0.3, 1.0):
        np.testing.assert_allclose(p(t), a + t * (b - a), atol=1e-15)
    pb = linear(rng.normal(size=(5, 4, 3)), rng.normal(size=(5, 4, 3)))
    assert pb.shape == (5,) and pb.is_batch and not p.is_batch and p.shape == ()


@pytest.mark.parametrize(
    "batch, per_path, tshape",
    [(None, False, t) for t in [(), (1,), (6,), (2, 3)]]
    + [(4, per, t) for per in (False, True) for t in [(), (1,), (6,)]],
)
def test_output_shapes(batch, per_path, tshape):
    rng = np.random.default_rng(1)
    p, d = 3, 2
    path = random_path(rng, k=5, p=p, d=d, batch=batch, per_path=per_path, zero_pieces=True)
    t = rng.uniform(0, 1, size=tshape) if tshape else 0.4
    out = path(t)
    assert out.shape == path.shape + np.shape(t) + (p, d)
    # batch evaluation == evaluating each path
    if batch is not None:
        for b in range(batch):
            np.testing.assert_allclose(out[b], path[b](t), atol=1e-15)


@pytest.mark.parametrize("per_path", [False, True])
def test_batch_2d_t(per_path):
    path = linear(np.zeros((4, 1, 2)), np.ones((4, 1, 2)))
    if per_path:
        path = PiecewiseLinearPath(np.tile([0.0, 1.0], (4, 1)), path.waypoints)
    assert path(np.zeros((2, 3))).shape == (4, 2, 3, 1, 2)


@settings(max_examples=30)
@given(seed=seeds, k=st.integers(2, 6), batch=st.sampled_from([None, 3]), zero=st.booleans())
def test_reversed(seed, k, batch, zero):
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k, batch=batch, zero_pieces=zero)
    rev = path.reversed()
    assert rev is not path
    twice = rev.reversed()
    np.testing.assert_array_equal(twice.waypoints, path.waypoints)
    np.testing.assert_allclose(twice.times, path.times, atol=1e-15)
    ts = rng.uniform(0, 1, 15)
    np.testing.assert_allclose(rev(ts), path(1.0 - ts), atol=1e-12)


@settings(max_examples=30)
@given(seed=seeds, q=st.integers(1, 4), batch=st.sampled_from([None, 3]))
def test_join(seed, q, batch):
    rng = np.random.default_rng(seed)
    paths = [random_path(rng, k=int(rng.integers(2, 5)), batch=batch) for _ in range(q)]
    for i in range(1, q):  # make them chain: start where the previous one ends
        wp = paths[i].waypoints.copy()
        wp[..., 0, :, :] = paths[i - 1].waypoints[..., -1, :, :]
        paths[i] = PiecewiseLinearPath(paths[i].times, wp)
    at = np.sort(rng.uniform(0.05, 0.95, q - 1))
    if q > 1 and np.any(np.diff(at) <= 0):
        return
    bounds = np.concatenate([[0.0], at, [1.0]])
    joined = join(paths, list(at))
    assert np.all(np.diff(joined.times, axis=-1) >= 0)
    assert np.all(joined.times[..., 0] == 0.0) and np.all(joined.times[..., -1] == 1.0)
    np.testing.assert_array_equal(joined(0.0), paths[0](0.0))
    np.testing.assert_array_equal(joined(1.0), paths[-1](1.0))
    for i, p in enumerate(paths):
        lo, hi = bounds[i], bounds[i + 1]
        local = rng.uniform(0, 1, 7)
        np.testing.assert_allclose(joined(lo + local * (hi - lo)), p(local), atol=1e-9)
    # the method form is the same function
    if q > 1:
        np.testing.assert_array_equal(paths[0].join(*paths[1:], at=list(at)).waypoints,
                                      joined.waypoints)


def test_join_default_is_equal_durations():
    a, b, c = np.zeros((1, 2)), np.ones((1, 2)), np.full((1, 2), 3.0)
    j = linear(a, b).join(linear(b, c))
    np.testing.assert_array_equal(j.times, [0.0, 0.5, 1.0])
    np.testing.assert_array_equal(j(0.5), b)


def test_join_rejects_mismatched_endpoints():
    a, b = np.zeros((2, 2)), np.ones((2, 2))
    c = b.copy()
    c[1, 1] = np.nextafter(1.0, 2.0)  # one bit off
    with pytest.raises(ValueError, match="path 1 does not start where path 0 ends"):
        linear(a, b).join(linear(c, a))
    with pytest.raises(ValueError, match="path 2 does not start where path 1 ends"):
        join([linear(a, b), linear(b, a), linear(b, a)])


@pytest.mark.parametrize("at", [[0.5, 0.5], [0.7, 0.2], [0.0, 0.5], [0.5, 1.0], [0.5]])
def test_join_rejects_bad_breakpoints(at):
    a, b = np.zeros((1, 2)), np.ones((1, 2))
    with pytest.raises(ValueError, match="`at`"):
        join([linear(a, b), linear(b, a), linear(a, b)], at)


def test_join_needs_a_path():
    with pytest.raises(ValueError, match="at least one"):
        join([])


def test_compose_via_deformations_time_fractions():
    """s_V(v)(tau) = h1(3 tau) | section(3 tau - 1) | h2(3 - 3 tau) (paper Remark)."""
    rng = np.random.default_rng(3)
    c, u, u2, c2 = rng.normal(size=(4, 3, 2))
    h1, sec, h2 = linear(c, u), linear(u, u2), linear(c2, u2)
    path = compose_via_deformations(h1, sec, h2)
    np.testing.assert_array_equal(path(0.0), c)
    np.testing.assert_array_equal(path.waypoints[-1], c2)
    np.testing.assert_allclose(path(1.0), c2, atol=1e-15)
    np.testing.assert_allclose(path.times, [0, 1 / 3, 2 / 3, 1], atol=0)
    np.testing.assert_allclose(path(1 / 3), u, atol=1e-15)
    np.testing.assert_allclose(path(2 / 3), u2, atol=1e-15)
    for tau in rng.uniform(0, 1, 12):
        if tau <= 1 / 3:
            want = h1(3 * tau)
        elif tau <= 2 / 3:
            want = sec(3 * tau - 1)
        else:
            want = h2(3 - 3 * tau)
        np.testing.assert_allclose(path(tau), want, atol=1e-12)


def test_compose_rejects_non_matching_pieces():
    a, b = np.zeros((1, 2)), np.ones((1, 2))
    with pytest.raises(ValueError, match="does not start"):
        compose_via_deformations(linear(a, b), linear(a, b), linear(a, b))


@settings(max_examples=25)
@given(seed=seeds, k=st.integers(2, 6), n=st.integers(2, 12), zero=st.booleans())
def test_resample(seed, k, n, zero):
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k, zero_pieces=zero)
    r = path.resample(n)
    np.testing.assert_array_equal(r.times, np.linspace(0, 1, n))
    np.testing.assert_allclose(r.waypoints, path(np.linspace(0, 1, n)), atol=0)
    with pytest.raises(ValueError, match="k >= 2"):
        path.resample(1)


@settings(max_examples=25)
@given(seed=seeds, k=st.integers(2, 6), batch=st.sampled_from([None, 3]))
def test_arc_length(seed, k, batch):
    rng = np.random.default_rng(seed)
    path = random_path(rng, k=k, batch=batch)
    disp = np.diff(path.waypoints, axis=-3)
    legs = np.linalg.norm(disp, axis=-1).sum(-1)
    np.testing.assert_allclose(path.leg_lengths(), legs)
    np.testing.assert_allclose(path.length(), legs.sum(-1))
    ar = path.arc_length_reparametrised()
    np.testing.assert_array_equal(ar.waypoints, path.waypoints)
    want = np.concatenate([np.zeros(legs.shape[:-1] + (1,)), np.cumsum(legs, -1)], -1)
    want = want / want[..., -1:]
    np.testing.assert_allclose(ar.times, want, atol=1e-14)
    assert np.all(ar.times[..., -1] == 1.0) and np.all(ar.times[..., 0] == 0.0)
    # constant speed: the distance travelled up to t is t * length
    # constant speed: every piece has length = duration * total length
    dur = np.diff(ar.times, axis=-1)
    np.testing.assert_allclose(legs, dur * legs.sum(-1, keepdims=True), rtol=1e-12, atol=1e-14)
    # the reparametrised path reaches waypoint i at its new breakpoint
    if batch is None:
        for i in range(k):
            np.testing.assert_allclose(ar(ar.times[i]), path.waypoints[i], atol=1e-12)


def test_arc_length_of_constant_path():
    wp = np.ones((4, 2, 2))
    ar = PiecewiseLinearPath([0, 0.1, 0.2, 1], wp).arc_length_reparametrised()
    np.testing.assert_allclose(ar.times, np.linspace(0, 1, 4))
    assert ar.length() == 0.0


def test_compact_drops_zero_duration_pieces():
    rng = np.random.default_rng(4)
    path = random_path(rng, k=6, zero_pieces=True)
    c = path.compact()
    assert np.all(np.diff(c.times) > 0)
    assert c.waypoints.shape[0] == path.waypoints.shape[0] - 1
    ts = np.linspace(0, 1, 33)
    np.testing.assert_allclose(c(ts), path(ts), atol=1e-12)
    plain = random_path(rng, k=4)
    assert plain.compact() is plain
    with pytest.raises(TypeError):
        random_path(rng, k=4, batch=2).compact()


def test_batch_container_protocol():
    rng = np.random.default_rng(6)
    shared = random_path(rng, k=4, batch=5)
    per = random_path(rng, k=4, batch=5, per_path=True)
    for path in (shared, per):
        assert len(path) == 5
        items = list(path)
        assert len(items) == 5 and all(not it.is_batch for it in items)
        for b, it in enumerate(items):
            np.testing.assert_array_equal(it.waypoints, path.waypoints[b])
            np.testing.assert_array_equal(it.times, path.times if path.times.ndim == 1
                                          else path.times[b])
            np.testing.assert_array_equal(path[b](0.37), path(0.37)[b])
        sub = path[1:3]
        assert sub.is_batch and len(sub) == 2
    single = items[0]
    with pytest.raises(TypeError, match="no len"):
        len(single)
    with pytest.raises(TypeError, match="not subscriptable"):
        single[0]
    with pytest.raises(TypeError):
        iter(single).__next__()
    assert "PiecewiseLinearPath" in repr(shared)
    np.testing.assert_array_equal(shared.as_array(), shared.waypoints)


@pytest.mark.parametrize("t", [-0.1, 1.1, np.nan, np.inf])
def test_evaluation_outside_unit_interval(t):
    path = linear(np.zeros((1, 2)), np.ones((1, 2)))
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        path(t)


@pytest.mark.parametrize(
    "times, wp, match",
    [
        ([0, 1], np.zeros((2, 2)), "waypoints"),
        ([0, 1], np.zeros((1, 2, 2, 2, 2)), "waypoints"),
        ([0, 0.5, 1], np.zeros((2, 1, 2)), "times"),
        (np.zeros((3, 2)), np.zeros((2, 1, 2)), "batched"),
    ],
)
def test_constructor_validates_shapes(times, wp, match):
    with pytest.raises(ValueError, match=match):
        PiecewiseLinearPath(times, wp)
