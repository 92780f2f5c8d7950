"""Scene families of issue 25 (item 7): seeded generators of rooms, swaps and 3-D rooms.

Every family lives in a box ``[0, SIZE]^d`` (SIZE = 10) with the required distance ``R = 0.3``
between any two robots and between a robot and an obstacle:

* ``room`` (d = 2, m = 6): obstacles uniform in the box, pairwise at least ``2 R + 2 (R/2)``
  apart and at least ``R`` from the walls; starts and goals uniform, each point at least
  ``MARGIN * R`` (1.1 R) from every other point of its configuration (robots and obstacles) and
  from the walls;
* ``swap`` (d = 2, m = 6): the same obstacles and starts; robots exchange places pairwise (robot
  2k's goal is robot 2k+1's start and vice versa; n even);
* ``room3d`` (d = 3, m = 4): as ``room`` in ``[0, SIZE]^3``;
* ``room_walls`` and ``swap_walls``: as ``room`` and ``swap``, with the obstacles at least
  ``WALL_GAP = 2 R + R/2`` from the walls: a wall keeps from an obstacle's disc the gap two
  obstacles' discs keep from each other (2 R, two robots side by side). In ``room`` and ``swap``
  an obstacle may sit R from a wall, and a robot of radius R/2 cannot pass between them
  (Mathematics §8: a planner continuous on a domain cannot always go round such an obstacle
  on the wide side).

:func:`queries` draws ``count`` queries of one row from a seed; the same (family, n, count,
seed) gives the same queries. Rows are drawn independently of each other
(``default_rng([seed, family index, n])``), so that ``--quick`` runs, which stop at smaller n and
fewer queries, plan a prefix of the full run's queries of the same row.

Not a test module (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "FAMILIES",
    "MARGIN",
    "SIZE",
    "WALL_GAP",
    "Family",
    "R",
    "continuity_total",
    "fmt_k",
    "group_table",
    "length_total",
    "queries",
    "refined_in_box",
    "rows_main",
    "run_head",
    "summary",
    "valid_total",
    "variant_rows",
    "variants_markdown",
    "variants_row",
]

#: the box side (the scene size)
SIZE = 10.0
#: the required distance between two robots and between a robot and an obstacle
R = 0.3
#: starts and goals keep MARGIN * R from every other point of their configuration and the walls
MARGIN = 1.1
#: obstacles are pairwise at least this far apart (2 R + 2 (R/2))
OBSTACLE_GAP = 2 * R + 2 * (R / 2)
#: in the ``*_walls`` families, the obstacles are at least this far from the walls (2 R + R/2:
#: the disc leaves 2 R to the wall, as two discs leave 2 R between them)
WALL_GAP = 2 * R + R / 2


class Family:
    """One scene family: its name, dimension d, number of obstacles m, and whether it swaps."""

    def __init__(self, name: str, d: int, m: int, swap: bool, index: int, wall: float = R):
        self.name, self.d, self.m, self.swap, self.index = name, d, m, swap, index
        #: the obstacles' least distance from the walls
        self.wall = wall

    def __repr__(self) -> str:  # pragma: no cover
        return f"Family({self.name!r}, d={self.d}, m={self.m})"


FAMILIES = {
    "room": Family("room", 2, 6, False, 0),
    "swap": Family("swap", 2, 6, True, 1),
    "room3d": Family("room3d", 3, 4, False, 2),
    "room_walls": Family("room_walls", 2, 6, False, 3, WALL_GAP),
    "swap_walls": Family("swap_walls", 2, 6, True, 4, WALL_GAP),
}


def _draw(rng: np.random.Generator, count: int, d: int, lo: float, hi: float,
          others: np.ndarray, gap_others: float, gap_self: float) -> np.ndarray:
    """``count`` points uniform in [lo, hi]^d, one at a time (rejection): each at least
    ``gap_others`` from every row of ``others`` and ``gap_self`` from the points drawn before."""
    pts: list[np.ndarray] = []
    for _ in range(count):
        for _attempt in range(100_000):
            x = rng.uniform(lo, hi, d)
            if others.size and np.linalg.norm(others - x, axis=1).min() < gap_others:
                continue
            if pts and np.linalg.norm(np.asarray(pts) - x, axis=1).min() < gap_self:
                continue
            pts.append(x)
            break
        else:  # pragma: no cover - the box is far from full for n <= 16
            raise RuntimeError("could not place a point: the box is too crowded")
    return np.asarray(pts).reshape(count, d)


def obstacles(rng: np.random.Generator, family: Family) -> np.ndarray:
    """m obstacles uniform in the box, pairwise >= OBSTACLE_GAP apart, >= ``family.wall`` (R, or
    WALL_GAP) from the walls."""
    return _draw(rng, family.m, family.d, family.wall, SIZE - family.wall,
                 np.empty((0, family.d)), 0.0, OBSTACLE_GAP)


def configuration(rng: np.random.Generator, family: Family, n: int,
                  obst: np.ndarray) -> np.ndarray:
    """n robot positions, each >= MARGIN R from the obstacles, the other robots and the walls."""
    g = MARGIN * R
    return _draw(rng, n, family.d, g, SIZE - g, obst, g, g)


def query(rng: np.random.Generator, family: Family, n: int):
    """One query (obstacles (m, d), starts (n, d), goals (n, d)) of the family."""
    o = obstacles(rng, family)
    s = configuration(rng, family, n, o)
    if family.swap:
        if n % 2:
            raise ValueError("the swap family needs an even number of robots")
        g = s.copy()
        g[0::2], g[1::2] = s[1::2], s[0::2]
    else:
        g = configuration(rng, family, n, o)
    return o, s, g


def queries(family: str, n: int, count: int, seed: int) -> list[tuple]:
    """``count`` queries of one row (family, n), drawn from ``seed`` (row-independent stream)."""
    fam = FAMILIES[family]
    rng = np.random.default_rng([seed, fam.index, n])
    return [query(rng, fam, n) for _ in range(count)]


def check(o: np.ndarray, s: np.ndarray, g: np.ndarray) -> bool:
    """Whether a query meets the family rules (distances, walls): used by the harness's self
    check and by the replanning run (drifting obstacles may break them)."""
    for c in (s, g):
        pts = np.concatenate([o, c])
        dist = np.linalg.norm(pts[:, None] - pts[None], axis=-1)
        m = len(o)
        np.fill_diagonal(dist, np.inf)
        if dist[m:].min() < R or np.any(c < 0) or np.any(c > SIZE):
            return False
    return True


def rows_main(name: str, doc: str, row, markdown, families, ns, seeds: str, argv=None,
              count: int = 16) -> int:
    """The command line of a per-row scene benchmark (``benchmarks/<name>.py``): ``--seeds``
    (default ``seeds``), ``--queries`` (default ``count``) and ``--from-json`` (rewrite the
    report from the JSON, no planning); one warm-up plan, then ``row(family, n, seed, count)``
    for every seed, family and n, written with the run's seconds to ``benchmarks/<name>.json``
    and, through ``markdown(result)``, ``.md`` (``_common.write_report``, which prints it)."""
    import argparse
    import datetime as _dt
    import sys
    import time

    from _common import rewrite_report, write_report

    import pmplan

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--seeds", default=seeds)
    ap.add_argument("--queries", type=int, default=count)
    ap.add_argument("--from-json", action="store_true", help="rewrite the .md from the .json")
    args = ap.parse_args(argv)
    if args.from_json:
        rewrite_report(name, markdown)
        return 0
    o, s, g = queries("room", 2, 1, 0)[0]  # warm-up / JIT
    pmplan.plan(o, s, g, bounds=(0.0, SIZE), refine=True, radius=R / 2)
    t0 = time.perf_counter()
    rows = [row(f, n, int(seed), args.queries) for seed in args.seeds.split(",")
            for f in families for n in ns]
    res = {"command": " ".join([f"python benchmarks/{name}.py", *(argv or sys.argv[1:])]),
           "date": _dt.date.today().isoformat(), "count": args.queries,
           "seconds": time.perf_counter() - t0, "rows": rows}
    write_report(name, res, markdown)
    return 0


def summary(label: str, qs: list, plan) -> dict:
    """One cell of a per-row scene benchmark: ``plan(o, s, g)`` (a refined pmplan.Plan) on
    every query of ``qs``; the valid count (``respects_radius``, the walls included), the
    median time per query (ms), the median length / LB and the invalid ones per
    ``category`` of their ``radius_miss`` (:class:`pmplan.reasons.RadiusMiss`), printed after
    ``label``."""
    import time

    ok, times, ratios, why = 0, [], [], {}
    for o, s, g in qs:
        t0 = time.perf_counter()
        p = plan(o, s, g)
        times.append(time.perf_counter() - t0)
        ok += bool(p.respects_radius)
        if not p.respects_radius:
            cat = p.radius_miss.category
            why[cat] = why.get(cat, 0) + 1
        ratios.append(p.path.length() / np.linalg.norm(g - s, axis=1).sum())
    out = {"valid": ok, "count": len(times), "time_ms": 1e3 * float(np.median(times)),
           "len_lb": float(np.median(ratios)), "why": why}
    print(f"{label}: {ok}/{len(times)} {out['time_ms']:.1f} ms len/LB {out['len_lb']:.2f}",
          flush=True)
    return out


def variants_row(fam: str, n: int, seed: int, count: int, variants: dict) -> dict:
    """One row of an A/B scene benchmark: pmplan's default plan in the box (``bounds=(0,
    SIZE)``) refined at its default effort with radius = obstacle_radius = R/2
    (:func:`refined_in_box`), under every variant of ``variants`` (name -> a function that
    switches pmplan to it; the first is switched back at the end), on the same queries
    (:func:`summary` per variant)."""
    qs = queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "variants": {}}
    for name, switch in variants.items():
        switch()
        out["variants"][name] = summary(f"seed {seed} {fam} n={n} {name}", qs, refined_in_box)
    next(iter(variants.values()))()
    return out


def attribute_variants(module, variants: dict) -> dict:
    """The switches :func:`variants_row` takes for variants that set attributes of ``module``
    (constants a pmplan function reads at every call): ``variants`` maps a name to its
    ``{attribute: value}``, the first pmplan's default; an attribute of another object (a
    planner class's method) is keyed ``(object, attribute)``."""
    def switch(values: dict):
        def apply() -> None:
            for key, value in values.items():
                target, name = key if isinstance(key, tuple) else (module, key)
                setattr(target, name, value)
        return apply
    return {name: switch(values) for name, values in variants.items()}


def refined_in_box(o: np.ndarray, s: np.ndarray, g: np.ndarray, planner: str | None = None):
    """pmplan's default plan of one query in the box ``(0, SIZE)``, refined at its default
    effort with radius = obstacle_radius = R/2: the plan the per-row scene benchmarks measure
    (``planner``: another planner's, the rest at its defaults)."""
    import pmplan

    return pmplan.plan(o, s, g, bounds=(0.0, SIZE), refine=True, radius=R / 2,
                       obstacle_radius=R / 2, planner=planner)


def refined_on_domains(o: np.ndarray, s: np.ndarray, g: np.ndarray):
    """:func:`refined_in_box` with the section pmplan's default takes on the domains of
    Mathematics §4.2 (the compact lanes, the one-side lanes from ``CROWD_LANES`` robots on):
    without the wall side (``obstacle_line_walls``, the default in a box), whose domains are
    cut along the wall of sides; the bounds of Mathematics §8 ("How often", "How long") are
    for planners continuous on these domains."""
    from pmplan.planners.base import default_planner

    return refined_in_box(o, s, g, default_planner(np.shape(o)[-1], len(s), len(o),
                                                   refining=True))


def fmt_k(k: float) -> str:
    """A modulus of continuity K in a report: ``4,489``, or ``4.7e+05`` from 1e5 on."""
    return f"{k:,.0f}" if k < 1e5 else f"{k:.1e}"


def valid_total(cells: list) -> str:
    """Over the cells of a group of rows: the valid queries over the queries."""
    return f"{sum(c['valid'] for c in cells)}/{sum(c['count'] for c in cells)}"


def continuity_total(cells: list) -> str:
    """Over the cells of a group of rows: those meeting issue 25's continuity goal (no probe
    above it, ``k_over``) and, in brackets, the largest K."""
    kmax = max(c["k_max"] for c in cells)
    return f"{sum(c['k_over'] == 0 for c in cells)}/{len(cells)} ({fmt_k(kmax)})"


def length_total(pairs: list) -> str:
    """Over the (cell, base cell) pairs of a group of rows: the geometric mean of the cell's
    median len/LB over the base's and, in brackets, the largest ratio."""
    ratio = np.array([c["len_lb"] / b["len_lb"] for c, b in pairs])
    return f"{float(np.exp(np.log(ratio).mean())):.3f} ({ratio.max():.2f})"


def variant_rows(res: dict, columns: str, cell) -> list[str]:
    """The per-row table of an A/B scene benchmark: per row (seed, family, n) and variant
    ``cell(entry)`` under ``"<variant>: <columns>"``, followed by the entry's probes above the
    continuity goal in brackets when it counts some (``k_over``)."""
    names = list(res["rows"][0]["variants"])
    lines = ["| seed | row | " + " | ".join(f"{v}: {columns}" for v in names) + " |",
             "|---|---|" + "---|" * len(names)]
    for r in res["rows"]:
        cells = [cell(e) + (f" ({e['k_over']})" if e.get("k_over") else "")
                 for e in r["variants"].values()]
        lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(cells) + " |")
    return lines


def group_table(res: dict, groups: list, totals, names: list) -> list[str]:
    """The totals table of an A/B scene benchmark: per group of seeds ``(name, seeds)`` and
    group of robot counts (n = 2 and 4, 8 and 16, all), ``totals(rows)`` -- one text per variant
    of ``names`` -- over the rows of ``res`` in both."""
    lines = ["| seeds | n | " + " | ".join(names) + " |", "|---|---|" + "---|" * len(names)]
    for name, group in groups:
        for label, ns in (("2, 4", {2, 4}), ("8, 16", {8, 16}), ("all", None)):
            rows = [r for r in res["rows"] if r["seed"] in group and (ns is None or r["n"] in ns)]
            if rows:
                lines.append(f"| {name} | {label} | " + " | ".join(totals(rows)) + " |")
    return lines


def run_head(res: dict, scene: str) -> str:
    """The opening of a scene A/B report: the command and date of the run ``res``, then
    ``scene`` (what the rows are), r, the queries per row and the plans compared -- pmplan's
    default plan in the box, refined at its default effort with radius = obstacle_radius =
    r/2 -- without a final stop."""
    return (f"Command: `{res['command']}` ({res['date']}). {scene}, r = {R}, {res['count']} "
            "queries per row, pmplan's default plan in the box refined at its default effort, "
            "radius = obstacle_radius = r/2")


def variants_markdown(res: dict, title: str, prose: str, names: list, new: str,
                      base: str) -> str:
    """The report of an A/B scene benchmark (rows of :func:`variants_row`): per row and
    variant the valid count, median ms and median length / LB; per seed the totals and the
    rows where ``new`` keeps the radii on more / fewer queries than ``base``."""
    lines = [f"# {title}", "", run_head(res, "Rooms 10 x 10") + ". " + prose
             + " valid = keeps the radii and the walls (decided exactly); time = median ms per "
             "query (plan + refinement, one core; a shared machine: compare within a row); "
             "len/LB = median length / sum of the straight distances.", "",
             *variant_rows(res, "valid, ms, len/LB",
                           lambda e: f"{e['valid']}/{e['count']}, {e['time_ms']:.1f}, "
                                     f"{e['len_lb']:.2f}")]
    lines += ["", "Totals (valid queries of all rows of a seed):", "",
              "| seed | " + " | ".join(names) + f" | rows where {new} beats {base} / loses |",
              "|---|" + "---|" * (len(names) + 1)]
    for seed in sorted({r["seed"] for r in res["rows"]}):
        rows = [r for r in res["rows"] if r["seed"] == seed]
        tot = [sum(r["variants"][v]["valid"] for r in rows) for v in names]
        den = sum(r["variants"][new]["count"] for r in rows)
        gain = sum(r["variants"][new]["valid"] > r["variants"][base]["valid"] for r in rows)
        loss = sum(r["variants"][new]["valid"] < r["variants"][base]["valid"] for r in rows)
        lines.append(f"| {seed} | " + " | ".join(f"{t}/{den}" for t in tot)
                     + f" | {gain} / {loss} |")
    return "\n".join(lines) + "\n"
