"""The command line: thin over the library (``pmplan --help``).

Every command parses its arguments, reads input, calls one public function and writes output.
Errors from pmplan (and unreadable files) are printed on one line to stderr with exit status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

__all__ = ["main", "build_parser"]

EPILOG = """\
commands and examples:
  pmplan demo                              plan one query per domain, raw and refined, print
                                           a table, draw a PNG
  pmplan plan query.json                   plan one query (JSON or npz in, JSON out)
  pmplan plan query.json --samples 50      ... printing 50 equally spaced samples
  pmplan plan query.json --lift scene      ... with the scene-scaled unit instead of lift 1
  pmplan plan query.json --refine --radius 0.05   ... refined: shorter, robots discs of radius
                                           0.05, same domain of continuity, certified
  pmplan batch queries.npz --out plans.npz plan many queries (npz arrays obstacles/start/goal)
  pmplan batch in.zarr --out plans.zarr --dask-workers 2   ... streamed, Zarr to Zarr, on dask
  pmplan info --d 2 --n 3 --m 2 [--r 3]    planner, number of domains, TC, optimality
  pmplan figures --out docs/figures        the paper's Section 4 figures from the planner
  pmplan animate query.json --out m.gif    animate a planned motion (.gif, or .mp4 with ffmpeg)
  pmplan animate query.json --refine --radius 0.2   ... a refined motion, robots as discs
  pmplan verify --d 2 --n 3 --m 2          check certificates and continuity per domain
  pmplan verify --d 2 --n 3 --m 2 --refine ... and the refined planner's, beside them
  pmplan explore                           the domains of continuity, live, in a browser

query.json: {"obstacles": [[0,0],[4,0]], "start": [[1,1]], "goal": [[3,-1]]}
  optional: "via": [[[2,2]]] (intermediate configurations), "lift": 1.0, "planner": "..."
A command-line option and the same key in the file must agree (or give only one of them).
Errors: one line on standard error, exit status 2.
"""

LIFT_HELP = ("unit of the lift: a positive number or 'scene' (a unit scaled with the "
             "obstacles); default: the robots' diameter for a refined motion, else 1 (the "
             "paper's unit)")

#: the options of a refined motion (``pmplan.refine``) other than ``--refine``, by dest
REFINE_OPTIONS = ("radius", "obstacle_radius", "waypoints", "steps")


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr with exit status 2."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _int_in(lo: int, hi: int | None = None, *, also: tuple[int, ...] = ()):
    """An argparse ``type``: an integer in [lo, hi] (or one of ``also``), else one clear line."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value in also or (value >= lo and (hi is None or value <= hi)):
            return value
        rng = f"at least {lo}" if hi is None else f"between {lo} and {hi:,}"
        extra = "".join(f" or {a}" for a in also)
        raise argparse.ArgumentTypeError(f"must be {rng}{extra}, got {value:,}")

    return parse


def _lift(text: str):
    """An argparse ``type`` for ``--lift``: the word ``scene``, or a number (the API checks it)."""
    if text == "scene":
        return "scene"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected a positive number or the word 'scene', got {text!r}") from None


def _number(text: str) -> float:
    """An argparse ``type``: a number (the API checks its range: one source of the rule)."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def _integer(text: str) -> int:
    """An argparse ``type``: an integer (the API checks its range: one source of the rule)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def _add_refine_options(p) -> None:
    """``--refine``, ``--radius``, ``--obstacle-radius`` (and ``--waypoints``, ``--steps``)."""
    from .refine import (CROWD, CROWD_STEPS, CROWD_WAYPOINTS, DEFAULT_STEPS, DEFAULT_WAYPOINTS,
                         MAX_STEPS, MAX_WAYPOINTS, PLANE_STEPS, SETTLE, SPACE_CROWD_STEPS)

    p.add_argument("--refine", action="store_true",
                   help="refine the planned path (pmplan.refine): a fixed number of continuous, "
                   "collision-free shortening and clearing steps; the same domain of continuity, "
                   "certified again (docs/refinement.md)")
    p.add_argument("--radius", type=_number, default=None, metavar="R",
                   help="with --refine: the robots are discs (balls) of radius R >= 0, kept "
                   "2R apart where the refinement can (the output says whether it holds; "
                   "default 0)")
    p.add_argument("--obstacle-radius", type=_number, default=None, metavar="R",
                   help="with --refine: the obstacles are discs (balls) of radius R >= 0, robots "
                   "kept radius + R from them where the refinement can (default 0)")
    p.add_argument("--waypoints", type=_integer, default=None, metavar="S",
                   help="with --refine: sub-pieces per piece of the raw path, a power of two "
                   f"from 1 to {MAX_WAYPOINTS} (default {DEFAULT_WAYPOINTS}"
                   + ("" if CROWD_WAYPOINTS == DEFAULT_WAYPOINTS else
                      f"; {CROWD_WAYPOINTS} for more than {CROWD} robots") + ")")
    p.add_argument("--steps", type=_integer, default=None, metavar="K",
                   help=f"with --refine: number of refinement steps, 1 to {MAX_STEPS:,} "
                   f"(default {DEFAULT_STEPS}; in the plane {PLANE_STEPS} for {SETTLE + 1} to "
                   f"{CROWD} robots; for more than {CROWD} robots {CROWD_STEPS} in the plane, "
                   f"{SPACE_CROWD_STEPS} in d >= 3)")


def _refine_options(args) -> dict | None:
    """The keyword arguments of :func:`pmplan.refine` from the command line; None without
    ``--refine``. A refinement option without ``--refine`` is an InputError (never ignored)."""
    from .errors import InputError

    given = {k: getattr(args, k) for k in REFINE_OPTIONS if getattr(args, k, None) is not None}
    if not args.refine:
        if given:
            flag = "--" + next(iter(given)).replace("_", "-")
            raise InputError(f"{flag} applies to a refined motion: add --refine")
        return None
    return given


def _refined(result, options: dict | None, **extra):
    """``result`` (a Plan or PlanBatch) refined with ``options``, or as it is when None."""
    if options is None:
        return result
    from .api import refine

    return refine(result, **options, **extra)


def _version() -> str:
    """The installed distribution's version (importlib.metadata), else ``pmplan.__version__``."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("pmplan")
    except PackageNotFoundError:
        from .version import __version__

        return __version__


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``pmplan``."""
    from .checks import planner_names
    from .planners.base import CROWD_LANES, ROBOT_LANES, WALL_LANES

    parser = _Parser(
        prog="pmplan",
        description="Optimal parametrised motion planners for point robots among point "
        "obstacles (Zapata & Gonzalez), exact and certified.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"pmplan {_version()}",
                        help="print the version of pmplan and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    names = planner_names()
    planner_help = ("planner name (default: chosen from d, n, m: planar_three for one robot "
                    "among three obstacles in the plane, obstacle_line_compact otherwise, "
                    f"obstacle_line_oneside for --refine with {CROWD_LANES} robots or more in "
                    f"the plane, obstacle_line_robots for --refine with --bounds and {WALL_LANES} "
                    f"to {ROBOT_LANES} robots in the plane, obstacle_line_walls with more; "
                    "obstacle_line: the paper's lanes)")

    _parser_plan(sub, names, planner_help)
    _parser_batch(sub, names, planner_help)
    _parser_demo(sub, names, planner_help)
    _parser_info(sub, names, planner_help)
    _parser_figures(sub, names, planner_help)
    _parser_animate(sub, names, planner_help)
    _parser_verify(sub, names, planner_help)
    _parser_explore(sub, names, planner_help)
    return parser


def _parser_plan(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan plan``."""
    from .io import MAX_SAMPLES

    p = sub.add_parser("plan", help="plan one query from a JSON (or npz) file",
                       description="Plan one query. Example: pmplan plan query.json --samples 20")
    p.add_argument("query", help="query JSON file ('-' for standard input), or an npz with "
                   "arrays obstacles (m, d), start (n, d), goal (n, d)")
    p.add_argument("--samples", type=_int_in(2, MAX_SAMPLES), default=None, metavar="K",
                   help=f"print K equally spaced samples instead of the waypoints "
                   f"(2 <= K <= {MAX_SAMPLES:,})")
    p.add_argument("--planner", default=None, choices=names, help=planner_help)
    p.add_argument("--lift", type=_lift, default=None, metavar="LIFT", help=LIFT_HELP)
    p.add_argument("--bounds", type=_bound, nargs=2, default=None, metavar=("LO", "HI"),
                   help=BOUNDS_HELP)
    p.add_argument("--indent", type=_int_in(0, 16), default=None, metavar="N",
                   help="indent the JSON output by N spaces (default: one line)")
    _add_refine_options(p)


def _parser_batch(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan batch``."""
    p = sub.add_parser("batch", help="plan a batch of queries (npz, JSON list or Zarr store) "
                       "into an npz or a Zarr store",
                       description="Example: pmplan batch queries.npz --out plans.npz; "
                       "pmplan batch queries.zarr --out plans.zarr --dask-workers 2")
    p.add_argument("queries", help="npz with arrays obstacles (B,m,d), start (B,n,d), goal "
                   "(B,n,d) and optional via (B,k,n,d), lift, planner; a JSON list of queries; "
                   "or a Zarr store (directory) with arrays obstacles, start, goal, optional via")
    p.add_argument("--out", required=True, metavar="PLANS.npz|PLANS.zarr",
                   help="output npz (the suffix .npz is added when missing), or a Zarr store "
                   "(a name ending in .zarr), written chunk by chunk")
    p.add_argument("--planner", default=None, choices=names, help=planner_help)
    p.add_argument("--lift", type=_lift, default=None, metavar="LIFT", help=LIFT_HELP)
    p.add_argument("--bounds", type=_bound, nargs=2, default=None, metavar=("LO", "HI"),
                   help=BOUNDS_HELP)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--workers", type=_int_in(1, also=(-1,)), default=1, metavar="W",
                   help="threads planning in parallel (-1: one per CPU; default 1)")
    p.add_argument("--chunk", type=_int_in(1), default=None, metavar="N",
                   help="queries per chunk when streaming to a Zarr store (default: the input "
                   "store's chunks, or 65536)")
    p.add_argument("--resume", action="store_true",
                   help="finish an interrupted run into an existing Zarr --out: plan only the "
                   "chunks not yet written")
    p.add_argument("--no-compress", action="store_true",
                   help="write the Zarr chunks uncompressed (faster, about twice the disk)")
    dask_opts = p.add_mutually_exclusive_group()
    dask_opts.add_argument("--scheduler", default=None, metavar="ADDRESS",
                           help="plan the chunks on this dask.distributed scheduler "
                           "(e.g. tcp://10.0.0.1:8786; needs pmplan[dask] and a Zarr --out)")
    dask_opts.add_argument("--dask-workers", type=_int_in(1, 1024), default=None, metavar="N",
                           help="plan the chunks on a local dask cluster of N worker processes "
                           "(needs pmplan[dask] and a Zarr --out)")
    _add_refine_options(p)


def _parser_demo(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan demo``."""
    p = sub.add_parser("demo", help="the main job: one query per domain, raw and refined, "
                       "table and picture",
                       description="Example: pmplan demo --out demo.png")
    p.add_argument("--n", type=_int_in(1, 8), default=3,
                   help="number of robots among the two obstacles, 1 to 8 (default 3)")
    p.add_argument("--out", default="pmplan-demo.png", metavar="FILE",
                   help="picture to write: .png (default pmplan-demo.png), .pdf or .svg")
    p.add_argument("--lift", type=_lift, default=1.0, metavar="LIFT", help=LIFT_HELP)
    p.add_argument("--radius", type=_number, default=None, metavar="R",
                   help="radius of the robots of the refined motions drawn beside the raw ones "
                   "(default 0)")
    p.add_argument("--obstacle-radius", type=_number, default=None, metavar="R",
                   help="radius of the obstacles of the refined motions (default 0)")


def _parser_info(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan info``."""
    from .io import MAX_POINTS

    p = sub.add_parser("info", help="which planner applies to (d, n, m, r) and its optimality",
                       description="Example: pmplan info --d 3 --n 2 --m 4 --r 3")
    p.add_argument("--d", type=_int_in(0, MAX_POINTS), required=True,
                   help="dimension of the space (planners need d >= 2)")
    p.add_argument("--n", type=_int_in(0, MAX_POINTS), required=True, help="number of robots")
    p.add_argument("--m", type=_int_in(0, MAX_POINTS), required=True,
                   help="number of obstacles (planners need m >= 2)")
    p.add_argument("--r", type=_int_in(0, MAX_POINTS), default=2,
                   help="number of configurations of a sequential motion (default 2: start "
                   "and goal)")
    p.add_argument("--planner", default=None, choices=names, help=planner_help)
    p.add_argument("--json", action="store_true", help="print the record as JSON")


def _parser_figures(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan figures``."""
    p = sub.add_parser("figures", help="draw the paper's Section 4 figures from the planner",
                       description="Example: pmplan figures --out docs/figures")
    p.add_argument("--out", default="docs/figures", metavar="DIR",
                   help="directory for the 13 PNGs (created if missing; default docs/figures)")


def _parser_animate(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan animate``."""
    from .animation import MAX_FPS, MAX_FRAMES

    p = sub.add_parser("animate", help="animate a planned motion",
                       description="Example: pmplan animate query.json --out motion.gif")
    p.add_argument("query", help="query JSON file ('-' for standard input) or npz, as for "
                   "pmplan plan")
    p.add_argument("--out", default="motion.gif", metavar="FILE",
                   help=".gif (default motion.gif) or .mp4 (needs ffmpeg)")
    p.add_argument("--frames", type=_int_in(2, MAX_FRAMES), default=120,
                   help=f"number of frames, 2 to {MAX_FRAMES:,} (default 120)")
    p.add_argument("--fps", type=_int_in(1, MAX_FPS), default=30,
                   help=f"frames per second, 1 to {MAX_FPS} (default 30)")
    p.add_argument("--planner", default=None, choices=names, help=planner_help)
    p.add_argument("--lift", type=_lift, default=None, metavar="LIFT", help=LIFT_HELP)
    _add_refine_options(p)


def _parser_verify(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan verify``."""
    from .io import MAX_POINTS
    from .verify import MAX_QUERIES, MIN_QUERIES

    p = sub.add_parser("verify", help="check certificates and continuity, domain by domain",
                       description="Example: pmplan verify --d 2 --n 3 --m 2 --queries 500")
    p.add_argument("--planner", default=None, choices=names, help=planner_help)
    p.add_argument("--d", type=_int_in(2, MAX_POINTS), default=2,
                   help="dimension of the space (default 2)")
    p.add_argument("--n", type=_int_in(1, MAX_POINTS), default=2,
                   help="number of robots (default 2)")
    p.add_argument("--m", type=_int_in(2, MAX_POINTS), default=2,
                   help="number of obstacles (default 2)")
    p.add_argument("--lift", type=_lift, default=1.0, metavar="LIFT", help=LIFT_HELP)
    p.add_argument("--queries", type=_int_in(MIN_QUERIES, MAX_QUERIES), default=400,
                   help=f"size of the base families of queries, {MIN_QUERIES} to "
                   f"{MAX_QUERIES:,} (default 400)")
    p.add_argument("--seed", type=_int_in(0), default=0,
                   help="seed of the random queries, a non-negative integer (default 0)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--refine", action="store_true",
                   help="also check the refined planner (pmplan.refine, radius 0): its "
                   "certificates, labels and continuity moduli per domain, beside the raw ones")


def _parser_explore(sub, names: list[str], planner_help: str) -> None:
    """The parser of ``pmplan explore``."""
    p = sub.add_parser("explore", help="the domains of continuity, live, in a browser",
                       description="Serve an interactive page on this machine (needs the "
                       "extra pmplan[explore]). Example: pmplan explore --port 8765")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1, this machine only; any "
                   "other address is warned about)")
    p.add_argument("--port", type=_int_in(0, 65535), default=8765,
                   help="TCP port, 0 to 65535 (default 8765; 0: any free port)")
    p.add_argument("--no-browser", action="store_true",
                   help="only print the address; do not open it in the default browser")


def _read_query_arg(path: str) -> dict:
    from .io import parse_query, read_query
    from .errors import InputError

    if path == "-":
        try:
            return parse_query(json.loads(sys.stdin.read()))
        except json.JSONDecodeError as exc:
            raise InputError(f"standard input is not valid JSON: {exc.msg} at line {exc.lineno}") from None
    return read_query(path)


BOUNDS_HELP = ("the workspace box: every path stays in [LO, HI] (each a number, or comma-"
               "separated coordinates: --bounds 0,0 10,5); the same as \"bounds\" in a query")


def _shown(value, quote: bool) -> str:
    """An option's value as the message shows it (a box as nested lists; a file's word
    quoted)."""
    if isinstance(value, (list, tuple)):
        return repr(np.asarray(value, dtype=float).tolist())
    return repr(value) if quote else str(value)


def _bound(text: str):
    """An argparse ``type`` for ``--bounds``: a number or comma-separated numbers (the API
    checks the box)."""
    try:
        parts = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number or comma-separated numbers, got "
                                         f"{text!r}") from None
    return parts[0] if len(parts) == 1 else parts


def _source(path: str) -> str:
    return "standard input" if path == "-" else path


def _with_options(q: dict, args, source: str) -> dict:
    """Return the query ``q`` with the command line's ``--planner`` and ``--lift`` applied.

    An option and the same key in the file must agree: a contradiction is an InputError,
    never silently resolved.
    """
    from .errors import InputError
    from .io import same_value

    q = dict(q)
    for key in ("planner", "lift", "bounds"):
        value = getattr(args, key, None)
        if value is None:
            continue
        if key in q and not same_value(q[key], value):
            raise InputError(
                f"--{key} {_shown(value, False)} contradicts \"{key}\": {_shown(q[key], True)} "
                f"in {source}; "
                f"give only one of them, or the same value"
            )
        q[key] = value
    return q


def cmd_plan(args) -> int:
    from .api import plan_query
    from .io import plan_to_dict, with_defaults

    q = _with_options(_read_query_arg(args.query), args, _source(args.query))
    options = _refine_options(args)
    result = _refined(plan_query(with_defaults(q, options)), options)
    print(json.dumps(plan_to_dict(result, samples=args.samples), indent=args.indent))
    return 0


def cmd_batch(args) -> int:
    from . import api
    from .io import read_queries, with_defaults, write_plans

    options = _refine_options(args)
    if _streams(args):  # Zarr in or out, or a dask option: chunk by chunk (pmplan.scale)
        return _cmd_batch_store(args, options)
    q = with_defaults(_with_options(read_queries(args.queries), args, args.queries), options)
    common = dict(lift=q["lift"], progress=not args.no_progress, workers=args.workers,
                  bounds=q.get("bounds"), planner=q.get("planner"))
    if "via" in q:
        configs = [q["start"], *np.moveaxis(q["via"], 1, 0), q["goal"]]
        batch = api.plan_sequence_batch(q["obstacles"], configs, **common)
    else:
        batch = api.plan_batch(q["obstacles"], q["start"], q["goal"], **common)
    batch = _refined(batch, options, workers=args.workers, progress=not args.no_progress)
    written = write_plans(args.out, batch)
    if len(batch):
        counts = {int(k): int(v) for k, v in zip(*np.unique(batch.domain, return_counts=True))}
        what = f"; domains {counts}; min clearance {batch.clearance.min():.3g}"
        if options is not None:
            what += (f"; refined, radii respected by {int(batch.respects_radius.sum())} of "
                     f"{len(batch)}")
            missed = np.flatnonzero(~batch.respects_radius)
            if missed.size:
                what += f" (query {missed[0]}: {batch[int(missed[0])].radius_reason})"
    else:
        what = ""
    print(f"planned {len(batch)} queries with {batch.planner}{what}; wrote {written}")
    return 0


def _streams(args) -> bool:
    from .scale import is_store

    return (is_store(args.queries) or Path(args.out).suffix == ".zarr" or args.resume
            or args.chunk is not None or args.no_compress or args.scheduler is not None
            or args.dask_workers is not None)


def _quiet_dask() -> None:
    """Silence dask.distributed's own log lines in this process: a failed run ends in one line,
    pmplan's, which names the store and what finishes it."""
    import logging

    try:
        import distributed  # noqa: F401 - its import sets up its loggers: quiet them after it
    except ImportError:
        return  # plan_store says how to install it
    tops = ("distributed", "tornado", "asyncio")
    names = [k for k in logging.root.manager.loggerDict if k.split(".")[0] in tops]
    for name in set(names) | set(tops):
        log = logging.getLogger(name)
        log.handlers[:] = [logging.NullHandler()] if name in tops else []
        log.propagate = name not in tops


class _SiblingWrites:
    """A :mod:`logging` filter for the ``asyncio`` logger: drops "Task exception was never
    retrieved", which asyncio logs when a task that failed is garbage collected unawaited.

    Zarr writes a store's files in concurrent tasks and gathers them: when one write fails (a
    full disk), the gather raises it and ``pmplan batch`` reports it in its one line, while the
    sibling writes that failed the same way are never awaited and would be logged after that
    line, one traceback each. These are the only tasks whose exceptions go unretrieved; every
    other record of the logger passes.
    """

    PREFIX = "Task exception was never retrieved"

    def filter(self, record) -> bool:
        return not str(record.msg).startswith(self.PREFIX)


def _quiet_sibling_writes() -> None:
    """Install :class:`_SiblingWrites` on the ``asyncio`` logger, once per process."""
    import logging

    log = logging.getLogger("asyncio")
    if not any(isinstance(f, _SiblingWrites) for f in log.filters):
        log.addFilter(_SiblingWrites())


def _cmd_batch_store(args, options: dict | None) -> int:
    """``pmplan batch`` into a Zarr store, chunk by chunk (:func:`pmplan.scale.plan_store`),
    every chunk refined with ``options`` (``--refine``) when given."""
    from .errors import InputError
    from .io import read_queries
    from .scale import is_store, plan_store

    if Path(args.out).suffix != ".zarr":
        raise InputError(f"--out {args.out}: Zarr input, --chunk, --resume, --no-compress, "
                         "--scheduler and --dask-workers write a Zarr store; give --out a name "
                         "ending in .zarr")
    if is_store(args.queries):
        source, lift, planner = args.queries, args.lift, args.planner
    else:
        source = _with_options(read_queries(args.queries), args, args.queries)
        lift = planner = None
    bounds = source.pop("bounds", None) if isinstance(source, dict) else args.bounds
    _quiet_sibling_writes()
    if args.scheduler is not None or args.dask_workers is not None:
        _quiet_dask()
    try:
        rep = plan_store(source, args.out, planner=planner, lift=lift, chunk=args.chunk,
                         resume=args.resume, scheduler=args.scheduler,
                         dask_workers=args.dask_workers, workers=args.workers,
                         progress=not args.no_progress, compress=not args.no_compress,
                         refine=options, bounds=bounds)
    except KeyboardInterrupt:  # Ctrl-C: the chunks marked done are kept
        print(f"pmplan batch: interrupted; {args.out} is incomplete: rerun with --resume to plan "
              "only the chunks not yet written", file=sys.stderr)
        return 130
    counts = dict(sorted(rep.domains.items()))
    what = (f"; domains {counts}; min clearance {rep.min_clearance:.3g}" if rep.queries else "")
    if rep.queries and rep.respects_radius is not None:
        what += f"; refined, radii respected by {rep.respects_radius} of {rep.queries}"
    skipped = f" ({rep.skipped} chunks were already written)" if rep.skipped else ""
    print(f"planned {rep.queries} queries in {rep.planned} of {rep.chunks} chunks with "
          f"{rep.planner}{skipped}{what}; wrote {rep.path}")
    return 0


def cmd_demo(args) -> int:
    from . import api
    from .examples import crowded_room_plans, obstacle_line_examples

    out = _picture_path(args.out)
    import numpy as np

    from ._compiling import announce_compile

    radii = {k: getattr(args, k) for k in ("radius", "obstacle_radius")
             if getattr(args, k) is not None}
    with announce_compile(lambda notice: print(f"pmplan demo: {notice}", file=sys.stderr,
                                               flush=True)):
        # one batch (the demo needs no single-query kernel: nothing more to compile)
        queries = [np.stack(a) for a in zip(*obstacle_line_examples(args.n))]
        batch = api.plan_batch(*queries, lift=args.lift)
        plans = list(batch)
        refined = list(api.refine(batch, **radii))
        extra = _planar_three_demo(args.lift)
        refined += [api.refine(p, **radii) for p in extra]
        room, room_refined = crowded_room_plans()
    from .display import display_for

    print(f"pmplan demo: {args.n} robots among 2 obstacles in the plane "
          f"({len(plans)} domains, optimal: TC = {api.parametrised_tc(2, args.n, 2)})"
          + (", and 1 robot among 3 obstacles (paper Section 4, 4 domains)" if extra else ""))
    print("each query raw and refined (pmplan.refine"
          + "".join(f", {k} {v:g}" for k, v in radii.items())
          + "): the same domain and stratum, certified again")
    print(f"{'':<48} {'raw motion':^20} {'refined motion':^20}")
    print(f"{'planner':<21} {'domain':<7} {'stratum':<18} {'length':>9} {'clearance':>10} "
          f"{'length':>9} {'clearance':>10}")
    for p, r in zip(plans + extra + [room], refined + [room_refined]):
        dom = f"{display_for(p.planner).domain_prefix}{p.domain}"
        print(f"{p.planner:<21} {dom:<7} {p.stratum[:18]:<18} {p.path.length():9.3f} "
              f"{p.clearance:10.4f} {r.path.length():9.3f} {r.clearance:10.4f}")
    print(f"the last row: {room.dims[1]} robots among {room.dims[2]} obstacles in the box "
          f"[0, 10]^2 (bounds=), refined with radius {room_refined.radius:g}: radii and walls "
          f"{'kept' if room_refined.respects_radius else 'NOT kept'}")
    from .plotting import plan_grid
    import matplotlib

    matplotlib.use("Agg")
    what = f"{args.n} robot{'s' if args.n > 1 else ''} among 2 obstacles ({plans[0].planner})" + (
        ", 1 robot among 3 obstacles (planar_three, paper Section 4)" if extra else "")
    what += f"; a crowded room: {room.dims[1]} robots, {room.dims[2]} obstacles, box [0, 10]$^2$"
    pairs = [q for pair in zip(plans + extra + [room], refined + [room_refined]) for q in pair]
    fig = plan_grid(pairs, ncols=4, same_axes=2,
                    suptitle="pmplan demo: one certified motion per domain of "
                    f"continuity $W_l$, raw (left) and refined (right)\n{what}")
    fig.savefig(out, dpi=110)
    print(f"wrote {out.resolve()}")
    return 0


#: most domains ``pmplan info`` lists (it prints every label with --json)
MAX_INFO_LABELS = 1_000_000

#: picture formats ``pmplan demo --out`` writes (by suffix)
PICTURE_SUFFIXES = (".png", ".pdf", ".svg")


def _picture_path(out: str) -> Path:
    """The file ``pmplan demo`` writes for ``--out``: ``.png`` added when there is no suffix."""
    from .errors import InputError

    path = Path(out)
    if path.suffix == "":
        path = path.with_name(path.name + ".png")
    if path.suffix.lower() not in PICTURE_SUFFIXES:
        raise InputError(f"cannot draw the demo into {path.name!r}: use a file name ending in "
                         f"{', '.join(PICTURE_SUFFIXES)}")
    return path


def _planar_three_demo(lift=1.0):
    from . import api

    try:
        from .examples import planar_three_examples
    except ImportError:
        return []
    return [api.plan(o, s, g, lift=lift) for o, s, g in planar_three_examples()]


def cmd_info(args) -> int:
    from . import api

    from .errors import InputError, UnsupportedError

    if args.r * args.n + args.m > MAX_INFO_LABELS:
        raise InputError(f"(d, n, m, r) = ({args.d}, {args.n}, {args.m}, {args.r}) has about "
                         f"r n + m = {args.r * args.n + args.m:,} domains, more than pmplan info "
                         f"lists ({MAX_INFO_LABELS:,}): ask for fewer robots or configurations")
    i = api.info(args.d, args.n, args.m, r=args.r, planner=args.planner)
    if i.planner is None:
        raise UnsupportedError(f"(d, n, m, r) = ({i.d}, {i.n}, {i.m}, {i.r}): {i.message}")
    if args.json:
        from dataclasses import asdict
        print(json.dumps(asdict(i)))
        return 0
    print(f"(d, n, m, r) = ({i.d}, {i.n}, {i.m}, {i.r})")
    print(f"planner:  {i.planner} -- {i.message}")
    print(f"domains:  {i.domains} (labels {i.labels[0]}..{i.labels[-1]})")
    ref = "Farber-Paul, sequential, unreduced" if i.r > 2 else "paper Theorem 2.6, Cohen-Farber-Weinberger"
    print(f"TC:       {i.tc} ({ref})")
    print(f"optimal:  {'yes' if i.optimal else 'no'}")
    return 0


def cmd_figures(args) -> int:
    from .figures import make_figures

    paths = make_figures(args.out)
    for p in paths:
        print(p.resolve())
    return 0


def cmd_animate(args) -> int:
    from .animation import animate_query

    q = _with_options(_read_query_arg(args.query), args, _source(args.query))
    out = animate_query(q, args.out, frames=args.frames, fps=args.fps,
                        refine=_refine_options(args))
    print(f"wrote {out.resolve()}")
    return 0


def cmd_verify(args) -> int:
    from .verify import verify

    report = verify(planner=args.planner, d=args.d, n=args.n, m=args.m, lift=args.lift,
                    queries=args.queries, seed=args.seed, progress=not args.no_progress,
                    refine=args.refine)
    print(report.to_json() if args.json else report.to_text())
    return 0 if report.ok else 1


def cmd_explore(args) -> int:
    from .web import require_extra

    require_extra()
    from .web.server import serve

    serve(args.host, args.port, open_browser=not args.no_browser)
    print("pmplan explore: stopped")
    return 0


COMMANDS = {
    "plan": cmd_plan,
    "batch": cmd_batch,
    "demo": cmd_demo,
    "info": cmd_info,
    "figures": cmd_figures,
    "animate": cmd_animate,
    "verify": cmd_verify,
    "explore": cmd_explore,
}


def main(argv=None) -> int:
    """Run the command line; return the exit status.

    0 on success, 1 when ``pmplan verify`` finds a problem, 2 for bad input or options (one
    line on stderr, no traceback); ``--help`` and ``--version`` print and return 0.
    """
    from .errors import PmplanError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) or a bad option (2, one line on stderr)
        return exc.code if isinstance(exc.code, int) else 2
    if args.command is None:
        print(f"pmplan: error: no command given; choose one of {', '.join(COMMANDS)} "
              "(see pmplan --help)", file=sys.stderr)
        return 2
    try:
        return COMMANDS[args.command](args)
    except PmplanError as exc:
        print(f"pmplan {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader left (``pmplan plan q.json | head``): no error line
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no error at exit
        return 141  # 128 + SIGPIPE, as a shell reports a command its reader left
    except OSError as exc:
        print(f"pmplan {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
