"""Pictures of plans: obstacles, robots' paths coloured by time, start and goal markers.

A planar plan (d = 2) is drawn in the plane: obstacles are black squares (``o_1``, ``o_2``,
...), starts white circles (``x_j``), goals stars (``x_j'``), and each robot's path a line whose
colour is the time t in [0, 1] (:data:`TIME_CMAP`; arrows give the direction), so two paths
that cross, or run along the same segment, are seen to do so at different times.
:func:`plan_grid` draws several plans in panels with one legend and one "time" colourbar
(``pmplan demo``, ``docs/demo.png``).

matplotlib is imported inside the functions; :func:`draw_plan` takes ``ax=None`` and returns the
axes it drew on (shapely's plotting style).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TIME_CMAP", "robot_colors", "time_cmap", "plan_title", "draw_radii", "draw_plan",
           "legend_handles", "plan_grid"]

#: the colormap of time along the paths (plasma without its palest tenth, visible on white)
TIME_CMAP = "plasma"
#: at most about this many arrows along one robot's path (every piece of a raw plan has one)
MAX_ARROWS = 8
_TIME_RANGE = (0.0, 0.88)


def robot_colors(n: int):
    """Return n distinct colours for robots."""
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab10" if n <= 10 else "turbo")
    return [cmap(i if n <= 10 else i / max(n - 1, 1)) for i in range(n)]


def time_cmap():
    """Return the colormap of time t in [0, 1] along the paths (:data:`TIME_CMAP`, trimmed)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    lo, hi = _TIME_RANGE
    return ListedColormap(plt.get_cmap(TIME_CMAP)(np.linspace(lo, hi, 256)), name="pmplan_time")


def plan_title(plan) -> str:
    """Return the panel title of a plan in matplotlib mathtext, e.g. ``$W_{4}$: $T_{2,2}$``.

    The stratum names of both planners are TeX (``T_{2,2}``, ``T^{2,3}_{4,4}``), so they are set
    as mathematics rather than printed raw. A refined plan (:func:`pmplan.refine`) says so
    before the same domain label and stratum as its raw plan.

    Examples
    --------
    >>> import pmplan
    >>> p = pmplan.plan([[0, 0], [2, 0]], [[1, 1]], [[1, -1]])
    >>> plan_title(p)
    'obstacle_line  $W_{6}$: $T_{3,3}$'
    >>> plan_title(pmplan.refine(p))
    'obstacle_line refined  $W_{6}$: $T_{3,3}$'
    """
    refined = " refined" if plan.refined else ""
    return f"{plan.planner}{refined}  $W_{{{plan.domain}}}$: ${plan.stratum}$"


def draw_radii(plan, ax, points, *, obstacles: bool = True, color="0.5", alpha: float = 0.18,
               zorder: float = 2):
    """Draw the robots of ``plan`` as discs of ``plan.radius`` at ``points`` (P, 2) (robots
    after the m obstacles), and (if ``obstacles``) the obstacles as discs of
    ``plan.obstacle_radius``, in data units; nothing for a zero radius.

    Returns
    -------
    list of matplotlib.collections.EllipseCollection
        The discs of the robots, then those of the obstacles (one collection each, if drawn).
    """
    from matplotlib.collections import EllipseCollection

    m = plan.dims[2]
    added = []
    for sel, r in ((slice(m, None), plan.radius),
                   (slice(0, m), plan.obstacle_radius if obstacles else 0.0)):
        if r > 0:
            xy = np.asarray(points, dtype=float)[sel]
            c = EllipseCollection(2 * r, 2 * r, 0.0, units="xy", offsets=xy,
                                  offset_transform=ax.transData, facecolors=color, alpha=alpha,
                                  edgecolors="none", zorder=zorder)
            ax.add_collection(c)
            added.append(c)
    return added


def _time_segments(plan, j: int, samples: int):
    """Segments of robot j's path and the time at the middle of each (for the colours)."""
    ts = np.union1d(np.linspace(0.0, 1.0, samples), plan.path.times)
    pts = plan.path(ts)[:, plan.dims[2] + j]
    return np.stack([pts[:-1], pts[1:]], axis=1), (ts[:-1] + ts[1:]) / 2


def draw_plan(plan, ax=None, *, samples: int = 400, title: str | None = None,
              arrows: bool = True, colorbar: bool | None = None):
    """Draw a planar plan (d = 2): obstacles, robots' paths coloured by time, starts and goals.

    Parameters
    ----------
    plan : pmplan.Plan
        A plan with d = 2.
    ax : matplotlib Axes, optional
    samples : int
        Number of samples of the path used for the lines (waypoints are always included).
    title : str, optional
        Default: :func:`plan_title` and the certified clearance.
    arrows : bool
        Arrows at the middle of every leg, in the colour of its time (of every k-th leg when
        the path has more than :data:`MAX_ARROWS` legs, as a refined path has).
    colorbar : bool, optional
        Add a "time" colourbar next to ``ax`` (default: only when ``ax`` is None).

    Returns
    -------
    matplotlib Axes
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize

    d, n, m = plan.dims
    if d != 2:
        raise ValueError(f"draw_plan draws planar plans (d = 2), got d = {d}")
    if colorbar is None:
        colorbar = ax is None
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5), layout="constrained")
    cmap, norm = time_cmap(), Normalize(0.0, 1.0)
    obs = plan.obstacles
    ax.plot(obs[:, 0], obs[:, 1], "s", color="black", ms=9, zorder=5)
    times = plan.path.times
    for j in range(n):
        segs, tmid = _time_segments(plan, j, samples)
        ax.add_collection(LineCollection(segs, cmap=cmap, norm=norm, array=tmid, lw=2.0,
                                         capstyle="round", zorder=3))
        if arrows:
            wp = plan.path.waypoints[:, m + j]
            every = max(1, (len(times) - 1) // MAX_ARROWS)  # a refined path has many pieces
            for k, (a, b, t0, t1) in enumerate(zip(wp[:-1], wp[1:], times[:-1], times[1:])):
                if k % every == every // 2 and np.linalg.norm(b - a) > 0:
                    mid = (a + b) / 2
                    ax.annotate("", xy=mid + (b - a) * 0.01, xytext=mid, zorder=4,
                                arrowprops=dict(arrowstyle="-|>", color=cmap(norm((t0 + t1) / 2)),
                                                lw=1.2, mutation_scale=11))
        ax.plot(*plan.start[j], "o", color=cmap(0.0), ms=8, mfc="white", mew=2, zorder=6)
        ax.plot(*plan.goal[j], "*", color=cmap(1.0), mec="black", mew=0.6, ms=13, zorder=6)
    draw_radii(plan, ax, plan.path.waypoints[0])  # robots and obstacles of a radius
    draw_radii(plan, ax, plan.path.waypoints[-1], obstacles=False)
    labels = [(f"$o_{{{k + 1}}}$", o) for k, o in enumerate(obs)]
    labels += [(f"$x_{{{j + 1}}}$", plan.start[j]) for j in range(n)]
    labels += [(f"$x_{{{j + 1}}}'$", plan.goal[j]) for j in range(n)]
    _place_labels(ax, labels, np.concatenate([obs, plan.start, plan.goal]))
    ax.margins(0.1)
    ax.autoscale_view()
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title if title is not None else
                 f"{plan_title(plan)}, clearance {plan.clearance:.3g}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.tick_params(labelsize=8)
    if colorbar:
        _time_colorbar(ax.figure, ax)
    return ax


# where a label may go around its marker: (direction in data units, offset in points, ha, va)
_LABEL_SPOTS = (
    ((1.0, 0.0), (7, 0), "left", "center"),
    ((-1.0, 0.0), (-7, 0), "right", "center"),
    ((0.0, 1.0), (0, 6), "center", "bottom"),
    ((0.0, -1.0), (0, -6), "center", "top"),
    ((0.8, 0.8), (5, 5), "left", "bottom"),
    ((-0.8, 0.8), (-5, 5), "right", "bottom"),
    ((0.8, -0.8), (5, -5), "left", "top"),
    ((-0.8, -0.8), (-5, -5), "right", "top"),
)


def _place_labels(ax, labels, points) -> None:
    """Annotate each (text, point) on the side of its marker farthest from the other markers
    and from the labels already placed (a greedy choice among eight spots), so that labels of
    nearby starts, goals and obstacles do not print over each other; the data limits grow to
    hold every label inside the panel."""
    points = np.asarray(points, dtype=float)
    span = float(np.ptp(points, axis=0).max()) or 1.0
    unit = 0.06 * span  # about the size of a label in data units at the panel sizes used
    taken = [p for p in points]
    for text, at in labels:
        at = np.asarray(at, dtype=float)
        best, best_score = _LABEL_SPOTS[0], -np.inf
        for spot in _LABEL_SPOTS:
            centre = at + unit * np.asarray(spot[0])
            others = [q for q in taken if not np.array_equal(q, at)]
            score = min((float(np.hypot(*(centre - q))) for q in others), default=span)
            if score > best_score + 1e-9 * span:
                best, best_score = spot, score
        ax.annotate(text, at, xytext=best[1], textcoords="offset points", fontsize=9,
                    ha=best[2], va=best[3], zorder=7)
        taken.append(at + unit * np.asarray(best[0]))
        ax.update_datalim([at + 2.0 * unit * np.asarray(best[0])])  # keep it inside the panel


def _time_colorbar(fig, ax, **kw):
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    bar = fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), time_cmap()), ax=ax, **kw)
    bar.set_label("time t along the motion (0 = start, 1 = goal)")
    return bar


def legend_handles():
    """Return the legend's proxy artists: obstacle, start, goal, path (coloured by time)."""
    from matplotlib.lines import Line2D

    cmap = time_cmap()
    return [
        Line2D([], [], ls="", marker="s", color="black", ms=8, label="obstacle $o_k$"),
        Line2D([], [], ls="", marker="o", color=cmap(0.0), mfc="white", mew=2, ms=8,
               label="start $x_j$ (t = 0)"),
        Line2D([], [], ls="", marker="*", color=cmap(1.0), mec="black", mew=0.6, ms=12,
               label="goal $x_j'$ (t = 1)"),
        Line2D([], [], color=cmap(0.5), lw=2, marker=">", ms=6,
               label="robot's path, coloured by time t, arrows: direction"),
    ]


def plan_grid(plans, titles=None, *, ncols: int = 4, panel: float = 3.6,
              suptitle: str | None = None):
    """Draw several planar plans in a grid of panels with one legend and a time colourbar.

    Parameters
    ----------
    plans : sequence of pmplan.Plan
    titles : sequence of str, optional
        Panel titles (default :func:`plan_title`).
    ncols : int
    panel : float
        Size of one panel in inches.
    suptitle : str, optional
        Title of the figure (the legend is below the panels).

    Returns
    -------
    matplotlib Figure
        Laid out by matplotlib's constrained layout, so titles, legend and colourbar do not
        overlap.
    """
    import matplotlib.pyplot as plt

    plans = list(plans)
    nrows = -(-len(plans) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel * ncols + 0.8, panel * nrows + 1.0),
                             squeeze=False, layout="constrained")
    for k, ax in enumerate(axes.flat):
        if k < len(plans):
            draw_plan(plans[k], ax, colorbar=False,
                      title=plan_title(plans[k]) if titles is None else titles[k])
        else:
            ax.axis("off")
    if suptitle is not None:
        fig.suptitle(suptitle, fontsize=13)
    fig.legend(handles=legend_handles(), loc="outside lower center", ncols=4, fontsize=10,
               frameon=False)
    _time_colorbar(fig, axes, shrink=0.6, pad=0.01, aspect=40)
    return fig
