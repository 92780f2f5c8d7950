"""Shared pieces of the benchmark scripts: machine facts, query generators, timing, reports.

Everything here uses pmplan's PUBLIC API only (``pmplan.plan``, ``plan_batch``,
``plan_sequence_batch``, ``PiecewiseLinearPath``), plus the optional planar three-obstacle
``pmplan.generators.planar_stratum_queries`` generator when that planner is installed.

Not a test module: ``benchmarks/conftest.py`` keeps pytest from importing it.
"""

from __future__ import annotations

import datetime as _dt
import gc
import json
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

__all__ = [
    "HERE",
    "ROOT",
    "degenerate_queries",
    "generic_queries",
    "machine_info",
    "ompl_section",
    "planar_three_available",
    "planar_three_mixed",
    "timeit",
    "write_reports",
]

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS_JSON = HERE / "results.json"
OMPL_JSON = HERE / "ompl_results.json"


# --------------------------------------------------------------------------- machine facts
def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _version(module: str) -> str:
    try:
        mod = __import__(module)
        return str(getattr(mod, "__version__", "?"))
    except Exception:  # noqa: BLE001 - a missing optional package is just "absent"
        try:
            from importlib.metadata import version

            return version(module)
        except Exception:  # noqa: BLE001
            return "absent"


def _git_commit() -> str:
    try:
        out = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=10,
            check=False,
        )
        dirty = subprocess.run(
            ["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=10,
            check=False,
        )
        return out.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "")
    except Exception:  # noqa: BLE001
        return "?"


def exit_after_ompl(rc: int) -> None:
    """End a script that used OMPL with status ``rc``: flush the output, then leave without the
    interpreter's teardown, where OMPL's nanobind bindings print spurious "leaked instance"
    reports."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(rc)


def rewrite_report(name: str, markdown: Callable[[dict], str]) -> None:
    """Rewrite ``benchmarks/<name>.md`` from ``benchmarks/<name>.json`` (``--from-json``)."""
    res = json.loads((HERE / f"{name}.json").read_text())
    (HERE / f"{name}.md").write_text(markdown(res))


def write_report(name: str, res: dict, markdown: Callable[[dict], str]) -> None:
    """Write ``res`` to ``benchmarks/<name>.json`` and its report to ``.md``, and print it."""
    (HERE / f"{name}.json").write_text(json.dumps(res, indent=1, default=float))
    text = markdown(res)
    (HERE / f"{name}.md").write_text(text)
    print(text)


def start_ompl(seed: int):
    """OMPL's ``util`` module with its log silenced and its random generator seeded with
    ``seed`` (before any planner draws), or None, after saying on stderr how to install it, when
    ``ompl`` is missing."""
    try:
        from ompl import util as ou
    except ImportError:
        print("ompl is not installed: pip install 'pmplan[bench]'", file=sys.stderr)
        return None
    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    ou.RNG.setSeed(seed)
    return ou


def machine_info() -> dict:
    """CPU model, core count, memory, OS, versions of Python/numpy/numba/pmplan/ompl, date."""
    mem = "?"
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                mem = f"{int(line.split()[1]) / 2**20:.1f} GiB"
    except OSError:
        pass
    try:
        from importlib.metadata import version

        ompl_v = version("ompl")
    except Exception:  # noqa: BLE001
        ompl_v = "absent"
    import pmplan

    return {
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "memory": mem,
        "os": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": _version("numba"),
        "pmplan": pmplan.__version__,
        "ompl": ompl_v,
        "git": _git_commit(),
        "date": _dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "planners": pmplan.planner_names(),
    }


# --------------------------------------------------------------------------- query generators
def generic_queries(rng: np.random.Generator, b: int, d: int, n: int, m: int):
    """B generic queries: i.i.d. standard normal coordinates.

    With probability 1 no two projections tie, so every query is in the top stratum
    (cp(C) = cp(C') = n + m): this measures the planner's common path.
    """
    return (
        rng.standard_normal((b, m, d)),
        rng.standard_normal((b, n, d)),
        rng.standard_normal((b, n, d)),
    )


def _coincident(points: np.ndarray) -> np.ndarray:
    """Rows (B,) of a (B, P, d) array with two exactly equal points (lexicographic sort)."""
    if points.dtype.kind in "iu" and np.abs(points).max(initial=0) < 8192 and points.shape[2] <= 4:
        # integer coordinates: one exact int64 key per point, sorted per row
        key = np.zeros(points.shape[:2], dtype=np.int64)
        for k in range(points.shape[2]):
            key = key * 16384 + (points[:, :, k].astype(np.int64) + 8192)
        key.sort(axis=1)
        return (key[:, 1:] == key[:, :-1]).any(axis=1)
    b, p, d = points.shape
    flat = points.reshape(b * p, d)
    row = np.repeat(np.arange(b), p)
    order = np.lexsort([flat[:, k] for k in reversed(range(d))] + [row])
    srt, rs = flat[order], row[order]
    same = (srt[1:] == srt[:-1]).all(axis=1) & (rs[1:] == rs[:-1])
    out = np.zeros(b, dtype=bool)
    out[rs[1:][same]] = True
    return out


def _lattice_rows(rng: np.random.Generator, b: int, d: int, n: int, m: int):
    """One draw of the degenerate generator (may contain coincident points)."""
    o1 = rng.integers(-2, 3, size=(b, 1, d))
    w = rng.integers(-2, 3, size=(b, 1, d))
    zero = ~w.any(axis=2)
    w[zero[:, 0], 0, 0] = 1
    # integer vectors orthogonal to w: w_{k+1} e_k - w_k e_{k+1}
    perp = np.zeros((b, d - 1, d), dtype=np.int64)
    for k in range(d - 1):
        perp[:, k, k] = w[:, 0, k + 1]
        perp[:, k, k + 1] = -w[:, 0, k]
    span = max(2, (n + m) ** 2 // 4)  # enough lattice points for n + m distinct ones

    def points(count: int) -> np.ndarray:
        a = rng.integers(-1, 3, size=(b, count, 1))  # columns -1, 0 (= o1), 1 (= o2), 2
        c = rng.integers(-span, span + 1, size=(b, count, d - 1))
        return o1 + a * w + np.einsum("bck,bkd->bcd", c, perp)

    obstacles = np.concatenate([o1, o1 + w, points(m - 2)], axis=1)
    return obstacles, points(n), points(n)


def degenerate_queries(rng: np.random.Generator, b: int, d: int, n: int, m: int):
    """B exactly degenerate queries: integer coordinates with many exact ties.

    Obstacles o1, o2 = o1 + w and every other point on the integer lattice
    ``o1 + a w + (integer vector orthogonal to w)`` with the column index ``a`` in
    {-1, 0, 1, 2}: robots share columns with o1, o2 and with each other, so cp(C) < n + m and
    the desingularization of paper (3.2) and the exact tie decisions of the predicates are exercised.
    Rows with two coincident points are redrawn.
    """
    obs, st, go = _lattice_rows(rng, b, d, n, m)
    for _ in range(200):
        bad = _coincident(np.concatenate([obs, st], 1)) | _coincident(np.concatenate([obs, go], 1))
        if not bad.any():
            break
        k = int(bad.sum())
        o2, s2, g2 = _lattice_rows(rng, k, d, n, m)
        obs[bad], st[bad], go[bad] = o2, s2, g2
    else:  # pragma: no cover - the span grows with n + m, so this does not happen
        raise RuntimeError("could not draw distinct lattice points")
    return obs.astype(float), st.astype(float), go.astype(float)


def _planar_three_module():
    try:
        from pmplan.planners import planar_three  # type: ignore[attr-defined]
    except ImportError:
        return None
    return planar_three


def _planar_three_strata(mod) -> list:
    for name in ("STRATA", "STRATUM_NAMES", "STRATA_NAMES"):
        val = getattr(mod, name, None)
        if val is not None:
            return list(val.keys() if isinstance(val, dict) else val)
    return list(range(12))


def planar_three_available() -> bool:
    """True when the ``planar_three`` planner is registered."""
    import pmplan

    return "planar_three" in pmplan.planner_names() and _planar_three_module() is not None


def planar_three_mixed(rng: np.random.Generator, b: int):
    """B queries for (d, n, m) = (2, 1, 3), mixed evenly over the 12 strata (paper Section 4).

    Uses the generator ``pmplan.generators.planar_stratum_queries(rng, stratum, count)`` and
    shuffles the result, so the batch exercises every branch of the planner.
    """
    mod = _planar_three_module()
    strata = _planar_three_strata(mod)
    counts = [b // len(strata) + (1 if i < b % len(strata) else 0) for i in range(len(strata))]
    try:
        from pmplan.generators import planar_stratum_queries
    except ImportError:  # an older pmplan (``run.py --baseline``): it was in the planner module
        planar_stratum_queries = mod.stratum_queries

    parts = [planar_stratum_queries(rng, s, c) for s, c in zip(strata, counts) if c > 0]
    obs = np.concatenate([np.asarray(p[0], float) for p in parts])
    st = np.concatenate([np.asarray(p[1], float) for p in parts])
    go = np.concatenate([np.asarray(p[2], float) for p in parts])
    perm = rng.permutation(obs.shape[0])
    return obs[perm], st[perm], go[perm]


# --------------------------------------------------------------------------- timing
def timeit(fn: Callable[[], object], repeats: int) -> list[float]:
    """Wall-clock seconds of ``repeats`` calls of ``fn`` (garbage collected before each)."""
    out = []
    for _ in range(repeats):
        gc.collect()
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


# --------------------------------------------------------------------------- reports
def _fmt(x: float, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "n/a"
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    return f"{x:.{digits}g}"


def _machine_md(info: dict) -> str:
    rows = [
        ("CPU", info["cpu"]),
        ("cores", info["cores"]),
        ("memory", info["memory"]),
        ("OS", info["os"]),
        ("Python", info["python"]),
        ("numpy", info["numpy"]),
        ("numba", info["numba"]),
        ("pmplan", f"{info['pmplan']} ({info['git']})"),
        ("ompl", info.get("ompl", "absent")),
        ("planners", ", ".join(info["planners"])),
        ("date", info["date"]),
    ]
    return "\n".join(["| | |", "|---|---|"] + [f"| {k} | {v} |" for k, v in rows])


def _baseline_rows(res: dict, part: str) -> tuple[dict, str]:
    """The rows of ``part`` ("throughput" or "latency") of the ``--baseline`` run by key, and
    the baseline's name (empty when there is none)."""
    base = res.get("baseline")
    if not base:
        return {}, ""
    if part == "throughput":
        rows = {(r["case"], r["family"], r["B"]): r for r in base.get(part, [])}
    else:
        rows = {r["case"]: r for r in base.get(part, [])}
    return rows, f"{base['ref']} ({base['commit']})"


def _head(cols: list[str], name: str) -> list[str]:
    """The head and rule lines of a throughput table, with the baseline ``name``'s columns."""
    if name:
        cols = [*cols, f"queries/s at {name}", "new / old"]
    return ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]


def _vs_old(old: dict, r: dict) -> str:
    """The baseline's columns of throughput row ``r``."""
    o = old.get((r["case"], r["family"], r["B"]))
    q = o["qps_best"] if o else float("nan")
    return f" {_fmt(q)} | {_fmt(r['qps_best'] / q)} |"


def _throughput_md(res: dict) -> str:
    old, name = _baseline_rows(res, "throughput")
    lines = _head(["case", "queries", "B", "queries/s (best)", "queries/s (median)",
                   "time / one copy of the output (best)", "the same with out=",
                   "out=, every core", "speed-up, every core", "output MB"], name)
    for r in res["throughput"]:
        line = (
            f"| {r['case']} | {r['family']} | {r['B']:,} | {_fmt(r['qps_best'])} | "
            f"{_fmt(r['qps_median'])} | {_fmt(r['copy_ratio_best'])} | "
            f"{_fmt(r.get('copy_ratio_out_best'))} | {_fmt(r.get('copy_ratio_out_all_best'))} | "
            f"{_fmt(r.get('speedup_all'))} | {r['out_mb']:.0f} |"
        )
        lines.append(line + (_vs_old(old, r) if name else ""))
    return "\n".join(lines)


def _summary_md(res: dict, rows: list) -> str:
    """The issue's table: for each (case, B) of ``rows`` (generic queries), the time of
    ``plan_batch(out=...)`` over one copy of the output on one core and on every core, the
    speed-up, and the old throughput when there is a baseline."""
    old, name = _baseline_rows(res, "throughput")
    lines = _head(["case", "B", "queries/s, one core", "ratio, one core", "ratio, every core",
                   "speed-up, every core"], name)
    for dims, b in rows:
        found = [r for r in res["throughput"] if r["dims"] == list(dims) and r["B"] == b
                 and r["family"] == "generic"]
        if not found:
            continue
        r = found[0]
        line = (f"| {r['case']} | {b:,} | {_fmt(r['qps_best'])} | "
                f"{_fmt(r.get('copy_ratio_out_best'))} | {_fmt(r.get('copy_ratio_out_all_best'))} "
                f"| {_fmt(r.get('speedup_all'))} |")
        lines.append(line + (_vs_old(old, r) if name else ""))
    return "\n".join(lines)


def _breakdown_md(res: dict) -> str:
    lines = ["| B | stage | time (ms) | / one copy of the output | queries/s |",
             "|---|---|---|---|---|"]
    for r in res.get("breakdown", []):
        lines.append(
            f"| {r['B']:,} | {r['stage']} | {_fmt(r['ms'])} | {_fmt(r['ratio'])} | "
            f"{_fmt(r['qps'])} |"
        )
    return "\n".join(lines)


def _latency_md(res: dict) -> str:
    old, name = _baseline_rows(res, "latency")
    head = "| case | p10 (us) | p50, median (us) | p90 (us) | calls |"
    rule = "|---|---|---|---|---|"
    if name:
        head += f" p50 at {name} (us) |"
        rule += "---|"
    lines = [head, rule]
    for r in res["latency"]:
        line = (
            f"| {r['case']} | {_fmt(r['p10_us'])} | {_fmt(r['median_us'])} | "
            f"{_fmt(r['p90_us'])} | {r['calls']} |"
        )
        if name:
            o = old.get(r["case"])
            line += f" {_fmt(o['median_us'] if o else float('nan'))} |"
        lines.append(line)
    return "\n".join(lines)


def _memory_md(res: dict) -> str:
    lines = [
        "| case | B | output MB | tracemalloc peak / output | peak RSS growth / output |",
        "|---|---|---|---|---|",
    ]
    for r in res["memory"]:
        lines.append(
            f"| {r['case']} | {r['B']:,} | {r['out_mb']:.0f} | "
            f"{_fmt(r['tracemalloc_ratio'])} | {_fmt(r['rss_ratio'])} |"
        )
    return "\n".join(lines)


def _scaling_md(res: dict) -> str:
    lines = ["| n | B | us / query | ns / output byte | queries/s |", "|---|---|---|---|---|"]
    for r in res["scaling_n"]:
        lines.append(
            f"| {r['n']} | {r['B']:,} | {_fmt(r['us_per_query'])} | "
            f"{_fmt(r['ns_per_byte'])} | {_fmt(r['qps'])} |"
        )
    lines += [
        "",
        "| r (sequential, n = 4) | B | us / query | ns / output byte | queries/s |",
        "|---|---|---|---|---|",
    ]
    for r in res["scaling_r"]:
        lines.append(
            f"| {r['r']} | {r['B']:,} | {_fmt(r['us_per_query'])} | "
            f"{_fmt(r['ns_per_byte'])} | {_fmt(r['qps'])} |"
        )
    return "\n".join(lines)


def _goals_md(res: dict) -> str:
    g = res["goals"]
    lines = ["| goal | target | measured | met |", "|---|---|---|---|"]
    for row in g:
        lines.append(
            f"| {row['goal']} | {row['target']} | {row['measured']} | "
            f"{'yes' if row['met'] else 'no'} |"
        )
    return "\n".join(lines)


def _ompl_md(om: dict) -> str:
    cols = (
        "| n | queries | planner | success | median time / query (ms) | median length / "
        "lower bound | median sup distance after 1e-6 start perturbation | "
        "min clearance along path: median (min) | clearance >= r |"
    )
    lines = [cols, "|---|---|---|---|---|---|---|---|---|"]
    for r in om["rows"]:
        lines.append(
            f"| {r['n']} | {r['family']} ({r['count']}) | {r['planner']} | "
            f"{r['success']}/{r['count']} | {_fmt(r['time_ms_median'])} | "
            f"{_fmt(r['length_ratio_median'])} | {_fmt(r['probe_median'], 2)} | "
            f"{_fmt(r['clearance_median'], 4)} ({_fmt(r.get('clearance_min', float('nan')), 4)}) | "
            f"{r['clear_r']}/{r['success']} |"
        )
    return "\n".join(lines)


OMPL_EXPLAIN = """\
Scene: the unit square [0, 1]^2, obstacles o1 = (0.35, 0.5), o2 = (0.65, 0.5), robot clearance
r = {r} (5 % of the scene). OMPL plans in R^(2n) (RealVectorStateSpace bounded by the square)
with a validity checker that requires every robot-obstacle and robot-robot distance to be
>= r, checked along motions at a resolution of r/4 in state space. *generic* queries: uniform
starts and goals with that clearance; *blocked* queries: the straight-line motion collides
(a robot's segment passes within r of an obstacle, and for n >= 2 two robots swap places).
pmplan plans the same queries with `lift = {lift}` (the scale of the lift, scene-sized).

How to read it:
* *time / query*: wall clock of one `pmplan.plan` call, of one OMPL `solve` (+ path
  simplification for RRTConnect); RRT* always uses its whole {budget} s budget.
* *length / lower bound*: sum over robots of the distance each robot travels, divided by the
  sum of the robots' |x' - x| (a lower bound for any motion). Medians over successful queries.
* *sup distance after perturbation*: every start moved by 1e-6 (random direction), both paths
  resampled at 201 equal arc-length parameters, the largest distance between corresponding
  samples. pmplan is continuous on each domain, so this is O(1e-6); a randomised planner
  returns a different path on each call.
* *min clearance*: the exact minimum distance between any two points along the returned
  polyline (closed form per piece), not only at OMPL's checked states.
* *clearance >= r*: how many returned paths keep every distance >= r all along.
  **pmplan treats robots as points**: its certificate guarantees clearance > 0, not >= r, so
  its paths may come closer than r; OMPL's paths respect r at the checked states only.
  **pmplan refined** (`pmplan.plan(..., refine=True, radius={half}, obstacle_radius={half})`,
  issue 14, `docs/refinement.md`) refines the same certified path by a fixed number of
  continuous, collision-free steps, with robots and obstacles discs of radius r/2 = {half}: every
  robot-robot and robot-obstacle distance it certifies is >= r, exactly what OMPL's checker
  asks (and it says so only when it holds: `Plan.respects_radius`). Its time includes the plan,
  the refinement and both certificates. Neither pmplan row knows the walls of the square.
"""


def _sections(text: str) -> list[tuple[str, list[str]]]:
    """The ``## `` sections of a markdown text: (title line, its lines), in order; what comes
    before the first one is left out."""
    out: list[tuple[str, list[str]]] = []
    for line in text.splitlines():
        if line.startswith("## "):
            out.append((line.rstrip(), [line]))
        elif out:
            out[-1][1].append(line)
    return out


def _foreign_sections(path: Path, owned: set[str]) -> list[str]:
    """The lines of every ``## `` section of the file ``path`` whose title is not in ``owned``
    -- the sections other scripts write into RESULTS.md (the explore load test, the refinement,
    the certificate...) -- so that rewriting the file keeps them, in their order."""
    if not path.exists():
        return []
    lines: list[str] = []
    for title, sect in _sections(path.read_text()):
        if title not in owned:
            while sect and not sect[-1].strip():
                sect = sect[:-1]
            lines += [*sect, ""]
    return lines


SUMMARY_EXPLAIN = """\
Generic queries, `plan_batch(..., out=earlier_batch)` (no new memory) divided by ONE `np.copyto`
of the output waypoints, measured in the same run: on one core, and with `workers=-1` (one
thread per core, {cores} here); the speed-up is the one-core time over the every-core time.
With `--baseline REF`, the throughput of REF measured in the same run (a separate process on
the same queries, just before this one's)."""


def ompl_section(ompl: dict) -> list[str]:
    """The lines of the section "## Comparison with OMPL" (``benchmarks/ompl_compare.py``)."""
    explain = OMPL_EXPLAIN.format(r=ompl["r"], lift=ompl["lift"], budget=ompl["budget"],
                                  half=ompl.get("radius", ompl["r"] / 2))
    return [
        "## Comparison with OMPL",
        "",
        explain,
        _ompl_md(ompl),
        "",
        ompl.get("verdict", ""),
        "",
        (
            f"OMPL comparison run: {ompl['date']}, total {ompl['total_s']:.0f} s"
            f"{' (quick)' if ompl.get('quick') else ''}."
        ),
        "",
    ]


def write_reports(results: dict | None = None, ompl: dict | None = None) -> None:
    """Write ``benchmarks/RESULTS.md`` from the saved JSON results (the docs include that file).

    Whichever of ``results`` / ``ompl`` is given is saved first; the other is read from its
    JSON file if a previous run left one, so the two scripts can run separately. Every section
    of the old RESULTS.md this function does not write (another script's) is kept.
    """
    if results is not None:
        RESULTS_JSON.write_text(json.dumps(results, indent=1, default=float))
    if ompl is not None:
        OMPL_JSON.write_text(json.dumps(ompl, indent=1, default=float))
    if results is None and RESULTS_JSON.exists():
        results = json.loads(RESULTS_JSON.read_text())
    if ompl is None and OMPL_JSON.exists():
        ompl = json.loads(OMPL_JSON.read_text())

    parts = [
        "# pmplan benchmark results",
        "",
        (
            "Generated by `python benchmarks/run.py` (and `benchmarks/ompl_compare.py`); "
            "see `benchmarks/README.md` for what every number means. Ratios are measured in "
            "the same run, so they are more stable than absolute times on this shared machine."
        ),
        "",
    ]
    if results is not None:
        mach = _machine_md(results["machine"])
        mode = "quick (`--quick`)" if results.get("quick") else "full"
        parts += [
            "## Machine",
            "",
            mach,
            "",
            f"Mode: {mode}. Seed: {results['seed']}.",
            "",
            "## Goals",
            "",
            _goals_md(results),
            "",
            "## Summary: time / one copy of the output, one core and every core",
            "",
            SUMMARY_EXPLAIN.format(cores=results["machine"]["cores"]),
            "",
            _summary_md(results, results.get("summary_rows", [])),
            "",
            "## Batch throughput (`plan_batch`, one core)",
            "",
            (
                "*generic*: standard-normal coordinates, the top stratum (no ties): the common "
                "path. *degenerate*: integer lattice with exact column ties between robots and "
                "obstacles: desingularization and exact tie decisions. *strata mix* "
                "(planar_three): the batch is spread evenly over all 12 strata. The copy "
                "column is the batch time divided by the time of ONE `np.copyto` of an array "
                "the size of the output waypoints, measured in the same run (1 = as fast as "
                "copying the answer once)."
            ),
            "",
            _throughput_md(results),
            "",
        ]
        if results.get("skipped"):
            parts += ["Skipped: " + "; ".join(results["skipped"]), ""]
        if results.get("breakdown"):
            parts += [
                "## Where the time of `plan_batch` goes, (2,4,2) generic",
                "",
                (
                    "Every stage timed on its own, in the same run as the copy. The kernels "
                    "alone (which validate the queries too), writing into arrays that already "
                    "exist, are the planner's own cost; `plan_batch` adds a fresh output (whose "
                    "pages the operating system zeroes when they are first written). The "
                    "two `workers=-1` rows use every core: not one-core figures, shown for "
                    "reference. The separate validation pass is what `plan_batch` saves by "
                    "validating inside the kernel."
                ),
                "",
                _breakdown_md(results),
                "",
            ]
        parts += [
            "## Single-query latency (`pmplan.plan`)",
            "",
            _latency_md(results),
            "",
            "## Peak memory of `plan_batch` relative to its output",
            "",
            (
                "tracemalloc sees numpy's allocations; the RSS column (peak resident set "
                "growth during the call, Linux `VmHWM`) also sees allocations made inside "
                "compiled kernels."
            ),
            "",
            _memory_md(results),
            "",
            "## Scaling",
            "",
            "![scaling](../docs/scaling.png)",
            "",
            _scaling_md(results),
            "",
        ]
    if ompl is not None:
        sect = ompl_section(ompl)
        parts += sect
    # the sections written by benchmarks/scale_bench.py, store_breakdown.py, cert_bench.py,
    # planar_bench.py and refine_bench.py
    for name in ("scale_results.md", "store_breakdown.md", "cert_results.md", "planar_results.md",
                 "refine_results.md"):
        section = HERE / name
        if section.exists():
            sect = section.read_text().rstrip().splitlines() + [""]
            parts += sect
    owned = {line.rstrip() for line in parts if line.startswith("## ")}
    parts += _foreign_sections(HERE / "RESULTS.md", owned)
    (HERE / "RESULTS.md").write_text("\n".join(parts))


def rss_now_kib() -> tuple[int, int]:
    """(VmRSS, VmHWM) of this process in KiB (Linux); (-1, -1) elsewhere."""
    try:
        vals = {}
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(("VmRSS", "VmHWM")):
                vals[line.split(":")[0]] = int(line.split()[1])
        return vals["VmRSS"], vals["VmHWM"]
    except (OSError, KeyError):
        return -1, -1


def reset_peak_rss() -> bool:
    """Reset this process's peak RSS (Linux ``clear_refs`` 5); False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


if __name__ == "__main__":  # pragma: no cover
    sys.exit("this is a helper module: run benchmarks/run.py")
