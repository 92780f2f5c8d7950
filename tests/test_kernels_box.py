"""pmplan.kernels.box: the maps of a workspace box as kernels, bit for bit the numpy references
of pmplan.workspace -- on random paths, on integer paths whose points sit exactly on the map's
nodes and on the box's edges, at every power-of-two magnitude, with the band of the plans and
the narrow one of the refinement, and with the reference's error for a width too small."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pmplan import workspace as W
from pmplan.kernels import box as K

SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _same(a, b) -> None:
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert np.asarray(a).shape == np.asarray(b).shape


def _paths(rng, d: int, e: int, integer: bool):
    """Paths (B, K, P, d) with their breakpoints and a box, scaled by 2^e: integer points of
    [-30, 40) in the box [0, 8]^d (the nodes of the band 1/8 are 7, 8, 10, 14, 22, ...: many
    points on them, and pieces with an end on one), or random ones spread far outside."""
    b, k, p = 2, int(rng.integers(2, 7)), int(rng.integers(1, 5))
    box = np.ldexp(np.stack([np.zeros(d), np.full(d, 8.0)]), e)
    if integer:
        wp = rng.integers(-30, 40, size=(b, k, p, d)).astype(float)
    else:
        wp = 4.0 + rng.normal(scale=10.0 ** rng.uniform(-1, 3), size=(b, k, p, d))
    wp[:, :, 0] = wp[:, :1, 0]  # an obstacle: the same point at every breakpoint
    inner = np.sort(rng.choice(np.arange(1, 64), size=k - 2, replace=False)) / 64.0
    times = np.concatenate([[0.0], inner, [1.0]])
    return times, np.ldexp(wp, e), box


@SETTINGS
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.integers(-200, 200), st.booleans())
def test_the_image_of_paths_is_the_reference_bit_for_bit(seed, d, e, integer):
    rng = np.random.default_rng(seed)
    times, wp, box = _paths(rng, d, e, integer)
    want = W.path_into_box_linear(times, wp, box)
    got = K.path_into_box_linear(times, wp, box, W.BAND)
    _same(got[0], want[0])
    _same(got[1], want[1])
    # per-query breakpoints, and a width larger than any piece needs
    per = np.stack([times, times])
    need = W.crossing_width(times, wp, box)
    want = W.path_into_box_linear(per, wp, box, width=need + 3)
    got = K.path_into_box_linear(per, wp, box, W.BAND, width=need + 3)
    _same(got[0], want[0])
    _same(got[1], want[1])
    if need:
        for image in (W.path_into_box_linear, lambda *a, **k: K.path_into_box_linear(
                *a, frac=W.BAND, **k)):
            with pytest.raises(ValueError, match=f"smaller than the {need} crossings"):
                image(times, wp, box, width=need - 1)


@SETTINGS
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.integers(-200, 200),
       st.sampled_from([W.BAND, W.SQUEEZE, 5 / 16]))
def test_the_point_maps_are_the_reference_bit_for_bit(seed, d, e, band):
    """Points inside the box (the queries: at eighths, on the nodes and the band's edges, and
    random) mapped out of it; points anywhere (the refined paths) brought into it."""
    rng = np.random.default_rng(seed)
    box = np.ldexp(np.stack([np.zeros(d), np.full(d, 8.0)]), e)
    inside = np.concatenate([rng.integers(1, 64, size=(30, d)) / 8.0,
                             rng.uniform(1e-9, 8.0 - 1e-9, size=(30, d))])
    inside = np.ldexp(inside, e)
    _same(K.from_box_linear(inside, box, band), W.from_box_linear(inside, box, band))
    anywhere = np.ldexp(np.concatenate([rng.integers(-30, 40, size=(30, d)).astype(float),
                                        rng.normal(scale=1e6, size=(10, d))]), e)
    _same(K.into_box(anywhere, box, band), W.into_box(anywhere, box, band))
    # the batch shapes of the run loop: (B, n, d)
    _same(K.from_box_linear(inside.reshape(6, 10, d), box, band),
          W.from_box_linear(inside.reshape(6, 10, d), box, band))


def test_a_piece_from_a_node_to_the_wall_side_and_a_still_point():
    """The reference's docstring example (the nodes 7 and 8 crossed), a piece that starts on
    a node (not cut there) and ends on one, and a point that does not move (no cut)."""
    box = np.array([[0.0, 0.0], [8.0, 8.0]])
    path = np.array([[[[4.0, 4.0]], [[10.0, 4.0]]],
                     [[[7.0, 4.0]], [[14.0, 4.0]]],
                     [[[5.0, 5.0]], [[5.0, 5.0]]]])
    t, w = K.path_into_box_linear(np.array([0.0, 1.0]), path, box, W.BAND)
    assert t[0].round(4).tolist() == [0.0, 0.5, 0.6667, 1.0]
    assert w[0, :, 0, 0].tolist() == [4.0, 7.0, 7.5, 7.75]
    assert w[1, :, 0, 0].tolist()[1:] == [7.5, 7.75, 7.875]  # the nodes 8 and 10 inside
    assert w[2, :, 0].tolist() == [[5.0, 5.0]] * 4
