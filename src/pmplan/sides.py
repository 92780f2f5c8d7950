"""The side of the obstacles' line that the lanes take in a workspace box (Mathematics §8, "The
side of the lanes").

The one-side lanes (Mathematics §4.4) slide every robot beyond every obstacle on the side of
``nu(e)``, so a robot that passes an obstacle passes between it and the box's wall on that side;
the planner with ``-nu(e)`` passes on the other side. In a box in the plane the planner
:class:`~pmplan.planners.obstacle_line.WallsLinePlanner` takes, query by query, the side where
the walls leave the obstacles the most room, through a continuous function ``f`` of the query:

* ``A(+-)``: the least, over the obstacles ``o_k``, of the parameter at which the ray
  ``o_k +- t J w`` (``w = o2 - o1``, ``J`` the quarter turn of ``nu``) leaves the box: the
  narrowest room a wall leaves an obstacle on each side, in units of ``|w|``;
  ``g = A(+) - A(-)``, in the box's coordinates;
* the guard ``G = D - GUARD |w'|^2``, in the coordinates the planner plans in (the query mapped
  out of the box, ``w' = o'2 - o'1``): ``D`` is the largest, over the robots of every
  configuration, of ``min_k |(x - o_k) . w'|``, ``|w'|`` times the distance from the robot's
  column to the nearest obstacle's column;
* ``f = max(g, -G)``: the lanes take the side of ``-nu(e)`` where ``f < 0`` (``g < 0`` and
  ``G > 0``), and the query lies on the *wall of sides* where ``f = 0``, where its label is one
  less than its stratum's.

The guard keeps the wall of sides away from the queries of the lowest label (every robot of
every configuration in an obstacle's column: ``D = 0``), which is what keeps the number of
labels (the proof is in Mathematics §8). Both signs are decided exactly: in floating point with
an error bound, and the rows that the bound leaves undecided again in rational arithmetic
(:class:`fractions.Fraction` of the floats), so a query's side and label are those of its
coordinates, at every magnitude.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from .predicates import TINY, U, projection_values

__all__ = ["GUARD", "ROBOT_BARRIER", "ROBOT_DELTA", "ROBOT_GAP", "ROBOT_KAPPA", "ROBOT_ROOM",
           "mirror", "robot_sides", "wall_sides"]

#: the guard's width: the side is that of ``nu(e)`` while every robot of every configuration is
#: within ``GUARD |o2 - o1|`` of an obstacle's column (in the coordinates the planner plans in)
GUARD = 2.0 ** -10

def _reach_each(points: np.ndarray, v: np.ndarray, box: np.ndarray) -> np.ndarray:
    """For every point (B, K, 2), the parameter t > 0 at which ``p + t v`` (v (B, 2) nonzero)
    leaves the box (2, 2): shape (B, K), floating point (inf on overflow)."""
    t = np.full(points.shape[:2], np.inf)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        for c in range(2):
            vc = v[:, None, c]
            up = (box[1, c] - points[..., c]) / vc
            dn = (box[0, c] - points[..., c]) / vc
            t = np.minimum(t, np.where(vc > 0, up, np.where(vc < 0, dn, np.inf)))
    return t


def _exact_columns(o: np.ndarray):
    """``(w, dot)`` of one query's obstacles (m, 2) in rational arithmetic: ``w = o2 - o1``
    and ``dot(y, u=w) = (y - o1) . u`` (a column; with ``u = J w`` a height)."""
    o1 = [Fraction(c) for c in o[0]]
    w = [Fraction(c) - a for c, a in zip(o[1], o1)]

    def dot(y, u=w):
        return sum((Fraction(c) - a) * b for c, a, b in zip(y, o1, u))

    return w, dot


def _rooms(o: np.ndarray, box: np.ndarray, sign: float) -> np.ndarray:
    """``A_k`` of every obstacle: the parameter at which ``o_k + sign t J w`` leaves the box,
    (B, m), floating point (each within 3.01 U relatively and TINY absolutely, see
    :func:`_g_signs`)."""
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        w = o[:, 1] - o[:, 0]
        v = sign * np.stack([-w[:, 1], w[:, 0]], axis=1)  # the quarter turn of predicates
    return _reach_each(o, v, box)


def _reach_exact(points, v, box) -> Fraction | None:
    """The least, over the points, of :func:`_reach_each` of one query in rational arithmetic
    (None: no coordinate of v moves)."""
    best = None
    for p in points:
        for c in range(2):
            if v[c] == 0:
                continue
            wall = Fraction(box[1 if v[c] > 0 else 0][c])
            t = (wall - Fraction(p[c])) / v[c]
            best = t if best is None or t < best else best
    return best


def _g_exact(o: np.ndarray, box: np.ndarray) -> int:
    """The sign of ``g`` of one query (obstacles (m, 2) in the box), exactly."""
    w = [Fraction(o[1, c]) - Fraction(o[0, c]) for c in range(2)]
    v = (-w[1], w[0])
    a = _reach_exact(o, v, box)
    b = _reach_exact(o, (-v[0], -v[1]), box)
    return (a > b) - (a < b)


def _g_signs(o: np.ndarray, box: np.ndarray) -> np.ndarray:
    """The sign of ``g`` of every query (obstacles (B, m, 2) in the box): int (B,). A float
    sign is kept where it exceeds the rounding error: each parameter ``(wall - p) / v`` is
    within 3.01 U of its value relatively (``v``, the subtraction and the quotient round once
    each; a subtraction that underflows is exact) and TINY absolutely (a quotient that
    underflows), and so are their minima; the rest is decided again exactly."""
    a, b = _rooms(o, box, 1.0).min(axis=1), _rooms(o, box, -1.0).min(axis=1)
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        g = a - b
        sure = np.isfinite(g) & (np.abs(g) > 4.1 * U * (a + b) + 3 * TINY)
    sign = np.where(g > 0, 1, -1).astype(np.int64)
    for i in np.flatnonzero(~sure):
        sign[i] = _g_exact(o[i], box)
    return sign


def _guard_exact(zo: np.ndarray, zc: list) -> int:
    """The sign of the guard ``G`` of one query (obstacles (m, 2), configurations (n, 2) each,
    mapped out of the box), exactly: with the columns ``(y - o1) . w`` of
    :mod:`pmplan.predicates`, ``(x - o_k) . w`` is the difference of two columns and
    ``|w|^2`` the column of ``o2``."""
    _, column = _exact_columns(zo)
    obstacles = [column(y) for y in zo]
    d = max(min(abs(column(x) - k) for k in obstacles) for conf in zc for x in conf)
    g = d - Fraction(GUARD) * obstacles[1]
    return (g > 0) - (g < 0)


def _guard_signs(zo: np.ndarray, zc: list) -> np.ndarray:
    """The sign of the guard ``G`` of every query: int (B,), from the columns of
    :func:`pmplan.predicates.projection_values` and their error bound ``E``: a float sign is
    kept where it exceeds ``2 E + U max|difference|`` and the last roundings; the rest is
    decided again exactly."""
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        robots, e_r = projection_values(np.concatenate(zc, axis=1), zo[:, 0], zo[:, 1])
        obstacles, e_o = projection_values(zo, zo[:, 0], zo[:, 1])
        diff = np.abs(robots[:, :, None] - obstacles[:, None, :])  # (x - o_k) . w
        d = diff.min(axis=2).max(axis=1)
        g = d - GUARD * obstacles[:, 1]  # |w|^2 is the column of o2
        err = 1.01 * (2.01 * np.maximum(e_r, e_o) + U * diff.max(axis=(1, 2))) + 2 * TINY
        sure = np.isfinite(g) & np.isfinite(err) & (np.abs(g) > err)
    sign = np.where(g > 0, 1, -1).astype(np.int64)
    for i in np.flatnonzero(~sure):
        sign[i] = _guard_exact(zo[i], [c[i] for c in zc])
    return sign


def wall_sides(obstacles: np.ndarray, z_obstacles: np.ndarray, z_configs: list,
               box: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The side of the lanes and the wall of sides of a batch of queries in the plane.

    Parameters
    ----------
    obstacles : ndarray, shape (B, m, 2)
        The obstacles, in the box.
    z_obstacles, z_configs : ndarray (B, m, 2) and a list of ndarrays (B, n, 2)
        The obstacles and the configurations mapped out of the box, as the planner plans them
        (:func:`pmplan.workspace.from_box_linear`).
    box : ndarray, shape (2, 2)
        The box's corners (:func:`pmplan.workspace.check_bounds`).

    Returns
    -------
    flip : ndarray of bool, shape (B,)
        The lanes take the side of ``-nu(e)``: ``f < 0``.
    wall : ndarray of bool, shape (B,)
        The query lies on the wall of sides, ``f = 0``: its label is one less.

    Examples
    --------
    Two obstacles on a line through the middle of the box leave as much room on each side
    (the wall of sides); moved up, more room below, on the side of ``-nu(e)``:

    >>> box = np.array([[0.0, 0.0], [10.0, 10.0]])
    >>> o = np.array([[[4.0, 5.0], [6.0, 5.0]], [[4.0, 7.0], [6.0, 7.0]]])
    >>> x = [np.array([[[1.0, 1.0]], [[1.0, 1.0]]]), np.array([[[9.0, 9.0]], [[9.0, 9.0]]])]
    >>> flip, wall = wall_sides(o, o, x, box)
    >>> flip.tolist(), wall.tolist()
    ([False, True], [True, False])
    """
    g = _g_signs(np.asarray(obstacles, dtype=float), np.asarray(box, dtype=float))
    guard = _guard_signs(np.asarray(z_obstacles, dtype=float),
                         [np.asarray(c, dtype=float) for c in z_configs])
    flip = (g < 0) & (guard > 0)
    wall = (g <= 0) & (guard >= 0) & ~flip
    return flip, wall


def mirror(points: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``points`` (B, ..., d) with the first coordinate of the rows ``rows`` (bool (B,))
    negated: the reflection that turns the planner's ``nu(e)`` into ``-nu(e)`` (exactly: a
    negation rounds nothing). A copy."""
    out = np.array(points, dtype=float, copy=True)
    out[rows, ..., 0] = -out[rows, ..., 0]
    return out


# --- a side per robot (Mathematics §8, "A side per robot") ------------------------------------

#: the weight of the walls' room against a robot's own heights in :func:`robot_sides`
ROBOT_KAPPA = 2.0
#: the width, in columns (units of ``|w|``), over which an obstacle's room comes to count for a
#: robot whose columns reach past it (:func:`robot_sides`)
ROBOT_DELTA = 0.125
#: what an obstacle no column of the robot reaches adds to its room (:func:`robot_sides`):
#: more than the room of any obstacle of the scene families, so that it does not count
ROBOT_ROOM = 4.0
#: a room the walls leave an obstacle is *narrow* below ROBOT_GAP units of the motion (the
#: lanes' spacing, by default the robots' diameter for a refined plan; :func:`robot_sides`)
ROBOT_GAP = 3.0
#: the weight of a narrow room on a robot's side (:func:`robot_sides`): it outweighs the
#: robot's own heights in the scene families, so that a robot passes an obstacle where a
#: robot fits
ROBOT_BARRIER = 32.0


def _clip01(x: Fraction) -> Fraction:
    return min(max(x, Fraction(0)), Fraction(1))


def _f_exact(o: np.ndarray, xs: list, box: np.ndarray, lift: float) -> list:
    """The signs of ``f_i`` of one query (obstacles (m, 2), the robot's positions ``xs`` (r
    arrays (n, 2)) in the box, the unit ``lift``, or the scene's for ``lift <= 0``),
    exactly."""
    w, col = _exact_columns(o)
    jw = (-w[1], w[0])
    ww = col(o[1])
    u2 = (Fraction(lift) ** 2 if lift > 0 else
          max(sum((Fraction(c) - Fraction(a)) ** 2 for c, a in zip(y, o[0])) for y in o[1:]))
    gap = Fraction(ROBOT_GAP) ** 2 * u2
    cols = [col(y) for y in o]
    rooms = [[_reach_exact([y], s, box) for y in o] for s in (jw, (-jw[0], -jw[1]))]
    signs = []
    for i in range(xs[0].shape[0]):
        h = sum(col(x[i], jw) for x in xs) / ww
        p = [col(x[i]) for x in xs]
        a, b = min(p), max(p)
        om = [_clip01(min(ck - a, b - ck) / (Fraction(ROBOT_DELTA) * ww)) for ck in cols]
        room = [min(side[k] + Fraction(ROBOT_ROOM) * (1 - om[k]) for k in range(len(cols)))
                for side in rooms]
        bar = [max(om[k] * _clip01(1 - side[k] ** 2 * ww / gap) for k in range(len(cols)))
               for side in rooms]
        f = (h + Fraction(ROBOT_KAPPA) * (room[0] - room[1])
             + Fraction(ROBOT_BARRIER) * (bar[1] - bar[0]))
        signs.append((f > 0) - (f < 0))
    return signs


def _f_signs(o: np.ndarray, xs: list, box: np.ndarray, lift: np.ndarray) -> np.ndarray:
    """The signs of ``f_i`` of every robot of every query (obstacles (B, m, 2), the robots'
    positions ``xs``, r arrays (B, n, 2), in the box; ``lift`` (B,), the unit, or the scene's
    where it is not positive): int (B, n).

    In floating point from the columns ``P = (y - o1) . w`` and heights ``Q = (y - o1) . J w``
    of :func:`pmplan.predicates.projection_values` (each within its bound ``E``) and ``|w|^2``,
    the column of o2: every later operation's error is carried to a bound on ``f_i`` (a
    quotient by ``|w|^2`` once ``|w|^2`` exceeds ``4 E``, the rooms within 3.01 U relatively,
    clip, min and max 1-Lipschitz, every rounding U relatively and TINY absolutely; the
    narrow rooms' quotient within 24 U relatively and its operands' bounds); a float sign
    beyond the bound is kept, the rest (and every row whose rooms or unit are below 2**-400 or
    whose unit's square is not finite) decided again exactly."""
    r = len(xs)
    b, m, _ = o.shape
    n = xs[0].shape[1]
    with np.errstate(over="ignore", invalid="ignore", under="ignore", divide="ignore"):
        robots = np.concatenate(xs, axis=1)  # (B, r n, 2)
        pts = np.concatenate([o, robots], axis=1)
        P, eP = projection_values(pts, o[:, 0], o[:, 1])
        Q, eQ = projection_values(robots, o[:, 0], o[:, 1], perpendicular=True)
        E = np.maximum(eP, eQ)[:, None]  # (B, 1)
        W = P[:, 1:2]  # |w|^2
        rel = E / W
        Pk, Pr = P[:, :m], P[:, m:].reshape(b, r, n)
        Qr = Q.reshape(b, r, n)
        hs = Qr.sum(axis=1)  # (B, n)
        e_hs = r * E + r * U * np.abs(Qr).sum(axis=1)
        h = hs / W
        e_h = 2 * (e_hs + 2 * np.abs(hs) * rel) / W + 2 * U * np.abs(h) + TINY
        lo, hi = Pr.min(axis=1), Pr.max(axis=1)  # (B, n)
        num = np.minimum(Pk[:, None, :] - lo[..., None], hi[..., None] - Pk[:, None, :])
        e_num = 2 * E[..., None] + U * np.abs(num)
        t = num / (ROBOT_DELTA * W[..., None])
        e_t = (2 * (e_num + 2 * np.abs(num) * rel[..., None]) / (ROBOT_DELTA * W[..., None])
               + 2 * U * np.abs(t) + TINY)
        om = np.clip(t, 0.0, 1.0)  # (B, n, m)
        d = o[:, 1:] - o[:, :1]
        u2 = np.where(lift > 0, lift * lift, (d * d).sum(-1).max(axis=1))[:, None, None]
        gap = ROBOT_GAP * ROBOT_GAP * u2  # (B, 1, 1), within 3.01 U
        tame = (u2[:, 0, 0] > 2.0**-400) & np.isfinite(u2[:, 0, 0])
        room, e_room, bar, e_bar = [], [], [], []
        for sign in (1.0, -1.0):
            a = _rooms(o, box, sign)[:, None, :]  # (B, 1, m)
            tame &= (a > 2.0**-400).all(axis=(1, 2))
            term = a + ROBOT_ROOM * (1.0 - om)
            e_term = 3.01 * U * a + TINY + ROBOT_ROOM * (e_t + U) + U * np.abs(term)
            room.append(term.min(axis=2))
            e_room.append(e_term.max(axis=2))
            y = a * a * W[..., None] / gap  # the narrow rooms' quotient
            e_y = (24 * U + 2 * rel[..., None]) * y
            lid = om * np.clip(1.0 - y, 0.0, 1.0)
            bar.append(lid.max(axis=2))
            e_bar.append((e_t + e_y + 2 * U + 2 * U * lid).max(axis=2))
        diff = room[0] - room[1]
        nar = bar[1] - bar[0]
        f = h + ROBOT_KAPPA * diff + ROBOT_BARRIER * nar
        err = 1.01 * (e_h + ROBOT_KAPPA * (e_room[0] + e_room[1] + U * np.abs(diff))
                      + ROBOT_BARRIER * (e_bar[0] + e_bar[1] + U * np.abs(nar))
                      + 2 * U * np.abs(f)) + 4 * TINY
        sure = (np.isfinite(f) & np.isfinite(err) & (np.abs(f) > err)
                & (W > 4 * E) & np.isfinite(W) & tame[:, None])
    sign = np.where(f > 0, 1, -1).astype(np.int64)
    for q in np.flatnonzero(~sure.all(axis=1)):
        sign[q] = _f_exact(o[q], [x[q] for x in xs], box, float(lift[q]))
    return sign


def _robot_guard_exact(zo: np.ndarray, zc: list) -> list:
    """The signs of the guards ``G_i`` of one query (obstacles (m, 2), configurations (n, 2)
    each, mapped out of the box), exactly (the columns as in :func:`_guard_exact`)."""
    _, column = _exact_columns(zo)
    obstacles = [column(y) for y in zo]
    confs = [[column(x) for x in conf] for conf in zc]
    signs = []
    for i in range(len(confs[0])):
        d = max(min(abs(cs[i] - p) for p in obstacles + cs[:i] + cs[i + 1:]) for cs in confs)
        g = d - Fraction(GUARD) * obstacles[1]
        signs.append((g > 0) - (g < 0))
    return signs


def _robot_guard_signs(zo: np.ndarray, zc: list) -> np.ndarray:
    """The signs of the guards ``G_i`` of every robot of every query: int (B, n), from the
    columns of :func:`pmplan.predicates.projection_values` and their bound, as
    :func:`_guard_signs`; the rest decided again exactly."""
    b, m, _ = zo.shape
    n = zc[0].shape[1]
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        cols, e = projection_values(np.concatenate([zo] + list(zc), axis=1), zo[:, 0], zo[:, 1])
        big = np.full((b, n), 0.0)
        d = np.full((b, n), -np.inf)
        for k in range(len(zc)):
            others = np.concatenate([cols[:, :m], cols[:, m + k * n:m + (k + 1) * n]], axis=1)
            x = cols[:, m + k * n:m + (k + 1) * n]
            diff = np.abs(x[:, :, None] - others[:, None, :])  # (B, n, m + n)
            diff[:, np.arange(n), m + np.arange(n)] = np.inf  # not the robot itself
            d = np.maximum(d, diff.min(axis=2))
            big = np.maximum(big, np.where(np.isfinite(diff), diff, 0.0).max(axis=2))
        g = d - GUARD * cols[:, 1:2]  # |w|^2 is the column of o2
        err = 1.01 * (2.01 * e[:, None] + U * big) + 2 * TINY
        sure = np.isfinite(g) & np.isfinite(err) & (np.abs(g) > err)
    sign = np.where(g > 0, 1, -1).astype(np.int64)
    for q in np.flatnonzero(~sure.all(axis=1)):
        sign[q] = _robot_guard_exact(zo[q], [c[q] for c in zc])
    return sign


def robot_sides(obstacles: np.ndarray, configs: list, z_obstacles: np.ndarray,
                z_configs: list, box: np.ndarray, lift=1.0) -> tuple[np.ndarray, np.ndarray]:
    """The side of every robot's lanes and the walls a query lies on, for a batch of queries
    in the plane (Mathematics §8, "A side per robot").

    For robot i, through its positions ``x_i^1..x_i^r`` (start, goal and any via):

    * ``h_i = sum_k (x_i^k - o1) . J w / |w|^2``, its heights above the line o1o2 in units of
      ``|w|`` (``w = o2 - o1``, ``J`` the quarter turn of ``nu``, in the box's coordinates);
    * ``R_i(+-) = min_k (A_k(+-) + ROBOT_ROOM (1 - omega_ik))``: the room the walls leave the
      obstacles on either side (``A_k(+-)`` as in :func:`wall_sides`, per obstacle), counted
      for the obstacles the robot's columns reach past: ``omega_ik = clip(min(c_k - a_i, b_i -
      c_k) / ROBOT_DELTA, 0, 1)`` with ``c_k`` the obstacle's column and ``[a_i, b_i]`` the
      span of the robot's columns, all in units of ``|w|``;
    * ``N_i(+-) = max_k omega_ik clip(1 - (A_k(+-) |w|)^2 / (ROBOT_GAP u)^2, 0, 1)``: how
      narrow the narrowest room is that the robot would pass on either side, against
      ``ROBOT_GAP`` units ``u`` of the motion (``lift``; for ``"scene"``, the obstacles' radius
      ``max_k |o_k - o1|`` in the box);
    * ``f_i = h_i + ROBOT_KAPPA (R_i(+) - R_i(-)) + ROBOT_BARRIER (N_i(-) - N_i(+))``, and the
      guard ``G_i``, in the
      coordinates the planner plans in: the largest, over the configurations, of the distance
      from the robot's column to the nearest column of another point (obstacle or robot),
      times ``|w'|``, less ``GUARD |w'|^2``;
    * ``f'_i = max(f_i, -G_i)``: robot i's lanes take the side of ``-nu(e)`` where
      ``f'_i < 0``, and the query lies on robot i's wall where ``f'_i = 0``.

    Every sign is decided exactly (floating point with an error bound, the undecided rows again
    in rational arithmetic).

    Parameters
    ----------
    obstacles : ndarray, shape (B, m, 2)
        The obstacles, in the box.
    configs : list of ndarray (B, n, 2)
        The configurations (start, goal and any via), in the box.
    z_obstacles, z_configs : ndarray (B, m, 2) and a list of ndarrays (B, n, 2)
        The same mapped out of the box, as the planner plans them
        (:func:`pmplan.workspace.from_box_linear`).
    box : ndarray, shape (2, 2)
        The box's corners (:func:`pmplan.workspace.check_bounds`).
    lift : float or ndarray (B,)
        The unit of the motion (:func:`pmplan.planners.base.lift_code`: a positive unit, or
        :data:`~pmplan.planners.base.SCENE_CODE` for the scene's).

    Returns
    -------
    down : ndarray of bool, shape (B, n)
        Robot i's lanes take the side of ``-nu(e)``: ``f'_i < 0``.
    walls : ndarray of int, shape (B,)
        The number of robots with ``f'_i = 0``: the query's label is that many less.

    Examples
    --------
    Two robots above the line of two obstacles in the middle of the box, and two below:

    >>> box = np.array([[0.0, 0.0], [10.0, 10.0]])
    >>> o = np.array([[[4.0, 5.0], [6.0, 5.0]]])
    >>> x = [np.array([[[1.0, 8.0], [2.0, 2.0]]]), np.array([[[9.0, 7.0], [8.0, 1.0]]])]
    >>> down, walls = robot_sides(o, x, o, x, box, lift=0.3)
    >>> down.tolist(), walls.tolist()
    ([[False, True]], [0])
    """
    o = np.asarray(obstacles, dtype=float)
    xs = [np.asarray(c, dtype=float) for c in configs]
    lift = np.broadcast_to(np.asarray(lift, dtype=float), o.shape[:1])
    f = _f_signs(o, xs, np.asarray(box, dtype=float), lift)
    guard = _robot_guard_signs(np.asarray(z_obstacles, dtype=float),
                               [np.asarray(c, dtype=float) for c in z_configs])
    down = (f < 0) & (guard > 0)
    wall = ~down & (((f == 0) & (guard >= 0)) | ((guard == 0) & (f <= 0)))
    return down, wall.sum(axis=1).astype(np.int64)
