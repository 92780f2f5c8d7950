"""pmplan.kernels.validation: the one-pass checks (finite, distinct points) agree with the
numpy reference on random, exactly coincident, signed-zero and non-finite queries."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.kernels import validation as kv


def _reference(o, s, g):
    """(valid per query, first query with two equal points in obstacles u start)."""
    ok = np.isfinite(o).all((1, 2)) & np.isfinite(s).all((1, 2)) & np.isfinite(g).all((1, 2))
    first = -1
    for b in range(o.shape[0]):
        for c in (s, g):
            pts = np.concatenate([o[b], c[b]])
            eq = (pts[:, None, :] == pts[None, :, :]).all(-1)
            dup = eq.sum() > pts.shape[0]
            ok[b] &= not dup
            if c is s and dup and first < 0:
                first = b
    return ok, first


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.integers(1, 4), st.integers(2, 4),
       st.sampled_from(["random", "integer", "zeros", "nonfinite"]))
def test_validation_kernels_agree_with_numpy(seed, m, n, d, kind):
    rng = np.random.default_rng(seed)
    b = 6
    if kind == "random":
        o, s, g = (rng.normal(size=(b, k, d)) for k in (m, n, n))
    else:
        o, s, g = (rng.integers(-1, 2, size=(b, k, d)).astype(float) for k in (m, n, n))
    if kind == "zeros":  # -0.0 == 0.0: coincident points
        s[rng.random(s.shape) < 0.3] *= -1.0
        s[s == 0] = -0.0
    if kind == "nonfinite":
        s.flat[rng.integers(s.size)] = rng.choice([np.nan, np.inf, -np.inf])
    o, s, g = (np.ascontiguousarray(a) for a in (o, s, g))
    ok, first = _reference(o, s, g)
    assert bool(kv.valid_queries(o, s, g)) == bool(ok.all())
    if np.isfinite(s).all() and np.isfinite(o).all():
        assert kv.first_coincident(o, s) == first
