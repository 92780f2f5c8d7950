"""
The paper's Figures 6-10, drawn by the planner
==============================================

The planar three-obstacle planner (paper Section 4, :doc:`/mathematics` §5) has 12 strata packed
into 4 domains. Each panel is the planner's own certified motion on an exact query of one
stratum, redrawn in the frame (u, h) of the query the way the paper's Figures 6-10 draw it.
"""

import matplotlib.pyplot as plt

import pmplan
from pmplan.figures import FIGURE_OF, draw_stratum, figure_queries
from pmplan.planners.planar_three import DOMAIN_OF

queries = figure_queries()
names = sorted(queries, key=lambda s: (DOMAIN_OF[s], s))
fig, axes = plt.subplots(3, 4, figsize=(13, 9), layout="constrained")
for name, ax in zip(names, axes.flat):
    plan = pmplan.plan(*queries[name])
    draw_stratum(plan, name, ax=ax)
    print(f"{name}: W_{plan.domain}, paper Figure {FIGURE_OF[name]}, "
          f"clearance {plan.clearance:.3g}")
