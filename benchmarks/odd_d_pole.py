"""Odd d: how far the obstacle-line planner's path moves near the pole N (measured, not a bug).

For odd d the lift direction ``nu(e)`` is a continuous unit tangent field on ``S^{d-1} \\ {N}``
(Mathematics §4.1, :mod:`pmplan.frame`); no continuous tangent field exists on the whole sphere (hairy
ball), so ``nu`` must wind once around the missing point N: on a small circle of angle theta
about N it turns through a full turn, and its modulus of continuity there grows like 1/theta.
Inside the domain the planner is still continuous, but near N a tiny change of the query can
move the path by O(1).

This script measures it for d = 3, n = 2, m = 2: ``o1 = 0``, ``o2 = (sin t, 0, cos t)``
(so ``e`` is at angle ``t`` from ``N = e_3``), two robots at fixed generic positions; the
perturbed query moves o2 by ``eps`` in the direction ``e_2`` (turning e about N, the
direction in which nu turns fastest). It prints, for each angle, the sup-distance
``sup_t |Gamma_Q(t) - Gamma_Q'(t)|`` (:func:`pmplan.verify.path_distance`) and the ratio to
``eps`` (the local modulus), for ``lift = 1``.

Usage (from the repository root)::

    python benchmarks/odd_d_pole.py [--eps 1e-9]
"""

from __future__ import annotations

import argparse

import numpy as np

import pmplan
from pmplan.path import PiecewiseLinearPath
from pmplan.verify import path_distance

START = np.array([[0.6, -1.3, 0.4], [-0.9, 0.5, 1.7]])
GOAL = np.array([[1.1, 0.8, -0.6], [-0.4, -1.5, 0.9]])
ANGLES = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)


#: the paper's lanes (robot i at i lambda): the figures of POLE_NOTE and the tutorial; the
#: compact lanes of the default planner put the highest robot at H + ceil(n/2) lift
PLANNER = "obstacle_line"

def pole_query(angle: float, shift: float = 0.0):
    """The query with e at ``angle`` from N = e_3, o2 moved by ``shift`` along e_2."""
    obstacles = np.array([[0.0, 0.0, 0.0], [np.sin(angle), shift, np.cos(angle)]])
    return obstacles, START, GOAL


def measure(angle: float, eps: float, lift: float = 1.0) -> tuple[float, int, int]:
    """Return (sup-distance of the two paths, label of Q, label of Q') at this angle."""
    a = pmplan.plan(*pole_query(angle), lift=lift, planner=PLANNER)
    b = pmplan.plan(*pole_query(angle, eps), lift=lift, planner=PLANNER)
    pa, pb = (PiecewiseLinearPath(p.path.times, p.path.waypoints[None]) for p in (a, b))
    return float(path_distance(pa, pb)[0]), a.domain, b.domain


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--eps", type=float, default=1e-9, help="size of the perturbation")
    args = parser.parse_args()
    print(f"d = 3, n = 2, m = 2, lift = 1; o2 moved by eps = {args.eps:g} about N")
    print(f"{'angle from N':>12}  {'sup |path - path_eps|':>21}  {'ratio / eps':>11}  "
          f"{'angle * ratio':>13}  labels")
    for angle in ANGLES:
        dist, la, lb = measure(angle, args.eps)
        ratio = dist / args.eps
        print(f"{angle:12.0e}  {dist:21.3g}  {ratio:11.3g}  {angle * ratio:13.3g}  {la} {lb}")


if __name__ == "__main__":
    main()
