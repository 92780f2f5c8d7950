"""The public facade: choose a planner, validate, plan in chunks, certify, return plans.

Data flows one way: input arrays -> validation (:mod:`pmplan.configuration`) -> the run loop
(:mod:`pmplan.running`) -> planner (:mod:`pmplan.planners`) -> path (:mod:`pmplan.path`) ->
certificate (:mod:`pmplan.certify`) -> :class:`~pmplan.results.Plan` /
:class:`~pmplan.results.PlanBatch` (:mod:`pmplan.results`, re-exported here). A single query
is a batch of one; :func:`plan` and
:func:`plan_sequence` first try a lean path (one validating kernel call, see
:func:`_plan_fast`) that gives the same :class:`Plan` and declines anything unusual.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from . import backend as _backend
from . import magnitude
from . import planners as _planners  # noqa: F401  (registers the planners)
from .certify import check_times
from .configuration import _plain, as_lift, as_points, as_real, check_query, check_same_obstacles
from .errors import InputError, PmplanError, ShapeError, UnsupportedError
from .path import PiecewiseLinearPath, _unchecked_path
from .planners.base import (REGISTRY, SCENE_CODE, Planner, default_planner, lift_code,
                            out_of_scope)
from .refine import (_MSG_PLAN, _MSG_REFINE_DASK, _MSG_REFINE_OUT, _MSG_REFINED, RefineStage,
                     check_parameters, check_radii)
from .refine import check_refine_flag
from .results import Plan, PlanBatch, PlannerInfo
from .running import CHUNK, _check_workers, _output_arrays, _Progress, _run, _single  # noqa: F401
from .running import run_stage

__all__ = [
    "Plan",
    "PlanBatch",
    "PlannerInfo",
    "plan",
    "plan_batch",
    "plan_configurations",
    "plan_sequence",
    "plan_sequence_batch",
    "plan_query",
    "refine",
    "info",
    "planner_names",
    "parametrised_tc",
    "choose_planner",
]

def planner_names() -> list[str]:
    """Return the documented planner names: ``obstacle_line`` and ``planar_three``."""
    return sorted(REGISTRY)


def choose_planner(d: int, n: int, m: int, planner: str | None = None) -> Planner:
    """Return the planner for (d, n, m): the named one, or the default.

    The default is ``planar_three`` (paper Section 4) for (d, n, m) = (2, 1, 3) and
    ``obstacle_line`` (paper Section 3 and Mathematics §4) for every other m >= 2.
    """
    if planner is None:
        planner = default_planner(d, n, m)
    if planner not in REGISTRY:
        raise UnsupportedError(
            f"unknown planner {planner!r}; choose one of {', '.join(planner_names())}"
        )
    p = REGISTRY[planner]
    why = p.supports(d, n, m)
    if why is not None:
        raise UnsupportedError(f"planner {planner!r} does not apply to (d, n, m) = ({d}, {n}, {m}): {why}")
    return p


def _check_lift(lift) -> float:
    """``lift`` checked (:func:`pmplan.configuration.as_lift`: a positive real number or
    ``"scene"``) as the float the planners take (:func:`pmplan.planners.base.lift_code`)."""
    return lift_code(as_lift(lift))


_check_backend = _backend.check


def plan_batch(
    obstacles, start, goal, *, planner: str | None = None, lift: float | str = 1.0,
    progress: bool = False, backend: str | None = None, workers: int = 1,
    out: PlanBatch | None = None, refine: bool = False, radius: float = 0.0,
    obstacle_radius: float = 0.0,
) -> PlanBatch:
    """Plan a batch of B queries at once (vectorised :func:`plan`).

    Parameters
    ----------
    obstacles : array_like, shape (B, m, d)
    start, goal : array_like, shape (B, n, d)
        Dask arrays (chunked along the batch axis only) are planned lazily by
        :func:`pmplan.scale.plan_batch`: the PlanBatch then holds dask arrays.
    planner : str, optional
        ``"obstacle_line"`` or ``"planar_three"``; default chosen from (d, n, m).
    lift : float or "scene"
        The unit of the motion; default 1, the paper's (the height scale of the lift in the
        obstacle-line planner, the 1 of ``H`` and ``s3`` in the planar one). ``"scene"``: the
        obstacles' radius ``u(O) = max_k |o_k - o_1|`` of each query, for scenes far from
        unit size (millimetres, kilometres) and for equivariance (a scaled, translated or
        rotated query gets the scaled, translated or rotated plan). A bool or a string other
        than ``"scene"`` is refused.
    progress : bool
        Show a progress bar (tqdm, on stderr) when the batch takes more than a few chunks, and
        say so when numba compiles the kernels (the first run only: they are cached on disk);
        the bar's estimate starts after that. Without it nothing is written.
    backend : {"numba", "numpy"}, optional
        Implementation of the obstacle-line and planar_three planners: the fused numba kernels
        (default when numba is installed) or the numpy references; both give identical plans.
    workers : int
        Threads that plan chunks of the batch in parallel (-1: one per CPU). The result does not
        depend on it. Only the fused planners (obstacle-line, planar_three) use threads.
    out : PlanBatch, optional
        A batch returned by an earlier call with the same planner, (d, n, m) and B: its arrays
        are overwritten with this batch's answers and ``out`` itself is returned, so that
        planning batch after batch allocates nothing (as ``np.copyto`` writes into an existing
        array). If the call raises, the contents of ``out`` are unspecified.

    Returns
    -------
    PlanBatch
        ``domain`` (B,), ``clearance`` (B,), ``waypoints`` (B, K, m+n, d), ``times``.

    Raises
    ------
    InputError
        (a ValueError) for malformed input: see :mod:`pmplan.errors`.
    CertificationError
        If a path fails a clause of its certificate (:data:`pmplan.certify.CLAUSES`, named in
        the message): e.g. it would not be collision-free in double precision, or it is not
        representable at the query's magnitude (the message says what to do).

    Notes
    -----
    Every returned path passes the whole certificate of :mod:`pmplan.certify` (finite times
    from 0 to 1 that never decrease; finite waypoints from exactly the start to exactly the
    goal; obstacles fixed; clearance > 0). Any finite input, from 5e-324 to 1.8e308, gets a
    certified path or a pmplan error: queries beyond ``2**430`` (or, with ``lift``, below
    ``2**-430``) are planned scaled by a power of two, which is exact, and scaled back
    (:mod:`pmplan.magnitude`); ordinary queries are not touched. ``B = 0`` is a valid empty
    batch.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> batch = plan_batch(rng.normal(size=(5, 2, 2)), rng.normal(size=(5, 3, 2)),
    ...                    rng.normal(size=(5, 3, 2)))
    >>> batch.domain.shape, batch.waypoints.shape, batch.times.shape
    ((5,), (5, 8, 5, 2), (8,))
    """
    refining = _asks_refine(refine, radius, obstacle_radius, out)
    if _is_dask(obstacles, start, goal):  # lazy plans of dask arrays (the optional extra)
        from . import scale

        return scale.plan_batch(obstacles, start, goal, planner=planner, lift=lift,
                                progress=progress, backend=backend, workers=workers, out=out,
                                refine=_radii(refining, radius, obstacle_radius))
    if refining:
        raw = plan_batch(obstacles, start, goal, planner=planner, lift=lift, progress=progress,
                         backend=backend, workers=workers)
        return refine_plans(raw, radius=radius, obstacle_radius=obstacle_radius,
                            progress=progress, workers=workers, backend=backend)
    lift = _check_lift(lift)
    workers = _check_workers(workers)
    # types and shapes here; the validity of every query (finite, no two equal points) is
    # checked by the planner's kernel in its own pass where it can, else here
    obstacles, start, goal = check_query(obstacles, start, goal, batched=True, deep=False)
    _, m, d = obstacles.shape
    n = start.shape[1]
    try:
        p = choose_planner(d, n, m, planner)
        _check_backend(backend)
    except PmplanError:  # an invalid query is reported first, as always
        check_query(obstacles, start, goal, batched=True)
        raise
    deferred = p.validates(d, backend)
    if not deferred:
        check_query(obstacles, start, goal, batched=True)
    into = _output_arrays(out, p, (d, n, m), obstacles.shape[0], 2, (obstacles, start, goal))
    res = _run(p, obstacles, [start, goal], lift, batched=True,
               progress=progress, backend=backend, workers=workers, validate=deferred, into=into)
    return out if out is not None else PlanBatch(planner=p.name, dims=(d, n, m), **res)


def _is_dask(*arrays) -> bool:
    """Whether any argument is a dask array (then :mod:`pmplan.scale` plans it lazily); dask
    is never imported here: an array of it exists only if the caller imported it."""
    da = sys.modules.get("dask.array")
    return da is not None and any(isinstance(a, da.Array) for a in arrays)


def plan(obstacles, start, goal, *, planner: str | None = None, lift: float | str = 1.0,
         backend: str | None = None, refine: bool = False, radius: float = 0.0,
         obstacle_radius: float = 0.0) -> Plan:
    """Plan one query: a certified collision-free motion from ``start`` to ``goal``.

    Parameters
    ----------
    obstacles : array_like, shape (m, d)
        The obstacles o_1..o_m (m >= 2); they stay fixed.
    start, goal : array_like, shape (n, d)
        Robot positions x_1..x_n and x'_1..x'_n.
    planner : str, optional
        ``"obstacle_line"`` or ``"planar_three"``; default chosen from (d, n, m).
    lift : float or "scene"
        The unit of the motion (default 1, the paper's; ``"scene"``: each query's obstacles'
        radius): see :func:`plan_batch`.
    backend : {"numba", "numpy"}, optional
        See :func:`plan_batch`.

    Returns
    -------
    Plan
        ``domain``, ``stratum``, ``clearance`` and ``path`` (waypoints (K, m+n, d)).

    Raises
    ------
    InputError, CertificationError
        As :func:`plan_batch` (whose Notes describe the certificate and extreme magnitudes).

    Examples
    --------
    A robot in the column of o1 (exact degeneracy: cp(C) = 2) going to a generic goal:

    >>> p = plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    >>> p.domain, p.stratum, p.path.waypoints.shape
    (5, 'T_{2,3}', (8, 3, 2))
    >>> p.path(0.0)[2], p.path(1.0)[2]
    (array([0., 1.]), array([ 1., -1.]))
    """
    if _asks_refine(refine, radius, obstacle_radius):
        raw = plan(obstacles, start, goal, planner=planner, lift=lift, backend=backend)
        return refine_plans(raw, radius=radius, obstacle_radius=obstacle_radius,
                            backend=backend)
    if _backend.uses_kernels(backend):
        fast = _plan_fast(obstacles, start, goal, planner, lift)
        if fast is not None:
            return fast
    lift = _check_lift(lift)
    obstacles, start, goal = check_query(obstacles, start, goal, batched=False)
    _, m, d = obstacles.shape
    n = start.shape[1]
    p = choose_planner(d, n, m, planner)
    _check_backend(backend)
    out = _run(p, obstacles, [start, goal], lift, batched=False,
               backend=backend)
    return _single(p, (d, n, m), out)


def _plan_fast(obstacles, start, goal, planner, lift) -> Plan | None:
    """The lean path of :func:`plan` for planners with a single-query kernel (one call, see
    :meth:`pmplan.planners.base.Planner.single_query`).

    Returns None -- and :func:`plan` then takes the general path, which raises the proper error
    or re-decides exactly -- for anything but a plain valid query whose kernel result needs no
    exact re-decision. The kernel function, the planner's name, the dims and the stratum names
    are looked up once per (planner, shapes) (:func:`_fast_entry`); inputs that already are C-contiguous float64 arrays are not copied
    (:func:`_fast_array`); the :class:`Plan` and its path are built without re-checking arrays
    the kernel wrote.
    """
    if type(lift) is not float or not 0.0 < lift < math.inf:  # (False for NaN)
        lift = _fast_lift(lift)
        if lift is None:
            return None
    if lift != SCENE_CODE and not _LIFT_LOW <= lift < _LIFT_HIGH:  # extreme: the general path
        return None
    o = _fast_array(obstacles)
    s = _fast_array(start)
    g = _fast_array(goal)
    if o is None or s is None or g is None or (planner is not None and type(planner) is not str):
        return None
    key = (planner, o.shape, s.shape, g.shape)
    entry = _FAST.get(key, _UNSEEN)
    if entry is _UNSEEN:
        entry = _fast_entry(key)
    if entry is None:
        return None
    run, p, dims, names = entry
    return _fast_answer(run(o, s, g, lift), p, dims, names)


def _fast_answer(res, p: Planner, dims: tuple[int, int, int], names: dict) -> Plan | None:
    """The :class:`Plan` of a fast-path kernel result ``(times, waypoints, domain, row,
    clearance)``, or None when the kernel declined (``res`` is None).

    The kernel certified the path: every clause of :data:`pmplan.certify.CLAUSES`, read back
    from its outputs (a failing one is flagged, and the kernel declines); the obstacle-line
    breakpoints are the constant :func:`~pmplan.planners.obstacle_line.path_times`, checked
    once (:func:`_fast_entry`)."""
    if res is None:
        return None
    times, wp, domain, row, clearance = res
    stratum = names.get(row)
    if stratum is None:
        stratum = _stratum_name(p, row, dims, names)
    return Plan(domain, stratum, clearance, _unchecked_path(times, wp), p.name, dims)


def _fast_lift(lift) -> float | None:
    """``lift`` as the float :func:`_check_lift` makes of it (the same rule), or None when it
    is invalid (the general path raises the error)."""
    try:
        return _check_lift(lift)
    except InputError:
        return None


def _fast_array(a) -> np.ndarray | None:
    """``a`` itself if it already is a writeable C-contiguous float64 ndarray, else ``a`` as a
    new one (converted by :func:`pmplan.configuration.as_real`, the rule of
    :func:`~pmplan.configuration.as_points`), or None if it does not convert (the general path
    raises the error)."""
    if type(a) is np.ndarray and a.dtype is _F64 and a.flags.carray:
        return a
    if type(a) is list and _plain(a):  # floats and ints a double holds: as_real's first case
        try:
            return np.array(a, dtype=np.float64)
        except ValueError:
            return None
    try:
        a = as_real(a, "array")
    except InputError:
        return None
    return a if a.flags.carray else np.array(a, order="C")


def _fast_entry(key: tuple):
    """``(run, planner, dims, stratum names)`` of the single-query fast path for ``key =
    (planner name or None, obstacles shape, start shape, goal shape)``, or None if that shape
    never takes it; cached in :data:`_FAST`."""
    planner, oshape, sshape, gshape = key
    entry = None
    if len(oshape) == 2 and len(sshape) == 2 and sshape == gshape and oshape[1] == sshape[1]:
        (m, d), n = oshape, sshape[0]
        if planner is None:
            planner = default_planner(d, n, m)
        p = REGISTRY.get(planner)
        if p is not None and p.supports(d, n, m) is None:
            run = p.single_query(m, n, d)
            if run is not None and _times_certified(p, 2):
                entry = (run, p, (d, n, m), {})
    if len(_FAST) < 1024:
        _FAST[key] = entry
    return entry


def _times_certified(p: Planner, r: int) -> bool:
    """Whether the planner's shared breakpoints for r configurations (if it has them) pass
    clauses 1-4 of the certificate -- checked once per fast-path entry, not per call. A
    planner with per-query breakpoints checks them in its kernel (flag ``BROKEN``)."""
    times = p.path_times(r)
    return times is None or check_times(times) == 0


def _stratum_name(p: Planner, row: tuple, dims: tuple[int, int, int], names: dict) -> str:
    """``p.stratum_name(row, d, n, m)``, remembered in ``names`` (by row)."""
    d, n, m = dims
    name = p.stratum_name(row, d, n, m)
    if len(names) < 4096:
        names[row] = name
    return name


_F64 = np.dtype(np.float64)
#: the single-query fast paths plan only lifts in this range (and, as the kernels check,
#: coordinates below 2**LIMIT): the other queries may need scaling (:mod:`pmplan.magnitude`)
_LIFT_LOW = 2.0**-magnitude.LIMIT
_LIFT_HIGH = 2.0**magnitude.LIMIT
_UNSEEN = object()
#: the single-query fast paths by (planner, shapes) (see :func:`_fast_entry`); None: never
_FAST: dict = {}
#: the sequential fast path by (r, obstacles shape, configuration shape) (see
#: :func:`_sequence_entry`); None: never
_FAST_SEQUENCE: dict = {}


def plan_configurations(c_start, c_goal, m: int = 2, **kwargs) -> Plan:
    """Plan between two full configurations (m+n, d) whose first m rows are the obstacles.

    Raises :class:`~pmplan.errors.ObstacleMismatchError` if the obstacles differ.
    """
    if isinstance(m, (bool, np.bool_)) or not isinstance(m, (int, np.integer)):
        raise InputError(f"`m` (the number of obstacles) must be an int, got {type(m).__name__} "
                         f"{m!r}")
    c_start = as_points(c_start, "start configuration", False)
    c_goal = as_points(c_goal, "goal configuration", False)
    if c_start.shape != c_goal.shape:
        raise ShapeError(
            f"Expected both configurations to have the same shape, got {c_start.shape} and "
            f"{c_goal.shape}."
        )
    if m < 2:
        raise UnsupportedError(out_of_scope(2, 1, m))
    if m >= c_start.shape[0]:
        raise ShapeError(f"m = {m} obstacles leave no robot in a configuration of {c_start.shape[0]} points")
    check_same_obstacles(c_start, c_goal, m, batched=False)
    return plan(c_start[:m], c_start[m:], c_goal[m:], **kwargs)


def _check_sequence(obstacles, configs, batched: bool):
    try:
        if isinstance(configs, (str, bytes)):
            raise TypeError
        configs = list(configs)
    except TypeError:
        raise InputError(f"`configs` must be a list of r >= 2 arrays of real numbers, got "
                         f"{type(configs).__name__}") from None
    configs = [as_real(c, f"configs[{k}]") for k, c in enumerate(configs)]
    if len(configs) < 2:
        raise ShapeError(f"Expected at least r = 2 configurations, got {len(configs)}.")
    r = len(configs)
    obstacles_b, first, _ = check_query(
        obstacles, configs[0], configs[-1], batched=batched,
        names=("configuration 1 (start)", f"configuration {r} (goal)"),
    )
    out = [first]
    for k, c in enumerate(configs[1:], start=2):
        _, ck, _ = check_query(obstacles, c, c, batched=batched,
                               names=(f"configuration {k}", f"configuration {k}"))
        if ck.shape != first.shape:
            raise ShapeError(f"configuration {k} has shape {ck.shape[1:]}, expected {first.shape[1:]}")
        out.append(ck)
    return obstacles_b, out


def plan_sequence_batch(obstacles, configs, *, lift: float | str = 1.0,
                        backend: str | None = None, progress: bool = False,
                        workers: int = 1, out: PlanBatch | None = None, refine: bool = False,
                        radius: float = 0.0, obstacle_radius: float = 0.0) -> PlanBatch:
    """Plan batches of motions through r >= 2 configurations (Mathematics §4.3).

    ``obstacles`` (B, m, d); ``configs`` a list of r arrays (B, n, d). The path passes through
    configuration k at tau = (k-1)/(r-1); labels sum_k cp(C_k) - (r-1) cp_o + 2 (- 1 when
    e == N in odd d). ``lift``, ``backend``, ``progress``, ``workers``, ``out``: see
    :func:`plan_batch`.
    """
    refining = _asks_refine(refine, radius, obstacle_radius, out)
    if isinstance(configs, (list, tuple)) and _is_dask(obstacles, *configs):
        from . import scale

        return scale.plan_sequence_batch(obstacles, configs, lift=lift, progress=progress,
                                         backend=backend, workers=workers, out=out,
                                         refine=_radii(refining, radius, obstacle_radius))
    if refining:
        raw = plan_sequence_batch(obstacles, configs, lift=lift, backend=backend,
                                  progress=progress, workers=workers)
        return refine_plans(raw, radius=radius, obstacle_radius=obstacle_radius,
                            progress=progress, workers=workers, backend=backend)
    lift = _check_lift(lift)
    workers = _check_workers(workers)
    obstacles, configs = _check_sequence(obstacles, configs, batched=True)
    _, m, d = obstacles.shape
    n = configs[0].shape[1]
    p = choose_planner(d, n, m, default_planner(d, n, m, sequential=True))
    _check_backend(backend)
    into = _output_arrays(out, p, (d, n, m), obstacles.shape[0], len(configs),
                          (obstacles, *configs))
    res = _run(p, obstacles, configs, lift, batched=True, progress=progress,
               backend=backend, workers=workers, into=into)
    return out if out is not None else PlanBatch(planner=p.name, dims=(d, n, m), **res)


def plan_sequence(obstacles, configs, *, lift: float | str = 1.0,
                  backend: str | None = None, refine: bool = False, radius: float = 0.0,
                  obstacle_radius: float = 0.0) -> Plan:
    """Plan one motion through r >= 2 robot configurations with the same obstacles (Mathematics §4.3).

    Parameters
    ----------
    obstacles : array_like, shape (m, d)
    configs : sequence of r array_like, each (n, d)
    lift : float or "scene"
        The unit of the motion (default 1, the paper's; ``"scene"``: each query's obstacles'
        radius): see :func:`plan_batch`.
    backend : {"numba", "numpy"}, optional
        See :func:`plan_batch`.

    Examples
    --------
    >>> p = plan_sequence([[0, 0], [2, 0]], [[[0, 1]], [[1, -1]], [[3, 3]]])
    >>> p.domain, p.path.waypoints.shape
    (6, (15, 3, 2))
    >>> p.path(0.5)[2]
    array([ 1., -1.])
    """
    if _asks_refine(refine, radius, obstacle_radius):
        raw = plan_sequence(obstacles, configs, lift=lift, backend=backend)
        return refine_plans(raw, radius=radius, obstacle_radius=obstacle_radius,
                            backend=backend)
    if _backend.uses_kernels(backend):
        fast = _plan_sequence_fast(obstacles, configs, lift)
        if fast is not None:
            return fast
    lift = _check_lift(lift)
    obstacles, configs = _check_sequence(obstacles, configs, batched=False)
    _, m, d = obstacles.shape
    n = configs[0].shape[1]
    p = choose_planner(d, n, m, default_planner(d, n, m, sequential=True))
    _check_backend(backend)
    out = _run(p, obstacles, configs, lift, batched=False, backend=backend)
    return _single(p, (d, n, m), out)


def _plan_sequence_fast(obstacles, configs, lift) -> Plan | None:
    """The lean path of :func:`plan_sequence`: one validating kernel call
    (:meth:`pmplan.planners.base.Planner.sequence_query`), as :func:`_plan_fast` for :func:`plan`.

    Returns None -- and :func:`plan_sequence` then takes the general path, which raises the
    proper error or re-decides exactly -- for anything but a plain valid query (a list, tuple or
    array of r >= 2 configurations of one shape (n, d), obstacles (m, d), d <= MAX_D) whose
    kernel result needs no exact re-decision.
    """
    if type(lift) is not float or not 0.0 < lift < math.inf:  # (False for NaN)
        lift = _fast_lift(lift)
        if lift is None:
            return None
    if lift != SCENE_CODE and not _LIFT_LOW <= lift < _LIFT_HIGH or not (
        type(configs) in (list, tuple) or type(configs) is np.ndarray and configs.ndim == 3
    ):
        return None
    o = _fast_array(obstacles)
    if o is None or len(configs) < 2:
        return None
    cs = [_fast_array(c) for c in configs]
    shape = None if cs[0] is None else cs[0].shape
    for c in cs:
        if c is None or c.shape != shape:
            return None
    key = (len(cs), o.shape, shape)
    entry = _FAST_SEQUENCE.get(key, _UNSEEN)
    if entry is _UNSEEN:
        entry = _sequence_entry(key)
    if entry is None:
        return None
    run, p, dims, names = entry
    return _fast_answer(run(o, cs, lift), p, dims, names)


def _sequence_entry(key: tuple):
    """``(run, planner, dims, stratum names)`` of the sequential fast path for ``key = (r,
    obstacles shape, configuration shape)``, or None; cached in :data:`_FAST_SEQUENCE`."""
    r, oshape, cshape = key
    entry = None
    if len(oshape) == 2 and len(cshape) == 2 and oshape[1] == cshape[1]:
        (m, d), n = oshape, cshape[0]
        p = REGISTRY[default_planner(d, n, m, sequential=True)]
        if p.supports(d, n, m) is None:
            run = p.sequence_query(r, m, n, d)
            if run is not None and _times_certified(p, r):
                entry = (run, p, (d, n, m), {})
    if len(_FAST_SEQUENCE) < 1024:
        _FAST_SEQUENCE[key] = entry
    return entry


def _check_sequential(planner: str | None) -> None:
    """Raise :class:`~pmplan.errors.UnsupportedError` if the named planner does not plan
    through intermediate configurations (a query with ``via``)."""
    if planner is not None and not (planner in REGISTRY and REGISTRY[planner].sequential):
        names = [p.name for p in REGISTRY.values() if p.sequential]
        raise UnsupportedError(f"a query with 'via' is planned by the {' or '.join(names)} "
                               "planner")


def parametrised_tc(d: int, n: int, m: int, r: int = 2) -> int:
    """Return the (unreduced, sequential) parametrised topological complexity.

    ``2n+m-1`` (d even) / ``2n+m`` (d odd) for r = 2 (paper Theorem 2.6,
    Cohen-Farber-Weinberger); ``rn+m-1`` / ``rn+m`` for r >= 2 (Farber-Paul, unreduced).
    """
    return r * n + m - 1 if d % 2 == 0 else r * n + m


def info(d: int, n: int, m: int, r: int = 2, planner: str | None = None) -> PlannerInfo:
    """Which planner applies to (d, n, m, r), how many domains it has, and whether it is optimal.

    Examples
    --------
    >>> i = info(2, 3, 2)
    >>> i.planner, i.domains, i.tc, i.optimal
    ('obstacle_line', 7, 7, True)
    >>> info(3, 1, 1).message
    'no planner covers m = 1: the planners need m >= 2 obstacles (they define the line L_C)'
    """
    why = out_of_scope(d, n, m, r)
    if why is not None:
        return PlannerInfo(d, n, m, r, None, None, (), None, False, f"no planner covers {why}")
    tc = parametrised_tc(d, n, m, r)
    if r > 2:
        name = default_planner(d, n, m, sequential=True)
        if planner not in (None, name):
            raise UnsupportedError(f"sequential planning (r > 2) uses the {name} planner")
        p = REGISTRY[name]
        labels = tuple(p.domain_labels(d, n, m, r))
        msg = f"sequential planner (Mathematics §4.3) on the {name} planner"
    else:
        p = choose_planner(d, n, m, planner)
        labels = tuple(p.domain_labels(d, n, m))
        msg = p.summary
    k = len(labels)
    return PlannerInfo(d, n, m, r, p.name, k, labels, tc, k == tc, msg)


def plan_query(query: dict, planner: str | None = None) -> Plan:
    """Plan a query given as a dict (the form :func:`pmplan.io.read_query` returns).

    Keys ``obstacles``, ``start``, ``goal`` and optional ``via`` (intermediate configurations:
    then :func:`plan_sequence`), ``lift`` and ``planner`` (overridden by ``planner``).

    Examples
    --------
    >>> plan_query({"obstacles": [[0, 0], [2, 0]], "start": [[0, 1]], "goal": [[1, -1]],
    ...             "via": [[[3, 3]]]}).stratum
    'T_{2,3,3}'
    """
    planner = planner or query.get("planner")
    lift = query.get("lift", 1.0)
    if "via" in query:
        _check_sequential(planner)
        configs = [query["start"], *query["via"], query["goal"]]
        return plan_sequence(query["obstacles"], configs, lift=lift)
    return plan(query["obstacles"], query["start"], query["goal"], planner=planner, lift=lift)


def refine(plan_or_batch: Plan | PlanBatch, *, radius: float = 0.0, obstacle_radius: float = 0.0,
           waypoints: int | None = None, steps: int | None = None, workers: int = 1,
           progress: bool | None = None, backend: str | None = None) -> Plan | PlanBatch:
    """Refine a plan (or a batch): a shorter motion that keeps the radii, still certified,
    continuous on the same domains (so still optimal). See :mod:`pmplan.refine`.

    Parameters
    ----------
    plan_or_batch : Plan or PlanBatch
        Unrefined plans returned by :func:`plan`, :func:`plan_batch`, :func:`plan_sequence` or
        :func:`plan_sequence_batch`.
    radius : float
        The robots' radius: the refinement aims at keeping any two robots ``2 radius`` apart
        and every robot ``radius + obstacle_radius`` off every obstacle. Default 0: it keeps
        half the raw plan's clearance instead (:data:`pmplan.refine.KAPPA`).
    obstacle_radius : float
        The obstacles' radius.
    waypoints : int, optional
        Sub-pieces per piece of the raw path at the finest level, a power of two (default
        :data:`pmplan.refine.DEFAULT_WAYPOINTS` = 2: 14 pieces per leg of the obstacle-line
        planner). The refined path has ``(K - 1) waypoints + 1`` breakpoints.
    steps : int, optional
        Refinement steps (default :data:`pmplan.refine.DEFAULT_STEPS` = 56), split over the
        coarse-to-fine levels 1, 2, 4, .., ``waypoints``. The defaults were chosen from the
        length / time measurements of ``benchmarks/refine_bench.py``.
    workers : int
        Threads refining separate chunks (-1: one per CPU); the result does not depend on it.
    progress : bool, optional
        Show a progress bar for large batches (as :func:`plan_batch`).
    backend : {"numba", "numpy"}, optional
        The kernel (default) or the numpy reference; both give identical paths.

    Returns
    -------
    Plan or PlanBatch
        The same type as given, with the same domains and strata; ``refined`` True,
        ``radius``, ``obstacle_radius``, ``robot_distance``, ``obstacle_distance`` (exact
        minima along the refined path) and ``respects_radius`` (decided exactly: never True
        when the radii are not kept).

    Raises
    ------
    InputError
        For a bad parameter, an already refined plan, or a start, goal or intermediate
        configuration that violates the radii (:class:`~pmplan.errors.CollisionError` naming
        the two points).
    CertificationError
        If a refined path fails its certificate (nothing is returned).

    Examples
    --------
    >>> p = plan([[0.35, 0.5], [0.65, 0.5]], [[0.1, 0.5]], [[0.9, 0.5]])
    >>> q = refine(p, radius=0.025, obstacle_radius=0.025)
    >>> q.domain == p.domain, q.stratum == p.stratum, q.refined, q.respects_radius
    (True, True, True, True)
    >>> bool(q.path.length() < p.path.length())
    True
    """
    radius, obstacle_radius, s, steps = check_parameters(radius, obstacle_radius, waypoints,
                                                         steps)
    workers = _check_workers(workers)
    if progress is None:
        progress = False
    if not isinstance(progress, (bool, np.bool_)):
        raise InputError(f"`progress` must be True, False or None, got {progress!r}")
    _check_backend(backend)
    single = isinstance(plan_or_batch, Plan)
    if single:
        batch = plan_or_batch
        times = batch.path.times
        wp = batch.path.waypoints[None]
        clearance = np.array([batch.clearance])
        refined = batch.refined
    elif isinstance(plan_or_batch, PlanBatch):
        batch = plan_or_batch
        times, wp, clearance = batch.times, batch.waypoints, batch.clearance
        if _is_dask(wp):
            raise InputError(_MSG_REFINE_DASK)
        refined = bool(batch.refined.any())
    else:
        raise InputError(_MSG_PLAN.format(value=type(plan_or_batch).__name__))
    if refined:
        raise InputError(_MSG_REFINED.format(radius=f"{float(np.max(batch.radius)):g}"))
    p = REGISTRY[batch.planner]
    m = batch.dims[2]
    fixed = p.fixed_waypoints(np.asarray(times))  # start, intermediate configurations, goal
    stage = RefineStage(times, wp, clearance, m, fixed, radius, obstacle_radius, s, steps, backend)
    check_radii(wp[:, 0, :m], [wp[:, kj, m:] for kj in fixed], radius, obstacle_radius,
                batched=not single, kernel=stage.kernel)
    run_stage(stage, progress=progress, workers=workers)
    extra = stage.extra()
    if single:
        path = PiecewiseLinearPath(stage.times, stage.waypoints[0])
        return Plan(batch.domain, batch.stratum, float(stage.clearance[0]), path.compact(),
                    batch.planner, batch.dims, **{k: v[0].item() for k, v in extra.items()})
    return PlanBatch(domain=batch.domain.copy(), strata=batch.strata.copy(),
                     clearance=stage.clearance, times=stage.times, waypoints=stage.waypoints,
                     planner=batch.planner, dims=batch.dims, _names=batch._names, _extra=extra)


#: :func:`refine` under a name the planning functions' ``refine=`` flag does not hide
refine_plans = refine


def _asks_refine(refine, radius, obstacle_radius, out=None) -> bool:
    """Whether a planning function was asked ``refine=True`` (the flag and the radii checked:
    :func:`pmplan.refine.check_refine_flag`; radii without the flag are refused, and so is
    ``out=`` with it: a refined batch has other shapes)."""
    if refine is False and type(radius) is float and type(obstacle_radius) is float \
            and radius == 0.0 and obstacle_radius == 0.0:
        return False
    if check_refine_flag(refine, radius, obstacle_radius):
        check_parameters(radius, obstacle_radius, None, None)
        if out is not None:
            raise InputError(_MSG_REFINE_OUT)
        return True
    return False


def _radii(refining: bool, radius, obstacle_radius) -> dict | None:
    """The refinement options handed to :mod:`pmplan.scale` (None: raw plans)."""
    return {"radius": radius, "obstacle_radius": obstacle_radius} if refining else None
