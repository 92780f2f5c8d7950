"""The frame of a configuration: nu(e) is a unit tangent field (paper Section 3, Mathematics §4.1)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.frame import Frame, nu, unit

TOL = 1e-13


def ref_unit(w: np.ndarray) -> np.ndarray:
    """w/|w| computed independently (scaled by a power of two, exact, to avoid under/overflow)."""
    w = np.asarray(w, dtype=float)
    big = np.abs(w).max(-1, keepdims=True)
    k = np.frexp(big)[1]  # big = f 2**k, f in [0.5, 1)
    ws = np.ldexp(w, -k)
    return ws / np.linalg.norm(ws, axis=-1, keepdims=True)


def families(rng: np.random.Generator, d: int, b: int) -> np.ndarray:
    """Directions of many kinds: generic, huge, tiny, subnormal, near N, near -N, axes."""
    out = [rng.normal(size=(b, d))]
    out.append(rng.normal(size=(b, d)) * 1e300)
    out.append(rng.normal(size=(b, d)) * 1e-300)
    out.append(rng.integers(-3, 4, size=(b, d)) * 5e-324)
    near = np.zeros((b, d))
    near[:, :-1] = rng.normal(size=(b, d - 1)) * 10.0 ** rng.integers(-300, -1, size=(b, 1))
    near[:, -1] = rng.uniform(0.5, 2.0, size=b)
    out += [near, near * np.array([1.0] * (d - 1) + [-1.0])]
    axes = np.zeros((2 * d, d))
    axes[np.arange(d), np.arange(d)] = rng.uniform(0.1, 10.0)
    axes[d + np.arange(d), np.arange(d)] = -rng.uniform(0.1, 10.0)
    out.append(axes)
    w = np.concatenate(out)
    return w[(w != 0).any(-1)]


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 9))
def test_nu_is_unit_and_orthogonal(seed, d):
    w = families(np.random.default_rng(seed), d, 8)
    v, pole = nu(w)
    assert v.shape == w.shape and pole.shape == w.shape[:1] and pole.dtype == bool
    assert np.isfinite(v).all()
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), 1.0, atol=TOL)
    e = ref_unit(w)
    assert np.abs((v * e).sum(-1)).max() <= TOL


@pytest.mark.parametrize("d", [3, 5, 7, 9])
@pytest.mark.parametrize("c", [1.0, 2.0, 1e-300, 5e-324, 1e300, 3.5])
def test_at_pole_exactly_positive_multiples_of_N(d, c):
    w = np.zeros((4, d))
    w[0, -1] = c  # c N: the pole
    w[1, -1] = -c  # -N: not the pole
    w[2, -1] = c
    w[2, 0] = 5e-324  # tiny nonzero head coordinate: not the pole
    w[3, -1] = c
    w[3, d // 2] = -1e-300
    v, pole = nu(w)
    np.testing.assert_array_equal(pole, [True, False, False, False])
    a = np.zeros(d)
    a[0] = 1.0
    np.testing.assert_array_equal(v[0], a)  # nu(N) = a = e_1 (Mathematics §4.1)
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), 1.0, atol=TOL)
    assert np.abs((v * ref_unit(w)).sum(-1)).max() <= TOL


@pytest.mark.parametrize("d", [2, 4, 6, 8])
def test_no_pole_in_even_dimension(d):
    w = np.zeros((2, d))
    w[0, -1] = 1.0
    w[1, -1] = -3.0
    _, pole = nu(w)
    assert not pole.any()


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), half=st.integers(1, 4))
def test_even_dimension_is_the_papers_field(seed, half):
    """nu(a1, b1, ..., al, bl) = (-b1, a1, ..., -bl, al) (paper Section 3)."""
    d = 2 * half
    w = families(np.random.default_rng(seed), d, 6)
    e = ref_unit(w)
    want = np.empty_like(e)
    want[:, 0::2] = -e[:, 1::2]
    want[:, 1::2] = e[:, 0::2]
    np.testing.assert_allclose(nu(w)[0], want, atol=TOL)


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([3, 5, 7, 9]))
def test_odd_dimension_is_normalised_xi(seed, d):
    """nu(v) = xi(v)/|xi(v)|, xi(v) = (1 - v.N) a + (a.v)(N - v), away from N (Mathematics §4.1)."""
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(10, d))
    w[:, -1] = np.where(rng.random(10) < 0.3, -np.abs(w[:, -1]) * 5, w[:, -1])  # near -N too
    v = ref_unit(w)
    a = np.zeros(d)
    a[0] = 1.0
    north = np.zeros(d)
    north[-1] = 1.0
    xi = (1 - v[:, -1:]) * a + v[:, :1] * (north - v)
    want = xi / np.linalg.norm(xi, axis=-1, keepdims=True)
    np.testing.assert_allclose(nu(w)[0], want, atol=1e-12)


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 9),
       delta=st.sampled_from([1e-3, 1e-6, 1e-9]))
def test_nu_is_continuous_away_from_the_pole(seed, d, delta):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(20, d))
    e = ref_unit(w)
    # stay at angular distance >= 0.3 from N
    w = w[e[:, -1] < 0.95]
    pert = w + delta * np.linalg.norm(w, axis=-1, keepdims=True) * rng.normal(size=w.shape)
    change = np.linalg.norm(nu(pert)[0] - nu(w)[0], axis=-1)
    # nu is Lipschitz on {e_d <= 0.95}; a generous constant, still O(delta)
    assert (change <= 100 * delta * np.sqrt(d)).all()


@pytest.mark.parametrize("d", [3, 5])
def test_nu_near_minus_N_is_smooth(d):
    """Near -N (far from the pole) nu changes little: no cancellation blow-up."""
    w = np.zeros((3, d))
    w[:, -1] = -1.0
    w[1, 0] = 1e-12
    w[2, 1] = 1e-12
    v = nu(w)[0]
    assert np.linalg.norm(v[1] - v[0]) < 1e-9
    assert np.linalg.norm(v[2] - v[0]) < 1e-9


def test_nu_is_scale_invariant_and_shape_polymorphic():
    rng = np.random.default_rng(5)
    w = rng.normal(size=(4, 3, 5))
    v, pole = nu(w)
    assert v.shape == (4, 3, 5) and pole.shape == (4, 3)
    for s in (2.0**-1000, 3.0, 2.0**1000):
        np.testing.assert_allclose(nu(w * s)[0], v, atol=TOL)
    v1, p1 = nu(w[0, 0])
    assert v1.shape == (5,) and p1.shape == ()
    np.testing.assert_allclose(v1, v[0, 0], atol=0)


def test_unit():
    w = np.array([[3.0, 4.0], [0.0, 0.0], [1e-310, 0.0], [1e308, 1e308]])
    u = unit(w)
    np.testing.assert_allclose(u[0], [0.6, 0.8], atol=1e-16)
    np.testing.assert_array_equal(u[1], [0.0, 0.0])
    np.testing.assert_allclose(u[2], [1.0, 0.0], atol=1e-16)
    np.testing.assert_allclose(u[3], [2**-0.5, 2**-0.5], atol=1e-15)


@settings(max_examples=20)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 6))
def test_frame_columns_and_perpendicular_parts(seed, d):
    rng = np.random.default_rng(seed)
    obstacles = rng.normal(size=(3, 2, d)) * 5
    pts = rng.normal(size=(3, 7, d)) * 5
    fr = Frame(obstacles[:, 0], obstacles[:, 1])
    assert fr.w.shape == (3, d) and fr.norm.shape == (3,)
    np.testing.assert_allclose(fr.norm, np.linalg.norm(obstacles[:, 1] - obstacles[:, 0], axis=-1))
    s = fr.columns(pts)
    r = fr.perpendicular(pts)
    rel = pts - obstacles[:, :1]
    # y - o1 = s(y) e + r(y), r(y) . e = 0, and o2 has column |w|
    np.testing.assert_allclose(s[..., None] * fr.e[:, None] + r, rel, atol=1e-12)
    assert np.abs((r * fr.e[:, None]).sum(-1)).max() < 1e-12
    np.testing.assert_allclose(fr.columns(obstacles)[:, 1], fr.norm, rtol=1e-14)
    np.testing.assert_allclose(fr.columns(obstacles)[:, 0], 0.0, atol=0)
    same = Frame(obstacles[:, 0], obstacles[:, 1])
    np.testing.assert_array_equal(same.nu, fr.nu)
