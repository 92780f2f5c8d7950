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

__all__ = ["GUARD", "wall_sides", "mirror"]

#: the guard's width: the side is that of ``nu(e)`` while every robot of every configuration is
#: within ``GUARD |o2 - o1|`` of an obstacle's column (in the coordinates the planner plans in)
GUARD = 2.0 ** -10

def _reach(points: np.ndarray, v: np.ndarray, box: np.ndarray) -> np.ndarray:
    """The least, over the points (B, K, 2), of the parameter t > 0 at which ``p + t v`` (v
    (B, 2) nonzero) leaves the box (2, 2): shape (B,), floating point (inf on overflow)."""
    t = np.full(points.shape[:2], np.inf)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        for c in range(2):
            vc = v[:, None, c]
            up = (box[1, c] - points[..., c]) / vc
            dn = (box[0, c] - points[..., c]) / vc
            t = np.minimum(t, np.where(vc > 0, up, np.where(vc < 0, dn, np.inf)))
    return t.min(axis=1)


def _reach_exact(points, v, box) -> Fraction | None:
    """:func:`_reach` of one query in rational arithmetic (None: no coordinate of v moves)."""
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
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        w = o[:, 1] - o[:, 0]
        v = np.stack([-w[:, 1], w[:, 0]], axis=1)  # the quarter turn of pmplan.predicates
        a, b = _reach(o, v, box), _reach(o, -v, box)
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
    o1 = [Fraction(c) for c in zo[0]]
    w = [Fraction(c) - a for c, a in zip(zo[1], o1)]

    def column(y):
        return sum((Fraction(c) - a) * b for c, a, b in zip(y, o1, w))

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
