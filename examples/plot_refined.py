"""
A refined motion: shorter, with a radius, still continuous
==========================================================

:func:`pmplan.refine` turns the paper's staircase into a short motion that keeps discs of a
given radius apart, with the same domain and stratum (:doc:`/mathematics` §7). The raw motion
(left) and the refined one (right) share their axes; the discs of the refined plan are drawn
at the start and at the goal.
"""

import pmplan
from pmplan.plotting import plan_grid

obstacles = [[0.35, 0.5], [0.65, 0.5]]
start = [[0.1, 0.5], [0.5, 0.2]]
goal = [[0.9, 0.5], [0.5, 0.8]]
raw = pmplan.plan(obstacles, start, goal, lift=0.1)
fine = pmplan.refine(raw, radius=0.025, obstacle_radius=0.025)
print(f"domain W_{raw.domain} -> W_{fine.domain}, stratum {raw.stratum} -> {fine.stratum}")
print(f"length {raw.path.length():.3f} -> {fine.path.length():.3f}; "
      f"radii respected: {fine.respects_radius}")

fig = plan_grid([raw, fine], ncols=2, panel=4.5, same_axes=2)
