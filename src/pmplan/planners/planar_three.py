"""The planar three-obstacle planner: one robot, three obstacles, 12 strata, 4 domains.

This is the planner of paper Section 4 (``section3`` in the source) for ``pi_{4,3}``: one point
robot x among three point obstacles o1, o2, o3 in the plane (d = 2, n = 1, m = 3). It has four
domains of continuity W1..W4, so it is optimal (paper Theorem 2.6: TC = 2n+m-1 = 4).

Frame (paper Section 4, first picture). With ``w = o2 - o1``, ``e = w/|w|`` and
``nu(e) = (-e_2, e_1)`` every point y gets the coordinates::

    u(y) = (y - o1) . e        (column, the paper's p_C)
    h(y) = (y - o1) . nu(e)    (height, the paper's p^perp_C)

so that ``o1 = (0, 0)``, ``o2 = (|w|, 0)`` and ``o3 = (u3, h3)``. Counts of distinct values
(paper Section 4), all decided **exactly** by :func:`pmplan.predicates.projection_classes`:
``cp_perp_o`` / ``cp_perp(C)`` heights of o1, o2, o3 / and x; ``cp_o`` / ``cp(C)`` columns.

Strata (paper Section 4; they partition the query space, Corollary 4.1)::

    T1_{ij}   cp_perp_o = 1 (o3 on L_C),  cp_perp(C) = i,  cp_perp(C') = j    i, j in {1, 2}
    T22_{rs}  cp_perp_o = 2, cp_o = 2,    cp(C) = r,       cp(C') = s         r, s in {2, 3}
    T23_{kl}  cp_perp_o = 2, cp_o = 3,    cp(C) = k,       cp(C') = l         k, l in {3, 4}

Domains (paper (4.1)-(4.3))::

    W1 = T1_11 u T22_33 u T23_44
    W2 = T1_22 u T22_22
    W3 = T1_12 u T1_21 u T22_23 u T22_32 u T23_33
    W4 = T23_34 u T23_43

Paths (Mathematics §5) are polylines in the frame (u, h), traversed at constant speed:

* W1, Figure 6: ``x -> (u(x), H) -> (u(x'), H) -> x'`` with ``H = 1 + max(0, h3)``
  (see the typo note in :func:`frame_polyline_W1`). The 1 here and in ``s3 = c3 + 1`` below is
  the paper's unit: the planner's ``lift`` (default 1; ``lift="scene"``: the obstacles' radius
  ``u(O) = max(|o2 - o1|, |o3 - o1|)``, which makes the paths equivariant under translations,
  rotations and scalings).
* T1_12, T1_21, Figure 7: the segment ``x -> x'``.
* T1_22, T22_22, Figure 8: ``x -> (delta, h(x)) -> (delta, h(x')) -> x'`` with
  ``delta = min(|o1o2|, |o1o3|)/2`` (T1_22) and ``delta = |o1o2|/2`` (T22_22).
* T22_23, Figure 9: ``x -> (|w|/2, h(x)) -> (|w|/2, h3/2) -> (u(x'), h3/2) -> x'``;
  T22_32 is the reverse of the T22_23 path of the swapped query (C', C).
* T23_33, Figure 10: obstacle columns ``c1 < c2 < c3``, solid verticals
  ``s1 = (c1+c2)/2, s2 = (c2+c3)/2, s3 = c3 + 1``, solid horizontal ``h3/2``; x on ``c_a``,
  x' on ``c_b``: ``x -> (s_a, h(x)) -> (s_a, h3/2) -> (s_b, h3/2) -> (s_b, h(x')) -> x'``.
* T23_34: ``x -> (s_a, h(x)) -> (s_a, h3/2) -> (u(x'), h3/2) -> x'``; T23_43 is the reverse
  of the T23_34 path of the swapped query.

Every polyline has at most 5 legs; a batch pads them to WAYPOINTS = 6 waypoints by repeating the final
waypoint at time 1 (zero-duration pieces). A polyline of length 0 is the constant path.

Why every path is collision-free: each leg either runs along a column that holds no obstacle
(u(x) or u(x') off the obstacle columns, delta, ``|w|/2``, s_a), or along a height that holds no
obstacle (H, h3/2; h(x), h(x') != 0 when all obstacles lie on L_C), or leaves x (x') along its
height towards the first solid vertical, never reaching the next obstacle column.

Implementations: the numpy code below is the *reference* (``backend="numpy"``); the default
``backend="numba"`` runs the fused kernel of :mod:`pmplan.kernels.planar` (classification,
polyline, constant-speed times and certificate in one pass per query, flagged queries
re-decided here), whose waypoints, breakpoints, strata and clearances are identical. The
planner plugs into the run loop through the protocol of :class:`pmplan.planners.base.Planner`
(:meth:`~PlanarThreePlanner.reference`, :meth:`~PlanarThreePlanner.allocate`), and into the
numba backend through its glue there (:mod:`pmplan.backends.numba`).

References
----------
C. A. Ipanaque Zapata and J. Gonzalez, *Parametrised collision-free optimal motion planning
algorithms in Euclidean spaces*, Section 4 (Figures 6, 7, 8,
9, 10; Corollary 4.1; equations (4.1)-(4.3)).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..frame import Frame
from ..path import PiecewiseLinearPath
from ..predicates import projection_classes
from ..planar_strata import DOMAIN_BY_CODE, DOMAIN_OF, LUT, PAPER_SUPER, STRATA, WAYPOINTS
from .base import Planner, RawPlan, lift_code, register, unit

__all__ = [
    "DOMAIN_OF",
    "PLANAR_THREE",
    "STRATA",
    "WAYPOINTS",
    "PlanarThreePlanner",
    "StratumClassification",
    "classify",
    "frame_polyline_W1",
    "parse_stratum",
    "stratum_short_name",
]

def stratum_short_name(row) -> str:
    """Return the pmplan name (e.g. ``"T22_23"``) of a strata record ``(family, i, j)``."""
    f, i, j = (int(v) for v in row)
    return f"T{f}_{i}{j}"


def parse_stratum(stratum: str) -> str:
    """Return the pmplan name of a stratum given as ``"T22_23"`` or ``"T^{2,2}_{2,3}"``.

    Examples
    --------
    >>> parse_stratum("T^{2,3}_{3,4}"), parse_stratum("t1_12")
    ('T23_34', 'T1_12')
    """
    s = stratum.strip()
    m = re.fullmatch(r"T\^\{(1|2,2|2,3)\}_\{(\d),(\d)\}", s)
    if m:
        s = f"T{m.group(1).replace(',', '')}_{m.group(2)}{m.group(3)}"
    s = s[:1].upper() + s[1:]
    if s not in DOMAIN_OF:
        raise ValueError(
            f"unknown stratum {stratum!r}; expected one of {', '.join(STRATA)} "
            "(or the paper's notation, e.g. 'T^{2,2}_{2,3}')"
        )
    return s


def _ndistinct(labels: np.ndarray) -> np.ndarray:
    """Number of distinct values in every row of a small int array (B, P)."""
    s = np.sort(labels, axis=1)
    return 1 + (np.diff(s, axis=1) != 0).sum(axis=1)


@dataclass
class StratumClassification:
    """Exact classification of a batch of B queries into the strata of paper Section 4 (what
    :func:`classify` returns; the strata themselves are named in :data:`~pmplan.planar_strata.STRATA`).

    Attributes
    ----------
    record : ndarray of int64, shape (B, 3)
        ``(family, i, j)`` with family in {1, 22, 23} (T1_{ij}, T22_{ij}, T23_{ij}).
    code : ndarray of int64, shape (B,)
        Index of the stratum in :data:`~pmplan.planar_strata.STRATA`.
    domain : ndarray of int64, shape (B,)
        The domain W_a, a in {1, 2, 3, 4}.
    col_labels, height_labels : ndarray of int64, shape (B, 5)
        Exact classes of columns / heights of (o1, o2, o3, x, x'), numbered in increasing
        order of the projection (:func:`pmplan.predicates.projection_classes`).
    """

    record: np.ndarray
    code: np.ndarray
    domain: np.ndarray
    col_labels: np.ndarray
    height_labels: np.ndarray


def classify(obstacles, start, goal) -> StratumClassification:
    """Return the stratum and domain of every query (paper Section 4), decided exactly.

    Parameters
    ----------
    obstacles : array_like, shape (B, 3, 2)
    start, goal : array_like, shape (B, 1, 2)

    Returns
    -------
    StratumClassification

    Examples
    --------
    o3 on the column of o1 (exactly) and x on the column of o2: T22 with cp(C) = 2;
    x' off both columns: cp(C') = 3, so the stratum is T22_23, in W3 (Figure 9):

    >>> s = classify([[[0, 0], [4, 0], [0, 2]]], [[[4, 3]]], [[[3, -2]]])
    >>> s.record, s.domain, s.record.shape
    (array([[22,  2,  3]]), array([3]), (1, 3))
    """
    obstacles = np.asarray(obstacles, dtype=float)
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    pts = np.concatenate([obstacles, start, goal], axis=1)
    o1, o2 = obstacles[:, 0], obstacles[:, 1]
    cl, _, _ = projection_classes(pts, o1, o2)
    # h(o1) = 0 and h(o2) = (o2 - o1) . rot90(o2 - o1) = 0 exactly: classify o2 with o1 (this
    # also spares the exact fallback for that tie, which is slow when o2 - o1 is inexact)
    hl, _, _ = projection_classes(pts[:, [0, 2, 3, 4]], o1, o2, perpendicular=True)
    hl = hl[:, [0, 0, 1, 2, 3]]
    start_cols, goal_cols = [0, 1, 2, 3], [0, 1, 2, 4]
    cp_perp_o = _ndistinct(hl[:, :3])
    cp_o = _ndistinct(cl[:, :3])
    family = np.where(cp_perp_o == 1, 1, np.where(cp_o == 2, 22, 23)).astype(np.int64)
    t1 = family == 1
    i = np.where(t1, _ndistinct(hl[:, start_cols]), _ndistinct(cl[:, start_cols]))
    j = np.where(t1, _ndistinct(hl[:, goal_cols]), _ndistinct(cl[:, goal_cols]))
    fidx = np.where(t1, 0, np.where(family == 22, 1, 2))
    code = LUT[fidx, np.clip(i, 0, 4), np.clip(j, 0, 4)]
    if np.any(code < 0):  # impossible for configurations in F(R^2, 4) (Corollary 4.1)
        bad = int(np.flatnonzero(code < 0)[0])
        raise ValueError(f"query {bad} is in no stratum of paper Section 4: are its points distinct?")
    record = np.stack([family, i, j], axis=1).astype(np.int64)
    return StratumClassification(record=record, code=code, domain=DOMAIN_BY_CODE[code], col_labels=cl,
                  height_labels=hl)


# --------------------------------------------------------------------------------------------
# frame data and the polylines in (u, h) coordinates
# --------------------------------------------------------------------------------------------
@dataclass
class _Scene:
    """Float frame data of a group of queries (b queries), see the module docstring."""

    obstacles: np.ndarray  # (b, 3, 2)
    x: np.ndarray  # (b, 2) start robot
    xg: np.ndarray  # (b, 2) goal robot
    o1: np.ndarray  # (b, 2)
    e: np.ndarray  # (b, 2)
    nu: np.ndarray  # (b, 2)
    length: np.ndarray  # (b,) |w| = |o1 o2|
    u: np.ndarray  # (b, 5) columns of o1, o2, o3, x, x'
    h: np.ndarray  # (b, 5) heights
    cols: np.ndarray  # (b, 3) obstacle columns, sorted by their exact order
    rank_x: np.ndarray  # (b,) index a of the obstacle column c_a holding x (-1: none)
    rank_g: np.ndarray  # (b,) the same for x'
    unit: np.ndarray  # (b,) the unit: lift, or u(O) for lift="scene" (planners.base.unit)

    def take(self, idx: np.ndarray) -> _Scene:
        return _Scene(**{k: v[idx] for k, v in self.__dict__.items()})

    def swapped(self) -> _Scene:
        """The scene of the swapped query (C', C)."""
        u = self.u[:, [0, 1, 2, 4, 3]]
        h = self.h[:, [0, 1, 2, 4, 3]]
        return _Scene(self.obstacles, self.xg, self.x, self.o1, self.e, self.nu, self.length,
                      u, h, self.cols, self.rank_g, self.rank_x, self.unit)


def _scene(obstacles, start, goal, st: StratumClassification, lift=1.0) -> _Scene:
    o1, o2 = obstacles[:, 0], obstacles[:, 1]
    fr = Frame(o1, o2)
    pts = np.concatenate([obstacles, start, goal], axis=1)
    rel = pts - o1[:, None, :]
    u = (rel * fr.e[:, None, :]).sum(-1)
    h = (rel * fr.nu[:, None, :]).sum(-1)
    u[:, 0] = 0.0
    h[:, :2] = 0.0  # o1, o2 lie on L_C exactly
    u[:, 1] = fr.norm
    order = np.argsort(st.col_labels[:, :3], axis=1, kind="stable")
    cols = np.take_along_axis(u[:, :3], order, axis=1)
    olab = np.take_along_axis(st.col_labels[:, :3], order, axis=1)

    def rank(k):
        hit = olab == st.col_labels[:, k : k + 1]
        return np.where(hit.any(axis=1), hit.argmax(axis=1), -1)

    return _Scene(obstacles, start[:, 0], goal[:, 0], o1, fr.e, fr.nu, fr.norm, u, h, cols,
                  rank(3), rank(4), unit(obstacles, lift))


def _uh(*pairs) -> np.ndarray:
    """Stack (u, h) pairs of arrays (b,) into a frame polyline (b, k, 2)."""
    return np.stack([np.stack(np.broadcast_arrays(a, b), axis=-1) for a, b in pairs], axis=1)


def frame_polyline_W1(sc: _Scene) -> np.ndarray:
    """Return the W1 polyline of Figure 6 in (u, h) coordinates, shape (b, 4, 2).

    ::

        x -> (u(x), H) -> (u(x'), H) -> x',      H = 1 + max(0, h3)

    The 1 is the paper's unit: the planner's ``lift`` (default 1; with ``lift="scene"`` the
    obstacles' radius ``u(O) = max(|o2 - o1|, |o3 - o1|)``).

    Notes
    -----
    The paper (Section 4, text after Figure 6) describes the middle leg as "the
    L_C-parallel line having p_C projection 1+max{p_C(o_1), p_C(o_2), p_C(o_3)}". A line parallel
    to L_C is determined by its *height*, and every point of it has a different p_C projection,
    so this must be read with the perpendicular projection p^perp_C (heights): the line at height
    ``1 + max{h(o1), h(o2), h(o3)} = 1 + max(0, h3)``, which is what Figure 6 draws (one
    unit above the highest obstacle, in H_{C,+}).
    """
    ux, hx, ug, hg, h3 = sc.u[:, 3], sc.h[:, 3], sc.u[:, 4], sc.h[:, 4], sc.h[:, 2]
    # paper Section 4 after Figure 6: "p_C projection 1+max{p_C(o_i)}"
    # *** TYPO IN PAPER ***: an L_C-parallel line is fixed by its height: read p^perp_C
    big_h = sc.unit + np.maximum(0.0, h3)  # the paper's 1 is the unit (lift)
    return _uh((ux, hx), (ux, big_h), (ug, big_h), (ug, hg))


def _frame_straight(sc: _Scene) -> np.ndarray:
    """T1_12, T1_21 (Figure 7): the segment x -> x'."""
    return _uh((sc.u[:, 3], sc.h[:, 3]), (sc.u[:, 4], sc.h[:, 4]))


def _frame_porenmedio(sc: _Scene, delta: np.ndarray) -> np.ndarray:
    """T1_22, T22_22 (Figure 8): x -> (delta, h(x)) -> (delta, h(x')) -> x'."""
    ux, hx, ug, hg = sc.u[:, 3], sc.h[:, 3], sc.u[:, 4], sc.h[:, 4]
    return _uh((ux, hx), (delta, hx), (delta, hg), (ug, hg))


def _frame_T1_22(sc: _Scene) -> np.ndarray:
    """T1_22: ``delta_1 = min(d(o1, o2), d(o1, o3))/2`` (Figure 8, left)."""
    d13 = np.hypot(*(sc.obstacles[:, 2] - sc.obstacles[:, 0]).T)
    return _frame_porenmedio(sc, 0.5 * np.minimum(sc.length, d13))


def _frame_T22_22(sc: _Scene) -> np.ndarray:
    """T22_22: ``delta_2 = d(o1, o2)/2`` (Figure 8, right)."""
    return _frame_porenmedio(sc, 0.5 * sc.length)


def _frame_T22_23(sc: _Scene) -> np.ndarray:
    """T22_23 (Figure 9, left): lines l1 = h(x), l2 = |w|/2, l3 = h3/2, l4 = u(x')."""
    ux, hx, ug, hg = sc.u[:, 3], sc.h[:, 3], sc.u[:, 4], sc.h[:, 4]
    mid, h_half = 0.5 * sc.length, 0.5 * sc.h[:, 2]
    return _uh((ux, hx), (mid, hx), (mid, h_half), (ug, h_half), (ug, hg))


def _solid_verticals(sc: _Scene) -> np.ndarray:
    """The solid verticals of Figure 10: (c1+c2)/2, (c2+c3)/2, c3 + 1, shape (b, 3)
    (the 1 is the unit, ``lift``)."""
    c = sc.cols
    return np.stack([0.5 * (c[:, 0] + c[:, 1]), 0.5 * (c[:, 1] + c[:, 2]), c[:, 2] + sc.unit],
                    axis=1)


def _frame_T23_33(sc: _Scene) -> np.ndarray:
    """T23_33 (Figure 10): x on c_a, x' on c_b, via s_a, the line h3/2 and s_b."""
    s = _solid_verticals(sc)
    sa = np.take_along_axis(s, sc.rank_x[:, None], axis=1)[:, 0]
    sb = np.take_along_axis(s, sc.rank_g[:, None], axis=1)[:, 0]
    ux, hx, ug, hg = sc.u[:, 3], sc.h[:, 3], sc.u[:, 4], sc.h[:, 4]
    h_half = 0.5 * sc.h[:, 2]
    return _uh((ux, hx), (sa, hx), (sa, h_half), (sb, h_half), (sb, hg), (ug, hg))


def _frame_T23_34(sc: _Scene) -> np.ndarray:
    """T23_34: as T23_33 for x; x' (off the columns) is joined vertically from h3/2."""
    s = _solid_verticals(sc)
    sa = np.take_along_axis(s, sc.rank_x[:, None], axis=1)[:, 0]
    ux, hx, ug, hg = sc.u[:, 3], sc.h[:, 3], sc.u[:, 4], sc.h[:, 4]
    h_half = 0.5 * sc.h[:, 2]
    return _uh((ux, hx), (sa, hx), (sa, h_half), (ug, h_half), (ug, hg))


def _to_world(sc: _Scene, poly: np.ndarray) -> np.ndarray:
    """Map a frame polyline (b, k, 2) to waypoints (b, k, 4, 2), obstacles first.

    The first and last waypoints are the query's x and x' exactly; the second (second to
    last) is computed as a displacement from x (x'), so a leg leaving x along e or nu is exactly
    that in floating point; interior points are ``o1 + u e + h nu``. Consecutive points that are
    equal in the frame are made equal in the plane, so zero-length legs are exactly constant.
    """
    b, k, _ = poly.shape
    u, h = poly[..., 0], poly[..., 1]
    robot = sc.o1[:, None, :] + u[..., None] * sc.e[:, None, :] + h[..., None] * sc.nu[:, None, :]
    if k > 2:
        for idx, anchor, col in ((1, sc.x, 3), (k - 2, sc.xg, 4)):
            du = u[:, idx] - sc.u[:, col]
            dh = h[:, idx] - sc.h[:, col]
            robot[:, idx] = anchor + du[:, None] * sc.e + dh[:, None] * sc.nu
    robot[:, 0] = sc.x
    robot[:, -1] = sc.xg
    same = (poly[:, 1:] == poly[:, :-1]).all(-1)  # (b, k-1): frame point k equals point k-1
    for i in range(1, k - 1):
        robot[:, i] = np.where(same[:, i - 1, None], robot[:, i - 1], robot[:, i])
    for i in range(k - 2, 0, -1):
        robot[:, i] = np.where(same[:, i, None], robot[:, i + 1], robot[:, i])
    wp = np.empty((b, k, 4, 2))
    wp[:, :, :3] = sc.obstacles[:, None]
    wp[:, :, 3] = robot
    return wp


def _constant_speed(sc: _Scene, poly: np.ndarray) -> PiecewiseLinearPath:
    wp = _to_world(sc, poly)
    k = wp.shape[1]
    return PiecewiseLinearPath(np.linspace(0.0, 1.0, k), wp).arc_length_reparametrised()


def _pad(path: PiecewiseLinearPath, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Pad a batch of paths to k waypoints by repeating the final waypoint at time 1."""
    wp = path.waypoints
    b, kk = wp.shape[:2]
    times = np.broadcast_to(path.times, (b, kk))
    if kk == k:
        return np.array(times), wp
    extra = k - kk
    times = np.concatenate([times, np.ones((b, extra))], axis=1)
    wp = np.concatenate([wp, np.repeat(wp[:, -1:], extra, axis=1)], axis=1)
    return times, wp


# the rule of every stratum: (frame polyline builder, reversed-of-swapped?)
_RULES = {
    "T1_11": (frame_polyline_W1, False),
    "T22_33": (frame_polyline_W1, False),
    "T23_44": (frame_polyline_W1, False),
    "T1_12": (_frame_straight, False),
    "T1_21": (_frame_straight, False),
    "T1_22": (_frame_T1_22, False),
    "T22_22": (_frame_T22_22, False),
    "T22_23": (_frame_T22_23, False),
    "T22_32": (_frame_T22_23, True),  # reverse of the T22_23 path of (C', C)
    "T23_33": (_frame_T23_33, False),
    "T23_34": (_frame_T23_34, False),
    "T23_43": (_frame_T23_34, True),  # reverse of the T23_34 path of (C', C)
}


class PlanarThreePlanner(Planner):
    """Planner of paper Section 4 for pi_{4,3}: d = 2, one robot, three obstacles, 4 domains."""

    name = "planar_three"
    summary = (
        "paper Section 4 (d = 2, n = 1, m = 3): 12 strata T1_ij, T22_rs, T23_kl "
        "packed into 4 domains W1..W4 (optimal)"
    )
    #: the query scaled by 2**k with its lift (the paper's unit) scaled by 2**k is planned as
    #: the path scaled by 2**k, bit for bit (see :mod:`pmplan.magnitude`)
    equivariant = True
    #: the default for (2, 1, 3), where ``obstacle_line`` applies too
    priority = 2

    def supports(self, d: int, n: int, m: int) -> str | None:
        """Return None for (d, n, m) = (2, 1, 3), else why the planner does not apply."""
        if (d, n, m) == (2, 1, 3):
            return None
        return (
            "the paper's Section 4 planner is for one robot among three obstacles in the plane, "
            f"(d, n, m) = (2, 1, 3); got ({d}, {n}, {m}) (use the obstacle_line planner)"
        )

    def domain_labels(self, d: int, n: int, m: int, r: int = 2) -> list[int]:
        """The domains W1..W4: ``[1, 2, 3, 4]``."""
        return [1, 2, 3, 4]

    def stratum_name(self, row, d: int, n: int, m: int) -> str:
        """Paper notation of a strata record ``(family, i, j)``, e.g. ``"T^{2,2}_{2,3}"``."""
        f, i, j = (int(v) for v in row)
        return f"T^{{{PAPER_SUPER[f]}}}_{{{i},{j}}}"

    def plan(self, obstacles, start, goal, *, lift: float = 1.0,
             backend: str | None = None) -> RawPlan:
        """Plan a batch of queries (paper Section 4).

        Parameters
        ----------
        obstacles : array_like, shape (B, 3, 2)
        start, goal : array_like, shape (B, 1, 2)
        lift : float or "scene"
            The unit of the paper's constructions: the 1 in ``H = 1 + max(0, h3)`` (W1, Figure
            6) and in ``s3 = c3 + 1`` (T23, Figure 10). Default 1, the paper's;
            ``"scene"`` (or :data:`~pmplan.planners.base.SCENE_CODE`) makes it the obstacles'
            radius ``u(O) = max(|o2 - o1|, |o3 - o1|)`` of each query, so that the planner is
            equivariant under translations, rotations and scalings. Every other leg is
            built from the scene alone.
        backend : {"numba", "numpy"}, optional
            ``"numpy"`` runs the reference implementation below; ``"numba"`` (the default when
            numba is installed) the fused kernel of :mod:`pmplan.kernels.planar`, whose
            waypoints, breakpoints, labels and strata are identical. The input is not
            validated here (see :mod:`pmplan.configuration`).

        Returns
        -------
        RawPlan
            ``domain`` in {1, 2, 3, 4}, ``strata`` rows ``(family, i, j)``, and paths with
            times (B, 6) and waypoints (B, 6, 4, 2) (obstacles in rows 0..2, the robot in row 3).

        Notes
        -----
        Queries are grouped by stratum and every group is built with array operations. The
        paper's constructions use an absolute unit (``H = 1 + max(0, h3)``, ``s3 = c3 + 1``):
        for scenes whose coordinates exceed ~2**50 that unit (``lift=1``) is below the
        resolution of the coordinates and the certificate of :mod:`pmplan.api` rejects the
        path (``CertificationError``); ``lift="scene"`` scales it with the scene. The
        certificate also fails when a gap of the scene (e.g. ``h3`` or ``u(x') - u(o1)``) is
        below the resolution of its coordinates.
        """
        return self.planned(obstacles, [start, goal], lift, backend)

    def reference(self, obstacles, configs, lift) -> RawPlan:
        """The mathematics of :meth:`plan` (paper Section 4), in numpy: the strata decided
        exactly, every stratum's construction built with array operations (the numpy
        backend's plan)."""
        if len(configs) != 2:
            raise ValueError(f"the planar_three planner plans r = 2 configurations, got "
                             f"{len(configs)}")
        lift = lift_code(lift)
        obstacles = np.asarray(obstacles, dtype=float)
        start = np.asarray(configs[0], dtype=float)
        goal = np.asarray(configs[1], dtype=float)
        b = obstacles.shape[0]
        st = classify(obstacles, start, goal)
        sc = _scene(obstacles, start, goal, st, lift)
        times = np.empty((b, WAYPOINTS))
        wp = np.empty((b, WAYPOINTS, 4, 2))
        for code in np.unique(st.code):
            idx = np.flatnonzero(st.code == code)
            build, reverse = _RULES[STRATA[code]]
            sub = sc.take(idx)
            if reverse:
                path = _constant_speed(sub.swapped(), build(sub.swapped())).reversed()
            else:
                path = _constant_speed(sub, build(sub))
            times[idx], wp[idx] = _pad(path, WAYPOINTS)
        return RawPlan(domain=st.domain, strata=st.record, path=PiecewiseLinearPath(times, wp))

    # --- the run loop and the fast path (pmplan.planners.base.Planner) -----------------------
    def allocate(self, b: int, r: int, m: int, n: int, d: int) -> dict:
        """Output arrays of a batch of b queries: per-query breakpoints (b, WAYPOINTS)."""
        if (r, m, n, d) != (2, 3, 1, 2):
            raise ValueError(
                f"the planar_three planner plans (d, n, m) = (2, 1, 3) and r = 2; "
                f"got ({d}, {n}, {m}) and r = {r}"
            )
        return {
            "domain": np.empty(b, np.int64),
            "strata": np.empty((b, 3), np.int64),
            "clearance": np.empty(b),
            "times": np.empty((b, WAYPOINTS)),
            "waypoints": np.empty((b, WAYPOINTS, 4, 2)),
        }



PLANAR_THREE = register(PlanarThreePlanner())
