"""One query: the lean path of :func:`pmplan.plan` and :func:`pmplan.plan_sequence`.

A single query is a batch of one: :func:`plan_one` and :func:`plan_one_sequence` check it and
run it through the run loop (:func:`pmplan.running.run_loop`) as a batch of one -- after first
trying a lean path for planners with a single-query kernel (one validating, certifying kernel
call, the backend's ``single_query``), which gives the same
:class:`~pmplan.results.Plan` and declines anything unusual.
"""

from __future__ import annotations

import math

import numpy as np

from . import backends as _backend
from . import magnitude
from .certify import check_times
from .checks import check_backend, check_lift, check_sequential, choose_planner
from .configuration import as_real, check_query, check_sequence, is_plain
from .errors import InputError
from .path import unchecked_path
from .planners.base import REGISTRY, SCENE_CODE, Planner, default_planner
from .results import Plan
from .running import plan_arrays, refine_plans, run_loop, single_plan

__all__ = ["plan_one", "plan_one_in_box", "plan_one_sequence"]


def plan_one(obstacles, start, goal, planner: str | None = None, lift=1.0,
             backend: str | None = None) -> Plan:
    """:func:`pmplan.plan` of an unrefined query: the lean path, else the general one."""
    if backend is None or type(backend) is str and backend in _backend.REGISTRY:
        fast = _plan_fast(obstacles, start, goal, planner, lift, backend)
        if fast is not None:
            return fast
    lift = check_lift(lift)
    obstacles, start, goal = check_query(obstacles, start, goal, batched=False)
    _, m, d = obstacles.shape
    n = start.shape[1]
    p = choose_planner(d, n, m, planner)
    check_backend(backend)
    out = run_loop(p, obstacles, [start, goal], lift, batched=False, backend=backend)
    return single_plan(p, (d, n, m), out)


def plan_one_in_box(obstacles, configs: list, bounds, planner: str | None = None, lift=1.0,
                    backend: str | None = None, sequential: bool = False,
                    radii: tuple[float, float] | None = None) -> Plan:
    """:func:`pmplan.plan` or :func:`pmplan.plan_sequence` in a workspace box (``bounds``,
    :mod:`pmplan.workspace`; None: in R^d) as a batch of one (the box's map runs on the
    batch), refined when ``radii`` = (radius, obstacle_radius) are given (with the default
    planner of a refined plan, :func:`~pmplan.checks.choose_planner`)."""
    if sequential:
        check_sequential(planner)  # (the planner first, as plan_arrays checks it)
        obstacles, configs = check_sequence(obstacles, configs, batched=False)
    else:
        obstacles, start, goal = check_query(obstacles, configs[0], configs[1], batched=False)
        configs = [start, goal]
    batch = plan_arrays(obstacles, configs, planner=planner, lift=lift, backend=backend,
                        sequential=sequential, bounds=bounds, batched=False,
                        refining=radii is not None)
    if radii is not None:
        return refine_plans(batch[0], radius=radii[0], obstacle_radius=radii[1],
                            backend=backend)
    return batch[0]


def plan_one_sequence(obstacles, configs, lift=1.0, backend: str | None = None,
                      planner: str | None = None) -> Plan:
    """:func:`pmplan.plan_sequence` of an unrefined query: the lean path, else the general
    one."""
    if backend is None or type(backend) is str and backend in _backend.REGISTRY:
        fast = _plan_sequence_fast(obstacles, configs, lift, backend, planner)
        if fast is not None:
            return fast
    lift = check_lift(lift)
    check_sequential(planner)  # (the planner first, as plan_arrays checks it)
    obstacles, configs = check_sequence(obstacles, configs, batched=False)
    _, m, d = obstacles.shape
    n = configs[0].shape[1]
    p = choose_planner(d, n, m, planner, sequential=True)
    check_backend(backend)
    out = run_loop(p, obstacles, configs, lift, batched=False, backend=backend)
    return single_plan(p, (d, n, m), out)


def _plan_fast(obstacles, start, goal, planner, lift, backend=None) -> Plan | None:
    """The lean path of :func:`plan` for planners whose backend has a single-query call (see
    :mod:`pmplan.backends`: ``single_query``).

    Returns None -- and :func:`plan` then takes the general path, which raises the proper error
    or re-decides exactly -- for anything but a plain valid query whose kernel result needs no
    exact re-decision. The kernel function, the planner's name, the dims and the stratum names
    are looked up once per (planner, backend, shapes) (:func:`_fast_entry`); inputs that already are C-contiguous float64 arrays are not copied
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
    key = (planner, backend, o.shape, s.shape, g.shape)
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
    return Plan(domain, stratum, clearance, unchecked_path(times, wp), p.name, dims)


def _fast_lift(lift) -> float | None:
    """``lift`` as the float :func:`check_lift` makes of it (the same rule), or None when it
    is invalid (the general path raises the error)."""
    try:
        return check_lift(lift)
    except InputError:
        return None


def _fast_array(a) -> np.ndarray | None:
    """``a`` itself if it already is a writeable C-contiguous float64 ndarray, else ``a`` as a
    new one (converted by :func:`pmplan.configuration.as_real`, the rule of
    :func:`~pmplan.configuration.as_points`), or None if it does not convert (the general path
    raises the error)."""
    if type(a) is np.ndarray and a.dtype is _F64 and a.flags.carray:
        return a
    if type(a) is list and is_plain(a):  # floats and ints a double holds: as_real's first case
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
    (planner name or None, backend name or None, obstacles shape, start shape, goal shape)``,
    or None if that shape never takes it; cached in :data:`_FAST`."""
    planner, backend, oshape, sshape, gshape = key
    entry = None
    if len(oshape) == 2 and len(sshape) == 2 and sshape == gshape and oshape[1] == sshape[1]:
        (m, d), n = oshape, sshape[0]
        if planner is None:
            planner = default_planner(d, n, m)
        p = REGISTRY.get(planner)
        if p is not None and p.supports(d, n, m) is None:
            run = _backend.select(backend).single_query(p, m, n, d)
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


def _plan_sequence_fast(obstacles, configs, lift, backend=None, planner=None) -> Plan | None:
    """The lean path of :func:`plan_sequence`: one validating kernel call (the backend's
    ``sequence_query``), as :func:`_plan_fast` for :func:`plan`.

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
    if planner is not None and (type(planner) is not str or planner not in REGISTRY):
        return None
    key = (len(cs), backend, o.shape, shape, planner)
    entry = _FAST_SEQUENCE.get(key, _UNSEEN)
    if entry is _UNSEEN:
        entry = _sequence_entry(key)
    if entry is None:
        return None
    run, p, dims, names = entry
    return _fast_answer(run(o, cs, lift), p, dims, names)


def _sequence_entry(key: tuple):
    """``(run, planner, dims, stratum names)`` of the sequential fast path for ``key = (r,
    backend name or None, obstacles shape, configuration shape, planner name or None)``, or
    None; cached in :data:`_FAST_SEQUENCE`."""
    r, backend, oshape, cshape, name = key
    entry = None
    if len(oshape) == 2 and len(cshape) == 2 and oshape[1] == cshape[1]:
        (m, d), n = oshape, cshape[0]
        p = REGISTRY[name or default_planner(d, n, m, sequential=True)]
        if p.sequential and p.supports(d, n, m) is None:
            run = _backend.select(backend).sequence_query(p, r, m, n, d)
            if run is not None and _times_certified(p, r):
                entry = (run, p, (d, n, m), {})
    if len(_FAST_SEQUENCE) < 1024:
        _FAST_SEQUENCE[key] = entry
    return entry
