"""
A Dask run on the threaded scheduler
====================================

With the ``dask`` extra, :func:`pmplan.plan_batch` takes dask arrays chunked along the batch axis
and returns lazy dask arrays; :func:`pmplan.scale.compute` plans every chunk once. The result is
bit for bit the in-memory ``plan_batch`` on the same numbers, whatever the chunks.
"""

import dask.array as da
import matplotlib.pyplot as plt
import numpy as np

import pmplan
from pmplan import scale

rng = np.random.default_rng(1)
B = 40_000
o, s, g = (rng.normal(size=(B, k, 2)) for k in (2, 4, 4))
lazy = pmplan.plan_batch(*(da.from_array(a, chunks=(10_000, -1, -1)) for a in (o, s, g)))
plans = scale.compute(lazy, scheduler="threads")
eager = pmplan.plan_batch(o, s, g)
same = np.array_equal(plans.waypoints, eager.waypoints) and \
    np.array_equal(plans.domain, eager.domain)
print(f"{B:,} queries in {lazy.waypoints.numblocks[0]} chunks; equal to plan_batch: {same}")

fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
ax.hist(np.log10(plans.clearance), bins=60)
ax.set_xlabel("log10 of the certified clearance")
ax.set_ylabel("queries")
ax.set_title("Clearances of a Dask-planned batch (threaded scheduler)")
