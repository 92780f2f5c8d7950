"""
A batch: which domains random queries fall in
=============================================

:func:`pmplan.plan_batch` plans many queries at once. Random queries are generic: every point
has its own column, so they all fall in the top domain ``W_{2n+4}``; queries on a grid of integer
points share columns and spread over every domain. The histogram counts both.
"""

import matplotlib.pyplot as plt
import numpy as np

import pmplan

rng = np.random.default_rng(0)
B, n = 20_000, 3


def random_queries(integer: bool):
    """B queries of n robots among 2 obstacles, random or on a small integer grid."""
    while True:
        pts = rng.integers(-3, 4, size=(4 * B, 2 + 2 * n, 2)) if integer else \
            rng.normal(size=(B, 2 + 2 * n, 2))
        conf = np.concatenate([pts[:, :2 + n], np.concatenate([pts[:, :2], pts[:, 2 + n:]], 1)])
        # keep the queries whose start and goal are configurations (distinct points)
        d = np.linalg.norm(conf[:, :, None] - conf[:, None], axis=-1)
        ok = (d + np.eye(2 + n) > 0).all(axis=(1, 2)).reshape(2, -1).all(axis=0)
        if ok.sum() >= B:
            q = pts[ok][:B].astype(float)
            return q[:, :2], q[:, 2:2 + n], q[:, 2 + n:]


fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
labels = np.arange(4, 2 * n + 5)
for integer, name in ((False, "random (normal)"), (True, "integer grid")):
    batch = pmplan.plan_batch(*random_queries(integer))
    counts = np.array([(batch.domain == lab).sum() for lab in labels])
    print(f"{name}: min clearance {batch.clearance.min():.3g}, domains {dict(zip(labels.tolist(), counts.tolist()))}")
    ax.bar(labels + (0.2 if integer else -0.2), counts, width=0.4, label=name)
ax.set_xticks(labels, [f"$W_{{{lab}}}$" for lab in labels])
ax.set_ylabel(f"queries (of {B:,})")
ax.set_title(f"{n} robots, 2 obstacles: the domain of each query")
ax.legend()
