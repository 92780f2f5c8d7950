"""Continuity of the refined planner in floating point (issue 24, item 1): amplification per row.

Usage (from the repository root)::

    python benchmarks/refine_continuity.py                 # the rows of the table below
    python benchmarks/refine_continuity.py --quick         # a few queries per row
    python benchmarks/refine_continuity.py --seeds 3 --held-out ''   # another draw

For every family row (d, n, m, lift, family) it draws ``N`` valid queries (points at least
``GAP`` apart, radius ``RADIUS`` of the scene's size), plans and refines them, moves every
point of the query (starts, goals, obstacles) by ``delta`` times a uniform vector in
[-1, 1]^d for delta = 1e-6, 1e-9, 1e-12, refines again and measures the amplification ``K =
sup_t |path(t) - path'(t)| / delta`` -- the exact sup over the union of the breakpoints --
over the pairs whose domain label is the same. Per row: the largest K per delta, the raw
plan's own largest K, the largest K where the raw plan keeps the targets, the largest
``K_eff = K / max(1, target / c_raw)`` with its c_raw and target / c_raw, how many pairs have
K and K_eff above 1e3, the *jumps* (a perturbation of at most 1e-9 moving the path by more than
1e-3), and the refined clearance beside the raw one (no self-squeezing: the smallest ratio
refined / raw over the pairs of points, item 2); per draw, the pooled share of K_eff <= 1e3 and
the refinement's own share K_eff / max(1, raw K).

A replanning run: 4 robots swapping in a 10 x 10 room, 6 obstacles drifting 0.02 per tick,
replanned and refined every tick (80 ticks); the jumps (a change per drift above 25 and ten
times the raw plan's, with the same label), each bisected down to an obstacle move of 1e-10,
and those still above 1e-3 there bisected on down to ``DEEP`` (1e-14): a change that stays
above 1e-3 across such a move is a jump of the map in floating point; and the median change
per drift. For each persisting jump: whether its tick's drift carries a robot's column across
another point's (a wall of a lower label, Mathematics 4.2, between two queries with one
label; decided by the exact signs of the column differences), how far from that wall the
bisection stops, and, near the first such wall of the draw, the largest K at the distances
``WALL_DISTANCES`` from it.

Writes ``benchmarks/refine_continuity.md`` (linked from RESULTS.md). Not a test module.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import math
import time
from pathlib import Path

import numpy as np

import pmplan
from refine_bench import replace_section
from pmplan.errors import PmplanError
from pmplan.predicates import exact_projection_difference_sign

HERE = Path(__file__).resolve().parent
DELTAS = (1e-6, 1e-9, 1e-12)
GAP = 0.06
RADIUS = 0.025
GOAL_P999, GOAL_MAX = 1e3, 1e4
#: a persisting jump of the replanning run is bisected on down to an obstacle move this small
#: (a few units in the last place of the room's coordinates, which reach 10)
DEEP = 1e-14
#: the replanning run: the obstacles' drift per tick and the robots' radius (target 2 radius)
DRIFT = 0.02
REPLAN_RADIUS = 0.1
REPLAN_TARGET = 2 * REPLAN_RADIUS
#: the distances from a domain wall (scene units) at which the map is probed near a persisting
#: jump, and the moves of the probe there: the deltas of the rows (DELTAS), each where it is at
#: most WALL_REACH of the distance (a larger move may cross the wall, where the path must jump)
WALL_DISTANCES = (1e-7, 1e-6, 1e-5, 1e-4, 1e-3)
WALL_REACH = 0.1


def _points(rng, k: int, d: int, size: float, gap: float):
    """k points uniform in [0, size]^d, pairwise at least gap apart (rejection)."""
    while True:
        x = rng.uniform(0.0, size, (k, d))
        dist = np.linalg.norm(x[:, None] - x[None], axis=-1)
        if k < 2 or dist[np.triu_indices(k, 1)].min() >= gap:
            return x


def _uniform(rng, d, n, m, size=1.0, gap=GAP, integer=False):
    if integer:
        while True:
            pts = rng.integers(0, 4, (m + 2 * n, d)).astype(float)
            o, s, g = pts[:m], pts[m:m + n], pts[m + n:]
            ok = all(len({tuple(x) for x in np.concatenate([o, c])}) == m + n for c in (s, g))
            if ok:
                return o, s, g
    o = _points(rng, m, d, size, gap)
    while True:
        s = _points(rng, n, d, size, gap)
        g = _points(rng, n, d, size, gap)
        if all(np.linalg.norm(c[:, None] - o[None], axis=-1).min() >= gap for c in (s, g)):
            return o, s, g


def sup_paths(pa: pmplan.PiecewiseLinearPath, pb: pmplan.PiecewiseLinearPath) -> float:
    """The exact sup over t of the largest distance between the two paths' points (both are
    linear between the union of their breakpoints)."""
    t = np.union1d(pa.times, pb.times)
    a, b = pa(t), pb(t)
    return float(np.sqrt(((a - b) ** 2).sum(-1)).max())


def _sup(pa: pmplan.Plan, pb: pmplan.Plan) -> float:
    """:func:`sup_paths` of two plans' paths."""
    return sup_paths(pa.path, pb.path)


def _refined(o, s, g, lift, radius, via=None):
    kw = {"refine": True, "radius": radius}
    if via is not None:
        return pmplan.plan_sequence(o, [s, *via, g], lift=lift, **kw), \
            pmplan.plan_sequence(o, [s, *via, g], lift=lift)
    return pmplan.plan(o, s, g, lift=lift, **kw), pmplan.plan(o, s, g, lift=lift)


def _pair_ratio(raw: pmplan.Plan, ref: pmplan.Plan) -> float:
    """The smallest refined / raw minimum distance over the pairs of points (item 2)."""
    from pmplan.certify import segment_clearance

    m = raw.dims[2]
    p = raw.path.waypoints.shape[1]
    i, j = np.triu_indices(p, 1)
    keep = j >= m

    def mins(w):
        r = w[:, i[keep]] - w[:, j[keep]]
        return segment_clearance(r[:-1], r[1:]).min(axis=0)

    return float((mins(ref.path.waypoints) / mins(raw.path.waypoints)).min())


def row(name, d, n, m, lift, family, count, seed, size=1.0, radius=RADIUS):
    """The probes of one family row: per pair (query, perturbed query with the same label)
    its K, the raw plan's K and the query's target / c_raw."""
    rng = np.random.default_rng(seed)
    recs = []  # (delta, K, raw K, target / c_raw, c_raw / size)
    jumps = 0
    ratios = []
    t0 = time.process_time()
    done = 0
    tries = 0
    while done < count and tries < 5 * count:
        tries += 1
        via = None
        if family == "integer":
            o, s, g = _uniform(rng, d, n, m, integer=True)
            rad = 0.0
        else:
            o, s, g = _uniform(rng, d, n, m, size=size, gap=GAP * size)
            rad = radius * size
        if family == "sequence":
            via = [_points(rng, n, d, size, GAP * size)]
            if np.linalg.norm(via[0][:, None] - o[None], axis=-1).min() < GAP * size:
                continue
        try:
            ref, raw = _refined(o, s, g, lift, rad, via)
        except PmplanError:
            continue
        if family == "near-contact" and raw.clearance > 3e-3 * size:
            continue  # keep only raw plans that nearly touch
        done += 1
        ratios.append(_pair_ratio(raw, ref))
        target = max(2 * rad, 0.5 * raw.clearance) if rad else 0.5 * raw.clearance
        for dl in DELTAS:
            step = dl * size
            po, ps, pg = (x + step * rng.uniform(-1, 1, x.shape) for x in (o, s, g))
            pv = None if via is None else [v + step * rng.uniform(-1, 1, v.shape) for v in via]
            try:
                ref2, raw2 = _refined(po, ps, pg, lift, rad, pv)
            except PmplanError:
                continue
            if ref2.domain != ref.domain:
                continue
            change = _sup(ref, ref2)
            if dl <= 1e-9 and change > 1e-3 * size:
                jumps += 1
            recs.append((dl, change / step, _sup(raw, raw2) / step, target / raw.clearance,
                         raw.clearance / size))
    return summarise(name, recs, done, jumps, ratios, time.process_time() - t0)


def summarise(name, recs, done, jumps, ratios, cpu):
    """One row's figures from its probes (see the module docstring)."""
    k = np.array([r[1] for r in recs])
    kraw = np.array([r[2] for r in recs])
    tc = np.array([r[3] for r in recs])
    bound = k / np.maximum(1.0, tc) if k.size else k
    factor = bound / np.maximum(1.0, kraw) if k.size else k  # the refinement's own share
    clear = tc <= 1.0  # the raw plan keeps the targets: no pair is pushed out
    worst = int(np.argmax(bound)) if k.size else None
    return {
        "row": name, "queries": done, "cpu_s": cpu, "pairs": int(k.size), "jumps": jumps,
        "max": {dl: max((r[1] for r in recs if r[0] == dl), default=float("nan"))
                for dl in DELTAS},
        "raw_max": float(kraw.max()) if k.size else float("nan"),
        "clear_max": float(k[clear].max()) if clear.any() else float("nan"),
        "over1e3": int((k > GOAL_P999).sum()),
        "eff_over1e3": int((bound > GOAL_P999).sum()),
        "bound_constant": float(bound.max()) if k.size else float("nan"),
        "factor_max": float(factor.max()) if k.size else float("nan"),
        "factors": factor.tolist(),
        "worst_tc": float(tc[worst]) if worst is not None else float("nan"),
        "worst_c_raw": float(recs[worst][4]) if worst is not None else float("nan"),
        "min_ratio": float(min(ratios)) if ratios else float("nan"),
        "median_ratio": float(np.median(ratios)) if ratios else float("nan"),
    }


def meets(r) -> bool:
    """The goal of a row (item 1 with its stated limit, K_eff = K / max(1, target / c_raw)):
    no jump and K_eff <= 1e4 on every pair; K_eff <= 1e3 on >= 99.9 % is judged on the pairs
    of all rows together (:func:`pooled`: a row has 30-90 pairs)."""
    return r["jumps"] == 0 and not r["bound_constant"] > GOAL_MAX


def pooled(results) -> tuple[int, int]:
    """(pairs with K_eff > 1e3, pairs) over all rows."""
    return (sum(r["eff_over1e3"] for r in results), sum(r["pairs"] for r in results))


def _column_pairs(o, configs):
    """Every (configuration, robot point, other point) of a query: the pairs whose column tie
    is a wall of a lower label (Mathematics 4.2: a robot's column meeting another point's)."""
    m = len(o)
    return [(c, j, k) for c in range(len(configs)) for j in range(m, m + len(configs[c]))
            for k in range(m + len(configs[c])) if k != j and (k < m or k > j)]


def _ties(o, configs) -> np.ndarray:
    """The exact sign of every column difference of :func:`_column_pairs`: two queries with
    the same label whose signs differ lie on two sides of a wall of a lower label."""
    pairs = _column_pairs(o, configs)
    full = [np.concatenate([o, c]) for c in configs]
    ya = np.array([full[c][j] for c, j, _ in pairs])
    yb = np.array([full[c][k] for c, _, k in pairs])
    o1 = np.broadcast_to(o[0], ya.shape)
    o2 = np.broadcast_to(o[1], ya.shape)
    return exact_projection_difference_sign(ya, yb, o1, o2)


def _wall(o, configs):
    """The nearest wall of a lower label: ``(distance, configuration, robot point, other
    point)``, the distance the smallest |column difference| of :func:`_column_pairs` (in the
    scene's units; floats, to a few units in the last place)."""
    e = (o[1] - o[0]) / np.linalg.norm(o[1] - o[0])
    full = [np.concatenate([o, c]) for c in configs]
    best = (np.inf, 0, 0, 0)
    for c, j, k in _column_pairs(o, configs):
        gap = abs(float((full[c][j] - full[c][k]) @ e))
        if gap < best[0]:
            best = (gap, c, j, k)
    return best


def _point_name(i: int, m: int, c: int) -> str:
    return f"o{i + 1}" if i < m else ("x" if c == 0 else "x'") + str(i - m + 1)


def replanning(ticks=80, seed=0):
    """4 robots swapping in a 10 x 10 room, 6 obstacles drifting 0.02 per tick."""
    rng = np.random.default_rng(seed)
    o = _points(rng, 6, 2, 10.0, 1.0)
    s = np.array([[1.0, 1.0], [9.0, 1.0], [1.0, 9.0], [9.0, 9.0]])
    g = s[::-1].copy()
    vel = rng.normal(size=o.shape)
    vel *= DRIFT / np.linalg.norm(vel, axis=-1, keepdims=True)
    def at(obst):
        return pmplan.plan(obst, s, g, lift="scene", refine=True, radius=REPLAN_RADIUS)

    def halve(base, span, size, floor, plo, phi):
        """Bisect the obstacle move ``base -> base + span`` (its largest point move ``size``)
        toward the half that moves the path more, down to a move of ``floor`` (or a label
        change, or a refused query); returns ``(lo, hi, plan at lo, plan at hi)``, lo and hi
        fractions of ``span``."""
        lo, hi = 0.0, 1.0
        while (hi - lo) * size > floor:
            mid = 0.5 * (lo + hi)
            try:
                pm = at(base + mid * span)
            except PmplanError:
                break
            if pm.domain != plo.domain and pm.domain != phi.domain:
                break
            a_ = _sup(plo, pm) if pm.domain == plo.domain else -1.0
            b_ = _sup(pm, phi) if pm.domain == phi.domain else -1.0
            if a_ >= b_:
                hi, phi = mid, pm
            else:
                lo, plo = mid, pm
        return lo, hi, plo, phi

    def bisect(o0, o1, c0, c1):
        """The jump of a flagged tick, bisected: halve the drift toward the half that moves
        the path more, down to an obstacle move of 1e-10 (or a label change), and a jump that
        persists there on down to DEEP; returns (that move's size, the path change across it,
        the raw plan's clearance, (the DEEP move's size, the path change and the raw plan's
        change across it))."""
        lo, hi, plo, phi = halve(o0, o1 - o0, DRIFT, 1e-10, c0, c1)
        c_raw = pmplan.plan(o0 + lo * (o1 - o0), s, g, lift="scene").clearance
        change = _sup(plo, phi) if plo.domain == phi.domain else float("nan")
        deep = (float("nan"),) * 3
        wall = {"crosses": bool((_ties(o0, (s, g)) != _ties(o1, (s, g))).any())}
        if change > 1e-3:  # on, down to DEEP: a steep map or a jump in floating point?
            base, span = o0 + lo * (o1 - o0), (hi - lo) * (o1 - o0)
            size = float(np.linalg.norm(span, axis=-1).max())
            a0, a1, pa, pb = halve(base, span, size, DEEP, plo, phi)
            raw = [pmplan.plan(base + t * span, s, g, lift="scene") for t in (a0, a1)]
            deep = ((a1 - a0) * size, _sup(pa, pb), _sup(*raw))
            qa, qb = base + a0 * span, base + a1 * span
            dist, cw, j, k = _wall(qa, (s, g))
            wall.update(distance=min(dist, _wall(qb, (s, g))[0]), c_raw=raw[0].clearance,
                        between=bool((_ties(qa, (s, g)) != _ties(qb, (s, g))).any()),
                        pair=f"{_point_name(j, len(o), cw)} and {_point_name(k, len(o), cw)}",
                        probe=near_wall(qa, (dist, cw, j, k)) if k < len(o) else [],
                        ends=(qa, qb))  # (the two obstacle sets: to pin a jump in a test)
        return (hi - lo) * DRIFT, change, c_raw, deep, wall

    def near_wall(q, nearest):
        """The map probed at the distances WALL_DISTANCES from the wall ``nearest`` of the
        query ``q`` (its obstacle moved along the line's direction): per distance the
        largest K over 4 moves of the obstacles by each delta of DELTAS at most WALL_REACH of the
        distance (same label)."""
        dist, cw, j, k = nearest
        e = (q[1] - q[0]) / np.linalg.norm(q[1] - q[0])
        side = np.sign(float((np.concatenate([q, (s, g)[cw]])[j] - q[k]) @ e))
        prng = np.random.default_rng(0)
        out = []
        for target in WALL_DISTANCES:
            qd = q.copy()
            qd[k] = q[k] - side * (target - dist) * e
            ref = at(qd)
            worst = 0.0
            for dl in (dl for dl in DELTAS if dl <= WALL_REACH * target):
                for _ in range(4):
                    other = at(qd + dl * prng.uniform(-1.0, 1.0, qd.shape))
                    if other.domain == ref.domain:
                        worst = max(worst, _sup(ref, other) / dl)
            out.append((_wall(qd, (s, g))[0], worst))
        return out

    prev = None
    changes, raws, jumps, labels = [], [], 0, 0
    persisting, walls, crossing = [], [], 0
    for _ in range(ticks):
        o_before = o
        o = o + vel
        try:
            cur = at(o)
            raw = pmplan.plan(o, s, g, lift="scene")
        except PmplanError:
            prev = None
            continue
        if prev is not None:
            if prev[0].domain == cur.domain:
                c = _sup(prev[0], cur) / DRIFT
                rc = _sup(prev[1], raw) / DRIFT
                changes.append(c)
                raws.append(rc)
                if c > max(10 * rc, 25):  # a jump: 0.5 units more than ten raw changes
                    jumps += 1
                    size, change, c_raw, deep, wall = bisect(o_before, o, prev[0], cur)
                    crossing += wall["crosses"]
                    if change > 1e-3:
                        persisting.append((size, change, c_raw, *deep))
                        walls.append(wall)
            else:
                labels += 1
        prev = (cur, raw)
    return {"ticks": ticks, "compared": len(changes), "jumps": jumps, "label_changes": labels,
            "median": float(np.median(changes)) if changes else float("nan"),
            "max": float(max(changes)) if changes else float("nan"),
            "persisting": persisting, "walls": walls, "crossing": crossing,
            "raw_median": float(np.median(raws)) if raws else float("nan"),
            "raw_max": float(max(raws)) if raws else float("nan")}


ROWS = [
    # name, d, n, m, lift, family, size: every (d, n, m, lift) of item 1's uniform family
    *[(f"({d},{n},{m}) lift {lift} uniform", d, n, m, lift, "uniform", 1.0)
      for lift in (0.1, 1.0, "scene") for d in (2, 3) for n in (2, 4, 8, 16) for m in (2, 4, 6)],
    ("(2,4,2) integer grid", 2, 4, 2, "scene", "integer", 1.0),
    ("(3,4,2) integer grid", 3, 4, 2, "scene", "integer", 1.0),
    ("(2,8,4) near-contact raw", 2, 8, 4, 0.1, "near-contact", 1.0),
    ("(2,4,2) sequence r=3", 2, 4, 2, 0.1, "sequence", 1.0),
    ("(2,8,4) sequence r=3", 2, 8, 4, 0.1, "sequence", 1.0),
    ("(2,1,3) planar three", 2, 1, 3, "scene", "uniform", 1.0),
    *[(f"(2,{n},6) room 10x10", 2, n, 6, "scene", "uniform", 10.0) for n in (4, 8, 16)],
]


def _fmt(x):
    return "-" if x is None or math.isnan(x) else f"{x:.3g}"


def section(seed: int, held_out: bool, args, count: int) -> list[str]:
    """The rows and the replanning run of one draw, as the lines of its section."""
    results = []
    for index, (name, d, n, m, lift, fam, size) in enumerate(ROWS):
        if args.rows and args.rows not in name:
            continue
        c = count if n <= 8 else max(2, count // 3)
        r = row(name, d, n, m, lift, fam, c, seed * 1000 + index, size=size)
        results.append(r)
        print(name, {k: v for k, v in r.items() if k not in ("row", "factors")}, flush=True)
    rep = replanning(ticks=20 if args.quick else 80, seed=seed)
    print("replanning", rep, flush=True)
    lines = [
        f"## Seed {seed} ({'held out' if held_out else 'design'})",
        "",
        (f"`python benchmarks/refine_continuity.py --seeds {seed}` "
        f"({_dt.date.today().isoformat()}, {count} queries per row, a third for n = 16; "
        "every point of the query moved by delta times a uniform vector in [-1, 1]^d; "
        "K = exact sup change / delta over the pairs with the same label; c_raw the raw plan's "
        "clearance over the scene's size, target = max(2 radius, c_raw / 2); raw K the raw "
        "plan's amplification, which the refinement inherits). A pair the raw path brings "
        "within c_raw of contact and that the refinement pushes out to its target amplifies "
        "by about target / c_raw: that limit is real (docs/refinement.md), so the goal is on "
        "K_eff = K / max(1, target / c_raw), which is K wherever the raw plan keeps the targets. "
        "Goal (item 1): no jump (a move <= 1e-9 changing the path by > 1e-3); K_eff <= 1e4 on "
        "every pair (per row) and <= 1e3 on >= 99.9 % of the pairs (all rows together: a row "
        "has 30-90). The refined/raw column is the smallest ratio over the pairs of points of "
        "the refined to the raw minimum distance (no self-squeezing, item 2)."),
        "",
        ("| row | queries | K max 1e-6 | K max 1e-9 | K max 1e-12 | raw K max | "
         "K max where target <= c_raw | K_eff max | its c_raw, target/c_raw | "
         "K_eff / max(1, raw K) max | "
         "pairs K > 1e3 | pairs K_eff > 1e3 | jumps | "
         "refined/raw pair distance min (median) | goal |"),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            f"| {r['row']} | {r['queries']} | " + " | ".join(_fmt(r["max"][dl]) for dl in DELTAS)
            + f" | {_fmt(r['raw_max'])} | {_fmt(r['clear_max'])} | "
            f"{_fmt(r['bound_constant'])} | {_fmt(r['worst_c_raw'])}, {_fmt(r['worst_tc'])} | "
            f"{_fmt(r['factor_max'])} | "
            f"{r['over1e3']} | {r['eff_over1e3']} | {r['jumps']} | "
            f"{_fmt(r['min_ratio'])} ({_fmt(r['median_ratio'])}) | "
            + ("met" if meets(r) else "**missed**") + " |")
    missed = [r["row"] for r in results if not meets(r)]
    over, total = pooled(results)
    share = 100.0 * (total - over) / max(total, 1)
    lines += ["", f"**Rows that miss the goal:** {', '.join(missed) if missed else 'none'} "
              f"(of {len(results)}). **All rows together:** K_eff <= 1e3 on {total - over} of "
              f"{total} pairs ({share:.2f} %; goal >= 99.9 %: "
              f"{'met' if share >= 99.9 else 'missed'}); largest K_eff "
              f"{_fmt(max(r['bound_constant'] for r in results))}; largest K where the raw plan "
              f"keeps the targets {_fmt(np.nanmax([r['clear_max'] for r in results]))}; "
              f"pairs with K > 1e3 {sum(r['over1e3'] for r in results)}, each with its c_raw "
              "in its row. The refinement's own share, K_eff / max(1, raw K) (the raw plan's "
              "change is what it starts from): largest "
              f"{_fmt(max(r['factor_max'] for r in results))}, 99.9th percentile "
              f"{_fmt(float(np.quantile(sum((r['factors'] for r in results), []), 0.999)))}."]
    return lines + [""] + _replanning_lines(rep)


def _replanning_lines(rep) -> list[str]:
    """The replanning run's line and, where jumps persist, where they lie."""
    lines = ["Replanning (4 robots swapping in a 10 x 10 room, 6 obstacles drifting "
             f"{DRIFT:g} per tick, radius {REPLAN_RADIUS:g}, lift scene): "
             f"{rep['compared']} ticks compared, {rep['jumps']} jumps (a change per drift "
             "above 25 and above ten times the raw plan's), "
             f"{rep['label_changes']} label changes; change per drift: median "
             f"{_fmt(rep['median'])}, largest {_fmt(rep['max'])} (raw plans: median "
             f"{_fmt(rep['raw_median'])}, largest {_fmt(rep['raw_max'])}). Each flagged tick "
             "bisected toward the half that moves the path more, down to an obstacle move of "
             "1e-10: "
             + (f"{len(rep['persisting'])} jump(s) persist (path change > 1e-3 across moves "
                + ", ".join(f"{sz:.1e} -> {ch:.3g} (the raw plan {cr:.1e} from contact, "
                            f"target / c_raw {REPLAN_TARGET / cr:.1e}: K {ch / sz:.1e}, K_eff "
                            f"{ch / sz / max(1.0, REPLAN_TARGET / cr):.2g}, "
                            f"{'within' if ch / sz / max(1.0, REPLAN_TARGET / cr) <= GOAL_MAX else 'beyond'}"
                            f" the stated bound K_eff <= {GOAL_MAX:g}; bisected on: "
                            f"{dch:.3g} across {dsz:.1e}, the raw plan {_fmt(draw)}, "
                            f"{'a jump in floating point' if dch > 1e-3 else 'steep but continuous'})"
                            for sz, ch, cr, dsz, dch, draw in rep["persisting"])
                + f"). {sum(1 for *_, dch, _ in rep['persisting'] if dch > 1e-3)} of them still "
                f"change the path by more than 1e-3 across an obstacle move of {DEEP:g} or less"
                if rep["persisting"] else "none persists (every one is a steep but continuous "
                "change)") + ".", ""]
    if rep["persisting"]:
        lines += [_walls_paragraph(rep), ""]
    return lines


def _walls_paragraph(rep) -> str:
    """Where the persisting jumps of a replanning run lie: next to a wall of a lower label."""
    walls = rep["walls"]
    near = [w for w in walls if w["crosses"]]
    text = (f"*Where they lie.* {rep['crossing']} of the {rep['jumps']} flagged ticks carry a "
            "robot's column across another point's (the exact signs of the column differences "
            "differ between the two ticks): the drift crosses a wall of a lower label "
            "(Mathematics 4.2) between two queries with one label. "
            f"{len(near)} of the {len(walls)} persisting jumps are in such ticks; their last "
            "bisection step stops on one side of the wall ("
            + "; ".join(f"{w['pair']}: {w['distance']:.1e} from it, "
                        + ("across it" if w["between"] else "not across it")
                        + f", the raw plan {w['c_raw']:.1e} from contact"
                        for w in walls)
            + "; a wall's distance is the columns' distance, in the room's units): the raw "
            "plan's robot runs past that point at about the columns' distance, on one side of "
            "it on one side of the wall and on the other beyond.")
    probed = next((w for w in walls if w.get("probe")), None)
    if probed is not None:
        text += (f" The map near the wall of {probed['pair']} (the obstacle moved along the "
                 "line so that the nearest wall is at the distance given; largest K over 4 "
                 "moves of the obstacles by each of "
                 + ", ".join(f"{dl:g}" for dl in DELTAS) + f" up to {WALL_REACH:g} of the "
                 "distance, same label): "
                 + "; ".join(f"{dist:.1e} from the wall, K {_fmt(k)} (K_eff "
                             f"{_fmt(k / max(1.0, REPLAN_TARGET / dist))})"
                             for dist, k in probed["probe"])
                 + ("; at every one of them within the stated bound K_eff <= " if all(
                     k / max(1.0, REPLAN_TARGET / dist) <= GOAL_MAX for dist, k in probed["probe"])
                    else "; at one of them beyond the stated bound K_eff <= ") + f"{GOAL_MAX:g}.")
    return text


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--seeds", default="1,2", help="the design draws (comma-separated)")
    ap.add_argument("--held-out", default="5", help="draws not looked at while designing")
    ap.add_argument("--replanning-held-out", default="3,4,6,7,8,9",
                    help="more held-out draws of the replanning run alone")
    ap.add_argument("--count", type=int, default=None)
    ap.add_argument("--rows", default=None, help="substring filter on the row names")
    ap.add_argument("--out", default=str(HERE / "refine_continuity.md"))
    args = ap.parse_args(argv)
    count = args.count or (4 if args.quick else 30)
    design = [int(x) for x in args.seeds.split(",") if x]
    held = [int(x) for x in args.held_out.split(",") if x]
    lines = ["# Continuity of the refined planner in floating point (issue 24)", "",
             f"`python benchmarks/refine_continuity.py` ({_dt.date.today().isoformat()}): "
             f"design draws {design} (the constants and the stated bound were chosen on them), "
             f"held-out draws {held} (run once, after).", ""]
    for seed in design + held:
        lines += section(seed, seed in held, args, count)
    for seed in [int(x) for x in args.replanning_held_out.split(",") if x]:
        rep = replanning(ticks=20 if args.quick else 80, seed=seed)
        print("replanning", seed, rep, flush=True)
        lines += [f"## Seed {seed} (held out, the replanning run alone)", ""]
        lines += _replanning_lines(rep)
    Path(args.out).write_text("\n".join(lines))
    print("\n".join(lines))
    if args.out == str(HERE / "refine_continuity.md") and not (args.quick or args.rows):
        replace_section(HERE / "RESULTS.md", TITLE, results_section(lines))


TITLE = "## Refined continuity in floating point (issue 24)"


def results_section(lines: list[str]) -> str:
    """The section of RESULTS.md: per draw its summary, its replanning line and where its
    persisting jumps lie (the per-row tables stay in refine_continuity.md)."""
    out = [TITLE, "", "Generated by `python benchmarks/refine_continuity.py` with the tables: per row "
           "(d, n, m, lift, family) the amplification K at delta = 1e-6, 1e-9, 1e-12, the raw "
           "plan's own K, c_raw and target / c_raw beside K, the refined / raw pair distances "
           "and a replanning run, in [refine_continuity.md](refine_continuity.md). Per draw:", ""]
    for ln in lines:
        if ln.startswith("## Seed"):
            out.append(f"- **{ln[3:]}.**")
        elif ln.startswith(("**Rows that miss", "Replanning", "*Where they lie.*")):
            out.append(f"  {ln}")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    main()
