"""The grid, the schedule and the constants of the refinement map R, shared by its numpy
reference (:mod:`pmplan.refine.reference`) and its numba kernel (:mod:`pmplan.refine.kernel`),
which both import them from here and neither imports the other: the levels and their steps, the
overshoot, the subdivided breakpoints and waypoints, the mobility and chord fractions, the pairs,
the closed-form piece minima, the no-squeezing levels, and every gain, floor and slack of the
map (one source; the kernel reads them at every call, :func:`pmplan.refine.kernel.constants`).
See :mod:`pmplan.refine` for the map and ``docs/refinement.md`` for the argument.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..certify import point_pairs
from ..path import cut_along

__all__ = [
    "ALPHA",
    "BETA",
    "CROWD",
    "CROWD_FINAL",
    "CROWD_STEPS",
    "CROWD_WAYPOINTS",
    "DECAY",
    "DEFAULT_STEPS",
    "DEFAULT_WAYPOINTS",
    "ETA",
    "FINAL",
    "GAMMA",
    "GROWTH",
    "HOLD",
    "KAPPA_FLOOR",
    "KAPPA",
    "LAMBDA",
    "MARGIN",
    "MAX_SEQUENTIAL_D",
    "MAX_STEPS",
    "MAX_TARGET",
    "MAX_WAYPOINTS",
    "MOBILITY",
    "OMEGA",
    "PHI",
    "PHI_WAYPOINT",
    "PLANE_FINAL",
    "PLANE_STEPS",
    "SETTLE",
    "SHARE",
    "SLACK",
    "SPACE_CROWD_STEPS",
    "WALL_SLIDE",
    "chord_fraction",
    "default_effort",
    "final_steps",
    "hold_levels",
    "levels",
    "mobility",
    "overshoot",
    "pairs",
    "piece_counts",
    "piece_minima",
    "push_points",
    "raw_positions",
    "schedule",
    "split_mask",
    "subdivide",
    "subdivide_times",
]

#: push target T* = (1 + ETA) T at the coarsest level, divided by DECAY at every finer one
#: (:func:`overshoot`): the clearing overshoots the target
ETA = 0.5
#: the protected level is T (1 + MARGIN), far above the rounding of the update
MARGIN = 2.0**-30
#: the steps of a level are GROWTH times those of the next finer level (coarse steps are cheap)
GROWTH = 2.0
#: the overshoot of a level is DECAY times smaller than that of the next coarser one
DECAY = 2.0
#: the clearing-only steps at the end, a fraction of ``steps``, in d >= 3 and in the plane up to
#: ``SETTLE`` robots (they settle the pairs the shortening pressed below their target; more
#: robots in the plane: :data:`PLANE_FINAL` and :data:`CROWD_FINAL`). 1/4 rather than 1/8: on
#: the scene families in the box (rooms and swaps of 10 x 10, n = 2 to 16, r = 0.3) two n = 8
#: queries of the design draw (seed 1) ended 0.98-0.99 of their target in a crowd still
#: settling; on the held-out draws (seeds 2, 4, 5, 6; 64 rows) 1/4 keeps the radii on 9 more
#: queries, in 6 rows, on fewer in no row, at the same lengths (benchmarks/final_ab.py)
FINAL = 0.25
#: the clearing-only steps of a crowd in the plane (more than ``CROWD`` robots, d = 2), a
#: multiple of ``steps`` (:func:`final_steps`). A crowd's refinement leaves pairs pressed
#: together where the shortening and the clearing balance; steps that only clear settle them
#: at their targets, which keeps the radii on more queries and makes the refined plan less
#: sensitive to its query (a settled push is a fixed point, a push under way amplifies a
#: move of the raw plan). benchmarks/crowd_effort.py measures it against more steps and more
#: waypoints, with 16 robots, on design and held-out seeds
CROWD_FINAL = 2.0
#: the clearing-only steps in the plane of more than ``SETTLE`` and at most ``CROWD`` robots, a
#: multiple of ``steps`` (:func:`final_steps`): as many as the steps (72, :data:`PLANE_STEPS`;
#: 56 when it was chosen). Rather than a quarter (:data:`FINAL`, the share before): from 8
#: robots a refined plan in the plane takes the one-side lanes
#: (:data:`pmplan.planners.base.CROWD_LANES`), which press more pairs together,
#: and with 6 the compact lanes' pushes settle too; more plans keep the radii, on design and
#: held-out seeds, at the same lengths, within the 5 ms per query issue 25 asks of 8 robots
#: (benchmarks/plane_final.py)
PLANE_FINAL = 1.0
#: up to this many robots in the plane the refinement ends with ``FINAL`` of its steps that
#: only clear, more take ``PLANE_FINAL``: with 2 and 4 robots as many clearing-only steps as
#: steps keep the radii on a handful more of 1,600 queries (benchmarks/plane_final.py, an earlier
#: run) and cost a fifth of the time of a refined (2,4,2) query, whose goals (at most 1 ms,
#: at least 2,000 queries per second: benchmarks/refine_bench.py) they would miss
SETTLE = 4
#: mobility: clip(MOBILITY * (pieces) * (time to the nearest fixed time or neighbour), 0, 1)
MOBILITY = 4.0
#: no self-squeezing (two levels, both held): a pair never goes below ``HOLD min(T (1 +
#: MARGIN), D_raw)``, D_raw its smallest distance on the raw path, nor below ``min(T (1 +
#: MARGIN), KAPPA_FLOOR D_raw)`` -- so a pair the raw path keeps at least ``T / KAPPA_FLOOR``
#: apart never goes below its target (:func:`hold_levels`; the clearing's floor is at least
#: that, the shortening never lowers a pair below min(D, T)). The kernel's time on a refined
#: (2,4,2) query against KAPPA_FLOOR = 0 (alternating runs): 1/2 (the floor at T from 2 T on)
#: about 1.5x, 1/4 1.3-1.5x -- the caps bind far more often and the directional budgets are
#: computed -- 1/8 0.92-1.1x (docs/refinement.md)
HOLD = 0.5
#: see :data:`HOLD`
KAPPA_FLOOR = 0.125


# --- the map's gains, floors and slack (the reference and the kernel read them here) ----------

#: default sub-pieces per raw piece at the finest level (a power of two): 7 raw pieces per leg
#: of the obstacle-line planner, 2 of them still (kept one piece,
#: :meth:`pmplan.planners.base.Planner.still_pieces`), give 22 pieces per leg. 4 rather than
#: the 2 of benchmarks/refine_bench.py's length / time trade-off on the unit square: with the
#: same steps the finer level costs about as much (the steps are split over the levels, the
#: coarse ones cheap), and on the scene families in the box (rooms and swaps of 10 x 10 with
#: 2, 4 and 8 robots, r = 0.3, seeds 1, 2, 4; benchmarks/scenes_effort.py) it kept the radii on more
#: queries in total at each n and on fewer in no row of 8 robots (rerun with the one-side lanes
#: of 8 robots and the clearing-only steps: as many or more at each n, fewer in no row)
DEFAULT_WAYPOINTS = 4
#: default number of steps (each a clearing and a shortening substep), split over the levels
DEFAULT_STEPS = 56
#: default ``steps`` in the plane for more than ``SETTLE`` and at most ``CROWD`` robots,
#: followed by as many clearing-only steps (:data:`PLANE_FINAL`). 72 rather than 56 since the
#: refinement keeps the pieces that stand still one piece (the desingularization,
#: :meth:`pmplan.planners.base.Planner.still_pieces`): 23 waypoints a leg rather than 29, and
#: the time they saved spent on steps. Measured by benchmarks/still_ab.py (the scene families
#: in the box, r = 0.3, 100 queries per row; design seeds 11 and 12, held-out 30 and 31): with
#: 8 robots 954 of 1,000 held-out plans keep the radii against 950 before, paths 1.5-4.5 %
#: shorter in the plane, at about 4 ms per query (benchmarks/scenes_time.py)
PLANE_STEPS = 72
#: a crowd: more robots than this get the crowd's default effort (``CROWD_WAYPOINTS``,
#: ``CROWD_STEPS``, ``SPACE_CROWD_STEPS``). The effort depends on d and n alone, which every
#: query of a batch and every query of a domain shares, so the refinement stays continuous on
#: the same domains. Measured
#: by benchmarks/scenes_effort.py (rooms and swaps of 10 x 10, r = 0.3, in the box; seed 1,
#: held out 2 and 4): with 16 robots more steps keep the radii on more queries (the crowd's
#: steps: :data:`CROWD_STEPS`) within the 20 ms per query issue 25 asks; with 8, twice the
#: steps cost 5-8 ms, more than the 5 ms asked
CROWD = 8
#: default ``waypoints`` for more than ``CROWD`` robots
CROWD_WAYPOINTS = 4
#: default ``steps`` for more than ``CROWD`` robots in the plane, followed by ``CROWD_FINAL``
#: times as many clearing-only steps (:func:`final_steps`). 112 since the still pieces
#: (:data:`PLANE_STEPS`) save the time of 16 more steps (benchmarks/still_ab.py); before, 96
#: and 192 rather than 224 and 56 (benchmarks/crowd_effort.py; 16 robots, the same raw plans):
#: in the rooms and swaps of 100 queries more plans keep the radii, on design and held-out
#: seeds alike, at the same time per query, for paths a few percent longer; more waypoints or
#: more steps of both kinds cost more time for as much. Before, 224 steps rather than 112
#: (benchmarks/crowd_ab.py). In space see :data:`SPACE_CROWD_STEPS`
CROWD_STEPS = 112
#: default ``steps`` for more than ``CROWD`` robots in d >= 3: twice ``DEFAULT_STEPS``. There
#: the offsets keep the robots apart (Mathematics §4.4): every 3-D room with 16 robots keeps the
#: radii at 112, 168 and 224 steps alike, and more steps shorten by under 0.5 %. The steps do
#: not set the modulus of continuity in a way one can tune (benchmarks/space_crowd_ab.py, the
#: same queries and moves): on the seeds looked at first 168 lowered the largest K of the rooms
#: and of the rows (3, 16, m) of benchmarks/refine_continuity.py, on held-out ones it raised
#: them (a room at K 6.8e3, 4 of 540 pairs with K_eff > 1e3 against none at 112); 224 lowers
#: the rooms' K but raises the amplification of a raw plan near the pole of odd d (Mathematics
#: §4.1; 4.8e3 in the raw plan) from 1.3 to 16 times the raw plan's: K_eff 3.5e4, past issue
#: 24's bound 1e4
SPACE_CROWD_STEPS = 112
#: the largest ``waypoints`` accepted
MAX_WAYPOINTS = 64
#: the largest ``steps`` accepted
MAX_STEPS = 100_000
#: shortening gain: the fraction of the way to the chord point moved per step
ALPHA = 1.0
#: the walls of a workspace: a clearing move goes toward a wall's limit at most the room left
#: there plus WALL_SLIDE times its length (pmplan.refine.reference._wall_scale): a move is
#: never held back below this scale, so the hold is continuous
WALL_SLIDE = 0.25
#: clearing gain: the fraction of the deficit pushed per step
BETA = 0.5
#: clearing floor: a pair below its target may lose at most 1 - PHI of its distance per step
#: (measured with the 1e-6 probe: 0.25 against 0.5, smaller largest probes and shorter paths)
PHI = 0.25
#: the soft closest point of a piece: ``clip(-r0.v / (|v|^2 + LAMBDA (|r0|^2 + |r1|^2)), 0,
#: 1)``, continuous where the exact one (LAMBDA = 0) jumps (v -> 0); its slope is of order
#: 1 / LAMBDA, so a larger LAMBDA keeps the continuity modulus small (measured: 2**-4 halves
#: the largest 1e-6 probe of n = 8 against 2**-12, at the same lengths). It shares the push of
#: a piece between the piece's two ends. The push itself is along the piece's push point
#: (:func:`push_points`), whose parameter LAMBDA regularises by the squared distance from the
#: origin to the piece's line instead: along the soft point, a few per cent of the piece away
#: from the closest point, a pair that nearly touches mid-piece was pushed nearly along the
#: piece, inward on one side of its closest point, and its own directional budget held it at
#: its raw clearance (docs/refinement.md, "The push at the closest point"). Measured on the
#: scene families (seed 1, n = 4 to 16; every query moved by 1e-6, 1e-9, 1e-12): 1/16 and 1
#: keep the radii on as many queries (175 of 192), 1/16 with the smaller largest modulus (3.0e3,
#: at a raw clearance of 7e-6, against 4.4e3); 4, 16 and 64 shrink the parameter toward the
#: piece's start and keep 98, 60 and 20
LAMBDA = 2.0**-4
#: clearing floor of the waypoint pass (its pushes first, then the soft points' with PHI): a
#: pair below its target may lose at most 1 - PHI_WAYPOINT of its distance in that pass. Two
#: passes, so that the push at a waypoint where a pair nearly touches (along the path's turn,
#: outward on both pieces) is not held back by the soft points' pushes, nearly along the pieces
#: (measured on the n = 8 rows of benchmarks/refine_bench.py, three draws: 2 probes above 1e-4
#: of 400 against 4-13 in one pass; 0.9 keeps every path clear of 1e-2, 0.5 squeezes some to
#: 1e-9). The waypoint pass runs at the coarsest level only, where the raw path's
#: near-contacts are separated: at the finer levels and in the final steps it changed no probe
#: above 1e-5 and no length by 1e-3, and cost a fifth of the kernel's time
PHI_WAYPOINT = 0.9
#: the clearing's share of a pair's free distance ``D - F``: a move of a point within
#: ``SHARE c (D - F)`` (isotropic), or whose inward part along the piece stays within its share of
#: ``D^2 - F'^2`` (directional: a near-contact is pushed out, or slides, in large steps), keeps the
#: pair above ``F`` (1/2 makes the two kinds add up to at most ``D - F``; measured on the n = 8
#: rows of benchmarks/refine_bench.py: the largest 1e-6 probe 3-4e-4 against 0.7-4.9e-3 with the
#: isotropic cap alone, same lengths)
SHARE = 0.5
#: the push direction at an interior waypoint is ``r + GAMMA min(|v_in|, |v_out|) (v_out/|v_out|
#: - v_in/|v_in|)`` (r the relative position, v the relative path's pieces): where a pair nearly
#: touches at the end of a piece it follows the path's turn rather than ``r / |r|``
GAMMA = 0.25
#: the weight of the push at the waypoints (along the pair's relative position there) against
#: the push at the soft closest point of each piece (weight 1). Where a pair nearly touches at a
#: waypoint (clearance c) its direction turns by delta / c under a move delta of the query, so
#: it carries most of the continuity modulus; without it a pair pushed only at soft points,
#: nearly along the piece, can be squeezed to a clearance of 1e-17 (measured on the n = 8 rows
#: of benchmarks/refine_bench.py). 1/2: fewer 1e-6 probes above 1e-4 (9 against 22 of 640 for
#: 1), no squeezed path
OMEGA = 0.5
#: with no radius, the target clearance is KAPPA times the raw plan's clearance
KAPPA = 0.5
#: the kernel measures the refined paths for d below this (numpy sums fewer than 8 terms
#: sequentially, as the kernel does; beyond, numpy's pairwise sums round differently)
MAX_SEQUENTIAL_D = 8
#: the rounding slack of the caps, in the frame (extent in [1/2, 1)): every cap is measured
#: from ``D - 4 SLACK A`` (A the largest norm of a point of the path at the substep), every
#: directional budget from ``h - 4 SLACK e**2`` against an inward part raised by ``SLACK e
#: |move|`` (``e = 4 A + |r0| + |v| + |move|``), with a continuous ramp from 0 where the room above
#: F' is within 2 to 4 of that slack at a point where the move is not outward (the room raised
#: by the move's outward part, :func:`pmplan.refine.reference._room`: a move outward where the
#: pair is pressed against its floor is not held back by a ramp whose slope, ``|move| D / (2
#: err)``, was the 1e-12 probes' noise floor): the float piece minimum, the float inward part and the
#: rounded moves are within far less of the exact ones (about 2**-50 e), so every floor holds
#: for the floats computed, exactly (tests/test_refine_exact.py). Only norms and no absolute
#: term: the map commutes with rotations and scalings (to rounding)
SLACK = 2.0**-44
#: the largest target in the refinement's frame (:func:`pmplan.refine.frame.to_frame`: the path's extent is below 1
#: there)
MAX_TARGET = 2.0**20


def schedule(waypoints: int, steps: int) -> list[tuple[int, int]]:
    """The levels ``(sub-pieces s, steps at that level)``: s = 1, 2, 4, .., waypoints, each level
    :data:`GROWTH` times the steps of the next finer one (rounded; they sum to ``steps``).

    >>> schedule(4, 48)
    [(1, 27), (2, 14), (4, 7)]
    >>> schedule(1, 5)
    [(1, 5)]
    """
    levels = waypoints.bit_length()
    w = [GROWTH ** (levels - 1 - i) for i in range(levels)]
    cum = [0.0]
    for x in w:
        cum.append(cum[-1] + x)
    at = [int(steps * c / cum[-1] + 0.5) for c in cum]
    return [(1 << i, at[i + 1] - at[i]) for i in range(levels)]


def overshoot(level: int) -> float:
    """The overshoot of the push target at a level: ``T* = (1 + ETA DECAY**-level) T`` (large
    at the coarse levels, where it frees the caps, small at the fine ones, where it costs
    length; DECAY = 4 or 8 measured no shorter, and kept fewer paths clear of r at n = 8)."""
    return ETA * DECAY**-level


def final_steps(steps: int, n: int = 1, d: int = 2) -> int:
    """The clearing-only steps after the last level of a refinement of ``n`` robots in R^d:
    ``FINAL`` of ``steps``; in the plane ``PLANE_FINAL`` of them for more than ``SETTLE``
    robots and ``CROWD_FINAL`` of them for a crowd (more than ``CROWD``); at least 1. It
    depends on (d, n) and the effort alone, so the refinement stays continuous on the same
    domains.

    >>> final_steps(56, 4), final_steps(72, 8), final_steps(112, 16), final_steps(56, 8, 3)
    (14, 72, 224, 14)
    """
    if d != 2 or n <= SETTLE:
        share = FINAL
    elif n > CROWD:
        share = CROWD_FINAL
    else:
        share = PLANE_FINAL
    return max(1, int(share * steps))


@lru_cache(maxsize=256)
def pairs(p: int, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pairs (a < b) with a moving point b (index >= m): ``a``, ``b`` (int64) and ``c``
    (1/2 for two robots, 1 for an obstacle and a robot), in the kernel's order (read-only,
    cached)."""
    a, b = (v.astype(np.int64) for v in point_pairs(p, m))  # the certificate's pairs, its order
    c = np.where(a >= m, 0.5, 1.0)
    for arr in (a, b, c):
        arr.flags.writeable = False
    return a, b, c


# --- the grid ------------------------------------------------------------------------------

def default_effort(n: int, d: int = 2) -> tuple[int, int]:
    """The default ``(waypoints, steps)`` of a refinement of plans with ``n`` robots in R^d:
    ``(DEFAULT_WAYPOINTS, DEFAULT_STEPS)`` = (4, 56); in the plane ``PLANE_STEPS`` = 72 steps
    for more than ``SETTLE`` = 4 robots; for a crowd of more than ``CROWD`` = 8 robots
    ``(CROWD_WAYPOINTS, CROWD_STEPS)`` = (4, 112) in the plane, ``(CROWD_WAYPOINTS,
    SPACE_CROWD_STEPS)`` = (4, 112) in d >= 3. It depends on (d, n) alone, which every query
    of a domain shares, so the refinement stays continuous on the same domains.

    >>> default_effort(4), default_effort(8), default_effort(8, 3), default_effort(16)
    ((4, 56), (4, 72), (4, 56), (4, 112))
    """
    if n <= CROWD:
        return DEFAULT_WAYPOINTS, PLANE_STEPS if d == 2 and n > SETTLE else DEFAULT_STEPS
    return CROWD_WAYPOINTS, CROWD_STEPS if d == 2 else SPACE_CROWD_STEPS


def piece_counts(k: int, s: int, still=None) -> np.ndarray:
    """The sub-pieces of each of the ``k - 1`` raw pieces at the level of ``s`` (int64): ``s``,
    and 1 for a piece that stands still (``still``, a bool per raw piece, or None: none does;
    :meth:`pmplan.planners.base.Planner.still_pieces`).

    >>> piece_counts(4, 4, (True, False, True)).tolist()
    [1, 4, 1]
    """
    counts = np.full(k - 1, s, dtype=np.int64)
    if still is not None:
        counts[np.asarray(still, dtype=bool)] = 1
    return counts


def raw_positions(k: int, s: int, still=None) -> np.ndarray:
    """Where the ``k`` raw breakpoints are in the grid of ``s`` (int64): ``s j``, or with
    pieces that stand still the running sum of :func:`piece_counts`.

    >>> raw_positions(4, 4).tolist(), raw_positions(4, 4, (True, False, True)).tolist()
    ([0, 4, 8, 12], [0, 1, 5, 6])
    """
    out = np.zeros(k, dtype=np.int64)
    out[1:] = np.cumsum(piece_counts(k, s, still))
    return out


def subdivide_times(times: np.ndarray, s: int, still=None) -> np.ndarray:
    """Breakpoints of every piece cut into ``s`` equal sub-pieces: ``t_k + (j/s)(t_{k+1} -
    t_k)``, j = 0..s-1, then the last; shape (..., (K-1) s + 1); a piece that stands still
    (``still``, see :func:`piece_counts`) stays one piece. The raw breakpoints stay, and the
    other cuts are those of :func:`pmplan.path.cut_along`, bit for bit.

    >>> subdivide_times(np.array([0.0, 1.0, 3.0]), 2, (True, False)).tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    cut = cut_along(times, s, -1)
    if still is None or not any(still):
        return cut
    return cut[..., _kept_cuts(len(still), s, tuple(bool(v) for v in still))]


@lru_cache(maxsize=256)
def _kept_cuts(pieces: int, s: int, still: tuple) -> np.ndarray:
    """The breakpoints of the uniform grid of ``s`` that :func:`subdivide_times` keeps."""
    keep = np.ones(pieces * s + 1, dtype=bool)
    for j in np.flatnonzero(still):
        keep[j * s + 1:(j + 1) * s] = False
    keep.flags.writeable = False
    return keep


def levels(times: np.ndarray, waypoints: int, steps: int, still=None) -> list[tuple]:
    """The levels of :func:`schedule` on the breakpoints ``times`` (K,) or (B, K): per level
    ``(split, steps, breakpoints)``, ``split`` the pieces :func:`subdivide` halves on the way
    into the level (:func:`split_mask` of the level before; unused at the coarsest one, None
    there), with pieces that stand still kept whole (``still``, :func:`piece_counts`). The
    reference and the kernel both walk these.

    >>> [(split, n, t.tolist()) for split, n, t in levels(np.array([0.0, 1.0, 3.0]), 2, 3,
    ...                                                   (True, False))]
    [(None, 2, [0.0, 1.0, 3.0]), ((False, True), 1, [0.0, 1.0, 2.0, 3.0])]
    """
    k = np.shape(times)[-1]
    out, prev = [], None
    for s, n_steps in schedule(waypoints, steps):
        split = None if prev is None else split_mask(k, prev, still)
        out.append((split, n_steps, subdivide_times(times, s, still)))
        prev = s
    return out


def split_mask(k: int, s: int, still=None) -> tuple[bool, ...] | None:
    """The pieces of the grid of ``s`` that :func:`subdivide` halves on the way to ``2 s``
    (a bool per piece), or None: all of them (no piece stands still)."""
    if still is None or not any(still):
        return None
    counts = piece_counts(k, s, still)
    return tuple(bool(v) for v in np.repeat(~np.asarray(still, dtype=bool), counts))


@lru_cache(maxsize=256)
def _split_index(split: tuple) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For :func:`subdivide`: where the old waypoints go, where the midpoints go, and the
    pieces halved (int64, read-only)."""
    cut = np.asarray(split, dtype=bool)
    old = np.arange(cut.shape[0] + 1)
    old[1:] += np.cumsum(cut)
    pieces = np.flatnonzero(cut)
    out = (old, old[pieces] + 1, pieces)
    for arr in out:
        arr.flags.writeable = False
    return out


def subdivide(wp: np.ndarray, split: tuple | None = None) -> np.ndarray:
    """Insert the midpoint ``0.5 P_i + 0.5 P_{i+1}`` of every piece: (B, K, P, d) -> (B, 2K-1,
    P, d); with ``split`` (a bool per piece, :func:`split_mask`) of the pieces it marks only:
    (B, K + their number, P, d). The path is the same polyline (up to the rounding of the
    midpoints)."""
    b, k = wp.shape[:2]
    if split is None:
        out = np.empty((b, 2 * k - 1) + wp.shape[2:])
        out[:, ::2] = wp
        out[:, 1::2] = 0.5 * wp[:, :-1] + 0.5 * wp[:, 1:]
        return out
    old, mid, pieces = _split_index(tuple(split))
    out = np.empty((b, k + pieces.shape[0]) + wp.shape[2:])
    out[:, old] = wp
    out[:, mid] = 0.5 * wp[:, pieces] + 0.5 * wp[:, pieces + 1]
    return out


def mobility(times: np.ndarray, r: int) -> np.ndarray:
    """The mobility of every waypoint, (..., W): ``clip(MOBILITY (W-1) g, 0, 1)`` with ``g`` the
    smallest of the times to the two neighbours and to the fixed times ``k/(r-1)``; 0 at the
    ends. Continuous in the times."""
    w = times.shape[-1]
    out = np.zeros(times.shape)
    t = times[..., 1:-1]
    g = np.minimum(t - times[..., :-2], times[..., 2:] - t)
    for k in range(r):
        g = np.minimum(g, np.abs(t - k / (r - 1)))
    out[..., 1:-1] = np.clip((MOBILITY * (w - 1)) * g, 0.0, 1.0)
    return out


def chord_fraction(times: np.ndarray) -> np.ndarray:
    """``f_j = (t_j - t_{j-1}) / (t_{j+1} - t_{j-1})`` of the interior waypoints (..., W-2);
    1/2 where the two neighbours share their time (the mobility is 0 there)."""
    num = times[..., 1:-1] - times[..., :-2]
    den = times[..., 2:] - times[..., :-2]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.5)


# --- the closed-form piece minima and the no-squeezing levels ---------------------------------

def dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Sum over the last axis in the kernel's order: ``(0 + x0 y0) + x1 y1 + ..``."""
    s = 0.0 + x[..., 0] * y[..., 0]
    for k in range(1, x.shape[-1]):
        s = s + x[..., k] * y[..., k]
    return s


def piece_minima(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Closed-form minimum distance of every pair (a, b) on every piece: (B, W-1, pairs), in
    the arithmetic of :func:`pmplan.certify.segment_clearance` (the kernels' order)."""
    rel = x[:, :, a, :] - x[:, :, b, :]
    r0, r1 = rel[:, :-1], rel[:, 1:]
    v = r1 - r0
    vv = dot(v, v)
    num = -dot(r0, v)
    with np.errstate(invalid="ignore", divide="ignore"):
        q = num / vv
    q = np.where(num >= vv, 1.0, q)
    q = np.where(num <= 0, 0.0, q)
    q = np.where(vv > 0, q, 0.0)
    qx = r0 + q[..., None] * v
    return np.sqrt(dot(qx, qx))


def push_points(r0: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The point of every segment ``r0 + t v`` the clearing pushes along (..., d): ``r0 + q
    v``, ``q = clip(-(r0.v) |v|^2 / (|v|^4 + LAMBDA G), 0, 1)``, ``G = max(|r0|^2 |v|^2 -
    (r0.v)^2, 0)`` (``|v|^2`` times the squared distance h^2 from the origin to the segment's
    line; q = 0 where v = 0). Where the line passes close to the origin (h small against
    ``|v|``) q is the exact closest parameter to within ``LAMBDA h^2 / |v|^2``, and the push
    is outward along the whole piece (``r(t).p >= (1 - LAMBDA) h^2``); where the piece is
    short against its distance q varies slowly, so that ``q v`` is Lipschitz in the ends with
    a constant of order 1 (the exact closest point, whose parameter jumps as v -> 0, is only
    continuous there: it moved by up to ``delta |r0| / |v|`` under a move delta of the
    ends). Continuous: ``|q v| <= |v|``."""
    vv = dot(v, v)
    rv = dot(r0, v)
    gram = np.maximum(dot(r0, r0) * vv - rv * rv, 0.0)
    den = vv * vv + LAMBDA * gram
    with np.errstate(invalid="ignore", divide="ignore"):
        q = np.where(den > 0, -rv * vv / np.where(den > 0, den, 1.0), 0.0)
    return r0 + np.clip(q, 0.0, 1.0)[..., None] * v


def hold_levels(x, a, b, tgt) -> np.ndarray:
    """The no-squeezing level of every pair (B, pairs): ``min(T', max(HOLD min(T', D_raw),
    KAPPA_FLOOR D_raw))``, ``T' = T (1 + MARGIN)``, ``D_raw`` the pair's smallest distance on
    the raw path ``x`` (:data:`HOLD`, :data:`KAPPA_FLOOR`): at least ``HOLD min(T', D_raw)``
    and at least ``min(T', KAPPA_FLOOR D_raw)``, continuous in ``D_raw``."""
    keep = tgt * (1.0 + MARGIN)
    d = piece_minima(x, a, b).min(axis=1)
    return np.minimum(keep, np.maximum(HOLD * np.minimum(keep, d), KAPPA_FLOOR * d))
