"""Why a refined plan does not keep its radii: the reason a user can read (issue 25, item 3).

:func:`radius_reason` names the worst contact of the path -- the two robots, the robot and the
obstacle, or the robot and the wall of the workspace box that come closest measured against
what they need (``2 radius``, ``radius + obstacle_radius``, ``radius``), where on the path and
how close -- and, when the scene itself leaves no room there, says so: in the plane, the
robot's path (either robot's, for two robots pressed together) crosses the segment between two
obstacles, or between an obstacle and a wall,
whose discs leave a gap narrower than a robot (``2 radius``), and no motion that crosses that
gap keeps the radii (at the crossing point the two distances add up to less than they need).
Otherwise the fixed number of refinement steps did not clear the contact, and the reason says
which knob gives the refinement more steps; when the path passes there through a gap wider than
a robot but narrower than two side by side (:data:`TIGHT`), it names that gap too and what it
leaves to spare: a motion through it may keep the radii, near the gap's middle and one robot at
a time.

The reason is a :class:`RadiusMiss`, which a program reads by its fields (the contact, the
two things that meet, the distance against the need, the time, and the :class:`Gap` it names)
and a user by its sentence (``str``); :func:`radius_miss` builds it and :func:`radius_reason`
gives the sentence alone.

The decision itself (``respects_radius``) stays exact (:func:`pmplan.certify.radius_report`);
the distances quoted here are the closed-form piece minima in floating point, evaluated in the
path's power-of-two frame (no square underflows or overflows at any magnitude).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Literal

import numpy as np

from .certify import point_pairs, power_of_two_frame, segment_closest

__all__ = ["TIGHT", "Gap", "RadiusMiss", "radius_miss", "radius_reason"]

_MSG_ROBOTS = ("robots x{i} and x{j} come {dist} apart at t = {t:.3f}, closer than "
               "2 radius = {need}")
_MSG_OBSTACLE = ("robot x{i} comes {dist} from obstacle o{k} at t = {t:.3f}, closer than "
                 "radius + obstacle_radius = {need}")
_MSG_WALL = ("robot x{i} comes {dist} from the wall x[{c}] = {wall:.6g} at t = {t:.3f}, "
             "closer than radius = {need}")
_MSG_GAP_OBSTACLES = ("{whose} path crosses the gap between obstacles o{k} and o{l}, whose "
                      "discs leave {gap:.6g}, narrower than a robot (2 radius = {width:.6g}): "
                      "no motion that crosses that gap keeps the radii")
_MSG_GAP_WALL = ("{whose} path crosses the gap between obstacle o{k} and the wall x[{c}] = "
                 "{wall:.6g}, {gap:.6g} wide, narrower than a robot (2 radius = {width:.6g}): "
                 "no motion that crosses that gap keeps the radii")
_MSG_TIGHT_OBSTACLES = ("{whose} path passes through the gap between obstacles o{k} and o{l}, "
                        "whose discs leave {gap:.6g}, room for one robot (2 radius = "
                        "{width:.6g}) with {spare:.3g} to spare")
_MSG_TIGHT_WALL = ("{whose} path passes through the gap between obstacle o{k} and the wall "
                   "x[{c}] = {wall:.6g}, {gap:.6g} wide, room for one robot (2 radius = "
                   "{width:.6g}) with {spare:.3g} to spare")
#: a gap the path passes through is named beside a contact when it is narrower than this many
#: robots side by side (``TIGHT * 2 radius``): wider than one robot, so a motion through it may
#: keep the radii, but only one robot at a time and near its middle
TIGHT = 2
_MSG_EFFORT = ("the refinement's fixed steps did not clear it: more effort (larger "
               "`waypoints` and `steps` of pmplan.refine) may")


@dataclass(frozen=True)
class Gap:
    """A gap of the scene, in the plane, that a robot's path passes through: between two
    obstacles' discs, or between an obstacle's disc and a wall of the workspace box.

    Attributes
    ----------
    robot : str
        The robot whose path passes through it, ``"x1"`` .. ``"xn"``.
    between : tuple of str
        What leaves the gap: two obstacles (``("o5", "o6")``) or an obstacle and a wall
        (``("o5", "x[1] = 0")``, the wall where coordinate 1 is 0).
    width : float
        The room the gap leaves: the distance between the two discs, or from the disc to the
        wall.
    robot_width : float
        A robot's width, ``2 radius``.
    """

    robot: str
    between: tuple[str, str]
    width: float
    robot_width: float

    @property
    def narrow(self) -> bool:
        """Whether the gap is narrower than a robot: no motion that crosses it keeps the radii
        (else it has room for one robot, and fewer than :data:`TIGHT` side by side)."""
        return self.width < self.robot_width

    @property
    def spare(self) -> float:
        """``width - robot_width``: what the gap leaves to spare around one robot (negative
        for a narrow gap)."""
        return self.width - self.robot_width


@dataclass(frozen=True)
class RadiusMiss:
    """Why a refined plan misses its radii: the worst contact of its path, measured against
    what the two need, and the gap of the scene it passes through there, if any
    (:func:`radius_miss`). ``str()`` gives the sentence (:attr:`pmplan.Plan.radius_reason`).

    Attributes
    ----------
    contact : {"robots", "obstacle", "wall"}
        Two robots, a robot and an obstacle, or a robot and a wall of the workspace box.
    between : tuple of str
        The two that meet: ``("x1", "x7")``, ``("x8", "o2")`` or ``("x3", "x[1] = 0")``.
    distance : float
        How close they come (the closed-form piece minimum, in floating point).
    need : float
        What they need: ``2 radius``, ``radius + obstacle_radius`` or ``radius``.
    t : float
        When, in [0, 1].
    gap : Gap or None
        In the plane, the gap the path (either robot's, for two robots) passes through there:
        the narrowest one narrower than a robot (:attr:`Gap.narrow`), else the narrowest with
        room for fewer than :data:`TIGHT` robots side by side; None when it passes through
        neither.
    sentence : str
        The reason in one sentence a user can read.
    """

    contact: Literal["robots", "obstacle", "wall"]
    between: tuple[str, str]
    distance: float
    need: float
    t: float
    gap: Gap | None
    sentence: str

    @property
    def category(self) -> Literal["gap", "robots", "obstacle", "wall"]:
        """``"gap"`` when the path crosses a gap narrower than a robot (the scene leaves no
        room: no refinement clears it), else the contact the refinement did not clear."""
        return "gap" if self.gap is not None and self.gap.narrow else self.contact

    def as_dict(self) -> dict:
        """The fields as JSON-ready values, with :attr:`category` (the ``radius_miss`` of
        :func:`pmplan.io.plan_to_dict`)."""
        out = asdict(self)
        out["between"] = list(self.between)
        if self.gap is not None:
            out["gap"]["between"] = list(self.gap.between)
        out["category"] = self.category
        return out

    def __str__(self) -> str:
        return self.sentence


def _shown(dist: float, need: Fraction) -> dict:
    """``dist`` and the exact bound ``need`` as text: six significant digits, or seventeen when
    six would show them equal (a contact decided exactly, within rounding of the bound)."""
    if f"{dist:.6g}" != f"{float(need):.6g}":
        return {"dist": f"{dist:.6g}", "need": f"{float(need):.6g}"}
    with localcontext() as ctx:
        ctx.prec = 17
        exact = [+Decimal(dist), Decimal(need.numerator) / Decimal(need.denominator)]
    return {"dist": f"{exact[0]:g}", "need": f"{exact[1]:g}"}


def radius_reason(times, waypoints, m: int, radius: float, obstacle_radius: float,
                  bounds=None) -> str:
    """Return why the path does not keep the radii, in one sentence a user can read: the
    sentence of :func:`radius_miss` (empty when there is no pair to measure).

    Parameters
    ----------
    times : array_like, shape (K,)
    waypoints : array_like, shape (K, m+n, d)
        The path, obstacles first (:attr:`pmplan.Plan.path`).
    m : int
        Number of obstacles.
    radius, obstacle_radius : float
        The radii the plan was refined for.
    bounds : array_like, shape (2, d), optional
        The workspace box ``[lo, hi]``; the robots must keep ``radius`` from its walls.

    Returns
    -------
    str
        The worst contact (measured against what the pair needs), where and how close; then
        the gap of the scene it passes through when that gap is narrower than a robot, else
        the gap narrower than :data:`TIGHT` robots it passes through, if any, and the knob
        that gives the refinement more steps.

    Examples
    --------
    A robot that must pass between two obstacles whose discs leave a gap of 0.2, with radius
    0.2 (a robot 0.4 wide):

    >>> wp = np.array([[[0.0, 0.5], [0.0, -0.5], [-1.0, 0.0]],
    ...                [[0.0, 0.5], [0.0, -0.5], [1.0, 0.0]]])
    >>> print(radius_reason([0.0, 1.0], wp, 2, 0.2, 0.4))
    robot x1 comes 0.5 from obstacle o1 at t = 0.500, closer than radius + obstacle_radius = 0.6; its path crosses the gap between obstacles o1 and o2, whose discs leave 0.2, narrower than a robot (2 radius = 0.4): no motion that crosses that gap keeps the radii
    """
    miss = radius_miss(times, waypoints, m, radius, obstacle_radius, bounds)
    return "" if miss is None else miss.sentence


def radius_miss(times, waypoints, m: int, radius: float, obstacle_radius: float,
                bounds=None) -> RadiusMiss | None:
    """Return why the path does not keep the radii, as a :class:`RadiusMiss` (its fields, and
    the sentence of :func:`radius_reason`); None when there is no pair to measure (no radii).

    The parameters are :func:`radius_reason`'s.

    Examples
    --------
    A robot 0.5 wide (radius 0.25) that must pass between two obstacles (radius 0.5) whose
    discs leave 0.25:

    >>> wp = np.array([[[0.0, 0.625], [0.0, -0.625], [-1.0, 0.0]],
    ...                [[0.0, 0.625], [0.0, -0.625], [1.0, 0.0]]])
    >>> miss = radius_miss([0.0, 1.0], wp, 2, 0.25, 0.5)
    >>> miss.contact, miss.between, miss.distance, miss.need, miss.t
    ('obstacle', ('x1', 'o1'), 0.625, 0.75, 0.5)
    >>> miss.gap
    Gap(robot='x1', between=('o1', 'o2'), width=0.25, robot_width=0.5)
    >>> miss.gap.narrow, miss.category
    (True, 'gap')
    """
    t = np.asarray(times, dtype=float)
    wp = np.asarray(waypoints, dtype=float)
    _, p, d = wp.shape
    scaled, e, _ = power_of_two_frame(wp[None])
    ws, e = scaled[0], int(e[0])
    rad, orad = np.ldexp(float(radius), -e), np.ldexp(float(obstacle_radius), -e)
    pa, pb = point_pairs(p, m)
    need = np.where(pa >= m, 2.0 * rad, rad + orad)
    cands = []  # (ratio, kind, data)
    if pa.size and (need > 0).any():
        dist, frac = segment_closest(ws[:-1, pa] - ws[:-1, pb], ws[1:, pa] - ws[1:, pb])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(need > 0, dist / need, np.inf)
        j, q = np.unravel_index(int(np.argmin(ratio)), ratio.shape)
        cands.append((float(ratio[j, q]), "pair", (j, q, float(dist[j, q]), float(frac[j, q]))))
    box = None
    if bounds is not None and rad > 0:
        box = np.ldexp(np.asarray(bounds, dtype=float), -e)
        rob = ws[:, m:]
        slack = np.stack([rob - box[0], box[1] - rob])  # (2, K, n, d)
        side, k, i, c = np.unravel_index(int(np.argmin(slack)), slack.shape)
        cands.append((float(slack[side, k, i, c]) / rad, "wall", (side, k, i, c)))
    if not cands:
        return None
    _, kind, data = min(cands, key=lambda x: x[0])
    all_walls = [(side, c) for side in (0, 1) for c in range(d)]
    if kind == "wall":
        side, k, i, c = data
        dist = float(np.ldexp(slack[side, k, i, c], e))
        when, bound = float(t[k]), Fraction(radius)
        head = _MSG_WALL.format(i=i + 1, c=c, wall=float(bounds[side][c]), t=when,
                                **_shown(dist, bound))
        contact, between = "wall", (f"x{i + 1}", _wall(bounds, side, c))
        robots, ks, walls = (m + i,), range(m), [(side, c)]
    else:
        j, q, dist, frac = data
        dist = float(np.ldexp(dist, e))
        when = float(t[j] + frac * (t[j + 1] - t[j]))
        a, b = int(pa[q]), int(pb[q])
        if a >= m:
            bound = 2 * Fraction(radius)
            head = _MSG_ROBOTS.format(i=a - m + 1, j=b - m + 1, t=when, **_shown(dist, bound))
            contact, between = "robots", (f"x{a - m + 1}", f"x{b - m + 1}")
            # two robots pressed together: either one's path may cross a gap no robot passes
            # (then its own radii are lost there too, whatever the refinement does)
            robots, ks, walls = (a, b), range(m), all_walls
        else:
            bound = Fraction(radius) + Fraction(obstacle_radius)
            head = _MSG_OBSTACLE.format(i=b - m + 1, k=a + 1, **_shown(dist, bound), t=when)
            contact, between = "obstacle", (f"x{b - m + 1}", f"o{a + 1}")
            robots, ks, walls = (b,), [a], all_walls
    width = 2.0 * float(radius)
    found = []  # (robot, the narrowest gap narrower than TIGHT robots its path crosses)
    if d == 2:  # (a gap blocks only in the plane: in space a path goes around)
        for robot in robots:
            gap = _narrow_gap(ws[0, :m], ws[:, robot], rad, orad, box, ks, walls,
                              TIGHT * 2.0 * rad)
            if gap is not None:
                found.append((robot, gap))
    # a gap no robot passes first (of either robot, in order), else one only one robot passes
    found.sort(key=lambda rg: not rg[1][-1] < 2.0 * rad)
    miss = dict(contact=contact, between=between, distance=dist, need=float(bound), t=when)
    if not found:
        return RadiusMiss(**miss, gap=None, sentence=f"{head}; {_MSG_EFFORT}")
    robot, gap = found[0]
    narrow = gap[-1] < 2.0 * rad
    whose = "its" if len(robots) == 1 else f"robot x{robot - m + 1}'s"
    size = float(np.ldexp(gap[-1], e))
    if gap[0] == "obstacle":
        words = dict(whose=whose, k=gap[1] + 1, l=gap[2] + 1, gap=size, width=width)
        why = (_MSG_GAP_OBSTACLES.format(**words) if narrow else
               _MSG_TIGHT_OBSTACLES.format(**words, spare=size - width))
        pair = (f"o{gap[1] + 1}", f"o{gap[2] + 1}")
    else:
        _, k, side, c, _ = gap
        words = dict(whose=whose, k=k + 1, c=c, wall=float(bounds[side][c]), gap=size,
                     width=width)
        why = (_MSG_GAP_WALL.format(**words) if narrow else
               _MSG_TIGHT_WALL.format(**words, spare=size - width))
        pair = (f"o{k + 1}", _wall(bounds, side, c))
    sentence = f"{head}; {why}" if narrow else f"{head}; {why}; {_MSG_EFFORT}"
    return RadiusMiss(**miss, gap=Gap(f"x{robot - m + 1}", pair, size, width),
                      sentence=sentence)


def _wall(bounds, side: int, c: int) -> str:
    """The name of a wall of the box, as the sentences name it: ``"x[1] = 0"``."""
    return f"x[{c}] = {float(bounds[side][c]):.6g}"


def _crosses(path: np.ndarray, p: np.ndarray, q: np.ndarray) -> bool:
    """Whether the planar polyline ``path`` (K, 2) meets the segment [p, q] (orientation
    signs, touching included)."""
    def orient(a, b, c):
        return np.sign((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                       - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))

    a, b = path[:-1], path[1:]
    o1, o2 = orient(a, b, p), orient(a, b, q)
    o3, o4 = orient(p, q, a), orient(p, q, b)
    # (the boxes must overlap too: collinear segments pass the signs without meeting)
    boxes = ((np.minimum(a, b) <= np.maximum(p, q)) & (np.minimum(p, q) <= np.maximum(a, b)))
    return bool(((o1 * o2 <= 0) & (o3 * o4 <= 0) & boxes.all(axis=-1)).any())


def _narrow_gap(obs: np.ndarray, path: np.ndarray, rad: float, orad: float, box, ks, walls,
                limit: float | None = None):
    """The narrowest gap narrower than ``limit`` (default a robot, ``2 rad``) that the planar
    polyline ``path`` crosses: between an obstacle of ``ks`` and another obstacle
    (``("obstacle", k, l, gap)``), or between an obstacle of ``ks`` and a wall of ``walls``
    (``("wall", k, side, coordinate, gap)``, the segment from the obstacle to its foot on the
    wall); None when there is none. With the default ``limit``, a motion that crosses such
    a segment comes closer than ``rad + orad`` to one of its obstacles (the two distances from
    the crossing point add up to less than ``2 (rad + orad)``) or closer than ``rad`` to the
    wall."""
    limit = 2.0 * rad if limit is None else limit
    best = None
    for k in ks:
        for ell in range(obs.shape[0]):
            if ell == k:
                continue
            gap = float(np.sqrt(((obs[k] - obs[ell]) ** 2).sum())) - 2.0 * orad
            if gap < limit and (best is None or gap < best[-1]) \
                    and _crosses(path, obs[k], obs[ell]):
                best = ("obstacle", k, ell, gap)
        if box is None:
            continue
        for side, c in walls:
            gap = abs(float(box[side][c] - obs[k][c])) - orad
            foot = obs[k].copy()
            foot[c] = box[side][c]
            if gap < limit and (best is None or gap < best[-1]) \
                    and _crosses(path, obs[k], foot):
                best = ("wall", k, side, c, gap)
    return best
