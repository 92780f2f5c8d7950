"""The refined plans that miss the radii, one by one: why, and what more effort does to each.

Usage (from the repository root)::

    python benchmarks/misses.py --seeds 1,2

Rows: the 2-D scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls)
with n = 4, 8 and 16, 16 queries each, drawn as the scene benchmark draws them
(``benchmarks/scenes_compare.py``: seed 1 is its design draw, seed 2 its held-out one).
pmplan's default plan in the box (``bounds=(0, 10)``) refined with radius = obstacle_radius =
r/2 at the default effort (:func:`scenes.refined_in_box`); every plan that misses the radii is
listed with its reason (``Plan.radius_reason``: *gap*, the path crosses a gap of the scene
narrower than a robot, which no planner continuous on the domains of Mathematics §4.2 avoids on
every query, Mathematics §8; *robots*, *obstacle*, *wall*: the worst contact, which the
refinement's steps did not clear), its worst distances and its raw clearance, and the same raw
plan refined again at the efforts ``EFFORTS`` (waypoints / steps, larger than the default;
with 16 robots in the plane each followed by ``CROWD_FINAL`` times as many clearing-only
steps, as the default is): does it keep the radii there, the worst distance, the time of that
refinement (one core).

Per row it also gives the share of (piece, pair) combinations of the default refined paths
whose least distance exceeds ``3 r``: the pairs the refinement measures at every step without
pushing them (its cost at n = 16 is the time the larger efforts need).

Writes ``benchmarks/misses.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import pmplan

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes

from pmplan.refine.grid import default_effort, pairs, piece_minima

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [4, 8, 16]
#: the larger efforts tried on every miss (waypoints, steps)
EFFORTS = [(4, 224), (8, 448), (16, 1024)]
#: a (piece, pair) combination is far when its least distance exceeds FAR times r
FAR = 3.0
HALF = scenes.R / 2


def _far_share(p) -> float:
    """The share of (piece, pair) combinations of a refined plan farther apart than FAR r."""
    m = p.obstacles.shape[0]
    a, b, _ = pairs(p.waypoints.shape[1], m)
    d = piece_minima(np.asarray(p.waypoints)[None], a, b)[0]
    return float((d > FAR * scenes.R).mean())


def tight_gap(p) -> float | None:
    """The width of the gap with room for one robot only (``pmplan.reasons.TIGHT``) that the
    reason of a contact of plan ``p`` names (its ``radius_miss.gap``), or None."""
    gap = p.radius_miss.gap
    return None if gap is None or gap.narrow else gap.width


def _worst(p) -> float:
    """The smallest of the two distances over their required values (1: exactly kept)."""
    return min(p.robot_distance / (2 * HALF), p.obstacle_distance / (2 * HALF))


def row(fam: str, n: int, seed: int, count: int) -> dict:
    qs = scenes.queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "count": count, "far": [], "misses": []}
    for qi, (o, s, g) in enumerate(qs):
        p = scenes.refined_in_box(o, s, g)
        out["far"].append(_far_share(p))
        if p.respects_radius:
            continue
        miss = {"query": qi, "why": p.radius_miss.category, "tight": tight_gap(p),
                "reason": p.radius_reason, "worst": _worst(p),
                "raw_clearance": float(p.raw_clearance), "efforts": {}}
        # the raw plan of p: the default unit of a refined plan is the robots' diameter, and
        # its planner the refined default's (the one-side lanes for a crowd in the plane)
        raw = pmplan.plan(o, s, g, bounds=(0.0, scenes.SIZE), lift=2 * HALF, planner=p.planner)
        again = pmplan.refine(raw, radius=HALF, obstacle_radius=HALF)
        assert np.array_equal(again.waypoints, p.waypoints), "not the default plan's raw plan"
        for w, k in EFFORTS:
            t0 = time.perf_counter()
            q = pmplan.refine(raw, radius=HALF, obstacle_radius=HALF, waypoints=w, steps=k)
            miss["efforts"][f"{w}/{k}"] = {"valid": bool(q.respects_radius), "worst": _worst(q),
                                           "ms": 1e3 * (time.perf_counter() - t0)}
        print(f"seed {seed} {fam} n={n} query {qi}: {miss['why']} {miss['worst']:.3f} -> "
              + ", ".join(f"{e}: {v['valid']} {v['worst']:.3f}"
                          for e, v in miss["efforts"].items()), flush=True)
        out["misses"].append(miss)
    return out


def markdown(res: dict) -> str:
    eff = [f"{w}/{k}" for w, k in EFFORTS]
    lines = ["# The refined plans that miss the radii, and what more effort does", "",
             f"Command: `{res['command'].strip()}` ({res['date']}). Rooms 10 x 10, r = 0.3, "
             f"{res['count']} queries per row (the draws of the scene benchmark: seed 1 its "
             "design draw, 2 held out), pmplan's default plan in the box refined at "
             "radius = obstacle_radius = r/2. Every plan that misses the radii at the default "
             "effort (waypoints/steps: "
             + ", ".join(f"n = {n} {w}/{k}" for n in sorted({c["n"] for c in res["rows"]})
                         for w, k in [default_effort(n)])
             + "), refined again from the same raw plan at " + ", ".join(eff)
             + " (an effort equal to the default repeats it). *worst*: the smaller of the "
             "robot-robot "
             "and robot-obstacle distances over r (1: kept); *why*: the default plan's "
             "`radius_reason` (*gap*: it crosses a gap narrower than a robot, which no planner "
             "continuous on the domains of Mathematics §4.2 avoids on every query, Mathematics "
             "§8, and the default in a box, on the side the walls leave the most room, seldom "
             "meets; *robots*, "
             "*obstacle*, *wall*: the worst contact the refinement did not clear, and in "
             "brackets the gap with room for one robot only that the path passes through "
             "there, when the reason names one); *raw*: the "
             "raw plan's clearance; time: that refinement alone, one core (a shared machine).",
             "", "| seed | row | query | why | raw | default: worst | "
             + " | ".join(f"{e}: keeps r, worst, ms" for e in eff) + " |",
             "|---|---|---|---|---|---|" + "---|" * len(eff)]
    for c in res["rows"]:
        for mi in c["misses"]:
            cells = [f"{'yes' if v['valid'] else 'no'}, {v['worst']:.3f}, {v['ms']:.0f}"
                     for v in mi["efforts"].values()]
            width = mi["tight"]
            why = mi["why"] + ("" if width is None else f" (one-robot gap {width:.3g})")
            lines.append(f"| {c['seed']} | {c['family']} n = {c['n']} | {mi['query']} | "
                         f"{why} | {mi['raw_clearance']:.2g} | {mi['worst']:.3f} | "
                         + " | ".join(cells) + " |")
    lines.append("")
    tot = {}
    for c in res["rows"]:
        for mi in c["misses"]:
            kind = "gap" if mi["why"] == "gap" else "contact"
            t = tot.setdefault(kind, [0] + [0] * len(eff))
            t[0] += 1
            for i, v in enumerate(mi["efforts"].values()):
                t[i + 1] += v["valid"]
    for kind, t in sorted(tot.items()):
        lines.append(f"* {kind}: {t[0]} plans miss at the default effort; kept at "
                     + ", ".join(f"{e}: {v}" for e, v in zip(eff, t[1:])) + ".")
    contacts = [mi for c in res["rows"] for mi in c["misses"] if mi["why"] != "gap"]
    tight = [mi for mi in contacts if mi["tight"] is not None]
    lines.append(f"* of the {len(contacts)} contacts, {len(tight)} are where the path passes "
                 "through a gap with room for one robot only (wider than a robot, narrower than "
                 "two side by side; `pmplan.reasons.TIGHT`), which the reason names; kept at "
                 + ", ".join(f"{e}: {sum(mi['efforts'][e]['valid'] for mi in tight)}"
                             for e in eff) + ".")
    lines += ["", (f"Share of (piece, pair) combinations of the default refined paths "
                   f"farther apart than {FAR:g} r (median over the row's queries; range):"), "",
              "| seed | row | default effort | far share |", "|---|---|---|---|"]
    for c in res["rows"]:
        f = np.asarray(c["far"])
        w, k = default_effort(c["n"])
        lines.append(f"| {c['seed']} | {c['family']} n = {c['n']} | {w}/{k} | "
                     f"{np.median(f):.3f} ({f.min():.3f}-{f.max():.3f}) |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("misses", __doc__, row, markdown, FAMILIES, NS, "1,2", argv)


if __name__ == "__main__":
    raise SystemExit(main())
