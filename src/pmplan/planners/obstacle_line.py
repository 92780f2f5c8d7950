"""The obstacle-line planner: deform to the line through o1, o2, lift, slide, descend.

This is the planner of paper Section 3 (for pi_{n+2,2}: m = 2 obstacles, d even, any n >= 1,
2n+1 domains W_4..W_{2n+4}) and, with the same code, its extensions of Mathematics §4:
odd d >= 3 (Mathematics §4.1) and any number of obstacles m >= 2 (Mathematics §4.2). For m = 2 and even d the
paths and labels are exactly the paper's; there is one implementation.

Notation (paper Section 3, Figure 1): ``w = o2 - o1``, ``e = w/|w|``, the column
``s(y) = (y - o1).e``, the perpendicular part ``r(y) = (y - o1) - s(y) e``, and ``nu(e)`` the
unit normal of :mod:`pmplan.frame`.

* ``cp(C)``: number of distinct columns among the m+n points; ``cp_o``: among the obstacles.
* ``eps(C) = min{|s(a) - s(b)| : s(a) != s(b)} / (n+m)`` over all m+n points.
* Desingularization of paper (3.2), Figure 2: robot j (1-based) moves
  ``x_j -> x_j + t j eps(C) e``; it is the identity when no robot shares its column with another
  point (``cp(C) = cp_o + n``; for m = 2, ``cp(C) = n+2``).
* Projection of paper (3.6), Figure 3: robots ``x -> x - t r(x)``;
  obstacles never move. (The compact lanes, d >= 3: ``x -> x - t (r(x).nu) nu``, the robot
  keeps its offset ``r(x) - (r(x).nu) nu``, Mathematics §4.4.)
* ``H(C, s)``: the desingularization at 2s on [0, 1/2], then the projection at 2s - 1.
* Section over collinear pairs of paper (3.8), Figure 4: robot i is lifted by
  ``i lambda nu(e)``, slides from X_i to X'_i, and descends, with
  ``lambda = lift + max_{k>=3} |r(o_k)|`` (= lift for m = 2; the paper has lift = 1), where
  the unit ``lift`` is a positive number, or with ``lift="scene"`` the obstacles' radius
  ``u(O) = max_k |o_k - o_1|`` of the query (:func:`~pmplan.planners.base.scene_unit`), which
  makes the planner equivariant under translations, rotations (d = 2) and scalings.
* The whole path is the composition of paper Remark 2.5: [0,1/3] H(C, 3 tau),
  [1/3,2/3] the section, [2/3,1] H(C', 3 - 3 tau). Eight waypoints, at
  tau = 0, 1/6, 1/3, 4/9, 5/9, 2/3, 5/6, 1.
* Domain label (paper Section 3.5, "Repacking regions of continuity"; Mathematics §4.1, §4.2)::

      l = cp(C) + cp(C') - cp_o + 2 - [d odd and e == N]

  in {4, ..., 2n+m+2} for even d (2n+m-1 domains) and {3, ..., 2n+m+2} for odd d (2n+m):
  the parametrised topological complexity of paper Theorem 2.6, so the planner is optimal.

References
----------
C. A. Ipanaque Zapata and J. Gonzalez, *Parametrised collision-free optimal motion planning
algorithms in Euclidean spaces*, Section 3.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from ..frame import Frame
from ..path import DIRECT_AT, PiecewiseLinearPath, compose_via_deformations, join, linear
from ..predicates import projection_classes
from .base import Planner, RawPlan, lift_code, out_of_scope, register, unit

__all__ = [
    "ColumnStructure",
    "column_structure",
    "deformation",
    "offset",
    "section",
    "SECTION_TIMES",
    "path_times",
    "ObstacleLinePlanner",
    "CompactLinePlanner",
    "OBSTACLE_LINE",
    "OBSTACLE_LINE_COMPACT",
    "OBSTACLE_LINE_ONESIDE",
    "OBSTACLE_LINE_SHARED",
    "OBSTACLE_LINE_ROBOTS",
    "OBSTACLE_LINE_WALLS",
    "OneSideLinePlanner",
    "RobotsLinePlanner",
    "SharedLinePlanner",
    "WallsLinePlanner",
    "lane_heights",
    "lane_chains",
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
    key : ndarray of int64, shape (B, n)   every robot's place in the column order of
                                           ``H(C, 1)`` (the smaller key the smaller column): by
                                           its column class, then (robots the
                                           desingularization separates, paper (3.2)) by its
                                           index
    """

    cp: np.ndarray
    cp_o: np.ndarray
    desingularize: np.ndarray
    eps: np.ndarray
    key: np.ndarray


def column_structure(fr: Frame, obstacles: np.ndarray, robots: np.ndarray) -> ColumnStructure:
    """Return cp(C), cp_o, whether to desingularize, eps(C) and the robots' order keys, all
    decided exactly."""
    m, n = obstacles.shape[1], robots.shape[1]
    pts = np.concatenate([obstacles, robots], axis=1)
    labels, cp, gap = projection_classes(pts, obstacles[:, 0], obstacles[:, 1])
    olab = np.sort(labels[:, :m], axis=1)
    cp_o = 1 + (np.diff(olab, axis=1) != 0).sum(axis=1)
    eps = gap / fr.norm / (n + m)
    # robot j of a class moves by j eps(C) e (paper (3.2)) and eps(C) is below every gap
    # between classes: in H(C, 1) the robots are ordered by class, then by index
    key = labels[:, m:] * n + np.arange(n)[None, :]
    return ColumnStructure(cp=cp, cp_o=cp_o, desingularize=cp < cp_o + n, eps=eps, key=key)


def deformation(fr: Frame, obstacles, robots, cols: ColumnStructure,
                offsets: bool = False) -> PiecewiseLinearPath:
    """Return ``H(C, .)``: desingularization on [0, 1/2], projection on [1/2, 1].

    Waypoints C, C1 = F(C, 1) (paper (3.2)), C2 = phi(C1, 1) (paper
    (3.6)), shape (B, 3, m+n, d). With ``offsets`` (the compact lanes, Mathematics §4.4, for
    d >= 3) the projection removes only the ``nu(e)`` part of every robot's perpendicular part
    ``r(x)``: C2 keeps the *offset* ``r(x) - (r(x).nu) nu``, and lies in the hyperplane through
    the obstacle line orthogonal to ``nu``, not on the line (in the plane the offset is 0: the
    projection is paper (3.6)).
    """
    n = robots.shape[1]
    j = np.arange(1, n + 1, dtype=float)
    shift = np.where(cols.desingularize, cols.eps, 0.0)[:, None] * j[None, :]
    x1 = robots + shift[..., None] * fr.e[:, None, :]
    s1 = ((x1 - fr.o1[:, None, :]) * fr.e[:, None, :]).sum(-1)
    x2 = fr.o1[:, None, :] + s1[..., None] * fr.e[:, None, :]
    if offsets and robots.shape[2] > 2:
        x2 = x2 + offset(fr, x1 - x2)
    c0 = np.concatenate([obstacles, robots], axis=1)
    c1 = np.concatenate([obstacles, x1], axis=1)
    c2 = np.concatenate([obstacles, x2], axis=1)
    return linear(c0, c1).join(linear(c1, c2), at=[0.5])


def offset(fr: Frame, r: np.ndarray) -> np.ndarray:
    """The offsets ``r - (r.nu(e)) nu(e)`` of perpendicular parts ``r`` (B, n, d) (Mathematics
    §4.4), the sums over the coordinates in order (as the kernels compute them)."""
    t = np.zeros(r.shape[:2])
    for c in range(r.shape[2]):
        t = t + r[..., c] * fr.nu[:, None, c]
    return r - t[..., None] * fr.nu[:, None, :]


def lift_height(fr: Frame, obstacles: np.ndarray, lift: float) -> np.ndarray:
    """Return ``lambda = lift + max_{k >= 3} |r(o_k)|`` (Mathematics §4.2), shape (B,).

    ``lift`` is the unit: a positive float (the paper's 1 by default), or
    :data:`~pmplan.planners.base.SCENE_CODE` / ``"scene"`` for the unit
    ``u(O) = max_k |o_k - o_1|`` of each query (:func:`~pmplan.planners.base.scene_unit`).
    """
    u = unit(obstacles, lift)
    if obstacles.shape[1] <= 2:
        return u
    r = fr.perpendicular(obstacles[:, 2:])
    return u + np.sqrt((r * r).sum(-1)).max(axis=1)


def lane_chains(keys: list[np.ndarray], sides: int = 2,
                down: np.ndarray | None = None) -> np.ndarray:
    """Return the lane of every robot on its side of the line, 1, 2, ..., shape (B, n), for the
    shared lanes (Mathematics §4.4).

    ``keys`` holds, for every configuration ``C_k`` of the query, the robots' order keys of
    :class:`ColumnStructure` (B, n), distinct in each row. The odd robots (i = 1, 3, ...) take
    the side of ``nu``, the even ones the other (``sides=1``: every robot on the side of
    ``nu``, the planner ``obstacle_line_oneside``; ``down``, bool (B, n): the robots of
    ``down`` on the side of ``-nu``, the others on that of ``nu``, the planner
    ``obstacle_line_robots``). On each side the robots, taken in the order of
    their columns in ``H(C_1, 1)``, form *chains*: a robot joins the first chain whose last
    robot is before it in every ``H(C_k, 1)`` (they *keep their order*), else it opens a new
    one; the robots of the c-th chain share lane c. Two robots of one lane are in the same
    order in every configuration, so their columns, which move linearly between consecutive
    configurations during the slides, are never equal.
    """
    rk = np.stack(keys, axis=1)  # (B, r, n)
    b, _, n = rk.shape
    rows = np.arange(b)
    lane = np.zeros((b, n), np.int64)
    if down is None:  # robots 1, 3, ... (index 0, 2, ...), then 2, 4, ...
        groups = [np.broadcast_to(np.arange(n) % sides == side, (b, n)) for side in range(sides)]
    else:
        groups = [~down, down]
    for member in groups:
        # the robots of the side first, in the order of their columns in H(C_1, 1)
        order = np.lexsort((rk[:, 0], ~member), axis=-1)
        tail = np.zeros((b, n), np.int64)  # the last robot of chain c
        count = np.zeros(b, np.int64)
        for t in range(n):
            x = order[:, t]
            on = member[rows, x]
            if not on.any():
                break
            here = rk[rows, :, x]  # (B, r)
            pick = count.copy()
            for c in range(int(count.max()) - 1, -1, -1):  # the first chain that takes it
                before = (rk[rows, :, tail[:, c]] < here).all(axis=1)
                pick = np.where((c < count) & before, c, pick)
            lane[rows[on], x[on]] = pick[on] + 1
            tail[rows[on], pick[on]] = x[on]
            count = np.where(on, np.maximum(count, pick + 1), count)
    return lane


def lane_heights(fr: Frame, obstacles: np.ndarray, lift: float, n: int,
                 compact: bool = False, lanes: np.ndarray | None = None,
                 sides: int = 2, down: np.ndarray | None = None) -> np.ndarray:
    """Return the signed height ``h_i`` of every robot's lane above the line, shape (B, n):
    robot i slides at ``h_i nu(e)``.

    * The paper's lanes (``compact=False``; paper (3.8), Figure 4, and Mathematics §4.2):
      ``h_i = i lambda`` with ``lambda`` = ``lift_height``, every robot on the side of
      ``nu``.
    * The compact lanes (``compact=True``; Mathematics §4.4): the odd robots on the side of
      ``nu``, the even ones on the other, robot i at ``+-(H_+- + k_i u)``, where ``k_i`` is its
      lane on its side (``lanes``, (B, n), from :func:`lane_chains`; without it
      ``k_i = ceil(i / 2)``, every robot its own lane), ``u`` is the unit and
      ``H_+ = max(0, max_k t_k)``, ``H_- = max(0, max_k -t_k)`` for the obstacles' heights
      ``t_k = (o_k - o_1).nu`` (k >= 3). Two lanes differ by at least ``u``; a lane is at
      least ``u`` above (or below) every obstacle's height.
    * ``sides=1`` (with ``lanes`` from :func:`lane_chains` with ``sides=1``; the planner
      ``obstacle_line_oneside``): every robot on the side of ``nu``, ``h_i = H_+ + k_i u``;
      with ``down`` (bool (B, n), and ``lanes`` from :func:`lane_chains` with it; the planner
      ``obstacle_line_robots``) the robots of ``down`` at ``-(H_- + k_i u)``.
    """
    i = np.arange(1, n + 1, dtype=float)
    if not compact:
        lam = lift_height(fr, obstacles, lift)
        return lam[:, None] * i[None, :]
    u = unit(obstacles, lift)
    b, m, d = obstacles.shape
    hp = np.zeros(b)
    hm = np.zeros(b)
    for k in range(2, m):  # t_k summed in the order of the kernels
        t = np.zeros(b)
        for c in range(d):
            t = t + (obstacles[:, k, c] - obstacles[:, 0, c]) * fr.nu[:, c]
        hp = np.where(t > hp, t, hp)
        hm = np.where(-t > hm, -t, hm)
    k = np.ceil(i / 2.0)[None, :] if lanes is None else lanes.astype(float)
    up = (((i % 2.0) == 1.0) | (sides == 1))[None, :] if down is None else ~down
    return np.where(up, hp[:, None] + u[:, None] * k,
                    -(hm[:, None] + u[:, None] * k))


#: the breakpoints of :func:`section`: up to the lanes, along them, down
SECTION_TIMES = (0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0)


def section(fr: Frame, x_start, x_goal, heights: np.ndarray, m: int) -> PiecewiseLinearPath:
    """Return the section over collinear pairs, paper (3.8), Figure 4.

    ``x_start``, ``x_goal`` are collinear configurations (B, m+n, d) with the same obstacles;
    ``heights`` (B, n) the lanes of :func:`lane_heights` (``i lambda`` in the paper). Robot i
    (1-based)::

        [0, 1/3]   X_i + 3 tau h_i nu(e)
        [1/3, 2/3] X_i + h_i nu(e) + (3 tau - 1)(X'_i - X_i)
        [2/3, 1]   X'_i + (3 - 3 tau) h_i nu(e)
    """
    off = np.zeros_like(x_start)
    off[:, m:] = heights[..., None] * fr.nu[:, None, :]
    wp = np.stack([x_start, x_start + off, x_goal + off, x_goal], axis=1)
    return PiecewiseLinearPath(np.array(SECTION_TIMES), wp)


def two_configuration_path(fr, obstacles, h_start, h_goal, heights, direct: bool = False,
                           build=section) -> PiecewiseLinearPath:
    """Compose H(C), the section and H(C') reversed (paper Remark, via the path algebra).

    With ``direct`` (the compact lanes in the plane, Mathematics §4.4) every robot moves
    straight from its desingularized position to its lane, and back: waypoint 2 is replaced
    by ``W1 + DIRECT_AT (W3 - W1)`` and waypoint 5 by ``W6 + DIRECT_AT (W4 - W6)``
    (:data:`pmplan.path.DIRECT_AT`), the robots' rows only, so no robot stops on the obstacle
    line on its way (counted from the end of the path on its goal side: ``K - 3`` from ``K -
    2`` and ``K - 4``, for a section of ``build`` with more breakpoints than :func:`section`'s).
    ``build(fr, x_start, x_goal, heights, m)`` makes the section (:func:`section`; a benchmark
    measures another one with it).
    """
    m = obstacles.shape[1]
    sec = build(fr, h_start.waypoints[:, -1], h_goal.waypoints[:, -1], heights, m)
    path = compose_via_deformations(h_start, sec, h_goal)
    if not direct:
        return path
    wp = path.waypoints
    wp[:, 2, m:] = wp[:, 1, m:] + DIRECT_AT * (wp[:, 3, m:] - wp[:, 1, m:])
    wp[:, -3, m:] = wp[:, -2, m:] + DIRECT_AT * (wp[:, -4, m:] - wp[:, -2, m:])
    return path


@cache
def path_times(r: int, section_times: tuple = SECTION_TIMES) -> np.ndarray:
    """Return the breakpoints of a path through r >= 2 configurations, shape (7 (r - 1) + 1,)
    (with a section of other breakpoints ``section_times``, ``(len(section_times) + 3) (r -
    1) + 1``).

    They are computed by the reference path algebra itself (:func:`~pmplan.path.compose_via_deformations`
    and :meth:`~pmplan.path.PiecewiseLinearPath.join` on an empty batch), so both backends share them bitwise:
    tau = 0, 1/6, 1/3, 4/9, 5/9, 2/3, 5/6, 1 for r = 2.
    """
    empty = PiecewiseLinearPath(np.array([0.0, 0.5, 1.0]), np.zeros((0, 3, 1, 1)))
    sec = PiecewiseLinearPath(np.array(section_times), np.zeros((0, len(section_times), 1, 1)))
    leg = compose_via_deformations(empty, sec, empty)
    path = leg if r == 2 else join([leg] * (r - 1), [k / (r - 1) for k in range(1, r - 1)])
    out = path.times.copy()
    out.flags.writeable = False
    return out


#: what ``pmplan verify`` says for odd d (:meth:`pmplan.strata.ObstacleLineStrata.notes`) (measured by ``benchmarks/odd_d_pole.py``; Mathematics §4.1)
POLE_NOTE = (
    "odd d: near the pole N = e_d the modulus of continuity grows like 1/angle, about "
    "2 h / angle with h the highest lane (n lambda, lambda = lift + max_k |r(o_k)|, for the "
    "paper's lanes; H + ceil(n/2) lift for the compact ones); measured for d = 3, n = 2, lift 1, "
    "the paper's lanes: a 1e-9 move at 1e-8 rad from N moves the path by 0.4. Forced by "
    "topology (nu(e) is a unit "
    "tangent field on S^(d-1) minus N and must wind around N), not a bug; the moduli above come "
    "from queries away from N."
)



class ObstacleLinePlanner(Planner):
    """Planner of paper Section 3, extended to any m >= 2 and any d >= 2 (Mathematics §4.1, §4.2)."""

    name = "obstacle_line"
    summary = (
        "paper Section 3 (m = 2, d even) and its extensions to odd d and m >= 2 (Mathematics §4.1, §4.2): "
        "desingularize, project to the line o1o2, lift-slide-descend"
    )
    #: the lanes of the section: the paper's ``i lambda`` (False) or the compact ones of
    #: Mathematics §4.4 (:func:`lane_heights`)
    compact: bool = False
    #: with the compact lanes, the robots that keep their order share a lane (Mathematics §4.4,
    #: :func:`lane_chains`): 0, never; 2, the robots of a side (odd robots on the side of
    #: ``nu``, even ones on the other); 1, every robot on the side of ``nu``
    shared: int = 0
    #: planning ``2**k C`` with ``lift * 2**k`` gives exactly ``2**k`` times the path of C (every
    #: length of the construction is built from the coordinates and ``lift``): queries at
    #: extreme magnitudes are planned scaled (:mod:`pmplan.magnitude`)
    equivariant = True
    sequential = True

    def supports(self, d: int, n: int, m: int) -> str | None:
        """None for every d >= 2, n >= 1, m >= 2 (:func:`~pmplan.planners.base.out_of_scope`)."""
        return out_of_scope(d, n, m)

    def domain_labels(self, d: int, n: int, m: int, r: int = 2) -> list[int]:
        """``sum_k cp(C_k) - (r-1) cp_o + 2 - [e == N]`` over the strata: ``4..r n + m + 2``
        (d even), ``3..r n + m + 2`` (d odd, the pole e == N)."""
        low = 4 if d % 2 == 0 else 3
        return list(range(low, r * n + m + 3))

    def stratum_name(self, row, d: int, n: int, m: int) -> str:
        *cps, cp_o, pole = (int(v) for v in row)
        name = "T_{" + ",".join(str(c) for c in cps) + "}"
        extras = []
        if m > 2:
            extras.append(f"cp_o={cp_o}")
        if pole:
            extras.append("e=N")
        return name + (f"[{', '.join(extras)}]" if extras else "")

    def plan(self, obstacles, start, goal, *, lift: float = 1.0,
             backend: str | None = None) -> RawPlan:
        """Plan a batch: obstacles (B, m, d), start and goal (B, n, d) (see :meth:`plan_sequence`)."""
        return self.plan_sequence(obstacles, [start, goal], lift=lift, backend=backend)

    def plan_sequence(self, obstacles, configs, *, lift: float = 1.0,
                      backend: str | None = None) -> RawPlan:
        """Plan through r >= 2 robot configurations (Mathematics §4.3); r = 2 is :meth:`plan`.

        On ``[(k-1)/(r-1), k/(r-1)]`` the path is the two-configuration path from C_k to
        C_{k+1}; label ``sum_k cp(C_k) - (r-1) cp_o + 2 - [e == N]``.

        ``backend="numpy"`` runs the reference implementation below (numpy, exact predicates of
        :mod:`pmplan.predicates`); ``"numba"`` (the default when numba is installed) runs the
        fused kernel of :mod:`pmplan.kernels.obstacle_line`, whose waypoints and labels are identical.
        The input is not validated here (see :mod:`pmplan.configuration`).
        """
        return self.planned(obstacles, configs, lift, backend)

    def reference(self, obstacles, configs, lift, down: np.ndarray | None = None) -> RawPlan:
        """The mathematics of :meth:`plan_sequence`, in numpy with the exact predicates of
        :mod:`pmplan.predicates` (the numpy backend's plan). ``down`` (bool (B, n), a
        :attr:`~pmplan.planners.base.Planner.robot_side` planner only): the robots whose lanes
        take the side of ``-nu(e)``."""
        lift = lift_code(lift)
        obstacles = np.asarray(obstacles, dtype=float)
        configs = [np.asarray(c, dtype=float) for c in configs]
        r = len(configs)
        fr = Frame(obstacles[:, 0], obstacles[:, 1])
        cols = [column_structure(fr, obstacles, c) for c in configs]
        hs = [deformation(fr, obstacles, c, cs, self.compact) for c, cs in zip(configs, cols)]
        sides = self.shared or 2
        lanes = lane_chains([c.key for c in cols], sides, down) if self.shared else None
        heights = lane_heights(fr, obstacles, lift, configs[0].shape[1], self.compact, lanes,
                               sides, down)
        direct = self.compact and obstacles.shape[2] == 2  # (Mathematics §4.4)
        legs = [two_configuration_path(fr, obstacles, hs[k], hs[k + 1], heights, direct)
                for k in range(r - 1)]
        path = legs[0] if r == 2 else join(legs, [k / (r - 1) for k in range(1, r - 1)])
        cp_o = cols[0].cp_o
        pole = fr.at_pole.astype(np.int64)
        domain = sum(c.cp for c in cols) - (r - 1) * cp_o + 2 - pole
        strata = np.stack([c.cp for c in cols] + [cp_o, pole], axis=1).astype(np.int64)
        return RawPlan(domain=domain.astype(np.int64), strata=strata, path=path)

    def path_times(self, r: int) -> np.ndarray:
        """Breakpoints of every path through r configurations (see :func:`path_times`)."""
        return path_times(r)

    def still_pieces(self, r: int) -> np.ndarray:
        """The first and the last piece of every leg: the desingularization ``F(C, .)`` of
        paper (3.2) and its reverse, which move a robot only when it shares its column with
        another point (``eps`` is 0 otherwise, :func:`column_structure`)."""
        leg = np.zeros((path_times(r).shape[0] - 1) // (r - 1), dtype=bool)
        leg[[0, -1]] = True
        return np.tile(leg, r - 1)

    def allocate(self, b: int, r: int, m: int, n: int, d: int) -> dict:
        """Output arrays of a batch of b queries through r configurations (shared times)."""
        times = path_times(r)
        return dict(
            domain=np.empty(b, np.int64),
            strata=np.empty((b, r + 2), np.int64),
            clearance=np.empty(b),
            times=times.copy(),
            waypoints=np.empty((b, times.shape[0], m + n, d)),
        )


class CompactLinePlanner(ObstacleLinePlanner):
    """The obstacle-line planner with compact lanes (Mathematics §4.4): the default for every
    (d, n, m) but the planar three-obstacle one.

    The same deformation, strata, domains and labels as :class:`ObstacleLinePlanner` (so it is
    optimal on the same domains, paper Theorem 2.6); only the section's lanes differ
    (:func:`lane_heights`): the robots alternate between the two sides of the line, and the
    lanes are spaced by the unit above the obstacles' heights on each side, instead of
    ``i lambda``; in d >= 3 the projection keeps every robot's *offset*, the part of its
    perpendicular part orthogonal to ``nu(e)`` (:func:`offset`), and in the plane every robot
    moves straight from its desingularized position to its lane (the direct lift,
    ``two_configuration_path``), so that the robots do not all meet the obstacle line at
    once. The paths are shorter and stay nearer the obstacles' line, which is what a crowded
    workspace needs; ``planner="obstacle_line"`` gives the paper's paths.
    """

    name = "obstacle_line_compact"
    summary = (
        "the obstacle-line planner (same domains and labels) with compact lanes "
        "(Mathematics §4.4): robots alternate sides of the line o1o2, lanes one unit apart above "
        "the obstacles"
    )
    compact = True
    priority = 1


class SharedLinePlanner(CompactLinePlanner):
    """The compact lanes with *shared* lanes (Mathematics §4.4, "Shared lanes"): the robots of
    one side whose columns are in the same order in every ``H(C_k, 1)`` never share a column
    during a slide, so they may share a lane (:func:`lane_chains`). The same deformation,
    strata, domains and labels as :class:`CompactLinePlanner`, so it is optimal on the same
    domains (paper Theorem 2.6); the lanes are fewer, so a crowd slides nearer the obstacles'
    line. Two robots of one lane are only as far apart during the slide as their columns, so
    a query whose columns nearly coincide may be refused by the certificate (Mathematics §6.2)
    where the compact lanes keep them a unit apart. A raw plan costs more than with the
    compact lanes: the chains are computed query by
    query, and the certificate tests more (``benchmarks/shared_ab.py`` measures that cost and
    the refined plans in crowded rooms)."""

    name = "obstacle_line_shared"
    summary = (
        "the compact lanes (same domains and labels) shared by the robots of a side that keep "
        "their order (Mathematics §4.4): fewer lanes, a crowd nearer the line o1o2"
    )
    shared = 2
    priority = 0


class OneSideLinePlanner(CompactLinePlanner):
    """The shared lanes with *one side* (Mathematics §4.4, "One side"): every robot slides on
    the side of ``nu``, at ``H_+ + k_i u``, where ``k_i`` is its chain among all the robots
    (:func:`lane_chains` with ``sides=1``: the robots that keep their order share a lane). The
    same deformation, strata, domains and labels as :class:`CompactLinePlanner`, so it is
    optimal on the same domains (paper Theorem 2.6), collision-free by the argument of
    :class:`SharedLinePlanner`. Every robot passes every obstacle on the same side, so a narrow
    gap on the other side of the obstacles' line stops no robot: in a crowded room it crosses
    about half as many narrow gaps as the lanes on both sides (Mathematics §8), at the price of
    longer paths for a few robots: the default of a refined plan of at least
    :data:`~pmplan.planners.base.CROWD_LANES` robots in the plane
    (``benchmarks/crowd_default.py``)."""

    name = "obstacle_line_oneside"
    summary = (
        "the compact lanes (same domains and labels) all on one side of the line o1o2, shared by "
        "the robots that keep their order (Mathematics §4.4): a crowd crosses fewer narrow gaps"
    )
    shared = 1
    priority = 0
    #: the default of a refined plan of at least
    #: :data:`pmplan.planners.base.CROWD_LANES` robots in the plane without a box
    #: (:func:`pmplan.planners.base.default_planner`)
    crowd = True


class WallsLinePlanner(OneSideLinePlanner):
    """The one-side lanes on the side the walls leave the most room (Mathematics §8, "The side
    of the lanes"): without a workspace box, :class:`OneSideLinePlanner` itself; in a box in
    the plane, the lanes of a query take the side of ``-nu(e)`` where
    :func:`pmplan.sides.wall_sides` says so (the query mirrored, planned with these lanes, the
    plan mirrored back), and a query on the wall between the two sides has its label one less.
    The domains are those of :class:`CompactLinePlanner` cut along that wall, with the same
    number of labels, so it is optimal too (Mathematics §8 proves it). In the scene
    families' rooms, whose obstacles may sit near a wall, the lanes then cross a gap too narrow
    for a robot on few queries (``benchmarks/sides_ab.py``): the default of a refined plan of at
    least :data:`~pmplan.planners.base.WALL_LANES` robots in a box in the plane."""

    name = "obstacle_line_walls"
    summary = (
        "the one-side lanes (Mathematics §4.4), in a workspace box on the side of the line o1o2 "
        "where the walls leave the obstacles the most room (Mathematics §8): the same number "
        "of domains, cut along the wall between the sides"
    )
    #: not the default of a refined crowd without a box (``obstacle_line_oneside`` is,
    #: :func:`pmplan.planners.base.default_planner`)
    crowd = False
    #: in a box in the plane, the side :func:`pmplan.sides.wall_sides` chooses; the default
    #: of a refined plan of at least :data:`pmplan.planners.base.WALL_LANES` robots there
    wall_side = True


class RobotsLinePlanner(OneSideLinePlanner):
    """The one-side lanes with a side per robot (Mathematics §8, "A side per robot"): without
    a workspace box, :class:`OneSideLinePlanner` itself; in a box in the plane, robot i's lane
    takes the side of ``-nu(e)`` where :func:`pmplan.sides.robot_sides` says so (the robots of
    each side share lanes as the one-side lanes do, :func:`lane_chains`), and a query on the
    walls of k robots has its label k less. The domains are those of
    :class:`CompactLinePlanner` cut along those walls, with the same number of labels, so it
    is optimal too (Mathematics §8 proves it). A robot whose start and goal lie on one side of
    the obstacles' line passes the obstacles on that side unless the walls leave them too
    little room there, so its path goes round fewer obstacles: the default of a refined plan
    of :data:`~pmplan.planners.base.WALL_LANES` to
    :data:`~pmplan.planners.base.ROBOT_LANES` robots in a box in the plane
    (``benchmarks/robots_ab.py``). Planned by the numpy reference in a box (no kernel
    takes a side per robot)."""

    name = "obstacle_line_robots"
    summary = (
        "the one-side lanes (Mathematics §4.4), in a workspace box with a side of the line o1o2 "
        "per robot, chosen by its own positions and the walls' room (Mathematics §8): the "
        "same number of domains, cut along each robot's wall"
    )
    crowd = False
    #: in a box in the plane, the side :func:`pmplan.sides.robot_sides` chooses per robot;
    #: the default of a refined plan of :data:`pmplan.planners.base.WALL_LANES` to
    #: :data:`pmplan.planners.base.ROBOT_LANES` robots there
    robot_side = True


OBSTACLE_LINE = register(ObstacleLinePlanner())
OBSTACLE_LINE_COMPACT = register(CompactLinePlanner())
OBSTACLE_LINE_SHARED = register(SharedLinePlanner())
OBSTACLE_LINE_ONESIDE = register(OneSideLinePlanner())
OBSTACLE_LINE_WALLS = register(WallsLinePlanner())
OBSTACLE_LINE_ROBOTS = register(RobotsLinePlanner())
