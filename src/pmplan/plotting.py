"""Pictures of plans: obstacles, each robot's path in its own colour, time along it.

A planar plan (d = 2) is drawn in the plane: obstacles are black squares (``o_1``, ``o_2``,
...), and robot j has one colour (:func:`robot_colors`) for its start circle (``x_j``), its goal
star (``x_j'``) and its path. Time is a second channel: the path is thin and faint at t = 0 and
thick and solid at t = 1, with a dot at every time of :data:`TIME_TICKS` and arrows for the
direction, so two paths that cross, or run along the same segment, are told apart by colour and
seen to be passed at different times. :func:`plan_grid` draws several plans in panels with one
legend (``pmplan demo``, ``docs/demo.png``); panels of one query (raw and refined) can share one
axis range.

matplotlib is imported inside the functions; :func:`draw_plan` takes ``ax=None`` and returns the
axes it drew on (shapely's plotting style).
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_ARROWS", "TIME_TICKS", "robot_colors", "time_style", "plan_title", "draw_radii", "draw_plan",
           "legend_handles", "plan_grid"]

#: the times marked by a dot on every path
TIME_TICKS = (0.25, 0.5, 0.75)
#: at most about this many arrows along one robot's path (every piece of a raw plan has one)
MAX_ARROWS = 8
#: line width (points) and opacity of a path at t = 0 and at t = 1 (linear in between)
_WIDTH = (0.8, 3.4)
_ALPHA = (0.3, 1.0)


def robot_colors(n: int):
    """Return n distinct colours for robots.

    Parameters
    ----------
    n : int
        Number of robots.

    Returns
    -------
    list of tuple
        RGBA colours: matplotlib's ``tab10`` for up to 10 robots, ``turbo`` beyond.
    """
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab10" if n <= 10 else "turbo")
    return [cmap(i if n <= 10 else i / max(n - 1, 1)) for i in range(n)]


def time_style(t) -> tuple[np.ndarray, np.ndarray]:
    """Return the line width and opacity of a path at times ``t`` in [0, 1].

    Parameters
    ----------
    t : array_like
        Times along the motion.

    Returns
    -------
    width : numpy.ndarray
        Line widths in points, from 0.8 at t = 0 (thin) to 3.4 at t = 1 (thick), linear in t.
    alpha : numpy.ndarray
        Opacities, from 0.3 at t = 0 (faint) to 1 at t = 1 (solid), linear in t.

    Examples
    --------
    >>> w, a = time_style([0.0, 0.5, 1.0])
    >>> w.round(2).tolist(), a.round(2).tolist()
    ([0.8, 2.1, 3.4], [0.3, 0.65, 1.0])
    >>> time_style(0.5)[0].shape
    ()
    """
    t = np.clip(np.asarray(t, dtype=float), 0.0, 1.0)
    return _WIDTH[0] + (_WIDTH[1] - _WIDTH[0]) * t, _ALPHA[0] + (_ALPHA[1] - _ALPHA[0]) * t


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
    'obstacle_line_compact  $W_{6}$: $T_{3,3}$'
    >>> plan_title(pmplan.refine(p))
    'obstacle_line_compact refined  $W_{6}$: $T_{3,3}$'
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
    """Segments of robot j's path and the time at the middle of each (for width and opacity)."""
    ts = np.union1d(np.linspace(0.0, 1.0, samples), plan.path.times)
    pts = plan.path(ts)[:, plan.dims[2] + j]
    return np.stack([pts[:-1], pts[1:]], axis=1), (ts[:-1] + ts[1:]) / 2


def draw_plan(plan, ax=None, *, samples: int = 400, title: str | None = None,
              arrows: bool = True):
    """Draw a planar plan (d = 2): obstacles, each robot's path in its colour, starts and goals.

    Parameters
    ----------
    plan : pmplan.Plan
        A plan with d = 2.
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).
    samples : int
        Number of samples of the path used for the lines (waypoints are always included).
    title : str, optional
        Default: :func:`plan_title` and the certified clearance.
    arrows : bool
        Arrows at the middle of every leg, in the robot's colour (of every k-th leg when the
        path has more than :data:`MAX_ARROWS` legs, as a refined path has).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on. Robot j's path is a ``LineCollection`` whose widths and opacities
        grow with time (:func:`time_style`); a dot marks it at every time of :data:`TIME_TICKS`.
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.colors import to_rgba

    d, n, m = plan.dims
    if d != 2:
        raise ValueError(f"draw_plan draws planar plans (d = 2), got d = {d}")
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5), layout="constrained")
    colors = robot_colors(n)
    obs = plan.obstacles
    ax.plot(obs[:, 0], obs[:, 1], "s", color="black", ms=9, zorder=5)
    if plan.bounds is not None:  # the workspace box (pmplan.workspace), dashed
        (x0, y0), (x1, y1) = np.asarray(plan.bounds)
        ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], "--", color="0.35", lw=1.2,
                zorder=2)
    times = plan.path.times
    ticks = plan.path(np.asarray(TIME_TICKS))
    for j in range(n):
        segs, tmid = _time_segments(plan, j, samples)
        width, alpha = time_style(tmid)
        rgba = np.tile(to_rgba(colors[j]), (len(tmid), 1))
        rgba[:, 3] = alpha
        ax.add_collection(LineCollection(segs, colors=rgba, linewidths=width, capstyle="round",
                                         zorder=3, label=f"robot {j + 1}"))
        if arrows:
            wp = plan.path.waypoints[:, m + j]
            every = max(1, (len(times) - 1) // MAX_ARROWS)  # a refined path has many pieces
            for k, (a, b) in enumerate(zip(wp[:-1], wp[1:])):
                if k % every == every // 2 and np.linalg.norm(b - a) > 0:
                    mid = (a + b) / 2
                    ax.annotate("", xy=mid + (b - a) * 0.01, xytext=mid, zorder=4,
                                arrowprops=dict(arrowstyle="-|>", color=colors[j], lw=1.2,
                                                mutation_scale=11))
        ax.plot(ticks[:, m + j, 0], ticks[:, m + j, 1], "o", color=colors[j], mec="white",
                mew=0.8, ms=5, ls="", zorder=4)
        ax.plot(*plan.start[j], "o", color=colors[j], ms=8, mfc="white", mew=2, zorder=6)
        ax.plot(*plan.goal[j], "*", color=colors[j], mec="black", mew=0.6, ms=13, zorder=6)
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


def legend_handles(n: int = 0):
    """Return the legend's proxy artists: obstacle, start, goal, time along a path, robots.

    Parameters
    ----------
    n : int
        Number of robots whose colours get an entry ("robot 1" ...); 0 for none.

    Returns
    -------
    list of matplotlib.artist.Artist
        Four entries that explain the marks, then one per robot.
    """
    from matplotlib.lines import Line2D

    grey = "0.35"
    handles = [
        Line2D([], [], ls="", marker="s", color="black", ms=8, label="obstacle $o_k$"),
        Line2D([], [], ls="", marker="o", color=grey, mfc="white", mew=2, ms=8,
               label="start $x_j$ (t = 0)"),
        Line2D([], [], ls="", marker="*", color=grey, mec="black", mew=0.6, ms=12,
               label="goal $x_j'$ (t = 1)"),
        Line2D([], [], color=grey, lw=2, marker="o", mec="white", ms=5,
               label="time: thin, faint (t = 0) to thick (t = 1); dots at t = 1/4, 1/2, 3/4"),
    ]
    handles += [Line2D([], [], color=c, lw=3, label=f"robot {j + 1}")
                for j, c in enumerate(robot_colors(n))]
    return handles


def _share_limits(axes) -> None:
    """Give every axes of ``axes`` the union of their data ranges (equal aspect kept)."""
    lo = np.min([ax.get_xlim()[0] for ax in axes]), np.min([ax.get_ylim()[0] for ax in axes])
    hi = np.max([ax.get_xlim()[1] for ax in axes]), np.max([ax.get_ylim()[1] for ax in axes])
    for ax in axes:
        ax.set_aspect("equal", adjustable="box")  # the same limits in boxes of the same shape
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])


def plan_grid(plans, titles=None, *, ncols: int = 4, panel: float = 3.6,
              suptitle: str | None = None, same_axes: int = 1):
    """Draw several planar plans in a grid of panels with one legend.

    Parameters
    ----------
    plans : sequence of pmplan.Plan
        The plans, drawn row by row.
    titles : sequence of str, optional
        Panel titles (default :func:`plan_title`).
    ncols : int
        Number of panels in a row.
    panel : float
        Size of one panel in inches.
    suptitle : str, optional
        Title of the figure (the legend is below the panels).
    same_axes : int
        Consecutive groups of this many panels share one axis range: 2 for the raw and refined
        plans of one query side by side (``pmplan demo``); 1 (default) for none.

    Returns
    -------
    matplotlib.figure.Figure
        Laid out by matplotlib's constrained layout, so titles and legend do not overlap.
    """
    import matplotlib.pyplot as plt

    plans = list(plans)
    nrows = -(-len(plans) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel * ncols + 0.8, panel * nrows + 1.0),
                             squeeze=False, layout="constrained")
    drawn = []
    for k, ax in enumerate(axes.flat):
        if k < len(plans):
            drawn.append(draw_plan(plans[k], ax,
                                   title=plan_title(plans[k]) if titles is None else titles[k]))
        else:
            ax.axis("off")
    for k in range(0, len(drawn), max(1, same_axes)):
        group = drawn[k:k + max(1, same_axes)]
        for ax in group:
            ax.apply_aspect()  # the limits each panel shows, before they are shared
        _share_limits(group)
    if suptitle is not None:
        fig.suptitle(suptitle, fontsize=13)
    handles = legend_handles(max((p.dims[1] for p in plans), default=0))
    fig.legend(handles=handles, loc="outside lower center", fontsize=10, frameon=False,
               ncols=len(handles) if len(handles) <= 2 * ncols else ncols)
    return fig
