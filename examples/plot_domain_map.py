"""
The domain map: where the motion jumps
======================================

Fix the obstacles, the starts and every goal but robot 1's, and move robot 1's goal over a grid:
each pixel gets the label of the domain its query falls in (what ``pmplan explore`` draws). The
boundaries are the columns of the other points: crossing one changes ``cp(C')``, the label, and
the motion jumps. Here the line o1o2 is tilted, so the columns are tilted too.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

import pmplan

obstacles = np.array([[0.0, 0.0], [4.0, 1.0]])
start = np.array([[1.0, 1.0], [2.0, -1.0]])
goal = np.array([[3.0, -1.0], [1.0, 2.5]])
# a dyadic grid (step 1/32): the columns of two points are either equal or 1/32 * 4/|w| apart,
# never so close that double precision cannot separate them (Mathematics 6.2)
xs = np.arange(-1.5, 5.5, 1 / 32)
ys = np.arange(-2.5, 3.5, 1 / 32)
X, Y = np.meshgrid(xs, ys)
pts = np.stack([X.ravel(), Y.ravel()], axis=-1)
B = len(pts)
goals = np.repeat(goal[None], B, axis=0)
goals[:, 0] = pts
ok = ~(pts[:, None] == np.concatenate([obstacles, goal[1:]])[None]).all(-1).any(-1)
labels = np.full(B, np.nan)
batch = pmplan.plan_batch(np.repeat(obstacles[None], ok.sum(), 0),
                          np.repeat(start[None], ok.sum(), 0), goals[ok])
labels[ok] = batch.domain
print("labels met:", sorted(set(batch.domain.tolist())))

# the boundaries: the column lines s(y) = (y - o1).e of the other points, drawn as lines
e = (obstacles[1] - obstacles[0]) / np.linalg.norm(obstacles[1] - obstacles[0])
nu = np.array([-e[1], e[0]])
met = sorted(set(batch.domain.tolist()))
cmap = ListedColormap(plt.get_cmap("Set3").colors[:len(met)])
norm = BoundaryNorm(np.arange(met[0] - 0.5, met[-1] + 1), cmap.N)
fig, ax = plt.subplots(figsize=(8, 6.5), layout="constrained")
im = ax.pcolormesh(X, Y, labels.reshape(X.shape), cmap=cmap, norm=norm, shading="nearest")
for y in np.concatenate([obstacles, goal[1:]]):
    c = obstacles[0] + ((y - obstacles[0]) @ e) * e
    ax.axline(c, c + nu, color="0.1", lw=2.5, ls=(0, (6, 2)))
ax.plot(*obstacles.T, "ks", ms=9)
ax.plot(*start.T, "o", mfc="white", mec="k")
ax.plot(*goal[1:].T, "*", color="k", ms=12)
ax.set_xlim(xs[0], xs[-1])
ax.set_ylim(ys[0], ys[-1])
ax.set_aspect("equal")
bar = fig.colorbar(im, ax=ax, ticks=met, label="domain of robot 1's goal")
bar.ax.set_yticklabels([f"$W_{{{lab}}}$" for lab in met])
ax.set_title("Domain map of robot 1's goal (dashed: the domain boundaries)")
