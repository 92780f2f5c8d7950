"""The numba backend: the fused kernels of :mod:`pmplan.kernels`, bitwise equal to the
references, and what each planner needs to call them. The functions of :mod:`pmplan.backends`.

Every kernel plans a chunk into the output arrays and flags the queries it cannot decide in
floating point (:mod:`pmplan.kernels.common`: ``FALLBACK``, ``SUSPECT``, ``NONFINITE``,
``BROKEN``, ``INVALID``); :func:`redecide` re-decides the flagged rows exactly with the numpy
backend's reference and gives every row its certificate (the kernel read every clause of it
back from its outputs). A planner without a kernel here (or a shape a kernel does not take) is
planned by the reference.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..certify import CLEARANCE, check_paths
from ..certify import clearance as exact_clearance
from ..planar_strata import EVEN
from ..planners.obstacle_line import (
    OBSTACLE_LINE,
    OBSTACLE_LINE_COMPACT,
    OBSTACLE_LINE_ONESIDE,
    OBSTACLE_LINE_ROBOTS,
    OBSTACLE_LINE_SHARED,
    OBSTACLE_LINE_WALLS,
    path_times,
)
from ..planners.planar_three import PLANAR_THREE
from . import kernel_array, kernels, planar_kernels, shared_kernels
from . import numpy as reference

__all__ = ["NAME", "arrays", "available", "certify", "from_box_linear", "into_box", "measure",
           "path_into_box_linear", "plan", "redecide", "refine", "sequence_query",
           "single_query", "validates"]

NAME = "numba"


def certify(waypoints, start, goal, m: int, *, times=None, via=()):
    """The certificate of paths, ``(clearance, codes)`` (:func:`pmplan.certify.certificate`'s
    contract, bit for bit): clauses 1-9 by :func:`pmplan.certify.check_paths`, the clearance
    (clause 10) by the kernel's measure in the certificate's arithmetic (:func:`measure`),
    the rows it flags re-decided by :func:`pmplan.certify.clearance`, exactly; the reference's
    where the kernel does not measure. The kernels certify inside :func:`plan`; this is the
    certificate of paths made apart (a workspace box's, :mod:`pmplan.workspace`)."""
    wp = np.asarray(waypoints, dtype=float)
    measured = measure(np.ascontiguousarray(wp), m, (0.0, 0.0)) if wp.shape[0] else None
    if measured is None:
        return reference.certify(wp, start, goal, m, times=times, via=via)
    if times is None:
        times = np.linspace(0.0, 1.0, wp.shape[1])
    clause = check_paths(times, wp, start, goal, m, via)
    values, _, close = measured
    clr = np.array(values[:, 0])
    redo = np.flatnonzero(close)
    if redo.size:
        clr[redo] = exact_clearance(wp[redo], m)
    clause[(clause == 0) & ~(clr > 0)] = CLEARANCE
    return clr, clause


def available() -> bool:
    """Whether numba is installed."""
    return shared_kernels().AVAILABLE


# ----------------------------------------------------------------------------------------------
# the obstacle-line planner (paper Section 3 and its extensions): pmplan.kernels.obstacle_line

_TIMES2 = path_times(2)  # the breakpoints of every two-configuration path (read-only)


def _obstacle_line_arrays(obstacles, configs):
    return kernel_array(obstacles), [kernel_array(c) for c in configs]


def _obstacle_line_kernel(obstacles, configs, lift: float, out: dict,
                          validate: bool, compact: bool = False,
                          shared: int = 0) -> np.ndarray | None:
    """Plan a chunk with :func:`pmplan.kernels.obstacle_line.plan_chunk` into ``out``; return
    its flags.

    None for d > MAX_D: the kernel reproduces numpy's summation order for d <= MAX_D only,
    and the reference plans the chunk. With ``validate`` the kernel also checks every query
    (finite, no two equal points): an invalid one gets the flag ``INVALID``.
    """
    kern = kernels()
    obstacles = kernel_array(obstacles)
    configs = [kernel_array(c) for c in configs]
    b, m, d = obstacles.shape
    if d > kern.MAX_D:
        return None
    r = len(configs)
    n = configs[0].shape[1]
    middle = np.stack(configs[1:-1]) if r > 2 else np.empty((0, b, n, d))
    flags = np.empty(b, np.uint8)
    kern.plan_chunk(obstacles, configs[0], configs[-1], middle, lift, validate,
                    out["waypoints"], out["domain"], out["strata"], out["clearance"], flags,
                    kern.tables(r, m, n, d), compact, shared)
    return flags


def _obstacle_line_validates(d: int) -> bool:
    """With the kernel, for d <= MAX_D."""
    return d <= kernels().MAX_D


def _obstacle_line_single(m: int, n: int, d: int, compact: bool = False,
                          shared: int = 0):
    """``run(obstacles, start, goal, lift) -> (times, waypoints, domain, row, clearance) |
    None`` -- the caller guarantees C-contiguous, aligned, writeable float64 arrays of shapes
    (m, d), (n, d), (n, d) and a float ``lift`` (positive, or
    :data:`~pmplan.planners.base.SCENE_CODE` for ``"scene"``) -- or None when no kernel plans
    that shape (numba missing, d > MAX_D, m < 2, n < 1). The index tables are looked up once
    here, not per query."""
    kern = kernels()
    if not kern.AVAILABLE or not 2 <= d <= kern.MAX_D or m < 2 or n < 1:
        return None
    tab = kern.tables(2, m, n, d)
    kernel = kern.plan_one
    times = _TIMES2

    def run(obstacles, start, goal, lift):
        wp, domain, cp1, cp2, cp_o, pole, clr, flags = kernel(obstacles, start, goal, lift,
                                                              tab, compact, shared)
        if flags or not clr > 0:
            return None
        return times.copy(), wp, domain, (cp1, cp2, cp_o, pole), clr

    return run


def _obstacle_line_sequence(r: int, m: int, n: int, d: int, compact: bool = False,
                            shared: int = 0):
    """``run(obstacles, configs, lift) -> (times, waypoints, domain, row, clearance) | None``
    for one query through ``r >= 2`` configurations -- the caller guarantees C-contiguous,
    aligned, writeable float64 arrays ``obstacles`` (m, d) and ``configs`` (a sequence of r
    arrays (n, d)), and a float ``lift`` -- or None when no kernel plans that shape (numba
    missing, d > MAX_D, m < 2, n < 1, r < 2). ``run`` returns None whenever the kernel
    (:func:`pmplan.kernels.obstacle_line.plan_queries`, asked to validate, with the index tables
    looked up once here) flags the query or the clearance is not positive: the general path
    then raises the proper error or re-decides exactly. The breakpoints are
    :func:`~pmplan.planners.obstacle_line.path_times` ``(r)`` (strictly increasing, so the path
    is already compact)."""
    kern = kernels()
    if not kern.AVAILABLE or not 2 <= d <= kern.MAX_D or m < 2 or n < 1 or r < 2:
        return None
    times = path_times(r)
    if not (np.diff(times) > 0).all():  # pragma: no cover - never: path_times is strict
        return None
    kernel = kern.plan_queries  # one query: the scalar kernel, as plan_chunk would call it
    tab = kern.tables(r, m, n, d)
    sel = np.zeros(1, np.int64)  # (read only)
    oshape, rshape, mshape = (1, m, d), (1, n, d), (1, 1, n, d)
    wshape, sshape = (1, times.shape[0], m + n, d), (1, r + 2)
    mfull, mflat = (r - 2, 1, n, d), ((r - 2) * n, d)
    no_middle = np.empty((0, 1, n, d))
    empty, concatenate, i64, u8 = np.empty, np.concatenate, np.int64, np.uint8

    def run(obstacles, configs, lift):
        if r == 2:
            middle = no_middle
        elif r == 3:
            middle = configs[1].reshape(mshape)
        else:
            middle = empty(mfull)
            concatenate(configs[1:-1], out=middle.reshape(mflat))
        wp = empty(wshape)
        domain = empty(1, i64)
        strata = empty(sshape, i64)
        clearance = empty(1)
        flags = empty(1, u8)
        kernel(obstacles.reshape(oshape), configs[0].reshape(rshape),
               configs[-1].reshape(rshape), middle, lift, True, wp, domain, strata,
               clearance, flags, tab, sel, 1, compact, shared)
        clr = clearance.item()
        if flags.item() or not clr > 0:
            return None
        return times.copy(), wp[0], domain.item(), tuple(strata.tolist()[0]), clr

    return run


# ----------------------------------------------------------------------------------------------
# the planar three-obstacle planner (paper Section 4): pmplan.kernels.planar

def _planar_arrays(obstacles, configs):
    """C-contiguous float64 arrays (B, 3, 2) and [(B, 1, 2), (B, 1, 2)] for the kernel, or
    None (numba missing, other shapes: the reference decides, and raises its own errors)."""
    if len(configs) != 2 or not planar_kernels().AVAILABLE:  # pragma: no cover
        return None
    try:
        obstacles = kernel_array(obstacles)
        start = kernel_array(configs[0])
        goal = kernel_array(configs[1])
    except (TypeError, ValueError):
        return None
    b = obstacles.shape[0] if obstacles.ndim == 3 else -1
    if obstacles.shape != (b, 3, 2) or start.shape != (b, 1, 2) or goal.shape != (b, 1, 2):
        return None
    return obstacles, [start, goal]


def _planar_kernel(obstacles, configs, lift: float, out: dict,
                   validate: bool) -> np.ndarray | None:
    """Plan a chunk with :func:`pmplan.kernels.planar.plan_chunk` into ``out`` (per-query
    breakpoints); return its flags, or None for arrays the kernel does not take (the
    reference then decides, and raises its own errors)."""
    if len(configs) != 2:
        raise ValueError(f"the planar_three planner plans r = 2 configurations, got "
                         f"{len(configs)}")
    args = _planar_arrays(obstacles, configs)
    if args is None:
        return None
    obstacles, (start, goal) = args
    flags = np.empty(obstacles.shape[0], np.uint8)
    planar_kernels().plan_chunk(obstacles, start, goal, EVEN, lift, validate, out["times"],
                                out["waypoints"], out["domain"], out["strata"],
                                out["clearance"], flags)
    return flags


def _planar_validates(d: int) -> bool:
    """With the kernel (flag ``INVALID``), so :func:`pmplan.plan_batch` needs no separate
    pass."""
    return planar_kernels().AVAILABLE


def _planar_single(m: int, n: int, d: int):
    """``run(obstacles, start, goal, lift)`` returns ``(times (k,), waypoints (k, 4, 2),
    domain, strata row (tuple), clearance)`` -- the path already compacted, as
    :func:`pmplan.plan` returns it -- or None whenever the kernel flags the query or its
    certificate fails; None for shapes other than (m, n, d) = (3, 1, 2)."""
    kern = planar_kernels()
    if not kern.AVAILABLE or (m, n, d) != (3, 1, 2):  # pragma: no cover
        return None
    kernel = kern.plan_planar_one

    def run(obstacles, start, goal, lift):
        t, wp, dom, f, i, j, clr, flags = kernel(obstacles, start, goal, EVEN, lift)
        if flags or not clr > 0:
            return None
        return t, wp, int(dom), (f, i, j), float(clr)

    return run


def _obstacle_line_glue(planner) -> tuple:
    """The kernel glue of an obstacle-line planner: its lanes (``compact``, ``shared``) bound
    into the kernel calls."""
    lanes = dict(compact=planner.compact, shared=planner.shared)
    return (_obstacle_line_arrays, partial(_obstacle_line_kernel, **lanes),
            _obstacle_line_validates, partial(_obstacle_line_single, **lanes),
            partial(_obstacle_line_sequence, **lanes))


#: every planner's kernel glue, by planner (the registered object itself, so that another
#: planner under the same name gets none): (arrays, kernel, validates, single, sequence)
PLANNERS = {
    **{p: _obstacle_line_glue(p) for p in (OBSTACLE_LINE, OBSTACLE_LINE_COMPACT,
                                           OBSTACLE_LINE_SHARED, OBSTACLE_LINE_ONESIDE,
                                           OBSTACLE_LINE_WALLS, OBSTACLE_LINE_ROBOTS)},
    PLANAR_THREE: (_planar_arrays, _planar_kernel, _planar_validates, _planar_single, None),
}


# ----------------------------------------------------------------------------------------------
# the functions of a backend


def arrays(planner, obstacles, configs):
    """The arrays :func:`plan` takes for ``planner`` (C-contiguous float64), or None when no
    kernel plans them (the reference does)."""
    glue = PLANNERS.get(planner)
    return None if glue is None else glue[0](obstacles, configs)


def validates(planner, d: int) -> bool:
    """Whether :func:`plan` validates the queries of ``planner`` in dimension ``d``."""
    glue = PLANNERS.get(planner)
    return glue is not None and glue[2](d)


def single_query(planner, m: int, n: int, d: int):
    """``run(obstacles, start, goal, lift) -> (times, waypoints, domain, row, clearance) |
    None``: one query of shape (m, n, d) planned and certified in one kernel call (None
    whenever anything is unusual, so that the caller takes the general path), or None when no
    kernel plans that shape."""
    glue = PLANNERS.get(planner)
    return None if glue is None else glue[3](m, n, d)


def sequence_query(planner, r: int, m: int, n: int, d: int):
    """``run(obstacles, configs, lift)``: one query through r configurations in one kernel
    call (see :func:`single_query`), or None."""
    glue = PLANNERS.get(planner)
    return None if glue is None or glue[4] is None else glue[4](r, m, n, d)


def plan(planner, obstacles, configs, lift, out: dict, validate: bool = False,
         down: np.ndarray | None = None) -> np.ndarray:
    """Plan and certify a chunk into ``out``: the kernel, then :func:`redecide`; the
    reference (:func:`pmplan.backends.numpy.plan`) where no kernel plans the chunk, and where
    a robot's lanes take the side of ``-nu(e)`` (``down``, of a
    :attr:`~pmplan.planners.base.Planner.robot_side` planner: no kernel takes it)."""
    glue = PLANNERS.get(planner)
    side = down is not None and bool(np.any(down))
    flags = None if glue is None or side else glue[1](obstacles, configs, lift, out, validate)
    if flags is None:
        return reference.plan(planner, obstacles, configs, lift, out, down=down)
    return redecide(planner, flags, obstacles, configs, lift, out)


def redecide(planner, flags: np.ndarray, obstacles, configs, lift, out: dict) -> np.ndarray:
    """After a kernel: the certificate (B,) of a chunk whose kernel wrote ``out`` and ``flags``.

    ``FALLBACK`` rows are planned again whole by the numpy reference and certified
    (:func:`pmplan.backends.numpy.plan_rows`); ``SUSPECT`` rows (a clearance near the
    certificate's threshold) get their clearance from :func:`pmplan.certify.clearance`, exact
    on the suspect pairs; ``NONFINITE``, ``BROKEN`` and ``INVALID`` rows fail (the kernel read
    every clause of the certificate back from its outputs).
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
        ok[idx] = reference.plan_rows(planner, obstacles, configs, lift, idx, out)
    return ok


def measure(waypoints, m: int, need):
    """The kernel's measure of refined paths (``pmplan.kernels.measure.measure_batch``), in the
    certificate's arithmetic: ``(values (B, 3): clearance, robot and obstacle distances; kept
    (B,): the radii ``need`` kept; close (B,): rows to decide exactly)``, or None for d where
    the kernel's sums would round differently (the reference measures every row)."""
    from ..kernels.measure import CLOSE, SHORT, SUSPECT, measure_batch
    from ..refine.grid import MAX_SEQUENTIAL_D  # (the refinement imports the backends)

    if waypoints.shape[-1] >= MAX_SEQUENTIAL_D:
        return None
    vals, flags = measure_batch(waypoints, m, need)
    return vals, (flags & SHORT) == 0, (flags & (SUSPECT | CLOSE)) != 0


def refine(times, waypoints, m: int, r: int, target, s: int, steps: int, walls=None,
           still=None):
    """The refinement's map, the kernel (``pmplan.refine.kernel.refine_batch``)."""
    from ..refine.kernel import refine_batch  # (the refinement imports the backends: not at import)

    return refine_batch(times, waypoints, m, r, target, s, steps, walls, still)


def from_box_linear(x, box, frac: float):
    """Points of the box mapped out of it, the kernel (``pmplan.kernels.box``; bit for bit
    :func:`pmplan.workspace.from_box_linear`)."""
    from ..kernels.box import from_box_linear as kernel

    return kernel(x, box, frac)


def into_box(z, box, frac: float):
    """The algebraic map into the box, the kernel (bit for bit
    :func:`pmplan.workspace.into_box`)."""
    from ..kernels.box import into_box as kernel

    return kernel(z, box, frac)


def path_into_box_linear(times, waypoints, box, frac: float, width: int | None = None):
    """The exact image of paths in the box, the kernel (bit for bit
    :func:`pmplan.workspace.path_into_box_linear`, the same error for a ``width`` too small)."""
    from ..kernels.box import path_into_box_linear as kernel

    return kernel(times, waypoints, box, frac, width)
