"""The price of continuity (issue 25, item 5): path length against the measured modulus of
continuity, for pmplan at several refinement efforts and for OMPL.

Usage (from the repository root; needs ``pmplan[bench]``, i.e. ``ompl``)::

    python benchmarks/price_of_continuity.py            # about 3 minutes
    python benchmarks/price_of_continuity.py --seed 2   # the held-out draw (its own files)

A continuous section cannot always take the shortest route: inside a domain the route may not
switch sides of an obstacle, so it pays in length for being continuous. The dial a user has is
the refinement's effort (``waypoints``, ``steps`` of :func:`pmplan.refine`). On rows of the
scene families of ``benchmarks/scenes.py`` (box [0, 10]^d, r = 0.3, 16 queries per row), every
setting is measured on the same queries:

* *pmplan, effort (w, s)*: ``pmplan.refine(pmplan.plan(o, s, g, bounds=(0, 10), lift=r,
  planner=P), radius=r/2, obstacle_radius=r/2, waypoints=w, steps=s)`` (``lift=r`` and ``P``:
  the unit and the planner ``pmplan.plan(..., bounds=, refine=True)`` takes, the robots'
  diameter and, in the plane, ``obstacle_line_walls``; 4/56 is its default effort up
  to 4 robots and in space, 4/72 for 5 to 8 robots in the plane);
* *OMPL RRTConnect* (+ ``simplifySolution``) and *OMPL RRT\\** (0.5 s), as in
  ``scenes_compare.py``.

Per (row, setting): the valid share, the median length / lower bound over the valid paths, and
the modulus: every start moved by 1e-6 in a random direction, replanned, the sup distance of
the two paths / 1e-6 (the median and the 90th percentile over the queries; pmplan's at equal
times, OMPL's at 201 equal arc-length parameters, see ``scenes_compare.py``). Writes
``benchmarks/price_of_continuity.{json,md}`` and the picture ``docs/price_of_continuity.png``
(length / LB against the modulus, one marker per setting and row); another seed S writes only
``benchmarks/price_of_continuity_seedS.{json,md}``. Not a test module.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import scenes  # noqa: E402
from _common import exit_after_ompl, machine_info  # noqa: E402
from scenes_compare import (  # noqa: E402
    HALF,
    RC,
    RS,
    OmplRunner,
    PmplanRunner,
    _fmt,
    _kernels,
    evaluate,
    summarise,
)

import pmplan  # noqa: E402
from pmplan.planners.base import default_planner  # noqa: E402

#: the refinement efforts (waypoints, steps): pmplan's defaults are (4, 56) up to 4 robots and in
#: space up to 8, (4, 72) for 5 to 8 robots in the plane, (4, 112) beyond
#: (pmplan.refine.default_effort)
EFFORTS = [(1, 8), (1, 28), (2, 56), (4, 56), (4, 72), (4, 112), (4, 224)]
ROWS = [("room", 4), ("room", 8), ("swap", 4), ("swap", 8), ("room3d", 8)]
#: the default unit of a refined plan (pmplan.configuration.default_lift): here r
UNIT = pmplan.configuration.default_lift(None, HALF, HALF, True)


class EffortRunner(PmplanRunner):
    """pmplan refined in the box at one effort (waypoints, steps)."""

    def __init__(self, waypoints: int, steps: int):
        super().__init__(None, bounded=True)
        self.effort = dict(waypoints=waypoints, steps=steps)

    def plan(self, o, s, g):
        t0 = time.perf_counter()
        try:
            # (the unit and the planner pmplan.plan(..., bounds=, refine=True) takes: the
            # robots' diameter, the one-side lanes on the wall side in the plane)
            planner = default_planner(np.shape(o)[-1], len(s), len(o), refining=True,
                                      bounded=True)
            raw = pmplan.plan(o, s, g, bounds=self.kw["bounds"], lift=UNIT, planner=planner)
            p = pmplan.refine(raw, radius=HALF, obstacle_radius=HALF, **self.effort)
        except pmplan.PmplanError:
            return time.perf_counter() - t0, None
        return time.perf_counter() - t0, (p, p.path.waypoints)


def _name(setting) -> str:
    return setting if isinstance(setting, str) else f"pmplan, effort {setting[0]}/{setting[1]}"


def run(seed: int, count: int) -> dict:
    kernels = _kernels()
    rows = []
    for fam, n in ROWS:
        d = scenes.FAMILIES[fam].d
        qs = scenes.queries(fam, n, count, seed)
        rng = np.random.default_rng([seed, n, 7])
        dirs = []
        for _ in qs:
            v = rng.standard_normal((n, d))
            dirs.append(v / np.linalg.norm(v, axis=1, keepdims=True))
        cells = {}
        for setting in [*EFFORTS, RC, RS]:
            runner = (OmplRunner(n, d, setting, kernels) if isinstance(setting, str)
                      else EffortRunner(*setting))
            t0 = time.perf_counter()
            res = evaluate(runner, qs, dirs)
            summ = summarise(res)
            probes = [q["probe"] for q in res["queries"] if "probe" in q
                      and not q.get("probe_label_change")]
            summ["probe_p90"] = float(np.quantile(probes, 0.9)) if probes else float("nan")
            cells[_name(setting)] = summ
            print(f"{fam} n={n} {_name(setting):24s} valid {summ['valid']:2d}/{summ['count']} "
                  f"len/LB {summ['len_lb_median']:.3f} probe median {summ['probe_median']:.3g}"
                  f" p90 {summ['probe_p90']:.3g} time {summ['time_ms_median']:.2f} ms "
                  f"[{time.perf_counter() - t0:.0f} s]", flush=True)
        rows.append({"family": fam, "n": n, "d": d, "cells": cells})
    return {"seed": seed, "count": count, "rows": rows, "machine": machine_info(),
            "efforts": EFFORTS, "radius": HALF,
            "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def report(res: dict) -> str:
    held_out = res["seed"] != 1
    lines = ["# The price of continuity (issue 25, item 5)"
             + (f", seed {res['seed']} (held out)" if held_out else ""), "",
             f"`python benchmarks/price_of_continuity.py --seed {res['seed']}` ({res['date']}, "
             f"{res['count']} queries per row; see the script's docstring). *modulus*: sup "
             "change of the path / 1e-6 under a 1e-6 move of the starts (median, 90th "
             "percentile; pmplan over the moves that keep the domain label). *len/LB* over the "
             "valid paths (valid: every distance >= r along the path, exactly, and inside the "
             "box).", "",
             *(["The picture is the design draw's (seed 1); this draw confirms it in the "
                "table."] if held_out else
               ["![length / lower bound against the modulus of continuity]"
                "(../docs/price_of_continuity.png)"]), "",
             "| row | setting | valid | len/LB (median) | modulus median | modulus p90 | time "
             "(ms) |", "|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        for name, c in r["cells"].items():
            lines.append(f"| {r['family']} n = {r['n']} | {name} | {c['valid']}/{c['count']} | "
                         f"{_fmt(c['len_lb_median'])} | {_fmt(c['probe_median'])} | "
                         f"{_fmt(c['probe_p90'])} | {_fmt(c['time_ms_median'])} |")
    lines.append("")
    return "\n".join(lines)


def picture(res: dict, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.2), layout="constrained")
    markers = {"room": "o", "swap": "s", "room3d": "^"}
    names = [_name(e) for e in EFFORTS] + [RC, RS]
    cmap = plt.get_cmap("viridis")
    colors = {n: cmap(k / max(1, len(EFFORTS) - 1)) for k, n in enumerate(names[:len(EFFORTS)])}
    colors[RC], colors[RS] = "tab:red", "tab:orange"
    for r in res["rows"]:
        xs, ys = [], []
        for name in names[:len(EFFORTS)]:
            c = r["cells"][name]
            if c["valid"]:
                xs.append(c["probe_median"]), ys.append(c["len_lb_median"])
        ax.plot(xs, ys, "-", color="0.7", lw=1, zorder=1)
        for name in names:
            c = r["cells"][name]
            if not c["valid"]:
                continue
            ax.scatter(c["probe_median"], c["len_lb_median"], marker=markers[r["family"]],
                       color=colors[name], s=20 + 40 * c["valid"] / c["count"], zorder=3,
                       edgecolor="black", linewidth=0.5)
    for name in names:
        ax.scatter([], [], color=colors[name], label=name, edgecolor="black", linewidth=0.5)
    for fam, mk in markers.items():
        ax.scatter([], [], marker=mk, color="white", edgecolor="black", label=fam)
    ax.set_xscale("log")
    ax.set_xlabel("modulus of continuity: median sup change of the path / 1e-6 under a 1e-6 "
                  "move of the starts")
    ax.set_ylabel("median length / lower bound (valid paths)")
    ax.set_title("The price of continuity: pmplan (refinement effort waypoints/steps) and OMPL\n"
                 "marker size: valid share; grey lines join one row's pmplan efforts",
                 fontsize=10)
    ax.legend(fontsize=8, ncols=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.savefig(out, dpi=100)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--queries", type=int, default=16)
    args = ap.parse_args(argv)
    from ompl import util as ou

    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    ou.RNG.setSeed(args.seed)
    res = run(args.seed, args.queries)
    stem = "price_of_continuity" + ("" if args.seed == 1 else f"_seed{args.seed}")
    (HERE / f"{stem}.json").write_text(json.dumps(res, indent=1, default=float))
    (HERE / f"{stem}.md").write_text(report(res))
    if args.seed == 1:  # (the picture is the design draw's; other draws confirm it in tables)
        picture(res, HERE.parent / "docs" / "price_of_continuity.png")
    print(report(res))
    return 0


if __name__ == "__main__":
    exit_after_ompl(main())
