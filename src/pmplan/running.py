"""The run loop: plan a batch chunk by chunk into the output arrays, certified, and raise the
certificate's error; the progress display; the checks of ``workers`` and ``out=``.

:func:`run_loop` is the one loop of every entry point of :mod:`pmplan.api` (a single query is a
batch of one): per chunk (:func:`chunk_size`, at most :data:`CHUNK` queries) it asks the planner
(the backend's ``plan``, :mod:`pmplan.backends`: kernel -> flagged rows -> exact
re-decision -> certificate), or -- for queries at extreme magnitudes -- plans them scaled by a
power of two and certifies what it scales back (:mod:`pmplan.magnitude`). Threads
(``workers``) plan separate chunks. A path that fails its certificate is never returned: a
:class:`~pmplan.errors.CertificationError` names the clause and, where the magnitudes are the
cause, what to do.
"""

from __future__ import annotations

import sys

import numpy as np

from . import backends, magnitude, workspace
from .certify import CLEARANCE, certificate, check_times, describe
from .checks import (
    check_backend,
    check_lift,
    check_sequential,
    check_workers,
    choose_planner,
    is_dask,
)
from .configuration import check_query, check_sequence
from .errors import CertificationError, InputError, PmplanError
from .path import PiecewiseLinearPath
from .planners.base import REGISTRY, SCENE_CODE, Planner, Stage, scene_unit
from .refine import (
    MSG_PLAN,
    MSG_REFINE_DASK,
    MSG_REFINED,
    RefineStage,
    check_parameters,
    check_radii,
    subdivide_times,
)
from .results import Plan, PlanBatch, extra_row
from .sides import mirror, robot_sides, wall_sides
from .workspace import (
    BAND,
    check_bounds,
    check_inside,
    check_walls,
    crossing_width,
    inside,
    restore,
)

#: ``out=`` with ``bounds=`` (one source of the message)
MSG_BOUNDS_OUT = ("`out=` cannot be combined with `bounds=` (a path in a workspace is mapped "
                  "into it after planning): plan without `out`")
#: the most queries planned per chunk inside plan_batch: bounds the temporaries (memory) of a
#: batch (see :func:`chunk_size`)
CHUNK = 8192
#: the most output bytes (waypoints) per chunk: queries with many robots come in smaller chunks
CHUNK_BYTES = 32 * 2**20
#: the fewest queries per chunk that :func:`chunk_size` chooses (below, the per-chunk Python
#: work would dominate); a smaller :data:`CHUNK` still wins
MIN_CHUNK = 64
#: with several workers, a batch is cut into at least this many chunks per worker (when its
#: chunks stay above MIN_CHUNK), so that the threads share the work evenly
CHUNKS_PER_WORKER = 4


def chunk_size(b: int, row_bytes: int, workers: int) -> int:
    """Queries per chunk of a batch of ``b`` queries whose output waypoints take ``row_bytes``
    each: :data:`CHUNK`, fewer for large queries (:data:`CHUNK_BYTES` per chunk), and with
    ``workers > 1`` at most ``b / (CHUNKS_PER_WORKER workers)`` so that every thread gets work
    (never below :data:`MIN_CHUNK` unless CHUNK is). The plans do not depend on it.

    >>> chunk_size(100_000, 768, 1), chunk_size(1_000, 33_024, 1), chunk_size(1_000, 33_024, 2)
    (8192, 1016, 125)
    """
    c = max(MIN_CHUNK, CHUNK_BYTES // max(row_bytes, 1))
    if workers > 1:
        c = min(c, max(MIN_CHUNK, -(-b // (CHUNKS_PER_WORKER * workers))))
    return max(1, min(CHUNK, c))


def _raise_certificate(bad: np.ndarray, batched: bool, codes: np.ndarray | None = None,
                       obstacles: np.ndarray | None = None, configs=None,
                       lift=None, lift_is_unit: bool = True) -> None:
    """Raise the :class:`CertificationError` of the queries ``bad`` (bool, (B,)).

    ``codes`` (B,) are the clauses of :data:`pmplan.certify.CLAUSES` that failed (0 where only
    the kernel's clearance failed); with the query (``obstacles``, ``configs``, ``lift``) the
    message also says when the magnitudes, not the geometry, are the cause, and what to do
    (``lift_is_unit``: the planner's unit is ``lift``; else it is the paper's absolute 1).
    """
    idx = np.flatnonzero(bad)
    where = f" for queries {idx[:10].tolist()}{'...' if idx.size > 10 else ''}" if batched else ""
    first = idx[0] if idx.size else 0
    clause = int(codes[first]) if codes is not None and idx.size else 0
    clause = clause or CLEARANCE
    what = describe(clause)
    hint = None
    if obstacles is not None and idx.size:
        unit = np.broadcast_to(np.asarray(lift, dtype=float), bad.shape)[first] \
            if lift_is_unit else None
        if unit is not None and unit == SCENE_CODE:  # lift="scene": the query's own unit
            o = obstacles[first:first + 1]
            _, e = np.frexp(np.abs(o).max())  # measured at 2**-e: no square under/overflows
            with np.errstate(all="ignore"):
                unit = float(np.ldexp(scene_unit(np.ldexp(o, -e))[0], e))
        hint = _magnitude_hint(clause, obstacles[first], [c[first] for c in configs], unit)
    if hint is None:
        hint = ("the query is too nearly degenerate for double precision (two points would meet "
                "or the path is not finite)")
    raise CertificationError(
        f"the planned path failed its certificate{where}: {what}; {hint}; nothing was returned",
        indices=idx,
    )


def _magnitude_hint(clause: int, obstacles: np.ndarray, configs, lift: float | None
                    ) -> str | None:
    """Why a query at an extreme magnitude has no representable certified path, and what to do
    (None for a query of ordinary magnitude). ``lift`` None: the planner's unit is the paper's
    absolute 1, not ``lift``."""
    with np.errstate(all="ignore"):
        size = float(max(np.abs(obstacles).max(), *(np.abs(c).max() for c in configs)))
    unit = 1.0 if lift is None else lift
    if clause in (1, 5) and max(size, unit) > 2.0**LARGE:
        more = "" if lift is None else ", or use a smaller `lift`"
        return (f"the path leaves the range of double precision (coordinates up to {size:.3g}, "
                f"unit {unit:.3g}): scale the scene down{more}")
    if lift is None and size > 0 and unit < size * 2.0**-RESOLUTION:
        return (f"the planner's unit (the paper's 1) is below the resolution of the coordinates "
                f"(up to {size:.3g}): scale the scene down (by a power of two, which is exact)")
    if size > 0 and unit < size * 2.0**-RESOLUTION:
        return (f"`lift` = {lift:.3g} is below the resolution of the coordinates (up to "
                f"{size:.3g}), so the lifted robots cannot leave the line: use a larger `lift` "
                "(of the order of the scene's size, or lift=\"scene\", a unit that scales with the "
                "obstacles)")
    if 0 < size < 2.0**TINY:
        return (f"the coordinates (up to {size:.3g}) are at the bottom of the range of double "
                "precision, where the planner's constructions (e.g. eps(C), a gap divided by "
                "m + n) lose their bits: scale the scene up (by a power of two, which is exact)")
    return None


#: a path may overflow when the coordinates exceed 2**LARGE
LARGE = 1000
#: a lift below 2**-RESOLUTION times the largest coordinate is lost in rounding
RESOLUTION = 50
#: coordinates below 2**TINY are near the subnormal range
TINY = -1000


def _scaled_call(planner, obstacles, configs, lift, k: np.ndarray, call):
    """Plan the queries of a chunk each at its power of two ``2**-k`` (:mod:`pmplan.magnitude`).

    ``call(idx, obstacles, configs, lift)`` plans the rows ``idx`` of the chunk (given scaled)
    into new arrays and returns ``(arrays, ok)`` where ``arrays`` has ``waypoints``,
    ``clearance`` and the other outputs for those rows; the waypoints of scaled rows are scaled
    back by ``2**k`` and the whole certificate is checked again on what is returned
    (:func:`pmplan.certify.certificate`, which also gives the clearance). Yields ``(idx,
    arrays, ok)`` per group.
    """
    lift_arr = np.asarray(lift, dtype=float)
    for kg in np.unique(k):
        idx = np.flatnonzero(k == kg)
        kg = int(kg)
        if kg == 0:
            if lift_arr.ndim:
                lift_g = lift_arr[idx]
            else:
                lift_g = lift
            with np.errstate(all="ignore"):  # an extreme query planned as given: certified below
                arrays, ok = call(idx, obstacles[idx], [c[idx] for c in configs], lift_g)
            yield idx, arrays, ok
            continue
        lift_g = np.ldexp(lift_arr[idx], -kg) if lift_arr.ndim else float(np.ldexp(lift, -kg))
        arrays, ok = call(idx, np.ldexp(obstacles[idx], -kg),
                          [np.ldexp(c[idx], -kg) for c in configs], lift_g)
        with np.errstate(over="ignore", under="ignore"):
            arrays["waypoints"] = np.ldexp(arrays["waypoints"], kg)
        arrays["clearance"], clause = query_certificate(
            arrays["waypoints"], obstacles[idx], [c[idx] for c in configs], arrays["times"])
        yield idx, arrays, ok & (clause == 0)


def run_loop(planner: Planner, obstacles, configs, lift: float, batched: bool,
         progress: bool = False, backend: str | None = None, workers: int = 1,
         validate: bool = False, into: dict | None = None, down: np.ndarray | None = None):
    """Plan and certify in chunks; return the arrays of a PlanBatch.

    The planner (:class:`pmplan.planners.base.Planner`) allocates the output arrays
    (:meth:`~pmplan.planners.base.Planner.allocate`; ``into``, from :func:`_output_arrays`, are
    existing ones) and fills them chunk by chunk, certified
    by the backend ``backend`` (:func:`pmplan.backends.select`: its ``plan``, for the numba
    kernels kernel -> flagged rows -> exact re-decision -> certificate), so no temporary is
    larger than a chunk. With ``workers > 1``
    the chunks are planned by that many threads (the numba kernels release the GIL; every chunk
    writes its own rows). With ``validate`` the planner's kernel also validates the queries
    (where the backend's ``validates`` says it can): before a certificate error is raised, the
    queries are checked (:func:`pmplan.configuration.check_query`), which raises the input
    error if one of them is invalid -- the error the caller would have got from checking first.
    ``down`` (bool (B, n), a :attr:`~pmplan.planners.base.Planner.robot_side` planner only):
    the robots whose lanes take the side of ``-nu(e)``, passed on with each chunk's rows.
    """
    b, m, d = obstacles.shape
    n = configs[0].shape[1]
    be = backends.select(backend)
    out = planner.allocate(b, len(configs), m, n, d) if into is None else into
    per_query_times = out["times"].ndim == 2

    r = len(configs)
    # only a planner that maps 2**k C (with lift 2**k) to 2**k times the path of C is scaled;
    # another one plans extreme queries as given (its reference under np.errstate) and its
    # certificate decides
    equivariant = planner.equivariant
    # the breakpoints: shared ones are checked once here, per-query ones chunk by chunk
    shared_times = 0 if per_query_times else int(check_times(out["times"]))
    size = chunk_size(b, out["waypoints"][0].nbytes if b else 1, workers)

    def chunk(lo: int) -> tuple[int, int, np.ndarray]:
        hi = min(b, lo + size)
        obs = obstacles[lo:hi]
        cfg = [c[lo:hi] for c in configs]
        wp = out["waypoints"][lo:hi]
        times = out["times"][lo:hi] if per_query_times else out["times"]
        k = None
        lift_c = lift[lo:hi] if np.ndim(lift) else lift  # a per-query lift scales too
        down_c = None if down is None else down[lo:hi]
        if equivariant and magnitude.needs_scaling([obs, *cfg], lift_c):
            k = magnitude.exponents([obs, *cfg], lift_c)
        if k is None:
            rows = {"domain": out["domain"][lo:hi], "strata": out["strata"][lo:hi],
                    "clearance": out["clearance"][lo:hi], "times": times, "waypoints": wp}
            ok = be.plan(planner, obs, cfg, lift, rows, validate, down=down_c)
        else:
            ok = np.empty(hi - lo, dtype=bool)
            call = _fused_call(planner, r, m, n, d, per_query_times, validate, be, down_c)
            for idx, arrays, ok_g in _scaled_call(planner, obs, cfg, lift_c, k, call):
                wp[idx] = arrays["waypoints"]
                out["domain"][lo + idx] = arrays["domain"]
                out["strata"][lo + idx] = arrays["strata"]
                out["clearance"][lo + idx] = arrays["clearance"]
                if per_query_times:
                    times[idx] = arrays["times"]
                ok[idx] = ok_g
        # the kernels certified the waypoints (clauses 5-10, read back from their outputs), the
        # reference and the scaled rows by pmplan.certify; the breakpoints are checked here
        if per_query_times:
            ok &= check_times(times) == 0
        elif shared_times:
            ok[:] = False
        return lo, hi, ok

    def check(lo: int, hi: int, ok: np.ndarray) -> None:
        if not ok.all():
            if validate:  # an invalid query, or a certificate that fails
                check_query(obstacles, configs[0], configs[-1], batched=True)
            bad = np.zeros(b, dtype=bool)
            bad[lo:hi] = ~ok
            _raise_certificate(bad, batched, _failed_clauses(out, bad, obstacles, configs),
                               obstacles, configs, lift, equivariant)

    _each_chunk(chunk, range(0, b, size), progress, workers, check)
    return out


def _each_chunk(chunk, starts: range, progress: bool, workers: int, check,
                desc: str = "planning") -> None:
    """Call ``chunk(lo) -> (lo, hi, ok)`` for every start (``workers`` threads: the numba
    kernels release the GIL; every chunk writes its own rows), with the progress display, and
    ``check(lo, hi, ok)`` on each result in order (it raises the error of a failed chunk)."""
    bar = _Progress(progress, len(starts), desc)
    pool = None
    if workers > 1 and len(starts) > 1:
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(min(workers, len(starts)))
    try:
        bar.__enter__()
        done = map(chunk, starts) if pool is None else pool.map(chunk, starts)
        for lo, hi, ok in done:
            bar.update()
            check(lo, hi, ok)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        bar.__exit__(None, None, None)


def run_stage(stage: Stage, progress: bool = False, workers: int = 1) -> None:
    """Run a stage (:class:`pmplan.planners.base.Stage`, e.g. the refinement) over its rows
    chunk by chunk, as :func:`run_loop` runs a planner: ``workers`` threads plan separate chunks
    (the numba kernels release the GIL), ``progress`` shows the bar; the first chunk whose
    certificate fails raises the stage's error (:meth:`~pmplan.planners.base.Stage.fail`).
    With ``workers > 1`` a chunk holds at most ``b / (CHUNKS_PER_WORKER workers)`` rows (at
    least one), so that a batch smaller than the stage's chunk is shared among the threads too:
    a stage's row is costly (a refined crowd of 16 robots takes about 13 ms), and its per-chunk
    work is small beside it. The rows do not depend on it."""
    b = stage.size
    size = stage_chunk(stage.chunk, b, workers)

    def chunk(lo: int):
        hi = min(b, lo + size)
        return lo, hi, stage.run(lo, hi)

    def check(lo: int, hi: int, ok: np.ndarray) -> None:
        if not ok.all():
            bad = np.zeros(b, dtype=bool)
            bad[lo:hi] = ~ok
            stage.fail(bad)

    _each_chunk(chunk, range(0, b, size), progress, workers, check, stage.label)


def stage_chunk(chunk: int, b: int, workers: int) -> int:
    """Rows per chunk of a stage whose own chunk is ``chunk``, on a batch of ``b`` rows with
    ``workers`` threads (:func:`run_stage`).

    >>> stage_chunk(512, 16, 1), stage_chunk(512, 16, 2), stage_chunk(512, 10_000, 2)
    (512, 2, 512)
    """
    if workers > 1:
        chunk = min(chunk, -(-b // (CHUNKS_PER_WORKER * workers)))
    return max(1, chunk)


def query_certificate(waypoints, obstacles, configs: list, times, certify=certificate):
    """The certificate ``(clearance, clauses)`` of paths (B, K, P, d) against their queries:
    ``obstacles`` (B, m, d) and the r configurations ``configs`` (B, n, d) they pass through,
    the intermediate ones at ``k / (r - 1)`` (``certify``: :func:`pmplan.certify.certificate`
    or a backend's, the same contract)."""
    m, r = obstacles.shape[1], len(configs)
    full = [np.concatenate([obstacles, c], axis=1) for c in configs]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    return certify(waypoints, full[0], full[-1], m, times=times, via=via)


def _failed_clauses(out: dict, bad: np.ndarray, obstacles, configs) -> np.ndarray:
    """The clause of the certificate (:func:`pmplan.certify.certificate`) that each failing
    query (``bad``) of a fused run fails, for the error message; (B,) uint8."""
    idx = np.flatnonzero(bad)[:10]
    times = out["times"][idx] if out["times"].ndim == 2 else out["times"]
    with np.errstate(all="ignore"):
        _, clause = query_certificate(out["waypoints"][idx], obstacles[idx],
                                      [c[idx] for c in configs], times)
    codes = np.zeros(bad.shape[0], np.uint8)
    codes[idx] = clause
    return codes


def _fused_call(planner, r: int, m: int, n: int, d: int, per_query_times: bool, validate: bool,
                be, down: np.ndarray | None = None):
    """``call(idx, obstacles, configs, lift) -> (arrays, ok)`` for :func:`_scaled_call`: the
    backend ``be`` planning rows into new arrays (:meth:`allocate`, the backend's ``plan``;
    ``down``: the chunk's, of :func:`run_loop`)."""

    def call(idx, obstacles, configs, lift):
        arrays = planner.allocate(idx.size, r, m, n, d)
        ok = be.plan(planner, obstacles, configs, lift, arrays, validate,
                     down=None if down is None else down[idx])
        return arrays, ok

    return call


class _Progress:
    """The progress display of a batch of ``total`` chunks, on stderr when ``show``.

    While it is open, the notice :data:`pmplan._compiling.COMPILING` is written if a kernel is
    compiled (the first run only: not when numba loads it from its on-disk cache). The tqdm bar
    (for more than 4 chunks) starts when the first chunk is done (``update``), counting it, so
    that its rate and time estimate never include that compilation; a kernel that only a later
    chunk needs (the scalar kernel, for a query that is not generic) is announced once more.
    """

    def __init__(self, show: bool, total: int, desc: str = "planning") -> None:
        self.show, self.total, self.done, self.desc = show, total, 0, desc
        self.bar = None
        self.notice = None
        self.handle = None

    def __enter__(self) -> _Progress:
        if self.show:
            from ._compiling import announce_compile

            self.notice = announce_compile(self.write)
            self.handle = self.notice.__enter__()
        return self

    def write(self, message: str) -> None:
        if self.bar is not None:
            self.bar.write(f"pmplan: {message}", file=sys.stderr)
        else:
            print(f"pmplan: {message}", file=sys.stderr, flush=True)

    def update(self) -> None:
        """One more chunk done."""
        self.done += 1
        if not self.show or self.total <= 4:
            return
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=self.total, initial=self.done, desc=self.desc, unit="chunk",
                            file=sys.stderr)
            if self.handle is not None:
                self.handle.rearm()
        else:
            self.bar.update()

    def over(self, items):
        """Yield the chunks ``items``, counting each one done when the next is asked for."""
        with self:
            for item in items:
                yield item
                self.update()

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()
        if self.notice is not None:
            self.notice.__exit__(None, None, None)
            self.notice = None


def _output_arrays(out, planner: Planner, dims: tuple[int, int, int], b: int, r: int,
                   inputs: tuple) -> dict | None:
    """The arrays of ``out`` (the ``out=`` argument of the batch functions) to plan into.

    ``out`` must be a :class:`PlanBatch` of the same planner, dims and length whose arrays have
    the shapes and dtypes a new batch would have, are writeable and C-contiguous, and share no
    memory with the query (``inputs``). Shared breakpoints (``times`` of shape (K,)) are
    rewritten. Returns None when ``out`` is None.
    """
    if out is None:
        return None
    if not isinstance(out, PlanBatch):
        raise InputError(f"`out` must be a PlanBatch returned by plan_batch, got "
                         f"{type(out).__name__}")
    if out.planner != planner.name or tuple(out.dims) != dims or len(out) != b:
        raise InputError(
            f"`out` holds {len(out)} plans of the {out.planner} planner for (d, n, m) = "
            f"{tuple(out.dims)}; this batch needs {b} of the {planner.name} planner for "
            f"{dims}"
        )
    d, n, m = dims
    template = planner.allocate(0, r, m, n, d)
    arrays = {k: getattr(out, k) for k in template}
    for k, a in arrays.items():
        t = template[k]
        want = t.shape if k == "times" and t.ndim == 1 else (b,) + t.shape[1:]
        if a.shape != want or a.dtype != t.dtype:
            raise InputError(
                f"`out.{k}` has shape {a.shape} and dtype {a.dtype}; this batch needs shape "
                f"{want} and dtype {t.dtype}"
            )
        if not (a.flags.writeable and a.flags.c_contiguous):
            raise InputError(f"`out.{k}` must be a writeable C-contiguous array")
        if any(np.may_share_memory(a, x) for x in inputs):
            raise InputError(f"`out.{k}` shares memory with the query; pass separate arrays")
    if template["times"].ndim == 1:
        arrays["times"][...] = template["times"]
    return arrays


def single_plan(planner: Planner, dims: tuple[int, int, int], out: dict) -> Plan:
    """The :class:`~pmplan.Plan` of a batch of one (no PlanBatch in between)."""
    d, n, m = dims
    times = out["times"]
    path = PiecewiseLinearPath(times if times.ndim == 1 else times[0], out["waypoints"][0])
    return Plan(
        domain=int(out["domain"][0]),
        stratum=planner.stratum_name(out["strata"][0], d, n, m),
        clearance=float(out["clearance"][0]),
        path=path.compact(),
        planner=planner.name,
        dims=dims,
    )


def plan_arrays(obstacles, configs: list, *, planner: str | None = None, lift=1.0,
                backend: str | None = None, workers: int = 1, progress: bool = False,
                out: PlanBatch | None = None, sequential: bool = False,
                bounds=None, batched: bool = True, width: int | None = None,
                refining: bool = False) -> PlanBatch:
    """The one entry below the facade: plan a batch of queries through the configurations
    ``configs`` (r >= 2 arrays (B, n, d): start, intermediate ones, goal) among ``obstacles``
    (B, m, d): the arguments checked, the input validated, the planner chosen, the run loop.

    :func:`pmplan.plan_batch` (r = 2), :func:`pmplan.plan_sequence_batch` and every chunk of
    :mod:`pmplan.scale` call it; the keywords are theirs. ``sequential`` (implied by r > 2):
    a query through configurations (the planner must plan through intermediate ones; the
    default is the sequential planner of (d, n, m)). ``bounds``: the workspace box
    (:mod:`pmplan.workspace`): the queries are planned through its map and every path stays in
    it; ``width``: the breakpoints added to every piece of a path in the box
    (:func:`pmplan.workspace.path_into_box_linear`; default the most the batch needs, fixed
    first by :func:`box_width` where the output shapes are fixed before planning);
    ``batched=False``: one query (the messages name no query index); ``refining``: the plans
    will be refined (the default planner may then differ, :func:`~pmplan.checks.choose_planner`).
    """
    lift = check_lift(lift)
    workers = check_workers(workers)
    p, obstacles, configs, deferred = _prepare(obstacles, configs, planner, backend, sequential,
                                               bounds, refining)
    _, m, d = obstacles.shape
    n = configs[0].shape[1]
    if bounds is not None:
        return _plan_in_box(p, obstacles, configs, lift, bounds, backend, workers, progress, out,
                            batched, width)
    into = _output_arrays(out, p, (d, n, m), obstacles.shape[0], len(configs),
                          (obstacles, *configs))
    res = run_loop(p, obstacles, configs, lift, batched=True, progress=progress, backend=backend,
                   workers=workers, validate=deferred, into=into)
    return out if out is not None else PlanBatch(planner=p.name, dims=(d, n, m), **res)


def box_width(obstacles, configs: list, *, planner: str | None = None, lift=1.0,
              backend: str | None = None, workers: int = 1, sequential: bool = False,
              bounds=None) -> int:
    """The ``width`` of :func:`plan_arrays` that fits every query of this batch in the box
    ``bounds`` (:func:`pmplan.workspace.crossing_width` of its raw plans): the first pass of
    :mod:`pmplan.scale`, whose output shapes are fixed before any chunk is planned. The
    queries are checked as :func:`plan_arrays` checks them (the same errors)."""
    lift = check_lift(lift)
    workers = check_workers(workers)
    p, obstacles, configs, _ = _prepare(obstacles, configs, planner, backend, sequential, bounds)
    box, res = _raw_in_box(p, obstacles, configs, lift, bounds, backend, workers, False, True)
    return crossing_width(np.asarray(res["times"]), np.asarray(res["waypoints"]), box)


def _raw_in_box(p: Planner, obstacles, configs, lift, bounds, backend, workers, progress,
                batched: bool):
    """The raw plans of queries in a workspace box: ``(box, res)``, the box checked, every
    point checked strictly inside it, the queries mapped out of it by
    :func:`~pmplan.workspace.from_box_linear` and planned in R^d (``res`` of
    :func:`run_loop`). A planner that declares
    :attr:`~pmplan.planners.base.Planner.wall_side` plans, in the plane, the queries
    :func:`~pmplan.sides.wall_sides` flips mirrored (the planner with ``-nu(e)``), their plans
    mirrored back, and a query on the wall of sides gets its label one less (Mathematics §8,
    "The side of the lanes"); one that declares
    :attr:`~pmplan.planners.base.Planner.robot_side` plans, in the plane, every robot on the side
    :func:`~pmplan.sides.robot_sides` chooses for it, and a query on the walls of k robots gets
    its label k less (Mathematics §8, "A side per robot")."""
    box = check_bounds(bounds, obstacles.shape[2])
    check_inside(obstacles, configs, box, batched=batched)
    out_of = backends.select(backend).from_box_linear
    z_obstacles, z_configs = out_of(obstacles, box, BAND), [out_of(c, box, BAND) for c in configs]
    flip = down = None
    plane = obstacles.shape[2] == 2
    if p.wall_side and plane:  # (the side of the lanes, Mathematics §8)
        flip, wall = wall_sides(obstacles, z_obstacles, z_configs, box)
        z_obstacles, z_configs = mirror(z_obstacles, flip), [mirror(c, flip) for c in z_configs]
    elif p.robot_side and plane:  # (a side per robot, Mathematics §8)
        down, walls = robot_sides(obstacles, configs, z_obstacles, z_configs, box, lift)
    res = run_loop(p, z_obstacles, z_configs, lift, batched=batched, progress=progress,
                   backend=backend, workers=workers, down=down)
    if flip is not None:
        res["waypoints"] = mirror(res["waypoints"], flip)
        res["domain"][wall] -= 1
    if down is not None:
        res["domain"] -= walls
    return box, res


def _prepare(obstacles, configs, planner, backend, sequential: bool, bounds,
             refining: bool = False):
    """The checks of :func:`plan_arrays` before planning: ``(planner, obstacles, configs,
    deferred)``, the queries as arrays, and whether the planner's kernel validates them
    (else they are validated here)."""
    if not sequential and len(configs) == 2:
        # types and shapes here; the validity of every query (finite, no two equal points) is
        # checked by the planner's kernel in its own pass where it can, else here
        obstacles, start, goal = check_query(obstacles, configs[0], configs[1], batched=True,
                                             deep=False)
        configs = [start, goal]
        _, m, d = obstacles.shape
        n = start.shape[1]
        try:
            p = choose_planner(d, n, m, planner, refining=refining, bounded=bounds is not None)
            check_backend(backend)
        except PmplanError:  # an invalid query is reported first, as always
            check_query(obstacles, start, goal, batched=True)
            raise
        # (in a box the queries are validated here, before their points are tested against it)
        deferred = bounds is None and backends.select(backend).validates(p, d)
        if not deferred:
            check_query(obstacles, start, goal, batched=True)
    else:
        check_sequential(planner)
        obstacles, configs = check_sequence(obstacles, configs, batched=True)
        _, m, d = obstacles.shape
        n = configs[0].shape[1]
        p = choose_planner(d, n, m, planner, sequential=True, refining=refining,
                           bounded=bounds is not None)
        check_backend(backend)
        deferred = False
    return p, obstacles, configs, deferred


#: a chunk whose raw plans in the box need more breakpoints than its store was created with
MSG_WIDTH = ("the plans of these queries in the workspace box need {need} breakpoints more in a "
             "piece, but the output's shapes were fixed for {width} by a first pass over the "
             "input (a resumed store whose input changed in chunks not yet done): plan this "
             "input into another --out")


def _plan_in_box(p: Planner, obstacles, configs, lift, bounds, backend, workers, progress,
                 out, batched: bool, width: int | None = None) -> PlanBatch:
    """:func:`plan_arrays` in a workspace box (:mod:`pmplan.workspace`): the queries (checked,
    every point strictly inside) mapped out of the box by the inverse of the map linear on
    cells, planned, and the paths mapped back in exactly
    (:func:`~pmplan.workspace.path_into_box_linear`, every piece cut ``width`` times, default
    the most the batch needs) with the obstacles and configurations restored bit for bit, then
    certified again (every clause, and every waypoint inside the box)."""
    if out is not None:
        raise InputError(MSG_BOUNDS_OUT)
    b, m, d = obstacles.shape
    box, res = _raw_in_box(p, obstacles, configs, lift, bounds, backend, workers, progress,
                           batched)
    raw_times, raw = np.asarray(res["times"]), np.asarray(res["waypoints"])
    fixed = p.fixed_waypoints(raw_times)
    try:
        times, wp = backends.select(backend).path_into_box_linear(raw_times, raw, box, BAND,
                                                                  width)
    except ValueError:  # (a width too small; its crossings counted again only here)
        need = crossing_width(raw_times, raw, box)
        if width is None or need <= width:
            raise
        raise InputError(MSG_WIDTH.format(need=need, width=width)) from None
    c = (times.shape[1] - 1) // (raw_times.shape[-1] - 1)
    restore(wp, m, c * fixed, configs, obstacles)
    clearance, codes = query_certificate(wp, obstacles, configs, times,
                                         backends.select(backend).certify)
    bad = ~(clearance > 0) | (np.asarray(codes) != 0) | ~inside(wp, box)
    if bad.any():
        _raise_certificate(bad, batched, np.asarray(codes))
    res = {**res, "times": times, "waypoints": wp, "clearance": clearance}
    return PlanBatch(planner=p.name, dims=(d, configs[0].shape[1], m), **res,
                     _extra={"bounds": np.broadcast_to(box, (b, 2, d))})


def _evaluate(times: np.ndarray, waypoints: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Paths with breakpoints ``times`` (B, K) and waypoints (B, K, P, d) at the shared times
    ``t`` (J,) in [0, 1]: (B, J, P, d), each row computed from that row alone (the same bits
    in any batch)."""
    k = times.shape[1]
    idx = np.stack([np.count_nonzero(times <= tj, axis=1) for tj in t], axis=1) - 1
    idx = np.clip(idx, 0, k - 2)
    t0 = np.take_along_axis(times, idx, axis=1)
    t1 = np.take_along_axis(times, idx + 1, axis=1)
    dur = t1 - t0
    with np.errstate(invalid="ignore", divide="ignore"):
        lam = np.where(dur > 0, (t - t0) / np.where(dur > 0, dur, 1.0), 0.0)[..., None, None]
    rows = np.arange(times.shape[0])[:, None]
    return (1.0 - lam) * waypoints[rows, idx] + lam * waypoints[rows, idx + 1]


def box_start(p: Planner, times, waypoints, dims):
    """The polyline the refinement of plans in a workspace box starts from
    (:func:`refine_plans`): the plans (B, K', P, d) of :func:`_plan_in_box` at the raw
    planner's breakpoints (every ``c``-th one,
    :meth:`~pmplan.planners.base.Planner.cut_structure`: the map of the raw waypoints, bit for
    bit) and, with :data:`pmplan.workspace.RAW_CUTS` = k > 1, at k - 1 more equally spaced
    times inside every raw piece (points of the plan). Its breakpoints do not depend on how
    often the plan crosses the nodes of the map, so that the refinement is as continuous as
    the plan it starts from and a query refined alone is its row of a batch (bit for bit with
    k = 1; else to rounding, the plan's breakpoints being the batch's) (``docs/refinement.md``,
    Walls). Returns ``(times, waypoints)``, (K,) and (B, K, P, d) with
    K = (K_raw - 1) k + 1. The plans of a planner whose breakpoints are per query (the
    planar_three planner) are their own start."""
    times = np.asarray(times, dtype=float)
    cut = p.cut_structure(times)
    if cut is None:
        return times, waypoints
    c = cut[1]
    raw_t = times[::c] if times.ndim == 1 else times[0, ::c]
    cuts = workspace.RAW_CUTS
    if cuts == 1:
        return raw_t, np.ascontiguousarray(waypoints[:, ::c])
    t = subdivide_times(raw_t, cuts)
    b = waypoints.shape[0]
    wp = _evaluate(np.broadcast_to(times, (b, times.shape[-1])), waypoints, t)
    wp[:, ::cuts] = waypoints[:, ::c]
    wp[:, :, :dims[2]] = waypoints[:, :1, :dims[2]]  # the obstacles, fixed bit for bit
    return t, wp


MSG_BOX_START = ("the refinement of a plan in a workspace box starts from the plan at the raw "
                 "planner's breakpoints (pmplan.workspace.RAW_CUTS = {cuts} per raw piece), and "
                 "that polyline fails the certificate{where}: {what}. The plan itself is "
                 "certified; to refine it, set pmplan.workspace.RAW_CUTS to a larger value (a "
                 "start closer to the plan)")


def _start_clearance(p: Planner, times, wp, m: int, fixed, backend, single: bool) -> np.ndarray:
    """The clearance of the refinement's start in a box (:func:`box_start`), certified like
    a plan (every clause); a CertificationError (:data:`MSG_BOX_START`) when it fails."""
    configs = [wp[:, kj, m:] for kj in fixed]
    clearance, codes = query_certificate(wp, wp[:, 0, :m], configs, times,
                                         backends.select(backend).certify)
    codes = np.asarray(codes)
    bad = ~(clearance > 0) | (codes != 0)
    if bad.any():
        idx = np.flatnonzero(bad)
        where = "" if single else f" for queries {idx[:10].tolist()}"
        what = describe(int(codes[idx[0]]) or CLEARANCE)
        raise CertificationError(MSG_BOX_START.format(cuts=workspace.RAW_CUTS, where=where,
                                                      what=what), indices=idx)
    return clearance


def refine_plans(plan_or_batch, *, radius: float = 0.0, obstacle_radius: float = 0.0,
                 waypoints: int | None = None, steps: int | None = None, workers: int = 1,
                 progress: bool | None = None, backend: str | None = None):
    """:func:`pmplan.refine`: the plans refined by ``RefineStage`` (:mod:`pmplan.refine`) in the
    run loop (:func:`run_stage`), the start, intermediate and goal configurations
    checked against the radii first; a :class:`~pmplan.results.Plan` or a
    :class:`~pmplan.results.PlanBatch` as given."""
    # (the defaults depend on the plans' dimension and number of robots; a wrong type is
    # refused below)
    d, n = plan_or_batch.dims[:2] if isinstance(plan_or_batch, (Plan, PlanBatch)) else (2, 1)
    radius, obstacle_radius, s, steps = check_parameters(radius, obstacle_radius, waypoints,
                                                         steps, n=n, d=d)
    workers = check_workers(workers)
    if progress is None:
        progress = False
    if not isinstance(progress, (bool, np.bool_)):
        raise InputError(f"`progress` must be True, False or None, got {progress!r}")
    check_backend(backend)
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
        if is_dask(wp):
            raise InputError(MSG_REFINE_DASK)
        refined = bool(batch.refined.any())
    else:
        raise InputError(MSG_PLAN.format(value=type(plan_or_batch).__name__))
    if refined:
        raise InputError(MSG_REFINED.format(radius=f"{float(np.max(batch.radius)):g}"))
    p = REGISTRY[batch.planner]
    m = batch.dims[2]
    box = batch.bounds if single or batch.bounds is None else batch.bounds[0]
    if box is not None:  # the plans at the raw breakpoints: a grid the query does not move
        times, wp = box_start(p, times, wp, batch.dims)
    fixed = p.fixed_waypoints(np.asarray(times))  # start, intermediate configurations, goal
    if box is not None:
        clearance = _start_clearance(p, times, wp, m, fixed, backend, single)
    stage = RefineStage(times, wp, clearance, m, fixed, radius, obstacle_radius, s, steps, backend,
                        box=box, still=p.still_for(np.asarray(times)))
    check_radii(wp[:, 0, :m], [wp[:, kj, m:] for kj in fixed], radius, obstacle_radius,
                batched=not single, backend=stage.backend)
    if box is not None:
        check_walls([wp[:, kj, m:] for kj in fixed], box, radius, batched=not single)
    run_stage(stage, progress=progress, workers=workers)
    extra = stage.extra()
    if single:
        path = PiecewiseLinearPath(stage.times, stage.waypoints[0])
        return Plan(batch.domain, batch.stratum, float(stage.clearance[0]), path.compact(),
                    batch.planner, batch.dims,
                    **extra_row(extra, 0))
    return PlanBatch(domain=batch.domain.copy(), strata=batch.strata.copy(),
                     clearance=stage.clearance, times=stage.times, waypoints=stage.waypoints,
                     planner=batch.planner, dims=batch.dims, _names=batch._names, _extra=extra)
