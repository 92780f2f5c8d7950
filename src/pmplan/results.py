"""The results: :class:`Plan` (one query), :class:`PlanBatch` (a batch, vectorised) and
:class:`PlannerInfo` (what :func:`pmplan.info` says). Data only: built by :mod:`pmplan.api`.

A :class:`PlanBatch` behaves like a batch of scipy's ``Rotation``: ``len``, iteration over its
plans, ``batch[i]`` (a :class:`Plan`) and ``batch[slice | mask | indices]`` (a PlanBatch).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .path import PiecewiseLinearPath
from .planners.base import REGISTRY
from .reasons import RadiusMiss, radius_miss

__all__ = ["Plan", "PlanBatch", "PlannerInfo"]


@dataclass(frozen=True, init=False)
class Plan:
    """The answer to one query.

    Attributes
    ----------
    domain : int
        The label l of the domain of continuity W_l the query falls in.
    stratum : str
        The stratum in the paper's notation, e.g. ``"T_{3,5}"`` or ``"T^{2,3}_{3,4}"``.
    clearance : float
        Certified minimum distance between any two points along the whole motion.
    path : PiecewiseLinearPath
        ``path.times`` (K,), ``path.waypoints`` (K, m+n, d) with obstacles first; ``path(t)``.
    planner : str
        Name of the planner that produced it.
    dims : tuple of int
        ``(d, n, m)``.
    radius, obstacle_radius : float
        The radii a refined plan was asked for (:func:`pmplan.refine`); 0.0 when unrefined.
    refined : bool
        Whether the path is a refined motion (:mod:`pmplan.refine`).
    robot_distance, obstacle_distance : float
        Minimum robot-robot (``inf`` when n = 1) and robot-obstacle distances along the path,
        by the certificate's closed-form piece minima.
    respects_radius : bool
        ``robot_distance >= 2 radius`` and ``obstacle_distance >= radius + obstacle_radius``,
        decided exactly (always True for radii 0).
    radius_reason : str or None
        Why the radii are not kept, in one sentence (None when they are): the worst contact
        (two robots, a robot and an obstacle, or a robot and a wall), where and how close, and
        the gap of the scene it passes through when that gap is narrower than a robot
        (:func:`pmplan.reasons.radius_reason`).
    radius_miss : RadiusMiss or None
        The same reason for a program (None when the radii are kept): the contact, the two
        that meet, the distance against the need, the time, the gap and its width, and
        ``category`` (``"gap"`` when the scene leaves no room there;
        :class:`pmplan.reasons.RadiusMiss`).
    raw_clearance : float
        The clearance of the unrefined plan (``clearance`` itself when unrefined), or in a
        workspace box of the refinement's start, the plan at the raw breakpoints
        (:func:`pmplan.running.box_start`): a refined plan's pair distances never drop below
        ``min(T, KAPPA_FLOOR D_raw)`` of the ones it started from
        (:data:`pmplan.refine.grid.KAPPA_FLOOR`, ``docs/refinement.md``).
    bounds : ndarray, shape (2, d), or None
        The workspace box ``[lo, hi]`` the motion stays in (``bounds=`` of the planning
        functions, :mod:`pmplan.workspace`); None without one.
    """

    #: (not a dataclass field: set only when planned in a workspace box)
    bounds = None

    domain: int
    stratum: str
    clearance: float
    path: PiecewiseLinearPath
    planner: str
    dims: tuple[int, int, int]
    radius: float = 0.0
    obstacle_radius: float = 0.0
    refined: bool = False

    def __init__(self, domain: int, stratum: str, clearance: float, path: PiecewiseLinearPath,
                 planner: str, dims: tuple[int, int, int], radius: float = 0.0,
                 obstacle_radius: float = 0.0, refined: bool = False, **measured) -> None:
        # the one construction path, also the fast paths' (a frozen dataclass's own __init__
        # sets field by field through object.__setattr__): the fields go into the instance
        # dict at once; afterwards the dataclass refuses assignment (FrozenInstanceError).
        # ``measured``: robot_distance, obstacle_distance, respects_radius when known
        vars(self).update(domain=domain, stratum=stratum, clearance=clearance, path=path,
                          planner=planner, dims=dims, radius=radius,
                          obstacle_radius=obstacle_radius, refined=refined, **measured)

    @cached_property
    def _measured(self) -> tuple[float, float, bool]:
        from .refine import radius_report

        rd, od, ok = radius_report(self.path.waypoints[None], self.m, self.radius,
                                   self.obstacle_radius)
        return float(rd[0]), float(od[0]), bool(ok[0])

    @cached_property
    def raw_clearance(self) -> float:
        """The clearance of the unrefined plan (``clearance`` when this one is unrefined; NaN for
        a refined plan read from a store written before it was recorded)."""
        return float("nan") if self.refined else self.clearance

    @cached_property
    def robot_distance(self) -> float:
        """Minimum distance between two robots along the path (``inf`` when n = 1)."""
        return self._measured[0]

    @cached_property
    def obstacle_distance(self) -> float:
        """Minimum distance between a robot and an obstacle along the path."""
        return self._measured[1]

    @cached_property
    def respects_radius(self) -> bool:
        """Whether the robots, discs of ``radius``, keep off each other and off the obstacles
        (discs of ``obstacle_radius``) along the whole path -- decided exactly."""
        return self._measured[2]

    @cached_property
    def radius_miss(self) -> RadiusMiss | None:
        """Why the radii are not kept, for a program: a :class:`~pmplan.reasons.RadiusMiss`
        (its fields, and its sentence :attr:`radius_reason`); None when they are kept
        (:func:`pmplan.reasons.radius_miss`)."""
        if self.respects_radius:
            return None
        return radius_miss(self.path.times, self.path.waypoints, self.m, self.radius,
                           self.obstacle_radius, self.bounds)

    @property
    def radius_reason(self) -> str | None:
        """Why the radii are not kept, in one sentence a user can read; None when they are
        (:func:`pmplan.reasons.radius_reason`; the sentence of :attr:`radius_miss`)."""
        miss = self.radius_miss
        return None if miss is None else miss.sentence

    @property
    def m(self) -> int:
        """Number of obstacles (the first m rows of every waypoint)."""
        return self.dims[2]

    @property
    def obstacles(self) -> np.ndarray:
        """The obstacles, shape (m, d)."""
        return self.path.waypoints[0, : self.m]

    @property
    def start(self) -> np.ndarray:
        """The robots' start positions, shape (n, d)."""
        return self.path.waypoints[0, self.m :]

    @property
    def goal(self) -> np.ndarray:
        """The robots' goal positions, shape (n, d)."""
        return self.path.waypoints[-1, self.m :]

    @property
    def times(self) -> np.ndarray:
        return self.path.times

    @property
    def waypoints(self) -> np.ndarray:
        return self.path.waypoints


def extra_row(extra: dict, i: int) -> dict:
    """Row ``i`` of a batch's refinement record (:attr:`PlanBatch._extra`) as the keyword
    arguments of :class:`Plan`: a number per field, the box (2, d) as an array."""
    return {k: v[i].item() if np.ndim(v) == 1 else np.array(v[i]) for k, v in extra.items()}


def _recorded(key: str, doc: str) -> property:
    """A read-only attribute of :class:`PlanBatch` from its refinement record."""
    return property(lambda self: self._record(key), doc=doc)


@dataclass(frozen=True)
class PlanBatch:
    """The answers to a batch of B queries (vectorised :class:`Plan`).

    Attributes
    ----------
    domain : ndarray of int64, shape (B,)
    strata : ndarray of int64, shape (B, S)    the planner's stratum record
    clearance : ndarray of float, shape (B,)
    times : ndarray, shape (K,) or (B, K)
    waypoints : ndarray, shape (B, K, m+n, d)
    planner : str
    dims : tuple (d, n, m)
    radius, obstacle_radius, refined, robot_distance, obstacle_distance, respects_radius
    raw_clearance
        As in :class:`Plan`, arrays of shape (B,).
    """

    domain: np.ndarray
    strata: np.ndarray
    clearance: np.ndarray
    times: np.ndarray
    waypoints: np.ndarray
    planner: str
    dims: tuple[int, int, int]
    _names: dict = field(default_factory=dict, repr=False, compare=False)
    #: the refinement record: arrays (B,) ``radius``, ``obstacle_radius``, ``refined`` and,
    #: once measured, ``robot_distance``, ``obstacle_distance``, ``respects_radius``
    _extra: dict = field(default_factory=dict, repr=False, compare=False)

    def _record(self, key: str) -> np.ndarray:
        if key not in self._extra:
            b = len(self)
            if key in ("radius", "obstacle_radius"):
                self._extra[key] = np.zeros(b)
            elif key == "refined":
                self._extra[key] = np.zeros(b, dtype=bool)
            elif key == "raw_clearance":  # (NaN: a refined store written before it was kept)
                self._extra[key] = np.where(self._record("refined"), np.nan, self.clearance)
            else:
                from .refine import radius_report

                # (a refined batch has its record from pmplan.refine: this one is unrefined)
                rd, od, ok = radius_report(self.waypoints, self.dims[2], 0.0, 0.0)
                self._extra.update(robot_distance=rd, obstacle_distance=od, respects_radius=ok)
        return self._extra[key]

    radius = _recorded("radius", "The robots' radius asked of every plan (B,) (0 where unrefined).")
    obstacle_radius = _recorded("obstacle_radius",
                                "The obstacles' radius asked of every plan (B,) (0 where unrefined).")
    refined = _recorded("refined", "Whether every plan is a refined motion (B,) bool.")
    @property
    def bounds(self) -> np.ndarray | None:
        """The workspace box of every plan (B, 2, d) (``bounds=``), or None without one."""
        return self._extra.get("bounds")

    raw_clearance = _recorded("raw_clearance", "The clearance of every unrefined plan (B,) "
                              "(``clearance`` where unrefined; in a workspace box, of the "
                              "refinement's start), beside the refined one.")
    robot_distance = _recorded("robot_distance", "Minimum robot-robot distance along every "
                               "path (B,) (``inf`` when n = 1).")
    obstacle_distance = _recorded("obstacle_distance",
                                  "Minimum robot-obstacle distance along every path (B,).")
    respects_radius = _recorded("respects_radius",
                                "Whether every path keeps the radii (B,) bool, decided exactly.")

    @property
    def radius_miss(self) -> np.ndarray:
        """Why each plan misses its radii, for a program (B,) object array: the
        :class:`~pmplan.reasons.RadiusMiss` of :attr:`Plan.radius_miss` where
        ``respects_radius`` is False, None where it holds (computed for the missing rows only,
        on each access)."""
        out = np.full(len(self), None, dtype=object)
        for i in np.flatnonzero(~np.asarray(self.respects_radius, dtype=bool)):
            out[i] = self._plan(int(i)).radius_miss
        return out

    @property
    def radius_reason(self) -> np.ndarray:
        """Why each plan misses its radii (B,) object array: the sentence of
        :attr:`Plan.radius_reason` where ``respects_radius`` is False, None where it holds
        (computed for the missing rows only, on each access)."""
        out = np.full(len(self), None, dtype=object)
        for i, miss in enumerate(self.radius_miss):
            if miss is not None:
                out[i] = miss.sentence
        return out

    def __len__(self) -> int:
        return self.domain.shape[0]

    @property
    def path(self) -> PiecewiseLinearPath:
        """The batch of paths as one :class:`PiecewiseLinearPath`."""
        return PiecewiseLinearPath(self.times, self.waypoints)

    @property
    def stratum(self) -> np.ndarray:
        """Stratum names, an object array of shape (B,)."""
        d, n, m = self.dims
        p = REGISTRY[self.planner]
        out = np.empty(len(self), dtype=object)
        for i, row in enumerate(self.strata):
            key = tuple(row.tolist())
            if key not in self._names:
                self._names[key] = p.stratum_name(row, d, n, m)
            out[i] = self._names[key]
        return out

    def __getitem__(self, key) -> Plan | PlanBatch:
        """``batch[i]`` (an int): the :class:`Plan` of query i; ``batch[key]`` for a slice, a
        boolean mask (B,) or an integer array: the :class:`PlanBatch` of those queries (as
        numpy indexes ``domain``; shared breakpoints stay shared)."""
        if isinstance(key, (int, np.integer)) and not isinstance(key, (bool, np.bool_)):
            return self._plan(int(key))
        if not isinstance(key, slice):
            key = np.asarray(key)
            if key.ndim != 1 or key.dtype.kind not in "biu":
                raise IndexError(
                    "a PlanBatch is indexed by an int, a slice, a boolean mask (B,) or an "
                    f"integer array (k,); got {key.dtype} of shape {key.shape}"
                )
        return PlanBatch(
            domain=self.domain[key], strata=self.strata[key], clearance=self.clearance[key],
            times=self.times if self.times.ndim == 1 else self.times[key],
            waypoints=self.waypoints[key], planner=self.planner, dims=self.dims,
            _names=self._names, _extra={k: v[key] for k, v in self._extra.items()},
        )

    def _plan(self, i: int) -> Plan:
        d, n, m = self.dims
        times = self.times if self.times.ndim == 1 else self.times[i]
        path = PiecewiseLinearPath(times, self.waypoints[i]).compact()
        return Plan(
            domain=int(self.domain[i]),
            stratum=REGISTRY[self.planner].stratum_name(self.strata[i], d, n, m),
            clearance=float(self.clearance[i]),
            path=path,
            planner=self.planner,
            dims=self.dims,
            **extra_row(self._extra, i),
        )

    def __iter__(self):
        for i in range(len(self)):
            yield self._plan(i)


@dataclass(frozen=True)
class PlannerInfo:
    """What pmplan offers for (d, n, m, r); see :func:`info`."""

    d: int
    n: int
    m: int
    r: int
    planner: str | None
    domains: int | None
    labels: tuple[int, ...]
    tc: int | None
    optimal: bool
    message: str
