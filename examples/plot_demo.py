"""
The demo: one certified motion per domain of continuity
========================================================

``pmplan demo`` plans one query in each of the 2n+1 domains of 3 robots among 2 obstacles in
the plane (the paper's Section 3 planner: ``W_4`` .. ``W_10``) and draws each motion raw (left)
and refined (right, :func:`pmplan.refine`). Each robot has its own colour; time runs from thin
and faint (t = 0) to thick and solid (t = 1), with dots at t = 1/4, 1/2, 3/4.
"""

import numpy as np

import pmplan
from pmplan.examples import obstacle_line_examples
from pmplan.plotting import plan_grid

queries = [np.stack(a) for a in zip(*obstacle_line_examples(3))]
batch = pmplan.plan_batch(*queries)
refined = pmplan.refine(batch)
print("domains:", batch.domain.tolist())
print("raw lengths:    ", np.round([p.path.length() for p in batch], 2).tolist())
print("refined lengths:", np.round([p.path.length() for p in refined], 2).tolist())

pairs = [p for pair in zip(batch, refined) for p in pair]
fig = plan_grid(pairs[:8], ncols=4, panel=3.0,
                suptitle="3 robots, 2 obstacles: raw (left) and refined (right)")
