"""The refinement's grid and schedule (pmplan.refine.grid), shared by the reference and the
kernel: the levels sum to the steps, subdividing keeps the raw breakpoints and the polyline,
the mobility vanishes at the fixed times, the pairs are the certificate's, and the
no-squeezing level is min(T', max(HOLD min(T', D_raw), KAPPA_FLOOR D_raw)) (exactly its
definition, on integer paths)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.certify import point_pairs
from pmplan.refine.grid import (
    HOLD,
    KAPPA_FLOOR,
    MARGIN,
    chord_fraction,
    final_steps,
    hold_levels,
    mobility,
    pairs,
    piece_counts,
    piece_minima,
    raw_positions,
    schedule,
    split_mask,
    subdivide,
    subdivide_times,
)


@given(w=st.sampled_from([1, 2, 4, 8, 64]), steps=st.integers(1, 5000))
def test_schedule_sums_to_the_steps(w, steps):
    levels = schedule(w, steps)
    assert [s for s, _ in levels] == [1 << i for i in range(w.bit_length())]
    assert sum(k for _, k in levels) == steps and all(k >= 0 for _, k in levels)
    assert final_steps(steps) >= 1


@given(steps=st.integers(1, 5000), n=st.integers(1, 40), d=st.integers(2, 5))
def test_final_steps_depend_on_the_crowd_in_the_plane(steps, n, d):
    """The clearing-only steps: FINAL of the steps, but in the plane PLANE_FINAL of them for
    more than SETTLE robots and CROWD_FINAL of them for more than CROWD (a function of (d, n)
    and the effort alone), at least one."""
    from pmplan.refine.grid import CROWD, CROWD_FINAL, FINAL, PLANE_FINAL, SETTLE

    share = (FINAL if d > 2 or n <= SETTLE else CROWD_FINAL if n > CROWD else PLANE_FINAL)
    assert final_steps(steps, n, d) == max(1, int(share * steps))
    assert final_steps(steps) == final_steps(steps, 1, 2) == max(1, int(FINAL * steps))
    assert CROWD_FINAL > PLANE_FINAL > FINAL and SETTLE < CROWD


@settings(max_examples=40)
@given(data=st.data(), k=st.integers(2, 6), s=st.sampled_from([1, 2, 4]))
def test_subdivision_keeps_breakpoints_and_the_polyline(data, k, s):
    t = np.sort(np.array(data.draw(st.lists(st.integers(0, 8), min_size=k, max_size=k)),
                         dtype=float)) / 8
    t[0], t[-1] = 0.0, 1.0
    sub = subdivide_times(t, s)
    assert np.array_equal(sub[::s], t) and (np.diff(sub) >= 0).all()
    wp = np.array(data.draw(st.lists(st.integers(-4, 4), min_size=k * 4, max_size=k * 4)),
                  dtype=float).reshape(1, k, 2, 2)
    half = subdivide(wp)
    assert np.array_equal(half[:, ::2], wp)
    assert np.array_equal(half[:, 1::2], 0.5 * wp[:, :-1] + 0.5 * wp[:, 1:])


@settings(max_examples=40)
@given(data=st.data(), k=st.integers(2, 7), w=st.sampled_from([1, 2, 4, 8]))
def test_still_pieces_stay_one_piece_at_every_level(data, k, w):
    """With still pieces the grid of every level is the uniform one with the cuts inside the
    still pieces left out (bit for bit), the raw breakpoints are at ``raw_positions``, and
    halving the moving pieces level by level (``split_mask``, ``subdivide``) gives that grid:
    the waypoints of the uniform subdivision at the kept cuts, exactly on integer paths."""
    t = np.sort(np.array(data.draw(st.lists(st.integers(0, 8), min_size=k, max_size=k)),
                         dtype=float)) / 8
    t[0], t[-1] = 0.0, 1.0
    still = tuple(data.draw(st.lists(st.booleans(), min_size=k - 1, max_size=k - 1)))
    wp = np.array(data.draw(st.lists(st.integers(-4, 4), min_size=k * 4, max_size=k * 4)),
                  dtype=float).reshape(1, k, 2, 2) * 64
    x, uniform, prev = wp, wp, 1
    for s, _ in schedule(w, 10):
        if s > 1:
            x = subdivide(x, split_mask(k, prev, still))
            uniform = subdivide(uniform)
        prev = s
        cut, sub = subdivide_times(t, s), subdivide_times(t, s, still)
        at = raw_positions(k, s, still)
        counts = piece_counts(k, s, still)
        assert sub.shape == (int(counts.sum()) + 1,) == (at[-1] + 1,) and x.shape[1] == at[-1] + 1
        assert np.array_equal(sub[at], t) and np.array_equal(x[:, at], wp)
        assert counts.tolist() == [1 if c else s for c in still]
        keep = np.ones(cut.shape[0], dtype=bool)
        for j, c in enumerate(still):
            keep[j * s + 1:(j + 1) * s] = not c
        assert np.array_equal(sub, cut[keep]) and np.array_equal(x, uniform[:, keep])
    assert np.array_equal(subdivide_times(t, w, None), subdivide_times(t, w))
    assert split_mask(k, w, (False,) * (k - 1)) is None


def test_mobility_and_chord_fractions():
    t = np.array([0.0, 0.25, 0.5, 0.5, 0.75, 1.0])
    mob = mobility(t, 3)  # fixed times 0, 1/2, 1
    assert mob[0] == mob[-1] == 0 and mob[2] == mob[3] == 0 and (mob >= 0).all()
    assert (mob <= 1).all() and mob[1] > 0 and mob[4] > 0
    f = chord_fraction(t)
    assert f[0] == 0.5 and f[1] == 1.0 and f[2] == 0.0


@settings(max_examples=40)
@given(data=st.data(), robots=st.integers(1, 3), k=st.integers(2, 5), t=st.sampled_from([0.5, 1.0, 9.0]))
def test_hold_levels_hold_both_documented_floors(data, robots, k, t):
    """The level is ``min(T', max(min(T', D_raw) / 2, D_raw / 8))`` with the documented 1/2
    and 1/8 written here as literals (a planted HOLD or KAPPA_FLOOR fails): at least half the
    smaller of the target and the raw distance, at least ``min(T', D_raw / 8)`` (issue 24
    item 2: a pair the raw path keeps 8 T apart never goes below T), never above ``T'``."""
    m, p = 2, 2 + robots
    wp = np.array(data.draw(st.lists(st.integers(-4, 4), min_size=k * p * 2,
                                     max_size=k * p * 2)), dtype=float).reshape(1, k, p, 2)
    wp[:, :, :m] = wp[:, :1, :m]
    a, b, c = pairs(p, m)
    ia, ib = point_pairs(p, m)
    assert np.array_equal(a, ia) and np.array_equal(b, ib)
    assert np.array_equal(c, np.where(a >= m, 0.5, 1.0))
    tgt = np.full((1, a.size), t)
    got = hold_levels(wp, a, b, tgt)
    draw = piece_minima(wp, a, b).min(axis=1)
    tp = tgt * (1 + MARGIN)
    assert np.array_equal(got, np.minimum(tp, np.maximum(0.5 * np.minimum(tp, draw), draw / 8)))
    assert (got >= np.minimum(tp, draw / 8)).all() and (got >= 0.5 * np.minimum(tp, draw)).all()
    assert (got <= tp).all() and HOLD == 0.5 and KAPPA_FLOOR == 0.125
