"""pmplan.kernels.common: the primitives every kernel shares -- the error-free
transformations (TwoSum, TwoProduct) exact in rational arithmetic, and the 8 x 8 register
transposes between queries and lanes, bit for bit."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.kernels import common as kernels_common

FINITE = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)


@settings(max_examples=300)
@given(FINITE, FINITE)
def test_two_sum_is_exact(a, b):
    s, e = kernels_common.two_sum(a, b)
    assert s == a + b
    assert Fraction(s) + Fraction(e) == Fraction(a) + Fraction(b)


@settings(max_examples=300)
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e150, max_value=1e150),
       st.floats(allow_nan=False, allow_infinity=False, min_value=-1e150, max_value=1e150))
def test_two_prod_is_exact(a, b):
    p, e = kernels_common.two_prod(a, b)
    assert p == a * b
    if abs(p) > 2.0**-900 or a == 0 or b == 0:  # (far from underflow: exact)
        assert Fraction(p) + Fraction(e) == Fraction(a) * Fraction(b)


@settings(max_examples=40)
@given(st.integers(0, 2**32 - 1), st.sampled_from([8, 16, 32, 64]), st.integers(1, 200),
       st.integers(0, 3))
def test_write_lanes_is_the_transpose(seed, lanes, size, block):
    """``kernels.common.write_lanes`` (8 x 8 blocks transposed in registers, the rest element
    by element) writes ``S.T`` into rows ``b0 .. b0 + L`` of the output, bit for bit (NaN
    payloads, signed zeros, subnormals included), and touches no other row or element;
    ``read_lanes`` reads them back the other way."""
    rng = np.random.default_rng(seed)
    S = rng.standard_normal((size, lanes))
    special = np.array([np.nan, -0.0, np.inf, -np.inf, 5e-324, -1.7976931348623157e308])
    S.flat[rng.integers(0, S.size, 5)] = rng.choice(special, 5)
    S.view(np.uint64).flat[0] ^= np.uint64(1)  # (an odd bit pattern: a NaN payload or ulp)
    b0 = block * lanes
    out = np.full((b0 + 2 * lanes, size), 7.0)
    kernels_common.write_lanes(S, out, b0, lanes, size)
    want = np.full_like(out, 7.0)
    want[b0:b0 + lanes] = S.T
    assert np.array_equal(out.view(np.uint64), want.view(np.uint64))
    # and back: read_lanes reads those rows into rows y0 .. y0 + size of lanes-innermost rows
    y0 = block + 1
    back = np.full((y0 + size + 3, lanes), 7.0)
    kernels_common.read_lanes(out, b0, lanes, size, back, y0)
    want = np.full_like(back, 7.0)
    want[y0:y0 + size] = S
    assert np.array_equal(back.view(np.uint64), want.view(np.uint64))
