"""The command line: thin over the library (``pmplan --help``).

Every command parses its arguments, reads input, calls one public function and writes output.
Errors from pmplan (and unreadable files) are printed on one line to stderr with exit status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

__all__ = ["main", "build_parser"]

EPILOG = """\
commands and examples:
  pmplan demo                              plan one query per domain, print a table, draw a PNG
  pmplan plan query.json                   plan one query (JSON in, JSON out)
  pmplan plan query.json --samples 50      ... printing 50 equally spaced samples
  pmplan batch queries.npz --out plans.npz plan many queries (npz arrays obstacles/start/goal)
  pmplan info --d 2 --n 3 --m 2 [--r 3]    planner, number of domains, TC, optimality
  pmplan figures --out docs/figures        the paper's Section 4 figures from the planner
  pmplan animate query.json --out m.gif    animate a planned motion (.gif, or .mp4 with ffmpeg)
  pmplan verify --d 2 --n 3 --m 2          check certificates and continuity per domain

query.json: {"obstacles": [[0,0],[4,0]], "start": [[1,1]], "goal": [[3,-1]]}
  optional: "via": [[[2,2]]] (intermediate configurations), "lift": 1.0, "planner": "..."
"""


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``pmplan``."""
    parser = argparse.ArgumentParser(
        prog="pmplan",
        description="Optimal parametrised motion planners for point robots among point "
        "obstacles (Zapata & Gonzalez), exact and certified.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("plan", help="plan one query from a JSON file",
                       description="Plan one query. Example: pmplan plan query.json --samples 20")
    p.add_argument("query", help="query JSON file ('-' for standard input)")
    p.add_argument("--samples", type=int, default=None, metavar="K",
                   help="print K equally spaced samples instead of the waypoints")
    p.add_argument("--planner", default=None, help="planner name (default: chosen from d, n, m)")
    p.add_argument("--indent", type=int, default=None, help="indent the JSON output")

    p = sub.add_parser("batch", help="plan a batch of queries (npz or JSON list) into an npz",
                       description="Example: pmplan batch queries.npz --out plans.npz")
    p.add_argument("queries", help="npz with arrays obstacles (B,m,d), start (B,n,d), goal (B,n,d)")
    p.add_argument("--out", required=True, help="output npz")
    p.add_argument("--planner", default=None)
    p.add_argument("--lift", type=float, default=1.0)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--workers", type=int, default=1,
                   help="threads planning in parallel (-1: one per CPU; default 1)")

    p = sub.add_parser("demo", help="the main job: one query per domain, table and picture",
                       description="Example: pmplan demo --out demo.png")
    p.add_argument("--n", type=int, default=3, help="number of robots (default 3)")
    p.add_argument("--out", default="pmplan-demo.png", help="PNG to write")

    p = sub.add_parser("info", help="which planner applies to (d, n, m, r) and its optimality",
                       description="Example: pmplan info --d 3 --n 2 --m 4 --r 3")
    p.add_argument("--d", type=int, required=True)
    p.add_argument("--n", type=int, required=True)
    p.add_argument("--m", type=int, required=True)
    p.add_argument("--r", type=int, default=2)
    p.add_argument("--planner", default=None)
    p.add_argument("--json", action="store_true")

    p = sub.add_parser("figures", help="draw the paper's Section 4 figures from the planner",
                       description="Example: pmplan figures --out docs/figures")
    p.add_argument("--out", default="docs/figures")

    p = sub.add_parser("animate", help="animate a planned motion",
                       description="Example: pmplan animate query.json --out motion.gif")
    p.add_argument("query")
    p.add_argument("--out", default="motion.gif", help=".gif (or .mp4 when ffmpeg is present)")
    p.add_argument("--frames", type=int, default=120)
    p.add_argument("--fps", type=int, default=30)
    p.add_argument("--planner", default=None)

    p = sub.add_parser("verify", help="check certificates and continuity, domain by domain",
                       description="Example: pmplan verify --d 2 --n 3 --m 2 --queries 500")
    p.add_argument("--planner", default=None)
    p.add_argument("--d", type=int, default=2)
    p.add_argument("--n", type=int, default=2)
    p.add_argument("--m", type=int, default=2)
    p.add_argument("--queries", type=int, default=400)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", action="store_true")
    p.add_argument("--no-progress", action="store_true")
    return parser


def _read_query_arg(path: str) -> dict:
    from .io import parse_query, read_query
    from .errors import InputError

    if path == "-":
        try:
            return parse_query(json.loads(sys.stdin.read()))
        except json.JSONDecodeError as exc:
            raise InputError(f"standard input is not valid JSON: {exc.msg} at line {exc.lineno}") from None
    return read_query(path)


def cmd_plan(args) -> int:
    from .io import plan_to_dict

    q = _read_query_arg(args.query)
    from .api import plan_query

    result = plan_query(q, args.planner)
    print(json.dumps(plan_to_dict(result, samples=args.samples), indent=args.indent))
    return 0


def cmd_batch(args) -> int:
    from . import api
    from .io import read_queries, write_plans

    q = read_queries(args.queries)
    batch = api.plan_batch(q["obstacles"], q["start"], q["goal"], planner=args.planner,
                           lift=args.lift, progress=not args.no_progress,
                           workers=args.workers)
    write_plans(args.out, batch)
    counts = {int(k): int(v) for k, v in zip(*_unique(batch.domain))}
    print(f"planned {len(batch)} queries with {batch.planner}; domains {counts}; "
          f"min clearance {batch.clearance.min():.3g}; wrote {args.out}")
    return 0


def _unique(a):
    import numpy as np

    return np.unique(a, return_counts=True)


def cmd_demo(args) -> int:
    from . import api
    from .examples import obstacle_line_examples

    if args.n < 1 or args.n > 8:
        from .errors import UnsupportedError
        raise UnsupportedError(f"demo takes 1 <= n <= 8 robots, got {args.n}")
    import numpy as np

    from ._compiling import announce_compile

    rows = []
    with announce_compile(lambda notice: print(f"pmplan demo: {notice}", file=sys.stderr,
                                               flush=True)):
        # one batch (the demo needs no single-query kernel: nothing more to compile)
        queries = [np.stack(a) for a in zip(*obstacle_line_examples(args.n))]
        plans = list(api.plan_batch(*queries))
        extra = _planar_three_demo()
    for p in plans:
        rows.append(("obstacle_line", f"W_{p.domain}", p.stratum, p.path.length(), p.clearance))
    for p in extra:
        rows.append(("planar_three", f"W{p.domain}", p.stratum, p.path.length(), p.clearance))
    print(f"pmplan demo: {args.n} robots among 2 obstacles in the plane "
          f"({len(plans)} domains, optimal: TC = {api.parametrised_tc(2, args.n, 2)})"
          + (", and 1 robot among 3 obstacles (paper Section 4, 4 domains)" if extra else ""))
    print(f"{'planner':<14} {'domain':<7} {'stratum':<18} {'length':>9} {'clearance':>10}")
    for planner, dom, stratum, length, clr in rows:
        print(f"{planner:<14} {dom:<7} {stratum:<18} {length:9.3f} {clr:10.4f}")
    from .plotting import plan_grid
    import matplotlib

    matplotlib.use("Agg")
    allp = plans + extra
    titles = [f"W_{p.domain}: {p.stratum}" if p.planner == "obstacle_line"
              else f"W{p.domain}: {p.stratum}" for p in allp]
    fig = plan_grid(allp, titles, ncols=4)
    fig.suptitle("pmplan demo: one certified motion per domain of continuity", y=1.0)
    fig.savefig(args.out, dpi=110, bbox_inches="tight")
    print(f"wrote {Path(args.out).resolve()}")
    return 0


def _planar_three_demo():
    from . import api

    try:
        from .planners.planar_three import demo_examples
    except ImportError:
        return []
    return [api.plan(o, s, g) for o, s, g in demo_examples()]


def cmd_info(args) -> int:
    from . import api

    i = api.info(args.d, args.n, args.m, r=args.r, planner=args.planner)
    if args.json:
        from dataclasses import asdict
        print(json.dumps(asdict(i)))
        return 0
    if i.planner is None:
        print(f"(d, n, m, r) = ({i.d}, {i.n}, {i.m}, {i.r}): {i.message}")
        return 1
    print(f"(d, n, m, r) = ({i.d}, {i.n}, {i.m}, {i.r})")
    print(f"planner:  {i.planner} -- {i.message}")
    print(f"domains:  {i.domains} (labels {i.labels[0]}..{i.labels[-1]})")
    ref = "Farber-Paul, sequential, unreduced" if i.r > 2 else "paper Theorem gongra, Cohen-Farber-Weinberger"
    print(f"TC:       {i.tc} ({ref})")
    print(f"optimal:  {'yes' if i.optimal else 'no'}")
    return 0


def cmd_figures(args) -> int:
    from .figures import make_figures

    paths = make_figures(args.out)
    for p in paths:
        print(p)
    return 0


def cmd_animate(args) -> int:
    from .animation import animate_query

    q = _read_query_arg(args.query)
    out = animate_query(q, args.out, frames=args.frames, fps=args.fps, planner=args.planner)
    print(f"wrote {out}")
    return 0


def cmd_verify(args) -> int:
    from .verify import verify

    report = verify(planner=args.planner, d=args.d, n=args.n, m=args.m, queries=args.queries,
                    seed=args.seed, progress=not args.no_progress)
    print(report.to_json() if args.json else report.to_text())
    return 0 if report.ok else 1


COMMANDS = {
    "plan": cmd_plan,
    "batch": cmd_batch,
    "demo": cmd_demo,
    "info": cmd_info,
    "figures": cmd_figures,
    "animate": cmd_animate,
    "verify": cmd_verify,
}


def main(argv=None) -> int:
    """Run the command line; return the exit status (2 for bad input, one line on stderr)."""
    from .errors import PmplanError

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return COMMANDS[args.command](args)
    except PmplanError as exc:
        print(f"pmplan {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"pmplan {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
