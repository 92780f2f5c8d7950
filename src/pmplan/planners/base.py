"""What a planner is: the whole protocol (:class:`Planner`) and the one loop of every planner.

A planner takes a batch of queries -- obstacles (B, m, d), starts (B, n, d), goals (B, n, d) --
and returns a :class:`RawPlan`: the domain label of every query, a small integer record of its
stratum, and the batch of piecewise-linear paths. It does not validate, draw, print or read
files; :mod:`pmplan.api` validates, runs the chunks (:mod:`pmplan.running`) and returns the plans
(:mod:`pmplan.results`).

A planner is its mathematics (:meth:`Planner.reference`, exact, in numpy) and what it covers;
how a batch is computed -- the numpy reference or fused kernels -- is a backend's business
(:mod:`pmplan.backends`: :meth:`Planner.plan` asks the backend selected). Adding a planner is
one module in ``planners/`` that subclasses :class:`Planner` and calls :func:`register` (and,
for speed, a kernel module plus its glue in :mod:`pmplan.backends.numba`); what ``pmplan
verify`` needs of it lives in :mod:`pmplan.strata`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import backends
from ..errors import UnsupportedError
from ..path import PiecewiseLinearPath

__all__ = ["CROWD_LANES", "ROBOT_LANES", "WALL_LANES", "RawPlan", "Planner", "REGISTRY",
           "SCENE_CODE", "Stage", "default_planner", "lift_code", "out_of_scope", "register",
           "scene_unit", "spec_of_class", "unit"]

#: how the planners and their kernels receive ``lift="scene"``: a ``lift`` that is not > 0.
#: A positive lift is the unit itself; SCENE_CODE (0.0) asks for the unit u(O) of every query
#: (:func:`scene_unit`), computed by the numpy reference and by the numba kernels alike. A
#: float (not a string or an array), so the kernels keep one signature and scaling the lift
#: by a power of two keeps its meaning.
SCENE_CODE = 0.0

#: from this many robots a refined plan's default planner in the plane is the one that
#: declares :attr:`Planner.crowd` (:func:`default_planner`): in rooms with walls its lanes, all
#: on one side, cross fewer narrow gaps; below it, or in space, where a path can go around a
#: gap, they only lengthen the paths (``benchmarks/crowd_default.py`` measures both). 8 rather
#: than 16 since a refinement of 5 to 8 robots in the plane ends with as many clearing-only
#: steps as steps (:data:`pmplan.refine.PLANE_FINAL`), which clear the contacts the one-side
#: lanes left with 8 robots
CROWD_LANES = 8

#: from this many robots a refined plan's default planner in a workspace box in the plane is
#: the one that declares :attr:`Planner.wall_side` (:func:`default_planner`): its lanes, all on
#: one side of the obstacles' line, take the side where the walls leave the obstacles the most
#: room (:mod:`pmplan.sides`, Mathematics §8, "The side of the lanes"); with 2 robots, as with
#: more, they kept the radii on more plans than the compact lanes, at a median paired length
#: within 1 % (``benchmarks/sides_ab.py``); one robot keeps the default of (d, 1, m)
WALL_LANES = 2

#: up to this many robots a refined plan's default planner in a workspace box in the plane
#: (from :data:`WALL_LANES` on) is the one that declares :attr:`Planner.robot_side`
#: (:func:`default_planner`): each robot's lanes take the side of the obstacles' line where
#: its own positions lie unless the walls leave the obstacles it passes too little room there
#: (:mod:`pmplan.sides`, Mathematics §8, "A side per robot"), so that its path goes round
#: fewer obstacles. With 8 robots it kept the radii on a few queries fewer than the lanes of
#: one side for all, and, planned by the numpy reference, took more than the 5 ms per query
#: issue 25 asks (``benchmarks/robots_ab.py``'s docstring)
ROBOT_LANES = 4


def lift_code(lift) -> float:
    """The float a planner takes for ``lift``: the unit itself, or :data:`SCENE_CODE` for
    ``"scene"`` (the input is already checked, see :func:`pmplan.configuration.as_lift`)."""
    return SCENE_CODE if isinstance(lift, str) else float(lift)


def scene_unit(obstacles: np.ndarray) -> np.ndarray:
    """Return ``u(O) = max_{k >= 2} |o_k - o_1|`` of every query, shape (B,).

    The unit of ``lift="scene"``: the obstacles' radius about o1. It depends on the obstacles
    alone (so it is the same for start and goal and for every configuration of a sequence, and
    the planners stay continuous on every domain), is positive (the obstacles are distinct),
    invariant under translations and rotations and linear in scalings, so that the paths are
    equivariant. Computed as ``sqrt(max_k sum_c (o_k,c - o_1,c)^2)`` with the sum over the d
    coordinates in order -- the operations (and their order) of the numba kernels, which
    reproduce it bitwise (``sqrt`` is monotone and correctly rounded, so the maximum may be
    taken before it).
    """
    diff = obstacles[:, 1:] - obstacles[:, :1]
    return np.sqrt((diff * diff).sum(-1).max(axis=1))


def unit(obstacles: np.ndarray, lift: float) -> np.ndarray:
    """The unit of every query of a batch (B,): ``lift`` when it is positive, else (for
    :data:`SCENE_CODE` or ``"scene"``) :func:`scene_unit`."""
    lift = lift_code(lift)
    if lift > 0:
        return np.full(obstacles.shape[0], float(lift))
    return scene_unit(obstacles)


@dataclass
class RawPlan:
    """Output of a planner on a batch of B queries.

    Attributes
    ----------
    domain : ndarray of int64, shape (B,)
        The label ``l`` of the domain of continuity ``W_l`` of each query.
    strata : ndarray of int64, shape (B, S)
        The stratum record of every query: planner-specific integers that name its stratum
        (one row per query; ``Planner.stratum_name`` writes a row in the paper's notation).
    path : PiecewiseLinearPath
        Batch of paths, waypoints of shape (B, K, m+n, d).
    """

    domain: np.ndarray
    strata: np.ndarray
    path: PiecewiseLinearPath


class Planner:
    """The protocol every planner implements (see ``obstacle_line``, ``planar_three``).

    Subclass it; the members with a default here are optional. By concern:

    * the mathematics (required): :attr:`name`, :attr:`summary`, :meth:`supports`,
      :meth:`domain_labels`, :meth:`stratum_name`, :meth:`reference` (the numpy reference)
      and :meth:`allocate`; optional :attr:`equivariant`, :attr:`sequential`,
      :attr:`priority`, :attr:`crowd`, :attr:`wall_side`, :attr:`robot_side`,
      :meth:`path_times`, :meth:`still_pieces`, :meth:`fixed_waypoints`;
    * how a batch is computed is a backend's (:mod:`pmplan.backends`), what ``pmplan verify``
      needs is the planner's :class:`~pmplan.strata.StrataSpec` (:mod:`pmplan.strata`), and
      what the faces show of it its :class:`~pmplan.display.DisplaySpec`
      (:mod:`pmplan.display`), each found by :func:`spec_of_class`.

    The faces (:mod:`pmplan.verify`, :mod:`pmplan.animation`, the CLI, the web page) ask these
    members, never a planner's name.
    """

    #: the name users pass as ``planner=``
    name: ClassVar[str] = ""
    #: one line for :func:`pmplan.info`
    summary: ClassVar[str] = ""
    #: planning ``2**k C`` with ``lift * 2**k`` gives exactly ``2**k`` times the path of C: the
    #: run loop then plans queries at extreme magnitudes scaled (:mod:`pmplan.magnitude`)
    equivariant: ClassVar[bool] = False
    #: plans through r > 2 configurations (:meth:`plan_sequence`, Mathematics §4.3)
    sequential: ClassVar[bool] = False
    #: the default planner of the (d, n, m) it supports is the one of highest priority
    priority: ClassVar[int] = 0
    #: the default instead, where it supports (d, n, m), for a refined plan of at least
    #: :data:`CROWD_LANES` robots in the plane (:func:`default_planner`)
    crowd: ClassVar[bool] = False
    #: in a workspace box in the plane the lanes take the side of the obstacles' line that
    #: :func:`pmplan.sides.wall_sides` chooses (the query mirrored, planned, the plan mirrored
    #: back: the planner with ``-nu(e)``); the default, where it supports (d, n, m), for a
    #: refined plan of more than :data:`ROBOT_LANES` robots in a box in the plane
    wall_side: ClassVar[bool] = False
    #: in a workspace box in the plane each robot's lanes take the side of the obstacles' line
    #: that :func:`pmplan.sides.robot_sides` chooses for it: :meth:`reference` takes ``down``
    #: (bool (B, n), the robots on the side of ``-nu(e)``); the default, where it supports
    #: (d, n, m), for a refined plan of :data:`WALL_LANES` to :data:`ROBOT_LANES` robots in a
    #: box in the plane
    robot_side: ClassVar[bool] = False

    # --- what the planner covers ---------------------------------------------------------
    def supports(self, d: int, n: int, m: int) -> str | None:
        """Return None if (d, n, m) is covered, else a sentence saying why not."""
        raise NotImplementedError

    def domain_labels(self, d: int, n: int, m: int, r: int = 2) -> list[int]:
        """All domain labels the planner uses for (d, n, m) and r configurations."""
        raise NotImplementedError

    def stratum_name(self, row, d: int, n: int, m: int) -> str:
        """Human-readable stratum name in the paper's notation."""
        raise NotImplementedError

    # --- the mathematics ------------------------------------------------------------------
    def reference(self, obstacles, configs, lift) -> RawPlan:
        """Plan a batch of queries through the configurations ``configs`` (r arrays (B, n, d);
        r = 2 unless :attr:`sequential`) among ``obstacles`` (B, m, d) with the unit ``lift``
        (a positive float, or :data:`SCENE_CODE` for the unit :func:`scene_unit` of every
        query): the planner's mathematics in numpy, exact, the reference every backend is held
        to. The input is not validated here (see :mod:`pmplan.configuration`). A planner that
        declares :attr:`robot_side` also takes ``down`` (bool (B, n), the robots whose lanes
        take the side of ``-nu(e)``; None: none), which the box passes it."""
        raise NotImplementedError

    def plan(self, obstacles, start, goal, *, lift: float = 1.0,
             backend: str | None = None) -> RawPlan:
        """Plan a batch of queries from ``start`` to ``goal`` (B, n, d) among ``obstacles``
        (B, m, d) with the backend ``backend`` (:func:`pmplan.backends.select`; ``"numpy"``:
        :meth:`reference`). The input is not validated here."""
        return self.planned(obstacles, [start, goal], lift, backend)

    def plan_sequence(self, obstacles, configs, *, lift: float = 1.0,
                      backend: str | None = None) -> RawPlan:
        """Plan through ``len(configs)`` configurations (only when :attr:`sequential`; else
        r = 2 only, which is :meth:`plan`)."""
        if len(configs) != 2 and not self.sequential:
            raise NotImplementedError(f"the {self.name} planner plans r = 2 configurations only")
        return self.planned(obstacles, configs, lift, backend)

    def planned(self, obstacles, configs, lift, backend: str | None) -> RawPlan:
        """:meth:`plan_sequence` with the backend ``backend``: its :func:`plan` into new arrays
        when it takes these arrays (``arrays``), else :meth:`reference`."""
        be = backends.select(backend)
        lift = lift_code(lift)
        arrays = be.arrays(self, obstacles, configs)
        if arrays is None:
            return self.reference(obstacles, configs, lift)
        obstacles, configs = arrays
        b, m, d = obstacles.shape
        out = self.allocate(b, len(configs), m, configs[0].shape[1], d)
        be.plan(self, obstacles, configs, lift, out, False)
        return RawPlan(domain=out["domain"], strata=out["strata"],
                       path=PiecewiseLinearPath(out["times"], out["waypoints"]))

    # --- planning into output arrays, certified: the run loop's entry ------------------------
    def allocate(self, b: int, r: int, m: int, n: int, d: int) -> dict:
        """Output arrays of a batch of b queries through r configurations: ``domain`` (b,)
        int64, ``strata`` (b, S) int64, ``clearance`` (b,), ``times`` (K,) shared by every
        query or (b, K) per query, ``waypoints`` (b, K, m+n, d)."""
        raise NotImplementedError

    def path_times(self, r: int) -> np.ndarray | None:
        """The breakpoints (K,) every path through r configurations shares, or None when they
        are per query."""
        return None

    def cut_structure(self, times: np.ndarray) -> tuple[int, int] | None:
        """``(r, c)`` when the breakpoints ``times`` (K,), or every row of per-query ones (B,
        K), are this planner's :meth:`path_times` ``(r)`` with every piece cut into c pieces
        (every c-th breakpoint is one of them, bit for bit; the cuts anywhere inside): the
        times of a refined path, of a path in a box (:func:`pmplan.workspace.path_into_box_linear`
        cuts every piece where the points cross the nodes of its map, the same number of times
        in every path of a batch) or both; else None (per-query breakpoints of a planner without
        shared ones). The smallest r that fits, then the smallest c."""
        times = np.asarray(times, dtype=float)
        k = times.shape[-1]
        for r in range(2, k + 1):
            shared = _shared_times(self, r)
            if shared is None or shared.shape[0] > k:
                return None
            c, rest = divmod(k - 1, shared.shape[0] - 1)
            if rest == 0 and (times[..., ::c] == shared).all():
                return r, c
        return None

    def still_pieces(self, r: int) -> np.ndarray | None:
        """The pieces of :meth:`path_times` ``(r)`` along which no point moves for almost
        every query (bool (K-1,)), or None: none is declared.

        Such a piece moves only on a closed set of measure zero (the desingularization of
        paper (3.2) moves robots only when two share a column); elsewhere it is a constant
        path, already as short as it can be. The refinement (:mod:`pmplan.refine`) keeps it
        one piece at every level (the waypoint at its end inside the path still moves, and
        the map stays continuous where the piece does move) and spends its waypoints on the
        pieces that move. What a planner declares here depends on r alone, never on a query, so the
        refinement stays continuous on the same domains.
        """
        return None

    def still_for(self, times: np.ndarray) -> tuple[bool, ...] | None:
        """:meth:`still_pieces` for the breakpoints ``times`` (K,) or (B, K): when they are
        :meth:`path_times` ``(r)`` with every piece cut into c pieces (:meth:`cut_structure`),
        every cut of a still piece is still; else (per-query breakpoints of a planner without
        shared ones) None."""
        cut = self.cut_structure(times)
        if cut is None:
            return None
        r, c = cut
        still = self.still_pieces(r)
        if still is None:
            return None
        return tuple(bool(v) for v in np.repeat(np.asarray(still, dtype=bool), c))

    def fixed_waypoints(self, times: np.ndarray) -> np.ndarray:
        """The indices of the waypoints where a path of this planner with breakpoints ``times``
        passes through its r configurations, in order; r is the length of the result.

        A motion through r configurations (Mathematics §4.3, sequential planning) is at the start at
        time 0, at the intermediate configuration C_k at time ``k / (r - 1)`` and at the goal at
        time 1, each a breakpoint of the path; the stages that must keep them fixed
        (:func:`pmplan.refine`) read them here, the one place that decides them.

        Parameters
        ----------
        times : ndarray, shape (K,) or (B, K)
            Breakpoints shared by a batch, or per query.

        Returns
        -------
        ndarray of int64, shape (r,)
            For breakpoints of a :attr:`sequential` planner that are its :meth:`path_times`
            ``(r)`` with every piece cut into c pieces (:meth:`cut_structure`; shared, or the
            same structure in every row): the index ``c j`` of the breakpoint ``k / (r - 1)``
            of ``path_times(r)``. Else r = 2, the first and the last waypoint.
        """
        times = np.asarray(times, dtype=float)
        k = times.shape[-1]
        if self.sequential:
            cut = self.cut_structure(times)
            if cut is not None:
                r, c = cut
                at = np.searchsorted(_shared_times(self, r), np.arange(r) / (r - 1))
                return (c * at).astype(np.int64)
        return np.array([0, k - 1], dtype=np.int64)


@functools.lru_cache(maxsize=256)
def _shared_times(planner: Planner, r: int) -> np.ndarray | None:
    """``planner.path_times(r)``, computed once per (planner, r) (read-only)."""
    times = planner.path_times(r)
    if times is not None:
        times = np.asarray(times, dtype=float)
        times.flags.writeable = False
    return times


class Stage:
    """The protocol of a stage: a map applied to planned paths after the planner, chunk by
    chunk, by the run loop (:func:`pmplan.running.run_stage`, with ``workers`` and the progress
    display of :func:`pmplan.plan_batch`). The refinement (``RefineStage`` of
    :mod:`pmplan.refine`) is one.

    Subclass it: :attr:`size` (the batch length B), :attr:`chunk` and :meth:`run`, which
    processes rows ``lo:hi`` into the stage's own output arrays (each chunk writes its own rows,
    so chunks may run in parallel threads) and returns their certificate (bool, (hi - lo,)).
    """

    #: rows per chunk, at most (with several workers :func:`pmplan.running.run_stage` cuts a
    #: batch into smaller chunks, :func:`pmplan.running.stage_chunk`)
    chunk: ClassVar[int] = 1024
    #: what the progress bar says
    label: ClassVar[str] = "processing"
    #: the batch length B
    size: int = 0

    def run(self, lo: int, hi: int) -> np.ndarray:
        raise NotImplementedError

    def fail(self, bad: np.ndarray) -> None:
        """Raise the error of the rows ``bad`` (bool, (B,)) whose certificate failed."""
        raise NotImplementedError


REGISTRY: dict[str, Planner] = {}


def register(planner: Planner) -> Planner:
    """Add a planner instance to the registry under its ``name``."""
    REGISTRY[planner.name] = planner
    return planner


def out_of_scope(d: int, n: int, m: int, r: int = 2) -> str | None:
    """Why no planner covers (d, n, m) and r configurations (one sentence), or None: the one
    source of these messages (:func:`pmplan.info`, the planners' :meth:`~Planner.supports`)."""
    if d < 2:
        return f"d = {d}: planners need d >= 2"
    if n < 1:
        return f"n = {n}: at least one robot is needed"
    if m < 2:
        return f"m = {m}: the planners need m >= 2 obstacles (they define the line L_C)"
    if r < 2:
        return f"r = {r}: a motion needs r >= 2 configurations"
    return None


def default_planner(d: int, n: int, m: int, sequential: bool = False,
                    refining: bool = False, bounded: bool = False) -> str:
    """The name of the default planner for (d, n, m): among the registered planners that
    support it (and, for a sequence of configurations, are :attr:`~Planner.sequential`), the one of
    highest :attr:`~Planner.priority` -- ``planar_three`` (paper Section 4) for (2, 1, 3),
    ``obstacle_line_compact`` (paper Section 3 and Mathematics §4.4) otherwise -- but for a
    plan to be refined (``refining``) in the plane: in a workspace box (``bounded``) of
    :data:`WALL_LANES` to :data:`ROBOT_LANES` robots the one that declares
    :attr:`~Planner.robot_side` (``obstacle_line_robots``; Mathematics §8, "A side per
    robot"), of more the one that declares :attr:`~Planner.wall_side`
    (``obstacle_line_walls``; Mathematics §8, "The side of the lanes"), else of at least
    :data:`CROWD_LANES` robots the one that declares :attr:`~Planner.crowd`
    (``obstacle_line_oneside``; Mathematics §8, "Crowds"). Each is one section on all the
    queries of its (d, n, m), so the plans stay continuous on its domains. When none supports
    (d, n, m), the most general one (lowest priority), whose :meth:`~Planner.supports` then
    says why."""
    pool = [p for p in REGISTRY.values() if p.sequential or not sequential]
    fit = [p for p in pool if p.supports(d, n, m) is None]
    plane = refining and d == 2
    boxed = plane and bounded and n >= WALL_LANES
    robots = [p for p in fit if p.robot_side] if boxed and n <= ROBOT_LANES else []
    walls = [p for p in fit if p.wall_side] if boxed else []
    crowd = [p for p in fit if p.crowd] if plane and n >= CROWD_LANES else []
    if robots or walls or crowd:
        return (robots or walls or crowd)[0].name
    if fit:
        return max(fit, key=lambda p: p.priority).name
    return min(pool, key=lambda p: p.priority).name


def spec_of_class(table: dict, planner):
    """The entry of ``table`` (planner class -> what a concern needs of it, e.g.
    :data:`pmplan.strata.SPECS`) for ``planner`` (a planner, or the name of a registered one):
    its class's, or its nearest ancestor's."""
    if isinstance(planner, str):
        if planner not in REGISTRY:
            raise UnsupportedError(f"unknown planner {planner!r}; choose one of "
                                   f"{', '.join(sorted(REGISTRY))}")
        planner = REGISTRY[planner]
    return next(table[c] for c in type(planner).__mro__ if c in table)
