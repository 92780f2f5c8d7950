"""The figures of paper Section 4, redrawn from the planner's own output.

One picture per stratum of the ``planar_three`` planner (paper Section 4): the query is an exact
scene with the line o1o2 at a slant, it is planned with :func:`pmplan.plan` (so the path is the
certified output of the planner), and the picture is drawn in the frame (u, h) of C
(``u = (y - o1).e``, ``h = (y - o1).nu(e)``), so that it looks like the paper's TikZ figures:

* ``T1_11``, ``T22_33``, ``T23_44``: Figure 6 (the L_C-parallel line one unit above
  the highest obstacle);
* ``T1_12``, ``T1_21``: Figure 7;
* ``T1_22``, ``T22_22``: Figure 8 (the vertical at delta_1 / delta_2);
* ``T22_23``, ``T22_32``: Figure 9;
* ``T23_33``, ``T23_34``, ``T23_43``: Figure 10 (dashed: obstacle columns and heights;
  solid grey: the grid lines s1, s2, s3 and h3/2 the path runs on).

Dashed lines are L_C and L_C^perp (and the other obstacle columns/heights where the paper
draws them); the path is drawn leg by leg with arrows, and small dots mark the robot at
tau = 0.1, 0.2, ..., 0.9 (constant speed: equally spaced along the path).

matplotlib is imported inside the functions (the Agg backend is selected).
"""

from __future__ import annotations

import pathlib

import numpy as np

__all__ = ["FIGURE_OF", "draw_stratum", "figure_queries", "make_figures", "to_frame"]

#: the paper's printed figure number for every stratum (Figures 6-10 of its Section 4)
FIGURE_OF: dict[str, int] = {
    "T1_11": 6, "T22_33": 6, "T23_44": 6,
    "T1_12": 7, "T1_21": 7,
    "T1_22": 8, "T22_22": 8,
    "T22_23": 9, "T22_32": 9,
    "T23_33": 10, "T23_34": 10, "T23_43": 10,
}

# (U, V) coordinates of o3, x, x' with o1 = (0, 0), o2 = (4, 0): the paper's pictures; the
# world point is o1 + U w + V rot90(w), so its frame coordinates are (u, h) = |w| (U, V)
_SCENES: dict[str, tuple[tuple[float, float], ...]] = {
    "T1_11": ((-1.5, 0), (2, 0), (6, 0)),
    "T1_12": ((-1.5, 0), (2, 0), (6, 1.5)),
    "T1_21": ((-1.5, 0), (2, 1.5), (6, 0)),
    "T1_22": ((5.5, 0), (7, 1.5), (6, -2)),  # Figure 8: o3 between o1 and o2 ...
    "T22_22": ((0, 1.5), (4, 1.5), (0, -1.5)),
    "T22_23": ((0, 2), (0, 4), (3, -2)),
    "T22_32": ((0, 2), (3, -2), (0, 4)),
    "T22_33": ((4, 1.5), (1.5, -3), (7, 1)),
    "T23_33": ((6, 2), (0, -2), (6, -1.5)),
    "T23_34": ((2.5, 2), (2.5, -1.5), (6, 3)),
    "T23_43": ((2.5, 2), (6, 3), (2.5, -1.5)),
    "T23_44": ((5, 1.5), (1.5, -3), (7, -1.5)),
}
# ... in Figure 8 (left) o3 lies between o1 and o2: swap the roles there
_SWAP_O2_O3 = {"T1_22"}

# the slanted frame of the scenes: o1 = (1, -1), w = (1, 3/4), |w| = 5/4 (all exact dyadic)
_O1 = np.array([1.0, -1.0])
_W = np.array([1.0, 0.75])
_ROT = np.array([-0.75, 1.0])


def figure_queries() -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Return one exact query ``(obstacles (3, 2), start (1, 2), goal (1, 2))`` per stratum.

    The scenes reproduce the paper's Section 4 pictures on a slanted line o1o2
    (``w = (1, 3/4)``, ``|w| = 5/4``, so frame coordinates are 5/4 of the scene's grid
    coordinates); coordinates are dyadic, so every degeneracy is exact.

    Examples
    --------
    >>> from pmplan.planners.planar_three import classify, stratum_short_name
    >>> qs = figure_queries()
    >>> all(stratum_short_name(classify(o[None], s[None], g[None]).record[0]) == k
    ...     for k, (o, s, g) in qs.items())
    True
    """
    out = {}
    for name, (o3, x, xp) in _SCENES.items():
        uv = np.array([(0.0, 0.0), (4.0, 0.0), o3, x, xp])  # (U, V); frame (u, h) = 5/4 (U, V)
        if name in _SWAP_O2_O3:
            uv[[1, 2]] = uv[[2, 1]]
        pts = _O1 + uv[:, :1] * _W + uv[:, 1:] * _ROT
        out[name] = (pts[:3], pts[3:4], pts[4:5])
    return out


def to_frame(points: np.ndarray, obstacles: np.ndarray) -> np.ndarray:
    """Return the frame coordinates (u, h) of points (..., 2) for obstacles (3, 2)."""
    o1, o2 = obstacles[0], obstacles[1]
    e = (o2 - o1) / np.hypot(*(o2 - o1))
    nu = np.array([-e[1], e[0]])
    rel = np.asarray(points, dtype=float) - o1
    return np.stack([rel @ e, rel @ nu], axis=-1)


def _line(ax, a, b, **kw):
    ax.annotate("", xy=b, xytext=a, arrowprops=dict(arrowstyle="->", **kw))


def draw_stratum(plan, name: str, ax=None):
    """Draw a ``planar_three`` plan in the frame (u, h) of its query, paper style.

    Parameters
    ----------
    plan : pmplan.Plan
        A plan of the ``planar_three`` planner.
    name : str
        Its stratum in pmplan's notation (``"T22_23"``, Mathematics §5.2), which selects the auxiliary lines.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Axes
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 4))
    obs = plan.obstacles
    wp = to_frame(plan.path.waypoints[:, 3], obs)
    o = to_frame(obs, obs)
    o[:2, 1] = 0.0
    o[0] = 0.0
    h3 = o[2, 1]
    big = np.concatenate([wp, o])
    umin, umax = big[:, 0].min() - 1.0, big[:, 0].max() + 1.0
    hmin, hmax = big[:, 1].min() - 0.8, big[:, 1].max() + 0.8
    short = 0.5 * (umax - umin) - (hmax - hmin)  # keep the panels from getting too flat
    if short > 0:
        hmin, hmax = hmin - short / 2, hmax + short / 2
    dash = dict(color="0.45", lw=0.9, linestyle=(0, (4, 3)))
    grid = dict(color="0.75", lw=3.0, solid_capstyle="butt", zorder=0)
    # L_C and L_C^perp (paper Section 4, first picture), dashed and oriented
    _line(ax, (umin, 0), (umax, 0), color="0.45", lw=0.9, linestyle="--")
    _line(ax, (0, hmin), (0, hmax), color="0.45", lw=0.9, linestyle="--")
    ax.text(umax, 0, "  $L_C$", va="center", fontsize=8, color="0.35")
    ax.text(0, hmax, "$L_C^\\perp$ ", ha="right", va="top", fontsize=8, color="0.35")
    fam = name.split("_")[0]
    if fam == "T22":  # the second perpendicular \bar L_C^perp through o2
        ax.axvline(o[1, 0], **dash)
    if FIGURE_OF[name] == 10:  # Figure 10: dashed obstacle columns and heights, solid grid lines
        cols = np.sort(o[:, 0])
        for c in cols:
            ax.axvline(c, **dash)
        ax.axhline(h3, **dash)
        for s in ((cols[0] + cols[1]) / 2, (cols[1] + cols[2]) / 2, cols[2] + 1.0):
            ax.axvline(s, **grid)
        ax.axhline(h3 / 2, **grid)
    if name in ("T22_23", "T22_32"):  # Figure 9: the lines l2 (|w|/2) and l3 (h3/2)
        ax.axhline(h3 / 2, **grid)
        ax.axvline(o[1, 0] / 2, **grid)
    if FIGURE_OF[name] == 6:  # the L_C-parallel line at height 1 + max(0, h3)
        top = 1.0 + max(0.0, h3)
        ax.axhline(top, **grid)
        uu = umax + 0.35
        ax.annotate("", xy=(uu, top), xytext=(uu, top - 1.0),
                    arrowprops=dict(arrowstyle="<->", linestyle=":", color="0.3"))
        ax.text(uu + 0.1, top - 0.5, "1", fontsize=8, va="center")
    if FIGURE_OF[name] == 8:  # the vertical at delta, and delta marked above
        delta = wp[1, 0]
        ax.axvline(delta, **grid)
        ax.annotate("", xy=(delta, hmax - 0.3), xytext=(0, hmax - 0.3),
                    arrowprops=dict(arrowstyle="<->", linestyle=":", color="0.3"))
        ax.text(delta / 2, hmax - 0.25, "$\\delta_1$" if name == "T1_22" else "$\\delta_2$",
                ha="center", va="bottom", fontsize=9)
    # the path, leg by leg, with arrows; dots at tau = 0.1 .. 0.9 (constant speed)
    for a, b in zip(wp[:-1], wp[1:]):
        if np.hypot(*(b - a)) > 0:
            ax.annotate("", xy=b, xytext=a, zorder=3,
                        arrowprops=dict(arrowstyle="-|>", color="tab:blue", lw=2.0,
                                        shrinkA=0, shrinkB=3, mutation_scale=13))
    ticks = to_frame(plan.path(np.linspace(0.1, 0.9, 9))[:, 3], obs)
    ax.plot(ticks[:, 0], ticks[:, 1], ".", color="tab:blue", ms=4, zorder=4)
    ax.plot(o[:, 0], o[:, 1], "o", color="black", ms=6, zorder=5)
    for k in range(3):
        ax.annotate(f"$o_{k + 1}$", o[k], xytext=(-12, -13), textcoords="offset points",
                    fontsize=10)
    for p, lab, mk in ((wp[0], "$x$", "o"), (wp[-1], "$x'$", "s")):
        ax.plot(*p, mk, color="tab:red", ms=6, mfc="white", mew=1.8, zorder=6)
        ax.annotate(lab, p, xytext=(5, 4), textcoords="offset points", fontsize=10,
                    color="tab:red")
    ax.set_xlim(umin - 0.3, umax + 0.8)
    ax.set_ylim(hmin, hmax + 0.2)
    ax.set_aspect("equal")
    ax.set_xlabel("u = (y - o1).e", fontsize=7)
    ax.set_ylabel("h = (y - o1).nu(e)", fontsize=7)
    ax.tick_params(labelsize=7)
    ax.set_title(f"${plan.stratum}$ in $W_{plan.domain}$ (paper Figure {FIGURE_OF[name]})",
                 fontsize=10)
    return ax


def make_figures(out_dir: str | pathlib.Path = "docs/figures") -> list[pathlib.Path]:
    """Draw the 12 stratum pictures and one overview; return the written PNG paths.

    Every picture is drawn from :func:`pmplan.plan` on the exact query of
    :func:`figure_queries` (certified paths), in the frame (u, h) of the query.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Created if missing. Files: ``T1_11.png`` ... ``T23_44.png`` and ``overview.png``.

    Returns
    -------
    list of pathlib.Path
        13 paths: one per stratum (in the order of
        :data:`pmplan.planar_strata.STRATA`), then the overview.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .api import plan
    from .planners.planar_three import STRATA, PlanarThreePlanner

    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    queries = figure_queries()
    # these are the figures of one planner (paper Section 4): it is asked by its class, whose
    # ``name`` is the one source of the registry key
    section4 = PlanarThreePlanner.name
    plans = {name: plan(*queries[name], planner=section4) for name in STRATA}
    written = []
    for name in STRATA:
        fig, ax = plt.subplots(figsize=(5.2, 4.2))
        draw_stratum(plans[name], name, ax)
        fig.subplots_adjust(left=0.12, right=0.97, bottom=0.1, top=0.92)  # tight_layout is slow
        path = out / f"{name}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        written.append(path)
    from .planners.planar_three import DOMAIN_OF

    rows = [[s for s in STRATA if DOMAIN_OF[s] == a] for a in (1, 2, 3, 4)]  # one row per W_a
    fig, axes = plt.subplots(4, 5, figsize=(25, 17))
    for ax_row, names in zip(axes, rows):
        for k, ax in enumerate(ax_row):
            if k < len(names):
                draw_stratum(plans[names[k]], names[k], ax)
            else:
                ax.axis("off")
    fig.suptitle(f"pmplan {section4} (paper Section 4): one certified path per stratum, "
                 "one row per domain W1..W4, drawn in the frame (u, h) of C", fontsize=15)
    fig.subplots_adjust(left=0.04, right=0.99, bottom=0.04, top=0.94, wspace=0.25, hspace=0.3)
    path = out / "overview.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    written.append(path)
    return written
