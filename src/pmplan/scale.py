"""Beyond one machine: dask arrays in, lazy dask arrays out; chunked Zarr streaming.

A batch of queries larger than one process's memory is planned chunk by chunk: every chunk is
an ordinary :func:`pmplan.plan_batch` call (the same kernels, the same certificate), so the
plans are bit for bit those of ``plan_batch`` on the whole batch in memory, whatever the
chunking or the scheduler. Two faces:

* :func:`plan_batch` / :func:`plan_sequence_batch` on :class:`dask.array.Array` inputs
  (chunked along the batch axis only) return a :class:`~pmplan.PlanBatch` of lazy dask arrays
  built with ``map_blocks`` (``pmplan.plan_batch`` hands dask inputs over to this module);
  :func:`compute` computes all of them in one pass.
* :func:`plan_store` (``pmplan batch IN --out OUT.zarr``) streams from a Zarr store (or an npz)
  to a Zarr store: bounded memory (a few chunks per process), resumable (``resume=True``
  plans only the chunks not yet marked done), in-process or on a ``dask.distributed`` cluster
  (``scheduler=ADDRESS`` or ``dask_workers=N``: a LocalCluster).

The output store (:data:`FORMAT`): a Zarr group with arrays ``domain`` (B,) int64, ``strata``
(B, S) int64, ``clearance`` (B,) float64, ``waypoints`` (B, K, m+n, d) float64, ``times``
(K,) float64 (shared breakpoints, obstacle-line planner) or (B, K) (per query, planar_three),
all chunked along the batch axis only by ``chunk`` queries; ``inputs`` (number of chunks, 32)
uint8, the SHA-256 fingerprint of each chunk's input (its shapes and float64 bytes); and
``done`` (number of chunks,) bool. A chunk is written in the order outputs, fingerprint,
``done``: a chunk marked done holds the plans of the input its fingerprint names, and a resume
refuses an input that differs in a chunk already done. Group attributes: ``format``,
``planner``, ``lift`` (a number or ``"scene"``), ``pmplan_version``, ``dims`` [d, n, m], ``r``
(configurations per query), ``B``, ``chunk``, ``compress`` and ``complete`` (True only once
every chunk is done). :func:`open_plans` refuses an incomplete store. A store is created in a
hidden sibling directory and renamed into place once whole, so a crash while creating it
leaves none; a run stopped by the disk or the cluster says, in one line
(:class:`~pmplan.errors.StoreError`), which store it left and that ``resume`` finishes it.

Refined motions (:func:`pmplan.refine`, ``refine=`` here, ``pmplan batch --refine``) go the same
way: every chunk is planned and then refined, as :func:`pmplan.plan_batch` with
``refine=True`` does on the whole batch, so the refined plans are bit for bit the in-memory
ones. A refined store also has ``robot_distance``, ``obstacle_distance``, ``raw_clearance``
(B,) float64 and ``respects_radius`` (B,) bool (:data:`REFINED_OUTPUTS`), and the attribute ``refine`` (the
radii, waypoints and steps; ``null`` for raw plans).

This module is a face (ARCHITECTURE.md): the core never imports it, and it needs the optional
extra ``pip install "pmplan[dask]"`` (dask[array], distributed, zarr).
"""

from __future__ import annotations

import dataclasses
import errno
import hashlib
import logging
import os
import re
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .checks import check_backend, check_lift, check_sequential, check_workers, choose_planner
from .configuration import default_lift
from .errors import CertificationError, CollisionError, InputError, PmplanError, StoreError
from .results import PlanBatch
from .running import box_width, plan_arrays, refine_plans
from .workspace import check_bounds

__all__ = [
    "FORMAT",
    "INSTALL",
    "REFINED_OUTPUTS",
    "compute",
    "is_store",
    "open_plans",
    "plan_batch",
    "plan_sequence_batch",
    "plan_store",
    "StoreReport",
]

#: the ``format`` attribute of an output store
FORMAT = "pmplan-plans-2"
#: the formats :func:`open_plans` reads (1: before the input fingerprints)
READABLE_FORMATS = ("pmplan-plans-1", FORMAT)
#: how to get the optional dependencies of this module
INSTALL = 'pip install "pmplan[dask]"'
#: queries per chunk when streaming an input that has no chunking of its own (npz)
DEFAULT_CHUNK = 65536
#: the arrays of an output store, in the order they are written (``done`` last)
OUTPUTS = ("domain", "strata", "clearance", "times", "waypoints")
#: the arrays a store of refined motions has besides :data:`OUTPUTS` (written before ``done``)
REFINED_OUTPUTS = ("robot_distance", "obstacle_distance", "respects_radius", "raw_clearance")
_RECHUNK = "x.rechunk({1: -1, 2: -1})"
#: zstd's level in a compressed store: on plans it gives the ratio of Zarr's default (level 3),
#: about 1.9-2, two to three times as fast (``benchmarks/store_breakdown.py``)
ZSTD_LEVEL = 1


def _need(module: str):
    """Import ``module`` (dask.array, distributed, zarr) or raise the InputError saying how to
    install the extra."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise InputError(f"this needs the optional package {module.split('.')[0]!r}, which is not "
                         f"installed: {INSTALL}") from None


# ----------------------------------------------------------------------------------------------
# dask arrays in, lazy dask arrays out


def _real_dtype(dtype: np.dtype, name: str) -> None:
    """The rule of :func:`pmplan.configuration.as_real` on a dtype: float or integer."""
    if dtype.kind not in "iuf":
        raise InputError(f"`{name}` has dtype {dtype}; coordinates must be real numbers (a float "
                         f"or integer dtype): convert it, e.g. {name}.astype(float)")


def _dask_inputs(arrays: list, names: list[str]):
    """The inputs as dask arrays with one common chunking along the batch axis and one chunk
    along every other axis; a clear InputError for anything else (nothing is rechunked
    silently)."""
    da = _need("dask.array")
    ref = next(a for a in arrays if isinstance(a, da.Array))
    out = []
    for a, name in zip(arrays, names):
        if not isinstance(a, da.Array):
            a = np.asarray(a)
        _real_dtype(np.dtype(a.dtype), name)
        if a.ndim != 3:
            raise InputError(f"`{name}` has shape {a.shape}; expected (B, k, d) with the batch "
                             "axis first")
        if isinstance(a, da.Array):
            if any(np.isnan(c) for cs in a.chunks for c in cs):
                raise InputError(f"`{name}` has unknown chunk sizes; call "
                                 f"{name}.compute_chunk_sizes() first")
            if len(a.chunks[1]) > 1 or len(a.chunks[2]) > 1:
                raise InputError(
                    f"`{name}` is chunked along axes other than the batch axis (chunks "
                    f"{tuple(len(c) for c in a.chunks)}); plan_batch needs whole queries in "
                    f"every chunk: {name} = {name}.rechunk({{1: -1, 2: -1}})")
        else:
            a = da.from_array(a, chunks=(ref.chunks[0], -1, -1))
        out.append(a)
    b = {a.shape[0] for a in out}
    if len(b) > 1:
        raise InputError(f"the inputs have different batch sizes {[a.shape[0] for a in out]}")
    chunks = [a.chunks[0] for a in out]
    if any(c != chunks[0] for c in chunks):
        desc = ", ".join(f"{n}: {len(c)} chunks of up to {max(c, default=0)}"
                         for n, c in zip(names, chunks))
        raise InputError(
            f"the inputs are chunked differently along the batch axis ({desc}); give them the "
            f"same chunks, e.g. x = x.rechunk({{0: {names[0]}.chunks[0]}})")
    return da, out


def _record(template: dict, per_query_times: bool, refined: bool) -> np.dtype:
    """The structured dtype of one planned query: every output of a block packed into one
    array, so that one ``map_blocks`` call plans a block once."""
    fields = [("domain", np.int64), ("strata", np.int64, template["strata"].shape[1:]),
              ("clearance", np.float64), ("waypoints", np.float64, template["waypoints"].shape[1:])]
    if per_query_times:
        fields.append(("times", np.float64, template["times"].shape[1:]))
    if refined:
        fields += [("robot_distance", np.float64), ("obstacle_distance", np.float64),
                   ("respects_radius", np.bool_), ("raw_clearance", np.float64)]
    return np.dtype(fields)


def _refine_options(refine, n: int, d: int) -> dict | None:
    """The keywords of :func:`pmplan.refine` (``radius``, ``obstacle_radius``, ``waypoints``,
    ``steps``), validated and completed with the defaults for ``n`` robots in R^d; None for raw
    plans."""
    if refine is None:
        return None
    from .refine import check_parameters

    unknown = set(refine) - {"radius", "obstacle_radius", "waypoints", "steps"}
    if unknown:
        raise InputError(f"unknown refinement option(s) {sorted(unknown)}; expected radius, "
                         "obstacle_radius, waypoints and steps")
    radius, obstacle_radius, s, steps = check_parameters(
        refine.get("radius", 0.0), refine.get("obstacle_radius", 0.0), refine.get("waypoints"),
        refine.get("steps"), n=n, d=d)
    return {"radius": radius, "obstacle_radius": obstacle_radius, "waypoints": s, "steps": steps}


def _template(p, r: int, m: int, n: int, d: int, refine: dict | None, box: bool = False,
              width: int | None = None) -> dict:
    """Empty outputs (B = 0) of planner ``p``: their shapes past the batch axis, and the shared
    breakpoints. A plan in a box has ``width`` more breakpoints in every piece, per query
    (:func:`pmplan.workspace.path_into_box_linear`); a refined motion has ``(K - 1) waypoints +
    1`` breakpoints, less ``waypoints - 1`` per still piece (:meth:`Planner.still_for
    <pmplan.planners.base.Planner.still_for>`), with K those of the refinement's start (in a box,
    :func:`pmplan.running.box_start`: every raw piece cut into
    :data:`pmplan.workspace.RAW_CUTS`, or the plan itself)."""
    from .refine import subdivide_times
    from .workspace import RAW_CUTS

    template = p.allocate(0, r, m, n, d)
    times = np.asarray(template["times"], dtype=float)
    points = template["waypoints"].shape[2:]
    if box and (refine is None or times.ndim == 2):  # the plans themselves
        k = (times.shape[-1] - 1) * (width + 1) + 1
        times = np.empty((0, k))
    elif box:
        times = subdivide_times(times, RAW_CUTS)
    if refine is not None:
        s, k = refine["waypoints"], times.shape[-1]
        times = (subdivide_times(times, s, p.still_for(times)) if times.ndim == 1
                 else np.empty((0, (k - 1) * s + 1)))
    return {**template, "times": times, "waypoints": np.empty((0, times.shape[-1], *points))}


def _extra(refine: dict, measured: dict) -> dict:
    """The refinement record (:attr:`pmplan.PlanBatch._extra`) of lazy refined plans whose
    measured fields (robot and obstacle distance, radii respected: dask arrays) are
    ``measured``; the radii and the ``refined`` flag are constant dask arrays chunked alike."""
    da = _need("dask.array")
    rd = measured["robot_distance"]
    return {"radius": da.full(rd.shape, refine["radius"], chunks=rd.chunks),
            "obstacle_radius": da.full(rd.shape, refine["obstacle_radius"], chunks=rd.chunks),
            "refined": da.ones(rd.shape, dtype=bool, chunks=rd.chunks), **measured}


_ROWS = re.compile(r"(at index \(|query |`\w+\[)(\d+)")


def _shift_rows(msg: str, lo: int) -> str:
    """``msg`` with the rows it names (``at index (37, ...``, ``query 37``, ```start[37]``)
    counted in the whole batch: the chunk's rows shifted by its first row ``lo``."""
    return _ROWS.sub(lambda mo: f"{mo.group(1)}{int(mo.group(2)) + lo}", msg)


def _context(exc: PmplanError, lo: int, hi: int, where: str):
    """``exc`` again (same class) about rows of the whole batch: the query indices of a chunk's
    error are shifted by the chunk's first row ``lo``, and the chunk is named."""
    msg = str(exc)
    tail = f" [{where}: queries {lo}..{hi - 1} of the batch]"
    if isinstance(exc, CertificationError):
        idx = None if exc.indices is None else np.asarray(exc.indices) + lo
        if idx is not None and exc.indices is not None:
            old = np.asarray(exc.indices)
            more = "..." if old.size > 10 else ""
            msg = msg.replace(f"for queries {old[:10].tolist()}{more}",
                              f"for queries {idx[:10].tolist()}{more}", 1)
        return CertificationError(msg + tail, indices=idx)
    if isinstance(exc, CollisionError):
        idx = None if exc.index is None else exc.index + lo
        if idx is not None:
            msg = msg.replace(f"query {exc.index}", f"query {idx}", 1)
        return CollisionError(msg + tail, index=idx, which=exc.which, pair=exc.pair)
    msg = _shift_rows(msg, lo)
    try:
        return type(exc)(msg + tail)
    except TypeError:  # pragma: no cover - every pmplan error takes a message
        return exc


def _plan_chunk_arrays(obstacles, configs, planner, lift, backend, workers, refine=None,
                       bounds=None, width=None):
    """``plan_batch`` (r = 2) or ``plan_sequence_batch`` on one chunk of numpy arrays (in the
    workspace box ``bounds``, or None, with the raw paths' ``width`` fixed for the whole
    batch), then :func:`pmplan.refine` with the options ``refine`` (None: raw plans)."""
    batch = plan_arrays(obstacles, configs, planner=planner, lift=lift, backend=backend,
                        workers=workers, sequential=len(configs) > 2, bounds=bounds, width=width)
    if refine is None:
        return batch
    return refine_plans(batch, **refine, workers=workers, backend=backend)


def _width_block(obstacles, *configs, planner, lift, backend, workers, bounds,
                 block_info=None):
    """The first pass over one block of a lazy batch of raw plans in a box: (1,), the
    :func:`pmplan.running.box_width` of its queries."""
    lo = block_info[None]["array-location"][0][0] if block_info else 0
    width = _chunk_width(np.asarray(obstacles), [np.asarray(c) for c in configs], planner, lift,
                         backend, workers, bounds, lo, "dask block")
    return np.array([width], dtype=np.int64)


def _chunk_width(obstacles, configs, planner, lift, backend, workers, bounds, lo: int,
                 where: str) -> int:
    """:func:`pmplan.running.box_width` of one chunk of the first pass (rows ``lo`` on of the
    batch: its errors name them, and ``where``)."""
    try:
        return box_width(obstacles, configs, planner=planner, lift=lift, backend=backend,
                         workers=workers, sequential=len(configs) > 2, bounds=bounds)
    except PmplanError as exc:
        raise _context(exc, lo, lo + obstacles.shape[0], where) from None


def _plan_block(obstacles, *configs, planner, lift, backend, workers, record, refine=None,
                bounds=None, width=None, block_info=None):
    """One block of the lazy batch: its plans packed into ``record`` rows."""
    lo = block_info[None]["array-location"][0][0] if block_info else 0
    hi = lo + obstacles.shape[0]
    try:
        batch = _plan_chunk_arrays(np.asarray(obstacles), [np.asarray(c) for c in configs],
                                   planner, lift, backend, workers, refine, bounds, width)
    except PmplanError as exc:
        raise _context(exc, lo, hi, "dask block") from None
    out = np.empty(obstacles.shape[0], dtype=record)
    for name in record.names:
        out[name] = getattr(batch, name)
    return out


def _field(block: np.ndarray, name: str) -> np.ndarray:
    return np.ascontiguousarray(block[name])


def _lazy(obstacles, configs, names, planner, lift, backend, workers, sequential, refine=None,
          bounds=None):
    da, arrays = _dask_inputs([obstacles, *configs], names)
    obstacles, configs = arrays[0], arrays[1:]
    check_lift(lift)  # checked now, not at compute time
    workers = check_workers(workers)
    check_backend(backend)
    _, m, d = obstacles.shape
    n = configs[0].shape[1]
    refine = _refine_options(refine, n, d)
    for c, name in zip(configs, names[1:]):
        if c.shape[1:] != configs[0].shape[1:] or c.shape[2] != d:
            raise InputError(f"`{name}` has shape {c.shape}; expected (B, n, d) = "
                             f"({c.shape[0]}, {n}, {d})")
    if sequential:
        check_sequential(planner)
    p = choose_planner(d, n, m, planner, sequential=sequential, refining=refine is not None,
                       bounded=bounds is not None)
    box = _box(bounds, d)  # checked now
    width = None
    if _needs_width(p, len(configs), box, refine):  # the shapes of plans in a box: a first pass
        width = int(da.map_blocks(
            _width_block, obstacles, *configs, planner=p.name, lift=lift, backend=backend,
            workers=workers, bounds=box, dtype=np.int64, meta=np.empty((0,), np.int64),
            drop_axis=[1, 2], chunks=((1,) * len(obstacles.chunks[0]),),
            name="pmplan-box-width").max().compute())
    template = _template(p, len(configs), m, n, d, refine, box is not None, width)
    per_query_times = template["times"].ndim == 2
    record = _record(template, per_query_times, refine is not None)
    packed = da.map_blocks(
        _plan_block, obstacles, *configs, planner=p.name, lift=lift, backend=backend,
        workers=workers, record=record, refine=refine, bounds=box, width=width,
        dtype=record, meta=np.empty((0,), record), drop_axis=[1, 2],
        chunks=(obstacles.chunks[0],), name="pmplan-plan",
    )
    out = {}
    for name in record.names:
        shape = record.fields[name][0].shape
        base = record.fields[name][0].base
        out[name] = packed.map_blocks(
            _field, name, dtype=base, meta=np.empty((0,) * (1 + len(shape)), base),
            chunks=(packed.chunks[0], *((s,) for s in shape)),
            new_axis=list(range(1, 1 + len(shape))) or None, name=f"pmplan-{name}",
        )
    if not per_query_times:
        out["times"] = template["times"]
    extra = {}
    if refine is not None:
        extra = _extra(refine, {k: out.pop(k) for k in REFINED_OUTPUTS})
    if box is not None:
        extra["bounds"] = np.broadcast_to(box, (obstacles.shape[0], 2, d))
    return PlanBatch(planner=p.name, dims=(d, n, m), _extra=extra, **out)


def _needs_width(p, r: int, box, refine) -> bool:
    """Whether the output shapes of plans in the box ``box`` (or None) depend on how often their
    raw paths cross the nodes of the box's map (:func:`pmplan.workspace.path_into_box_linear`):
    raw plans, and refined plans of a planner without shared breakpoints (which the
    refinement starts from, :func:`pmplan.running.box_start`); and with
    :data:`pmplan.workspace.RAW_CUTS` > 1, whose start takes points of the plans, so that every
    chunk computes them as the whole batch does, bit for bit."""
    from . import workspace

    return box is not None and (refine is None or p.path_times(r) is None
                                or workspace.RAW_CUTS > 1)


def _box(bounds, d: int):
    """The workspace box (2, d) of the dask and Zarr paths (checked:
    :func:`pmplan.workspace.check_bounds`), or None."""
    return None if bounds is None else check_bounds(bounds, d)


def plan_batch(obstacles, start, goal, *, planner: str | None = None,
               lift: float | str | None = None,
               backend: str | None = None, workers: int = 1, progress: bool = False,
               out=None, refine: dict | None = None, bounds=None):
    """:func:`pmplan.plan_batch` on dask arrays: a PlanBatch of lazy dask arrays.

    ``obstacles`` (B, m, d), ``start`` and ``goal`` (B, n, d): dask arrays (a numpy array
    among them is chunked like the dask ones) of a real dtype, chunked along the batch axis
    only and all with the same batch chunks. Nothing is planned here: ``domain``, ``strata``,
    ``clearance``, ``waypoints`` (and ``times`` when per query) are dask arrays with the
    batch chunks of the input, built with ``map_blocks`` on one packed plan per block (so
    :func:`compute`, or ``dask.compute`` of several of them at once, plans every block once).
    Shared breakpoints ``times`` (K,) are a numpy array. Every block is
    :func:`pmplan.plan_batch` on its rows (``workers`` threads inside a block), so the result
    is bit for bit the numpy one, with any chunking and any scheduler. Errors of a block
    (an invalid query, a failed certificate) are raised at compute time, with the rows of the
    whole batch. To write several outputs, store them in one call (``dask.array.store`` of
    a list, or ``dask.compute``), which plans every block once, or stream with
    :func:`plan_store`. ``progress`` and ``out`` apply to numpy batches only. ``stratum`` names,
    indexing and iteration need the computed batch (:func:`compute`).

    ``refine``: the keywords of :func:`pmplan.refine` (``radius``, ``obstacle_radius``,
    ``waypoints``, ``steps``) to refine every block after planning it (what
    ``pmplan.plan_batch(..., refine=True)`` hands over); the lazy batch then also has the
    refinement record (``radius``, ``robot_distance``, ``respects_radius``, ...).
    ``bounds``: the workspace box of :func:`pmplan.plan_batch` (checked now, applied per
    block).

    Use the threaded scheduler on one machine (the numba kernels release the GIL) and
    processes or a ``dask.distributed`` cluster when Python-level work dominates (the numpy
    reference backend, many exactly degenerate queries) or to use several machines.
    """
    if out is not None:
        raise InputError("`out=` is for numpy batches; with dask arrays the result is lazy "
                         "(write it with dask.array.to_zarr, or use pmplan.scale.plan_store)")
    del progress  # dask's own diagnostics (e.g. dask.diagnostics.ProgressBar) report progress
    return _lazy(obstacles, [start, goal], ["obstacles", "start", "goal"], planner, lift,
                 backend, workers, sequential=False, refine=refine, bounds=bounds)


def plan_sequence_batch(obstacles, configs, *, lift: float | str | None = None,
                        backend: str | None = None, workers: int = 1, progress: bool = False,
                        out=None, refine: dict | None = None, bounds=None,
                        planner: str | None = None):
    """:func:`pmplan.plan_sequence_batch` on dask arrays (see :func:`plan_batch`)."""
    if out is not None:
        raise InputError("`out=` is for numpy batches; with dask arrays the result is lazy")
    del progress
    configs = list(configs)
    if len(configs) < 2:
        raise InputError(f"expected at least r = 2 configurations, got {len(configs)}")
    return _lazy(obstacles, configs, ["obstacles"] + [f"configs[{k}]" for k in range(len(configs))],
                 planner, lift, backend, workers, sequential=True, refine=refine, bounds=bounds)


def compute(batch, **kwargs):
    """A PlanBatch of dask arrays computed in one pass (every block planned once) into a
    PlanBatch of numpy arrays; ``kwargs`` go to :func:`dask.compute` (e.g. ``scheduler=``)."""
    import dask

    names = ["domain", "strata", "clearance", "waypoints", "times"]
    extra = sorted(batch._extra)
    values = dask.compute(*(getattr(batch, k) for k in names),
                          *(batch._extra[k] for k in extra), **kwargs)
    values = [np.asarray(v) for v in values]
    return PlanBatch(planner=batch.planner, dims=tuple(batch.dims),
                         _extra=dict(zip(extra, values[len(names):])),
                         **dict(zip(names, values)))


# ----------------------------------------------------------------------------------------------
# Zarr streaming


def is_store(path) -> bool:
    """Whether ``path`` names a Zarr store: a directory, or a name ending in ``.zarr``."""
    path = Path(path)
    return path.suffix == ".zarr" or path.is_dir()


@dataclass(frozen=True)
class StoreReport:
    """What :func:`plan_store` did."""

    path: Path
    planned: int          # chunks planned in this run
    skipped: int          # chunks already done (resume)
    chunks: int           # chunks in all
    queries: int          # queries planned in this run
    domains: dict         # label -> count, over the chunks planned in this run
    min_clearance: float  # over the chunks planned in this run (inf if none)
    planner: str
    respects_radius: int | None = None  # refined: plans of this run keeping the radii


@dataclass(frozen=True)
class _Spec:
    """Everything a chunk task needs (picklable, small)."""

    source: str | None      # path of the input store, or None: the rows come with the task
    out: str
    names: tuple            # input arrays: obstacles, start, [via], goal
    b: int
    chunk: int
    planner: str
    lift: object
    backend: str | None
    workers: int
    refine: dict | None = None  # the keywords of pmplan.refine, or None: raw plans
    bounds: list | None = None  # the workspace box [lo, hi] (lists of d floats), or None
    width: int | None = None  # raw plans in a box: the breakpoints added to every piece


def _open_input(path: Path):
    zarr = _need("zarr")
    try:
        group = zarr.open_group(str(path), mode="r")
    except Exception as exc:  # zarr raises several kinds for "not a store"
        raise InputError(f"cannot read {path} as a Zarr store: {exc}") from None
    present = set(group.array_keys())
    missing = [k for k in ("obstacles", "start", "goal") if k not in present]
    if missing:
        raise InputError(f"the Zarr store {path} lacks array(s) {missing} (it has "
                         f"{sorted(present)}); expected obstacles (B, m, d), start (B, n, d), "
                         "goal (B, n, d) and optional via (B, k, n, d)")
    unknown = present - {"obstacles", "start", "goal", "via"}
    if unknown:
        raise InputError(f"the Zarr store {path} has unknown array(s) {sorted(unknown)}; expected "
                         "obstacles, start, goal and optional via")
    return {k: group[k] for k in present}


def _check_inputs(arrays: dict, source: str, chunk: int | None):
    """Shapes, dtypes and batch chunks of the input arrays; returns (B, m, n, d, k, chunk)."""
    for k, a in arrays.items():
        if np.dtype(a.dtype).kind not in "iuf":
            raise InputError(f"array `{k}` in {source} has dtype {a.dtype}; coordinates must be "
                             "real numbers: write it as float64 (or an integer dtype)")
    o, s, g = arrays["obstacles"], arrays["start"], arrays["goal"]
    if o.ndim != 3 or s.ndim != 3 or s.shape != g.shape or o.shape[0] != s.shape[0] \
            or o.shape[2] != s.shape[2]:
        raise InputError(f"{source}: obstacles {o.shape}, start {s.shape}, goal {g.shape}; "
                         "expected (B, m, d), (B, n, d), (B, n, d)")
    b, m, d = o.shape
    n = s.shape[1]
    k = 0
    if "via" in arrays:
        v = arrays["via"]
        if v.ndim != 4 or v.shape[0] != b or v.shape[2:] != s.shape[1:]:
            raise InputError(f"array `via` in {source} has shape {v.shape}; expected (B, k, n, d)"
                             f" = ({b}, k, {n}, {d})")
        k = v.shape[1]
    if chunk is None:
        chunks = {name: getattr(a, "chunks", None) for name, a in arrays.items()}
        batch_chunks = {name: c[0] for name, c in chunks.items() if c is not None}
        if batch_chunks:
            if len(set(batch_chunks.values())) > 1:
                raise InputError(
                    f"the arrays of {source} are chunked differently along the batch axis "
                    f"({batch_chunks}); rewrite them with the same chunks along axis 0, or give "
                    "--chunk N (queries per chunk)")
            chunk = next(iter(batch_chunks.values()))
        else:
            chunk = DEFAULT_CHUNK
    return b, m, n, d, k, int(chunk)


def _read_rows(arrays: dict, lo: int, hi: int):
    """(obstacles, configs) of rows lo:hi."""
    o = np.asarray(arrays["obstacles"][lo:hi])
    configs = [np.asarray(arrays["start"][lo:hi])]
    if "via" in arrays:
        via = np.asarray(arrays["via"][lo:hi])
        configs += [via[:, j] for j in range(via.shape[1])]
    configs.append(np.asarray(arrays["goal"][lo:hi]))
    return o, configs


def _fingerprint(rows) -> np.ndarray:
    """SHA-256 of one chunk's input, (32,) uint8: the shapes and the float64 bytes of the
    obstacles and of every configuration (start, vias, goal), in that order. Two inputs with the
    same fingerprint give the same plans; the store keeps one per chunk (``inputs``) so that a
    resume can refuse an input that differs from the one a done chunk was planned from."""
    obstacles, configs = rows
    h = hashlib.sha256()
    for a in (obstacles, *configs):
        a = np.ascontiguousarray(a, dtype=np.float64)
        h.update(repr(a.shape).encode())
        h.update(a.tobytes())
    return np.frombuffer(h.digest(), dtype=np.uint8)


def _chunk_stats(i: int, domain, clearance, respects) -> tuple:
    labels, counts = np.unique(np.asarray(domain), return_counts=True)
    clearance = np.asarray(clearance)
    clr = float(clearance.min()) if clearance.size else float("inf")
    kept = None if respects is None else int(np.asarray(respects).sum())
    return i, clearance.size, dict(zip(labels.tolist(), counts.tolist())), clr, kept


def _run_chunk(spec: _Spec, i: int, rows=None, group=None):
    """Plan chunk ``i`` and write it: the outputs, then the input's fingerprint, then
    ``done[i]``. Returns (i, rows, domain counts, min clearance, plans keeping the radii or None
    when not refined). Runs in-process or as a dask.distributed task.

    A chunk already marked done with the same input (a task run again because the worker that
    held its result died) is not planned again: its summary is read back from the store.
    """
    zarr = _need("zarr")
    lo, hi = _rows(spec, i)
    try:
        if rows is None:
            rows = _read_rows(_open_input(Path(spec.source)), lo, hi)
        if group is None:
            group = zarr.open_group(spec.out, mode="r+")
    except (InputError, OSError) as exc:
        raise _unreachable(spec, i, exc, resumable=True) from None
    fingerprint = _fingerprint(rows)
    refined = spec.refine is not None
    if bool(group["done"][i]) and np.array_equal(group["inputs"][i], fingerprint):
        return _chunk_stats(i, group["domain"][lo:hi], group["clearance"][lo:hi],
                            group["respects_radius"][lo:hi] if refined else None)
    obstacles, configs = rows
    planner = spec.planner  # (the store's planner, sequential when r > 2)
    try:
        batch = _plan_chunk_arrays(obstacles, configs, planner, spec.lift, spec.backend,
                                   spec.workers, spec.refine,
                                   None if spec.bounds is None else np.array(spec.bounds),
                                   spec.width)
    except PmplanError as exc:
        raise _context(exc, lo, hi, f"chunk {i}") from None
    for name in OUTPUTS + (REFINED_OUTPUTS if refined else ()):
        a = getattr(batch, name)
        if name == "times" and a.ndim == 1:
            continue  # shared breakpoints, written once when the store was created
        if name == "raw_clearance" and name not in group:
            continue  # a refined store created before the raw clearance was kept
        group[name][lo:hi] = a
    group["inputs"][i] = fingerprint
    group["done"][i] = True
    return _chunk_stats(i, batch.domain, batch.clearance,
                        batch.respects_radius if refined else None)


def compressors(compress: bool = True):
    """The codecs of a store's arrays: zstd at level :data:`ZSTD_LEVEL`, or none."""
    zarr = _need("zarr")
    return (zarr.codecs.ZstdCodec(level=ZSTD_LEVEL),) if compress else None


def _create_arrays(group, template: dict, b: int, chunk: int, nchunks: int, compress: bool,
                   refined: bool) -> None:
    c = max(1, min(chunk, b))
    comp = compressors(compress)
    names = ["domain", "strata", "clearance", "waypoints"]
    if refined:
        template = {**template, "robot_distance": np.empty(0), "obstacle_distance": np.empty(0),
                    "respects_radius": np.empty(0, dtype=bool), "raw_clearance": np.empty(0)}
        names += list(REFINED_OUTPUTS)
    for name in names:
        t = template[name]
        group.create_array(name, shape=(b, *t.shape[1:]), chunks=(c, *t.shape[1:]),
                           dtype=t.dtype, fill_value=0, compressors=comp)
    t = template["times"]
    if t.ndim == 1:
        group.create_array("times", shape=t.shape, chunks=t.shape, dtype=t.dtype, fill_value=0)
        group["times"][...] = t
    else:
        group.create_array("times", shape=(b, *t.shape[1:]), chunks=(c, *t.shape[1:]),
                           dtype=t.dtype, fill_value=0, compressors=comp)
    # one Zarr chunk per entry: workers finishing different chunks never write the same file
    group.create_array("inputs", shape=(nchunks, 32), chunks=(1, 32), dtype=np.uint8,
                       fill_value=0)
    group.create_array("done", shape=(nchunks,), chunks=(1,), dtype=bool, fill_value=False)


def _creating(out: Path) -> str:
    """The prefix of the hidden sibling directories in which ``out`` is created."""
    return f".{out.name}.creating-"


def _remove_stale(out: Path) -> None:
    """Remove the hidden creation directories of ``out`` left by a process that died (SIGKILL,
    power loss) while it created the store; those of a live process are left alone."""
    for tmp in out.parent.glob(_creating(out) + "*"):
        try:
            os.kill(int(tmp.name.rsplit("-", 1)[1]), 0)
        except (ValueError, ProcessLookupError):
            shutil.rmtree(tmp, ignore_errors=True)
        except PermissionError:  # pragma: no cover - another user's live process
            pass


def _create_output(out: Path, attrs: dict, template: dict, b: int, chunk: int, nchunks: int,
                   compress: bool = True):
    """Create the output store whole or not at all: it is built in a hidden sibling directory
    and renamed to ``out`` once every array and attribute is written, so a crash while creating
    it leaves no ``out`` (and the next run removes the hidden directory)."""
    zarr = _need("zarr")
    _remove_stale(out)
    tmp = out.with_name(f"{_creating(out)}{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)  # this process's own, from an attempt cut short
    try:
        group = zarr.open_group(str(tmp), mode="w-")
        _create_arrays(group, template, b, chunk, nchunks, compress,
                       attrs.get("refine") is not None)
        group.attrs.update({**attrs, "complete": False})
        os.rename(tmp, out)
    except OSError as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        raise StoreError(_MSG_CREATE.format(out=out, cause=_os_text(exc), fix=_os_fix(exc)),
                         path=out) from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return zarr.open_group(str(out), mode="r+")


def _attrs(planner, lift, dims, r, b, chunk, refine=None, compress=True, bounds=None) -> dict:
    from .version import __version__

    return {"format": FORMAT, "planner": planner, "lift": lift, "pmplan_version": __version__,
            "dims": list(dims), "r": r, "B": b, "chunk": chunk, "refine": refine,
            "compress": bool(compress), "bounds": bounds}


# ----------------------------------------------------------------------------------------------
# what a failed run says: the store, and whether --resume finishes it

#: the option of ``pmplan batch`` (and the keyword of :func:`plan_store`) behind each attribute
_OPTIONS = {"planner": "--planner (planner=)", "lift": "--lift (lift=)",
            "chunk": "--chunk (chunk=)", "compress": "--no-compress (compress=)",
            "refine": "--refine, --radius, --obstacle-radius, --waypoints, --steps (refine=)",
            "bounds": "--bounds (bounds=)",
            "B": "the number of queries in the input", "dims": "the input's (d, n, m)",
            "r": "the input's configurations per query (via)", "format": "the store's format"}
_MSG_CREATE = "cannot create the output store {out}: {cause}; nothing was written: {fix}"
_MSG_INCOMPLETE = "{out} is incomplete ({done} of {total} chunks written): {fix}"
_MSG_FIRST_PASS = ("the dask cluster failed during the first pass over the input, which fixes "
                   "the shapes of plans in a workspace box ({cause}); nothing was written to "
                   "{out}: rerun (a running scheduler, or no --scheduler to plan in this "
                   "process)")
_MSG_UNREACHABLE = ("chunk {i} could not open its stores on host {host} ({cause}); every worker "
                    "must see the input and output stores at the same absolute paths")
_MSG_DIFFERENT_INPUT = (
    "cannot resume {out}: the input differs from the one it was planned from in {count} done "
    "chunk(s) {chunks}{more} (queries {rows}); resuming would mix the plans of two inputs in "
    "one store: resume with the original input, or plan this one into another --out")
_MSG_OTHER_RUN = ("cannot resume {out}: it was written with other options ({diff}); rerun with "
                  "the options it was written with, or choose another --out")
_MSG_NOT_A_STORE = ("cannot resume {out}: it is not a pmplan output store of this version "
                    "({why}); remove it (or choose another --out) and run again")


def _os_text(exc: OSError) -> str:
    where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
    return f"{exc.strerror or exc}{where}"


def _os_fix(exc: OSError) -> str:
    if exc.errno == errno.ENOSPC:
        return "free disk space"
    if exc.errno in (errno.EROFS, errno.EACCES, errno.EPERM):
        return "make the directory writable or choose another --out"
    return "fix the cause"


def _done_count(group) -> int | str:
    try:
        return int(np.asarray(group["done"][:]).sum())
    except Exception:  # noqa: BLE001 - the store may be unreadable now; say so, not crash
        return "?"


def _is_cluster_error(exc: BaseException) -> bool:
    """A failure of the dask cluster (scheduler lost, workers killed, cancelled tasks), told
    apart from the queries' errors and the disk's by where its class comes from."""
    import concurrent.futures

    return isinstance(exc, (concurrent.futures.CancelledError, TimeoutError)) or \
        type(exc).__module__.split(".")[0] in ("distributed", "tornado")


def _failure(exc: BaseException, out: Path, group, nchunks: int) -> BaseException | None:
    """The one-line error of a run stopped by ``exc``, naming the store and what finishes it;
    None for an exception passed on as it is (Ctrl-C, a bug)."""
    done = _done_count(group)
    if isinstance(exc, StoreError):  # creating the store (not resumable) or a chunk's stores
        if not exc.resumable:
            return exc
        return StoreError(f"{exc}; " + _MSG_INCOMPLETE.format(
            out=out, done=done, total=nchunks, fix="fix that, then rerun with --resume"),
            path=out, resumable=True)
    if isinstance(exc, PmplanError):  # a query: its rows are in the message
        text = _MSG_INCOMPLETE.format(out=out, done=done, total=nchunks,
                                      fix="fix the input and rerun with --resume")
        exc.args = (f"{exc}; {text}",)
        return exc
    if _is_cluster_error(exc):
        cause = f"the dask cluster failed ({type(exc).__name__}: {exc})"
        fix = ("rerun with --resume (the chunks written are kept; a running scheduler, or no "
               "--scheduler to plan in this process)")
    elif isinstance(exc, OSError):
        cause = f"writing {out} failed: {_os_text(exc)}"
        fix = f"{_os_fix(exc)}, then rerun with --resume"
    else:
        return None
    return StoreError(f"{cause}; " + _MSG_INCOMPLETE.format(out=out, done=done, total=nchunks,
                                                           fix=fix), path=out, resumable=True)


# ----------------------------------------------------------------------------------------------
# plan_store


def _source_arrays(source, out: Path, lift, planner):
    """(arrays, path of the input store or None, its name, lift, planner) of ``source``."""
    if isinstance(source, dict):
        arrays = {k: np.asarray(source[k]) for k in ("obstacles", "start", "goal", "via")
                  if k in source}
        for k in ("lift", "planner"):
            if source.get(k) is not None:
                mine = lift if k == "lift" else planner
                if mine is not None and mine != source[k]:
                    raise InputError(f"{k} {mine!r} contradicts {k} {source[k]!r} in the input")
        if source.get("bounds") is not None:  # (a JSON list's box: plan_store's `bounds`)
            raise InputError("give the workspace box of a streamed batch as `bounds=` "
                             "(--bounds), not in the input")
        return (arrays, None, "the input", source.get("lift", lift),
                source.get("planner", planner))
    src_path = Path(source).resolve()  # absolute: workers may run in another directory
    if src_path == out:
        raise InputError(f"the input and the output are the same store {out}")
    return _open_input(src_path), src_path, str(source), lift, planner


def _open_for_resume(out: Path, attrs: dict, resume: bool):
    """The existing output store ``out`` to resume (checked against this run's ``attrs``), or
    None when there is none."""
    zarr = _need("zarr")
    if not out.exists():
        return None
    if not resume:
        raise InputError(f"the output {out} already exists; pass --resume to finish an "
                         "interrupted run into it, or remove it / choose another --out")
    try:
        group = zarr.open_group(str(out), mode="r+")
        old = dict(group.attrs)
        keys = set(group.array_keys())
    except Exception as exc:  # noqa: BLE001 - zarr raises several kinds for "not a store"
        raise InputError(_MSG_NOT_A_STORE.format(out=out, why=" ".join(str(exc).split()))) \
            from None
    if old.get("format") != FORMAT or not {"done", "inputs"} <= keys:
        why = (f"format {old.get('format')!r}, expected {FORMAT!r}" if old.get("format")
               else "it has no pmplan attributes")
        if old.get("format") == "pmplan-plans-1":
            why += ": an older pmplan wrote it without the fingerprints of its inputs, so a " \
                   "resume could not check them"
        raise InputError(_MSG_NOT_A_STORE.format(out=out, why=why))
    diff = [f"{_OPTIONS.get(k, k)}: stored {old.get(k)!r}, now {v!r}"
            for k, v in attrs.items() if k != "pmplan_version" and old.get(k) != v]
    if diff:
        raise InputError(_MSG_OTHER_RUN.format(out=out, diff="; ".join(diff)))
    try:
        for partial in out.rglob("*.partial"):  # writes cut short (Zarr writes, then renames)
            partial.unlink(missing_ok=True)
    except OSError as exc:
        raise StoreError(f"cannot resume {out}: {_os_text(exc)}; " + _MSG_INCOMPLETE.format(
            out=out, done=_done_count(group), total=group["done"].shape[0],
            fix=f"{_os_fix(exc)}, then rerun with --resume"), path=out, resumable=True) \
            from None
    return group


def _check_fingerprints(group, arrays: dict, b: int, chunk: int, out: Path) -> None:
    """Refuse a resume whose input differs, in any chunk already done, from the input that
    chunk was planned from."""
    done = np.flatnonzero(np.asarray(group["done"][:]))
    stored = np.asarray(group["inputs"][:])
    bad = [int(i) for i in done
           if not np.array_equal(
               stored[i], _fingerprint(_read_rows(arrays, i * chunk, min(b, (i + 1) * chunk))))]
    if bad:
        rows = ", ".join(f"{i * chunk}..{min(b, (i + 1) * chunk) - 1}" for i in bad[:10])
        raise InputError(_MSG_DIFFERENT_INPUT.format(
            out=out, count=len(bad), chunks=bad[:10], more="..." if len(bad) > 10 else "",
            rows=rows + (", ..." if len(bad) > 10 else "")))


def plan_store(source, out, *, planner: str | None = None, lift: float | str | None = None,
               chunk: int | None = None, resume: bool = False, scheduler: str | None = None,
               dask_workers: int | None = None, workers: int = 1, backend: str | None = None,
               progress: bool = False, compress: bool = True,
               on_chunk: Callable[[int, int, int], None] | None = None,
               refine: dict | None = None, bounds=None) -> StoreReport:
    """Plan a batch from a Zarr store (or in-memory arrays) into a Zarr store, chunk by chunk.

    Parameters
    ----------
    source : path or dict
        A Zarr group with arrays ``obstacles`` (B, m, d), ``start``, ``goal`` (B, n, d) and
        optional ``via`` (B, k, n, d); or a dict of such numpy arrays (an npz read by
        :func:`pmplan.io.read_queries`, whose ``lift`` and ``planner`` are honoured).
    out : path
        The output Zarr store (see the module docstring for its arrays and attributes).
    chunk : int, optional
        Queries per chunk; default: the input store's chunks along the batch axis (which must
        then be the same for every array), or 65536 for in-memory input.
    resume : bool
        Continue an existing output: plan only the chunks not marked done. Without it an
        existing ``out`` is an error (and is left untouched). The options must be those the
        store was written with, and the input of every chunk already done must be the one it
        was planned from (its fingerprint, :func:`_fingerprint`); rows of chunks not yet done
        may differ (the fixed input of an interrupted run).
    scheduler, dask_workers : optional
        Plan the chunks as tasks on the dask.distributed scheduler at this address, or on a
        LocalCluster of this many worker processes (one thread each), and, for raw plans in a
        box, the first pass that fixes the store's shapes (one task per chunk). The workers
        read the input store and write the output store themselves (both sent as absolute
        paths), so they must see the same files (one machine, or a shared filesystem).
        Default: in this process.
    workers : int
        Threads per chunk (as in :func:`pmplan.plan_batch`).
    compress : bool
        Compress the output chunks (zstd at level :data:`ZSTD_LEVEL`: about half the disk);
        False writes them raw. A compressed run is bound by the compression, an uncompressed
        one by the disk (``benchmarks/store_breakdown.py`` times plan, compress and write).
    on_chunk : callable, optional
        Called as ``on_chunk(i, done, total)`` after chunk ``i`` is written and marked done.
    refine : dict, optional
        Refine every chunk after planning it (:func:`pmplan.refine`; ``pmplan batch
        --refine``): its keywords ``radius``, ``obstacle_radius``, ``waypoints``, ``steps``
        (the defaults for those not given). The store then holds the refined motions and
        :data:`REFINED_OUTPUTS`; ``resume`` needs the same options.

    Returns
    -------
    StoreReport

    Raises
    ------
    InputError
        For a missing or malformed input (missing arrays, wrong dtype, mismatched chunks),
        an existing output without ``resume``, or one that does not match this run (options,
        or the input of a chunk already done); nothing is written then. An invalid query or a
        failed certificate stops the run with the rows of the batch named; the chunks already
        written stay marked done, the output stays incomplete, and the message says so.
    StoreError
        The disk (full, read-only) or the dask cluster (scheduler lost, workers killed)
        stopped the run: the message names the store, how many chunks it holds, and whether
        ``resume`` finishes it. A store is created whole or not at all.
    """
    out = Path(out).resolve()
    arrays, src_path, src_name, lift, planner = _source_arrays(source, out, lift, planner)
    if chunk is not None and (isinstance(chunk, bool) or int(chunk) < 1):
        raise InputError(f"`chunk` must be a positive number of queries, got {chunk!r}")
    b, m, n, d, k, chunk = _check_inputs(arrays, src_name, chunk)
    refine = _refine_options(refine, n, d)
    lift = default_lift(lift, *(() if refine is None else
                                (refine["radius"], refine["obstacle_radius"], True)))
    check_lift(lift)
    workers = check_workers(workers)
    check_backend(backend)
    r = k + 2
    if r > 2:
        check_sequential(planner)
    p = choose_planner(d, n, m, planner, sequential=r > 2, refining=refine is not None,
                       bounded=bounds is not None)
    nchunks = -(-b // chunk)
    box = _box(bounds, d)
    box = None if box is None else box.tolist()
    attrs = _attrs(p.name, lift if isinstance(lift, str) else float(lift), (d, n, m), r, b,
                   chunk, refine, compress, box)
    if out.suffix != ".zarr":
        raise InputError(f"the output {out} must be a Zarr store: give it the suffix .zarr")
    group = _open_for_resume(out, attrs, resume)
    if group is not None:
        _check_fingerprints(group, arrays, b, chunk, out)
    spec = _Spec(source=None if src_path is None else str(src_path), out=str(out),
                 names=tuple(arrays), b=b, chunk=chunk, planner=p.name, lift=lift,
                 backend=backend, workers=workers, refine=refine, bounds=box)
    # connect before anything is written: an unreachable scheduler leaves no output behind
    client, cluster, owned = (None, None, False) if scheduler is None and dask_workers is None \
        else _connect(scheduler, dask_workers)
    # the rows sent with a chunk's task (None: the task reads them from the input store)
    rows_of = None if src_path is not None else (lambda i: _read_rows(arrays, *_rows(spec, i)))
    if _needs_width(p, r, box, refine):  # the shapes of plans in a box
        try:
            width = group.attrs["box_width"] if group is not None else \
                _store_width(spec, arrays, nchunks, client, rows_of)
        except BaseException as exc:
            _disconnect(client, cluster, owned)
            if _is_cluster_error(exc):
                raise StoreError(_MSG_FIRST_PASS.format(
                    out=out, cause=f"{type(exc).__name__}: {exc}"), path=out,
                    resumable=False) from None
            raise
        spec = dataclasses.replace(spec, width=width)
    stopped = None
    try:
        if group is None:
            group = _create_output(out, {**attrs, "box_width": spec.width},
                                   _template(p, r, m, n, d, refine, box is not None,
                                             spec.width), b, chunk, nchunks, compress)
        summary = _run(spec, group, client, rows_of, nchunks, progress, on_chunk)
    except Exception as exc:  # told once the cluster is closed: the count of chunks is final
        stopped = exc
    finally:
        _disconnect(client, cluster, owned)
    if stopped is not None:
        failure = _failure(stopped, out, group, nchunks)
        if failure is None:
            raise stopped
        raise failure from None
    if bool(np.asarray(group["done"][:]).all()):
        group.attrs["complete"] = True
    return StoreReport(out, summary["planned"], nchunks - summary["planned"], nchunks,
                       summary["queries"], summary["domains"], summary["clearance"], p.name,
                       summary["kept"])


def _store_width(spec: _Spec, arrays: dict, nchunks: int, client, rows_of) -> int:
    """The first pass of :func:`plan_store` for raw plans in a box: the largest
    :func:`pmplan.running.box_width` over the chunks (the raw plans only, not certified nor
    written), which fixes the shapes of the store's ``times`` and ``waypoints``. Chunk by chunk
    in this process (the rows read from ``arrays``), or one task per chunk on ``client``'s
    cluster (:func:`_distributed`), as the chunks are planned after it."""
    if client is None:
        return max(_width_task(spec, i, _read_rows(arrays, *_rows(spec, i)))
                   for i in range(nchunks))
    widths: list = []
    _distributed(client, _width_task, spec, range(nchunks), rows_of, widths.append)
    return max(widths)


def _unreachable(spec: _Spec, i: int, cause: BaseException, resumable: bool) -> StoreError:
    """The error of chunk ``i``'s task that could not open its stores on its host (resumable
    once the output exists, not in the first pass, before anything is written)."""
    import socket

    return StoreError(_MSG_UNREACHABLE.format(host=socket.gethostname(), i=i, cause=cause),
                      path=spec.out, resumable=resumable)


def _rows(spec: _Spec, i: int) -> tuple[int, int]:
    """The rows ``lo, hi`` of chunk ``i``."""
    return i * spec.chunk, min(spec.b, (i + 1) * spec.chunk)


def _width_task(spec: _Spec, i: int, rows=None) -> int:
    """The first pass over chunk ``i`` (:func:`_store_width`): its rows (read from the input
    store when not given), their :func:`pmplan.running.box_width`. Runs in-process or as a
    dask.distributed task."""
    lo, hi = _rows(spec, i)
    if rows is None:
        try:
            rows = _read_rows(_open_input(Path(spec.source)), lo, hi)
        except (InputError, OSError) as exc:
            raise _unreachable(spec, i, exc, resumable=False) from None
    obstacles, configs = rows
    return _chunk_width(obstacles, configs, spec.planner, spec.lift, spec.backend,
                        spec.workers, np.array(spec.bounds), lo, f"chunk {i}")


def _run(spec: _Spec, group, client, rows_of, nchunks: int, progress: bool, on_chunk) -> dict:
    """Plan the chunks not yet done, in this process or on ``client``'s cluster; the summary
    of this run (chunks and queries planned, domain counts, min clearance, radii kept)."""
    todo = np.flatnonzero(~np.asarray(group["done"][:])).tolist()
    state = {"planned": len(todo), "done": nchunks - len(todo), "queries": 0,
             "clearance": float("inf"), "kept": 0 if spec.refine is not None else None,
             "domains": {}}
    bar = None
    if progress and todo:
        from tqdm import tqdm

        bar = tqdm(total=nchunks, initial=nchunks - len(todo), desc="planning", unit="chunk",
                   file=sys.stderr)

    def record(result):
        i, q, counts, clr, kept = result
        if kept is not None:
            state["kept"] += kept
        state["done"] += 1
        state["queries"] += q
        state["clearance"] = min(state["clearance"], clr)
        for label, c in counts.items():
            state["domains"][label] = state["domains"].get(label, 0) + c
        if bar is not None:
            bar.update()
        if on_chunk is not None:
            on_chunk(i, state["done"], nchunks)

    try:
        if client is None:
            for i in todo:
                record(_run_chunk(spec, i, None if rows_of is None else rows_of(i), group))
        else:
            _distributed(client, _run_chunk, spec, todo, rows_of, record)
    finally:
        if bar is not None:
            bar.close()
    return state


def _connect(scheduler: str | None, dask_workers: int | None):
    """(client, cluster, owned): this process's default client when it already talks to the
    scheduler at ``scheduler`` (not ours to close), else a new client of that scheduler, or of
    a new LocalCluster of ``dask_workers`` worker processes (one thread each, its logs
    silenced: a failing chunk is reported once, by pmplan)."""
    distributed = _need("distributed")
    if scheduler is not None:
        try:
            current = distributed.default_client()
        except ValueError:
            current = None
        if current is not None and current.scheduler.address == scheduler \
                and current.status == "running":
            return current, None, False
        try:
            return distributed.Client(scheduler), None, True
        except (OSError, ValueError) as exc:
            raise InputError(f"cannot reach the dask scheduler {scheduler}: {exc}; nothing was "
                             "written") from None
    cluster = distributed.LocalCluster(n_workers=dask_workers, threads_per_worker=1,
                                       processes=True, dashboard_address=":0",
                                       silence_logs=logging.CRITICAL)
    return distributed.Client(cluster), cluster, True


def _disconnect(client, cluster, owned: bool) -> None:
    """Close what :func:`_connect` opened; a client whose scheduler is gone closes quietly."""
    import contextlib

    with contextlib.suppress(Exception):
        if owned:
            client.close(timeout=5)
        if cluster is not None:
            cluster.close(timeout=5)


def _distributed(client, task, spec: _Spec, todo, rows_of, record) -> None:
    """Run ``task(spec, i, rows)`` for the chunks ``todo`` on a dask.distributed cluster (the
    chunks' planning, :func:`_run_chunk`, or the first pass, :func:`_width_task`); ``record``
    each result as it comes.

    The future of a finished chunk is released at once, so a worker that dies later does not
    make the scheduler compute that chunk again; a task whose worker dies before it finishes is
    run again on another worker (and a task that finds its chunk already done with the same
    input reads its summary back instead of planning it). Nothing half-written is ever marked
    done.
    """
    distributed = _need("distributed")
    pending = {client.submit(task, spec, i, None if rows_of is None else rows_of(i),
                             pure=False) for i in todo}
    try:
        for fut in distributed.as_completed(pending):
            result = fut.result()
            pending.discard(fut)
            fut.release()
            record(result)
    except BaseException:
        import contextlib

        with contextlib.suppress(Exception):
            client.cancel(list(pending))
        raise


def open_plans(path):
    """The plans of a complete output store as a PlanBatch of lazy dask arrays.

    Raises InputError for a store that is not a pmplan output or is incomplete (an
    interrupted run: finish it with ``pmplan batch IN --out OUT --resume``).
    """
    zarr = _need("zarr")
    da = _need("dask.array")
    try:
        group = zarr.open_group(str(path), mode="r")
        attrs = dict(group.attrs)
    except Exception as exc:
        raise InputError(f"cannot read {path} as a Zarr store: {exc}") from None
    if attrs.get("format") not in READABLE_FORMATS:
        raise InputError(f"{path} is not a pmplan output store (format {attrs.get('format')!r})")
    done = np.asarray(group["done"][:])
    if not attrs.get("complete") or not done.all():
        raise InputError(f"{path} is incomplete ({int(done.sum())} of {done.size} chunks "
                         "written): finish it with pmplan batch IN --out OUT --resume")
    arrays = {k: da.from_zarr(group[k]) for k in OUTPUTS}
    if arrays["times"].ndim == 1:
        arrays["times"] = np.asarray(group["times"][:])
    d, n, m = attrs["dims"]
    extra = {}
    refine = attrs.get("refine")
    if refine is not None:
        # (a refined store created before the raw clearance was kept has none: NaN)
        extra = _extra(refine, {k: da.from_zarr(group[k]) for k in REFINED_OUTPUTS
                                if k in group})
    if attrs.get("bounds") is not None:
        extra["bounds"] = np.broadcast_to(np.array(attrs["bounds"]), (attrs["B"], 2, d))
    return PlanBatch(planner=attrs["planner"], dims=(d, n, m), _extra=extra, **arrays)
