"""What a planner is: the whole protocol (:class:`Planner`) and the one loop of every planner.

A planner takes a batch of queries -- obstacles (B, m, d), starts (B, n, d), goals (B, n, d) --
and returns a :class:`RawPlan`: the domain label of every query, a small integer record of its
stratum, and the batch of piecewise-linear paths. It does not validate, draw, print or read
files; :mod:`pmplan.api` validates, runs the chunks (:mod:`pmplan.running`) and returns the plans
(:mod:`pmplan.results`).

The loop every planner shares is written once here (:meth:`Planner.plan_certified`): its
optional numba kernel (:meth:`Planner.kernel`) plans a chunk into the output arrays and flags
the queries it cannot decide in floating point; the flagged rows are re-decided exactly by the
numpy reference (:func:`store_reference`) and every row gets its certificate
(:func:`redecide`). Adding a planner is one module in ``planners/`` that subclasses
:class:`Planner` and calls :func:`register` (and, for speed, a kernel module plus
:meth:`Planner.kernel` / :meth:`Planner.single_query`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar

import numpy as np

from ..backend import NUMBA, NUMPY, resolve, shared_kernels
from ..certify import certificate
from ..certify import clearance as exact_clearance
from ..path import PiecewiseLinearPath

__all__ = ["RawPlan", "Planner", "REGISTRY", "SCENE_CODE", "default_planner", "lift_code", "redecide",
           "out_of_scope", "register", "scene_unit", "store_reference", "unit"]

#: how the planners and their kernels receive ``lift="scene"``: a ``lift`` that is not > 0.
#: A positive lift is the unit itself; SCENE_CODE (0.0) asks for the unit u(O) of every query
#: (:func:`scene_unit`), computed by the numpy reference and by the numba kernels alike. A
#: float (not a string or an array), so the kernels keep one signature and scaling the lift
#: by a power of two keeps its meaning.
SCENE_CODE = 0.0


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

    Subclass it; the methods with a default here are optional. Required: :attr:`name`,
    :attr:`summary`, :meth:`supports`, :meth:`domain_labels`, :meth:`stratum_name`,
    :meth:`plan` (the numpy reference) and :meth:`allocate`. The faces (:mod:`pmplan.verify`,
    :mod:`pmplan.animation`, the CLI) ask these members, never a planner's name.
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
    #: how the faces write domain label l: ``f"{domain_prefix}{l}"`` (``W_5``, ``W1``)
    domain_prefix: ClassVar[str] = "W_"
    #: the planner decides on heights (distance to the line L_C) as well as on columns: the
    #: faces that draw or check the frame show the heights too
    uses_heights: ClassVar[bool] = False
    #: the named phases ``(name, what happens)`` of the pieces of a path, for the faces that
    #: show a motion (:func:`pmplan.animation.phase_at`): several -- the phases of every leg
    #: between two configurations, in order; one -- every piece is of that kind; none -- the
    #: pieces are unnamed
    phases: ClassVar[tuple[tuple[str, str], ...]] = ()

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

    # --- the reference ---------------------------------------------------------------------
    def plan(self, obstacles, start, goal, *, lift: float = 1.0,
             backend: str | None = None) -> RawPlan:
        """Plan a batch of queries with the unit ``lift`` (a positive float, or
        :data:`SCENE_CODE` for the unit :func:`scene_unit` of every query); ``backend="numpy"``
        is the reference. The input is not validated here (see :mod:`pmplan.configuration`)."""
        raise NotImplementedError

    def plan_sequence(self, obstacles, configs, *, lift: float = 1.0,
                      backend: str | None = None) -> RawPlan:
        """Plan through ``len(configs)`` configurations (only when :attr:`sequential`; else
        r = 2 only, which is :meth:`plan`)."""
        if len(configs) == 2:
            return self.plan(obstacles, configs[0], configs[1], lift=lift, backend=backend)
        raise NotImplementedError(f"the {self.name} planner plans r = 2 configurations only")

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
            For shared breakpoints of a :attr:`sequential` planner that are its
            :meth:`path_times` ``(r)`` (r <= K): the first index of each time ``k / (r - 1)``.
            Else (per-query breakpoints, or a planner of two configurations): r = 2, the first
            and the last waypoint.
        """
        k = times.shape[-1]
        if self.sequential and times.ndim == 1:
            for r in range(2, k + 1):
                shared = self.path_times(r)
                if shared is None or shared.shape[0] > k:
                    break
                if shared.shape[0] == k and np.array_equal(shared, times):
                    return np.searchsorted(times, np.arange(r) / (r - 1)).astype(np.int64)
        return np.array([0, k - 1], dtype=np.int64)

    def kernel(self, obstacles, configs, lift: float, out: dict,
               validate: bool) -> np.ndarray | None:
        """Plan a chunk with the numba kernel into ``out`` (the rows of :meth:`allocate`) and
        return its flags (B,) uint8 (:mod:`pmplan.kernels.common`: ``FALLBACK``, ``SUSPECT``,
        ``NONFINITE``, ``BROKEN``, ``INVALID``), or None when no kernel plans this chunk
        (then the reference plans it). Default: no kernel."""
        return None

    def validates(self, d: int, backend: str | None = None) -> bool:
        """Whether :meth:`kernel` checks the queries itself (``validate=True``): an invalid
        query then fails the certificate, and the caller raises the input error."""
        return False

    def plan_certified(self, obstacles, configs, lift, out: dict, *,
                       backend: str | None = None, validate: bool = False) -> np.ndarray:
        """Plan and certify a chunk into ``out`` (arrays as :meth:`allocate`, the chunk's rows;
        shared ``times`` as they are); return the certificate (B,).

        The one loop: the kernel (:meth:`kernel`, for ``backend`` numba) -> the flagged rows
        re-decided exactly by the reference -> the certificate (:func:`redecide`); without a
        kernel, the reference plans and :func:`pmplan.certify.certificate` certifies every row
        (:func:`store_reference`).
        """
        lift = lift_code(lift)
        if resolve(backend) == NUMBA:
            flags = self.kernel(obstacles, configs, lift, out, validate)
            if flags is not None:
                return redecide(self, flags, obstacles, configs, lift, out)
        obstacles = np.asarray(obstacles, dtype=float)
        configs = [np.asarray(c, dtype=float) for c in configs]
        return store_reference(self, obstacles, configs, lift, np.arange(obstacles.shape[0]),
                               out)

    # --- what pmplan.verify asks: the planner's strata, exact queries in them, moves inside them ---
    # Defaults: the column strata of the query space (Mathematics §4.2, paper Section 3;
    # :func:`pmplan.generators.strata`), for a planner that decides on columns as the obstacle-line
    # planner does. A planner with its own strata overrides all five.
    def stratum_count(self, d: int, n: int, m: int) -> int:
        """The number of strata :meth:`exact_queries` cycles through for (d, n, m)."""
        from .. import generators as gen

        return len(gen.strata(d, n, m))

    def exact_queries(self, rng: np.random.Generator, d: int, n: int, m: int, count: int
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """At least ``count`` exact degenerate queries covering every stratum, round robin (the
        first :meth:`stratum_count` queries meet every stratum): obstacles (B, m, d), starts and
        goals (B, n, d). Default: :func:`pmplan.generators.column_query` on every stratum of
        :func:`pmplan.generators.strata`, integer coordinates every other query."""
        from .. import generators as gen

        obs, st, go = [], [], []
        table = gen.strata(d, n, m)
        for k in range(max(count, len(table))):
            s = table[k % len(table)]
            q = gen.column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole,
                                 integer=k % 2 == 0)
            obs.append(q.obstacles)
            st.append(q.start)
            go.append(q.goal)
        return np.stack(obs), np.stack(st), np.stack(go)

    def near_degenerate_queries(self, rng: np.random.Generator, d: int, n: int, m: int,
                                count: int, scale: float
                                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``count`` exact degenerate queries whose ties are broken by about ``scale`` of the
        scene. Default: :func:`pmplan.generators.near_degenerate_queries`."""
        from .. import generators as gen

        return tuple(gen.near_degenerate_queries(rng, d, n, m, count, scale))

    def perturb_within_stratum(self, rng: np.random.Generator, query, delta: float):
        """Move one query (obstacles, start, goal) inside its stratum by about ``delta``; return
        the moved query, or None when the move left the stratum. Default:
        :func:`pmplan.generators.perturb_within_stratum`."""
        from .. import generators as gen

        return tuple(gen.perturb_within_stratum(rng, query, delta))

    def stratum_row(self, obstacles, start, goal) -> np.ndarray:
        """The record of the stratum of one query, decided exactly (what
        :meth:`stratum_name` reads). Default: :func:`pmplan.generators.stratum_of`."""
        from .. import generators as gen

        return np.asarray(gen.stratum_of((obstacles, start, goal)).record())

    def notes(self, d: int, n: int, m: int) -> list[str]:
        """Facts to read a check of (d, n, m) by (``pmplan verify`` prints them as notes)."""
        return []

    def map_boundaries(self, obstacles, others) -> list[tuple[np.ndarray, np.ndarray]]:
        """Return the lines of the plane on which the label of one moving point changes.

        The moving point is one robot's start (or goal); ``obstacles`` (m, 2) and ``others``
        (k, 2), the other robots of the same configuration, stay where they are. Its label
        changes exactly where its column meets another point's column (Mathematics §3.6,
        §4.2), so the default is the column line through every other point.

        Parameters
        ----------
        obstacles : numpy.ndarray
            The obstacles, shape (m, 2).
        others : numpy.ndarray
            The other robots' points of the mapped configuration, shape (k, 2).

        Returns
        -------
        list of tuple
            ``(point, direction)`` pairs of float arrays of shape (2,), one per line, with
            ``direction`` a unit vector; points on one column give one line.
        """
        o = np.asarray(obstacles, dtype=float)
        pts = np.concatenate([o, np.asarray(others, dtype=float).reshape(-1, 2)])
        e = (o[1] - o[0]) / np.hypot(*(o[1] - o[0]))
        nu = np.array([-e[1], e[0]])
        from ..predicates import projection_classes

        labels = projection_classes(pts[None], o[0][None], o[1][None])[0][0]
        first = [int(np.flatnonzero(labels == lab)[0]) for lab in np.unique(labels)]
        return [(pts[k], nu) for k in sorted(first)]

    # --- the single-query fast paths ---------------------------------------------------------
    def single_query(self, m: int, n: int, d: int) -> Callable | None:
        """``run(obstacles, start, goal, lift) -> (times, waypoints, domain, row, clearance) |
        None`` planning and certifying one query of shape (m, n, d) in one kernel call, or None
        when no kernel plans that shape.

        The caller guarantees C-contiguous, aligned, writeable float64 arrays (m, d), (n, d),
        (n, d) and a float ``lift`` (positive, or :data:`SCENE_CODE`); ``run`` returns None
        whenever anything is unusual (an invalid query, a flag, a failed certificate) so that
        the caller takes the general path; the path it returns is compact (no zero-duration
        piece), the breakpoints either checked by the kernel or :meth:`path_times`.
        """
        return None

    def sequence_query(self, r: int, m: int, n: int, d: int) -> Callable | None:
        """As :meth:`single_query` for one query through r configurations: ``run(obstacles,
        configs, lift)``."""
        return None


class Stage:
    """The protocol of a stage: a map applied to planned paths after the planner, chunk by
    chunk, by the run loop (:func:`pmplan.running.run_stage`, with ``workers`` and the progress
    display of :func:`pmplan.plan_batch`). The refinement (:class:`pmplan.refine.RefineStage`)
    is one.

    Subclass it: :attr:`size` (the batch length B), :attr:`chunk` and :meth:`run`, which
    processes rows ``lo:hi`` into the stage's own output arrays (each chunk writes its own rows,
    so chunks may run in parallel threads) and returns their certificate (bool, (hi - lo,)).
    """

    #: rows per chunk
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


def default_planner(d: int, n: int, m: int, sequential: bool = False) -> str:
    """The name of the default planner for (d, n, m): among the registered planners that
    support it (and, for a sequence of configurations, are :attr:`~Planner.sequential`), the one of
    highest :attr:`~Planner.priority` -- ``planar_three`` (paper Section 4) for (2, 1, 3),
    ``obstacle_line`` (paper Section 3 and Mathematics §4) otherwise. When none does, the most general
    one (lowest priority), whose :meth:`~Planner.supports` then says why."""
    pool = [p for p in REGISTRY.values() if p.sequential or not sequential]
    fit = [p for p in pool if p.supports(d, n, m) is None]
    if fit:
        return max(fit, key=lambda p: p.priority).name
    return min(pool, key=lambda p: p.priority).name


def store_reference(planner: Planner, obstacles, configs, lift, idx, out: dict) -> np.ndarray:
    """Plan rows ``idx`` of a chunk with the numpy reference, write them into ``out`` and
    certify them (:func:`pmplan.certify.certificate`, intermediate configurations included);
    return the certificate of those rows (bool, (len(idx),))."""
    obs = obstacles[idx]
    cfg = [c[idx] for c in configs]
    r = len(cfg)
    with np.errstate(all="ignore"):  # what overflows (coordinates ~1e308) fails the certificate
        if r == 2:
            raw = planner.plan(obs, cfg[0], cfg[1], lift=lift, backend=NUMPY)
        else:
            raw = planner.plan_sequence(obs, cfg, lift=lift, backend=NUMPY)
    pw = raw.path.waypoints
    out["waypoints"][idx] = pw
    out["domain"][idx] = raw.domain
    out["strata"][idx] = raw.strata
    if out["times"].ndim == 2:
        out["times"][idx] = raw.path.times
    full = [np.concatenate([obs, c], axis=1) for c in cfg]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    with np.errstate(all="ignore"):  # a non-finite path: NaN clearance, a failed clause
        clr, codes = certificate(pw, full[0], full[-1], obs.shape[1], times=raw.path.times,
                                 via=via)
    out["clearance"][idx] = clr
    return codes == 0


def redecide(planner: Planner, flags: np.ndarray, obstacles, configs, lift, out: dict
             ) -> np.ndarray:
    """After a kernel: the certificate (B,) of a chunk whose kernel wrote ``out`` and ``flags``.

    ``FALLBACK`` rows are planned again whole by the numpy reference and certified
    (:func:`store_reference`); ``SUSPECT`` rows (a clearance near the certificate's threshold)
    get their clearance from :func:`pmplan.certify.clearance`, exact on the suspect pairs;
    ``NONFINITE``, ``BROKEN`` and ``INVALID`` rows fail (the kernel read every clause of the
    certificate back from its outputs).
    """
    kern = shared_kernels()
    clearance = out["clearance"]
    failed = kern.NONFINITE | kern.BROKEN | kern.INVALID
    ok = (flags & failed) == 0
    if not flags.any():
        return ok & (clearance > 0)
    sus = np.flatnonzero((flags & (kern.SUSPECT | kern.FALLBACK | failed)) == kern.SUSPECT)
    if sus.size:
        clearance[sus] = exact_clearance(out["waypoints"][sus], obstacles.shape[1])
    ok &= clearance > 0
    idx = np.flatnonzero(flags & kern.FALLBACK)
    if idx.size:
        obstacles = np.asarray(obstacles, dtype=float)
        configs = [np.asarray(c, dtype=float) for c in configs]
        ok[idx] = store_reference(planner, obstacles, configs, lift, idx, out)
    return ok
