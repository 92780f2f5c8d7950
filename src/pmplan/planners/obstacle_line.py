"""The obstacle-line planner: deform to the line through o1, o2, lift, slide, descend.

This is the planner of paper Section 3 (for pi_{n+2,2}: m = 2 obstacles, d even, any n >= 1,
2n+1 domains W_4..W_{2n+4}) and, with the same code, its extensions of SPEC section 4:
odd d >= 3 (SPEC 4a) and any number of obstacles m >= 2 (SPEC 4b). For m = 2 and even d the
paths and labels are exactly the paper's; there is one implementation.

Notation (paper Section 3, Figure ``Lc``): ``w = o2 - o1``, ``e = w/|w|``, the column
``s(y) = (y - o1).e``, the perpendicular part ``r(y) = (y - o1) - s(y) e``, and ``nu(e)`` the
unit normal of :mod:`pmplan.frame`.

* ``cp(C)``: number of distinct columns among the m+n points; ``cp_o``: among the obstacles.
* ``eps(C) = min{|s(a) - s(b)| : s(a) != s(b)} / (n+m)`` over all m+n points.
* Desingularization ``(desin)``, Figure ``algorithm3``: robot j (1-based) moves
  ``x_j -> x_j + t j eps(C) e``; it is the identity when no robot shares its column with another
  point (``cp(C) = cp_o + n``; for m = 2, ``cp(C) = n+2``).
* Projection ``(linear-transformation-obs)``, Figure ``algorithm2``: robots ``x -> x - t r(x)``;
  obstacles never move.
* ``H(C, s)``: the desingularization at 2s on [0, 1/2], then the projection at 2s - 1.
* Section over collinear pairs ``(algorithm-gamma)``, Figure ``algorithm1``: robot i is lifted by
  ``i lambda nu(e)``, slides from X_i to X'_i, and descends, with
  ``lambda = lift + max_{k>=3} |r(o_k)|`` (= lift for m = 2; the paper has lift = 1).
* The whole path is the composition of paper Remark
  ``constructing-sections-via-deformations-higher-case``: [0,1/3] H(C, 3 tau),
  [1/3,2/3] the section, [2/3,1] H(C', 3 - 3 tau). Eight waypoints, at
  tau = 0, 1/6, 1/3, 4/9, 5/9, 2/3, 5/6, 1.
* Domain label (paper, "Repacking regions of continuity"; SPEC 4a/4b)::

      l = cp(C) + cp(C') - cp_o + 2 - [d odd and e == N]

  in {4, ..., 2n+m+2} for even d (2n+m-1 domains) and {3, ..., 2n+m+2} for odd d (2n+m):
  the parametrised topological complexity of paper Theorem ``gongra``, so the planner is optimal.

References
----------
C. A. Ipanaque Zapata and J. Gonzalez, *Parametrised collision-free optimal motion planning
algorithms in Euclidean spaces*, Section 3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..frame import Frame
from ..path import PiecewiseLinearPath, compose_via_deformations, join, linear
from ..predicates import projection_classes
from .base import RawPlan, register

__all__ = [
    "ColumnStructure",
    "column_structure",
    "deformation",
    "section",
    "ObstacleLinePlanner",
    "OBSTACLE_LINE",
]


@dataclass
class ColumnStructure:
    """Exact column data of a batch of configurations (B queries).

    Attributes
    ----------
    cp : ndarray of int64, shape (B,)      distinct columns among all m+n points
    cp_o : ndarray of int64, shape (B,)    distinct columns among the obstacles
    desingularize : ndarray of bool        some robot shares its column (cp < cp_o + n)
    eps : ndarray of float, shape (B,)     eps(C)
    """

    cp: np.ndarray
    cp_o: np.ndarray
    desingularize: np.ndarray
    eps: np.ndarray


def column_structure(fr: Frame, obstacles: np.ndarray, robots: np.ndarray) -> ColumnStructure:
    """Return cp(C), cp_o, whether to desingularize, and eps(C), all decided exactly."""
    m, n = obstacles.shape[1], robots.shape[1]
    pts = np.concatenate([obstacles, robots], axis=1)
    labels, cp, gap = projection_classes(pts, obstacles[:, 0], obstacles[:, 1])
    olab = np.sort(labels[:, :m], axis=1)
    cp_o = 1 + (np.diff(olab, axis=1) != 0).sum(axis=1)
    eps = gap / fr.norm / (n + m)
    return ColumnStructure(cp=cp, cp_o=cp_o, desingularize=cp < cp_o + n, eps=eps)


def deformation(fr: Frame, obstacles, robots, cols: ColumnStructure) -> PiecewiseLinearPath:
    """Return ``H(C, .)``: desingularization on [0, 1/2], projection to L_C on [1/2, 1].

    Waypoints C, C1 = F(C, 1) (paper ``(desin)``), C2 = phi(C1, 1) (paper
    ``(linear-transformation-obs)``), shape (B, 3, m+n, d).
    """
    n = robots.shape[1]
    j = np.arange(1, n + 1, dtype=float)
    shift = np.where(cols.desingularize, cols.eps, 0.0)[:, None] * j[None, :]
    x1 = robots + shift[..., None] * fr.e[:, None, :]
    s1 = ((x1 - fr.o1[:, None, :]) * fr.e[:, None, :]).sum(-1)
    x2 = fr.o1[:, None, :] + s1[..., None] * fr.e[:, None, :]
    c0 = np.concatenate([obstacles, robots], axis=1)
    c1 = np.concatenate([obstacles, x1], axis=1)
    c2 = np.concatenate([obstacles, x2], axis=1)
    return linear(c0, c1).join(linear(c1, c2), at=[0.5])


def lift_height(fr: Frame, obstacles: np.ndarray, lift: float) -> np.ndarray:
    """Return ``lambda = lift + max_{k >= 3} |r(o_k)|`` (SPEC 4b), shape (B,)."""
    if obstacles.shape[1] <= 2:
        return np.full(obstacles.shape[0], float(lift))
    r = fr.perpendicular(obstacles[:, 2:])
    return lift + np.sqrt((r * r).sum(-1)).max(axis=1)


def section(fr: Frame, x_start, x_goal, lam: np.ndarray, m: int) -> PiecewiseLinearPath:
    """Return the section over collinear pairs, paper ``(algorithm-gamma)``, Figure ``algorithm1``.

    ``x_start``, ``x_goal`` are collinear configurations (B, m+n, d) with the same obstacles.
    Robot i (1-based)::

        [0, 1/3]   X_i + 3 tau i lambda nu(e)
        [1/3, 2/3] X_i + i lambda nu(e) + (3 tau - 1)(X'_i - X_i)
        [2/3, 1]   X'_i + (3 - 3 tau) i lambda nu(e)
    """
    n = x_start.shape[1] - m
    i = np.arange(1, n + 1, dtype=float)
    off = np.zeros_like(x_start)
    off[:, m:] = (lam[:, None] * i[None, :])[..., None] * fr.nu[:, None, :]
    wp = np.stack([x_start, x_start + off, x_goal + off, x_goal], axis=1)
    return PiecewiseLinearPath(np.array([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]), wp)


def two_configuration_path(fr, obstacles, h_start, h_goal, lam) -> PiecewiseLinearPath:
    """Compose H(C), the section and H(C') reversed (paper Remark, via the path algebra)."""
    m = obstacles.shape[1]
    sec = section(fr, h_start.waypoints[:, -1], h_goal.waypoints[:, -1], lam, m)
    return compose_via_deformations(h_start, sec, h_goal)


class ObstacleLinePlanner:
    """Planner of paper Section 3, extended to any m >= 2 and any d >= 2 (SPEC 4a, 4b)."""

    name = "obstacle_line"
    summary = (
        "paper Section 3 (m = 2, d even) and its extensions to odd d and m >= 2 (SPEC 4a/4b): "
        "desingularize, project to the line o1o2, lift-slide-descend"
    )

    def supports(self, d: int, n: int, m: int) -> str | None:
        if d < 2:
            return f"d = {d}: planners need d >= 2"
        if n < 1:
            return f"n = {n}: at least one robot is needed"
        if m < 2:
            return f"m = {m}: this planner needs m >= 2 obstacles (they define the line L_C)"
        return None

    def domain_labels(self, d: int, n: int, m: int) -> list[int]:
        low = 4 if d % 2 == 0 else 3
        return list(range(low, 2 * n + m + 3))

    def stratum_name(self, row, d: int, n: int, m: int) -> str:
        *cps, cp_o, pole = (int(v) for v in row)
        name = "T_{" + ",".join(str(c) for c in cps) + "}"
        extras = []
        if m > 2:
            extras.append(f"cp_o={cp_o}")
        if pole:
            extras.append("e=N")
        return name + (f"[{', '.join(extras)}]" if extras else "")

    def plan(self, obstacles, start, goal, *, lift: float = 1.0) -> RawPlan:
        return self.plan_sequence(obstacles, [start, goal], lift=lift)

    def plan_sequence(self, obstacles, configs, *, lift: float = 1.0) -> RawPlan:
        """Plan through r >= 2 robot configurations (SPEC 4c); r = 2 is :meth:`plan`.

        On ``[(k-1)/(r-1), k/(r-1)]`` the path is the two-configuration path from C_k to
        C_{k+1}; label ``sum_k cp(C_k) - (r-1) cp_o + 2 - [e == N]``.
        """
        obstacles = np.asarray(obstacles, dtype=float)
        configs = [np.asarray(c, dtype=float) for c in configs]
        r = len(configs)
        fr = Frame(obstacles[:, 0], obstacles[:, 1])
        m = obstacles.shape[1]
        cols = [column_structure(fr, obstacles, c) for c in configs]
        hs = [deformation(fr, obstacles, c, cs) for c, cs in zip(configs, cols)]
        lam = lift_height(fr, obstacles, lift)
        legs = [two_configuration_path(fr, obstacles, hs[k], hs[k + 1], lam) for k in range(r - 1)]
        path = legs[0] if r == 2 else join(legs, [k / (r - 1) for k in range(1, r - 1)])
        cp_o = cols[0].cp_o
        pole = fr.at_pole.astype(np.int64)
        domain = sum(c.cp for c in cols) - (r - 1) * cp_o + 2 - pole
        strata = np.stack([c.cp for c in cols] + [cp_o, pole], axis=1).astype(np.int64)
        del m
        return RawPlan(domain=domain.astype(np.int64), strata=strata, path=path)


OBSTACLE_LINE = register(ObstacleLinePlanner())
