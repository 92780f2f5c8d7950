"""Pictures of plans: obstacles, robots' trails with arrows, start and goal markers.

matplotlib is imported inside the functions; every function takes ``ax=None`` and returns the
axes it drew on (shapely's plotting style).
"""

from __future__ import annotations

import numpy as np

__all__ = ["robot_colors", "draw_plan", "plan_grid"]


def robot_colors(n: int):
    """Return n distinct colours for robots."""
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab10" if n <= 10 else "turbo")
    return [cmap(i if n <= 10 else i / max(n - 1, 1)) for i in range(n)]


def draw_plan(plan, ax=None, *, samples: int = 400, title: str | None = None, arrows: bool = True):
    """Draw a planar plan (d = 2): obstacles, trails of the robots, start (o) and goal (*).

    Parameters
    ----------
    plan : pmplan.Plan
        A plan with d = 2.
    ax : matplotlib Axes, optional
    samples : int
        Number of samples of the path used for the trails (waypoints are always included).
    title : str, optional
        Default: domain, stratum and clearance.

    Returns
    -------
    matplotlib Axes
    """
    import matplotlib.pyplot as plt

    d, n, m = plan.dims
    if d != 2:
        raise ValueError(f"draw_plan draws planar plans (d = 2), got d = {d}")
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5))
    ts = np.union1d(np.linspace(0.0, 1.0, samples), plan.path.times)
    pts = plan.path(ts)
    colors = robot_colors(n)
    obs = plan.obstacles
    ax.plot(obs[:, 0], obs[:, 1], "s", color="black", ms=9, zorder=5)
    for k, o in enumerate(obs):
        ax.annotate(f"o{k + 1}", o, xytext=(4, 4), textcoords="offset points", fontsize=8)
    for j in range(n):
        tr = pts[:, m + j]
        ax.plot(tr[:, 0], tr[:, 1], "-", color=colors[j], lw=1.5, alpha=0.9)
        if arrows:
            wp = plan.path.waypoints[:, m + j]
            for a, b in zip(wp[:-1], wp[1:]):
                if np.linalg.norm(b - a) > 0:
                    mid = (a + b) / 2
                    ax.annotate("", xy=mid + (b - a) * 0.01, xytext=mid,
                                arrowprops=dict(arrowstyle="->", color=colors[j], lw=1.2))
        ax.plot(*plan.start[j], "o", color=colors[j], ms=7, mfc="white", mew=2, zorder=6)
        ax.plot(*plan.goal[j], "*", color=colors[j], ms=11, zorder=6)
        ax.annotate(f"x{j + 1}", plan.start[j], xytext=(4, -10), textcoords="offset points",
                    fontsize=8, color=colors[j])
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title if title is not None else
                 f"W_{plan.domain}  {plan.stratum}  clearance {plan.clearance:.3g}", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def plan_grid(plans, titles=None, *, ncols: int = 4, panel: float = 3.6):
    """Draw several planar plans in a grid of panels; return the Figure."""
    import matplotlib.pyplot as plt

    plans = list(plans)
    nrows = -(-len(plans) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel * ncols, panel * nrows), squeeze=False)
    for k, ax in enumerate(axes.flat):
        if k < len(plans):
            draw_plan(plans[k], ax, title=None if titles is None else titles[k])
        else:
            ax.axis("off")
    fig.tight_layout()
    return fig
