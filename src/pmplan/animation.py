"""Animations of planned motions: robots moving along the path, obstacles, trails, phases.

An *animation* of a plan Gamma: [0, 1] -> F(R^d, m+n) shows the configuration Gamma(t) for
equally spaced t, with each robot's trail since t = 0, the faint full path ahead, and the phase
of the construction the robots are in at time t:

* obstacle-line planner (paper Section 3, Mathematics §3, §4.1, §4.2): the path is the composition of paper
  Remark 2.5, deformation of C, section over
  collinear pairs, deformation of C' reversed; its 8 waypoints at
  tau = 0, 1/6, 1/3, 4/9, 5/9, 2/3, 5/6, 1 delimit seven phases (:data:`OBSTACLE_LINE_PHASES`)::

      [0, 1/6]     desingularization             F(C, 6 tau), paper (3.2)
      [1/6, 1/3]   projection to the line L_C    paper (3.6)
      [1/3, 4/9]   lift                          paper (3.8): robot i up by i lambda nu(e)
      [4/9, 5/9]   slide                         along L_C, from X to X'
      [5/9, 2/3]   descend                       back onto L_C at X'
      [2/3, 5/6]   projection reversed           lift back off the line to F(C', 1)
      [5/6, 1]     desingularization reversed    back to C'

  A sequential plan through r configurations (Mathematics §4.3) repeats these seven phases on each of its
  r - 1 legs; the leg number is shown too.
* planar three-obstacle planner (paper Section 4): the path is a polyline traversed at constant
  speed; the phase is "polyline leg k of K" (Figures 6, 8, 9, 10).
* a refined plan (:func:`pmplan.refine`, issue 14) no longer follows the construction's phases:
  the phase is "refined path, piece k of K", and robots (and obstacles) with a radius are drawn
  as discs of that radius.

Coordinates: for d = 2 the picture is the plane itself. For d > 2 it is drawn in the planner's own
frame (:class:`pmplan.frame.Frame`): horizontal axis the column ``s = (y - o1) . e`` along the line
o1o2, vertical axis the coordinate ``(y - o1) . nu(e)`` along the lift direction, and the norm of
the remaining part ``|r(y) - ((y - o1) . nu(e)) nu(e)|`` shown as marker size (the picture says so).

:func:`draw_frame` draws one frame; :func:`animate_plan` is a ``FuncAnimation`` built on it (for
notebooks); :func:`animate_query` plans a query (as read by :func:`pmplan.io.read_query`) and
writes a ``.gif`` (Pillow) or ``.mp4`` (ffmpeg). matplotlib is imported inside the functions.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .display import display_for
from .errors import InputError, UnsupportedError
from .frame import Frame
from .planners import OBSTACLE_LINE, REGISTRY

__all__ = [
    "MAX_FRAMES",
    "MAX_FPS",
    "OBSTACLE_LINE_PHASES",
    "Phase",
    "phase_at",
    "frame_coordinates",
    "draw_frame",
    "animate_plan",
    "render_frames",
    "animate_query",
]

#: the seven phases of one obstacle-line leg: (short name, what happens, paper reference);
#: the planner's display (:attr:`pmplan.display.DisplaySpec.phases`)
OBSTACLE_LINE_PHASES: tuple[tuple[str, str], ...] = display_for(OBSTACLE_LINE).phases

#: most frames in one animation (a .gif holds them all in memory while it is written)
MAX_FRAMES = 1000
#: highest frame rate (GIF delays are counted in hundredths of a second)
MAX_FPS = 100

#: the phase name of every piece of a refined plan
REFINED_PHASE = "refined path"

_FIGSIZE = (4.8, 4.4)
_BAR = (0.02, 0.98, 0.015)  # timeline: from x0 to x1 (axes fraction) at height y
_DPI = 80


@dataclass(frozen=True)
class Phase:
    """The phase of the construction a plan is in at one time t.

    Attributes
    ----------
    name : str
        Short name, e.g. ``"lift"`` or ``"polyline leg"``.
    index, count : int
        1-based phase (or polyline leg) number within the current leg, and how many there are.
    leg, legs : int
        1-based leg of a sequential plan and the number of legs (1 for a two-configuration plan).
    description : str
        One sentence with the paper reference.
    """

    name: str
    index: int
    count: int
    leg: int
    legs: int
    description: str

    def label(self) -> str:
        """Return the text shown on a frame, e.g. ``"leg 2/3 - phase 3/7: lift"``."""
        if self.name == "polyline leg":
            text = f"polyline leg {self.index} of {self.count}"
        elif self.name == REFINED_PHASE:
            text = f"{REFINED_PHASE}, piece {self.index} of {self.count}"
        else:
            text = f"phase {self.index}/{self.count}: {self.name}"
        if self.legs > 1:
            text = f"leg {self.leg}/{self.legs} - " + text
        return text


def _piece_index(times: np.ndarray, t: float) -> int:
    """Index k of the piece [t_k, t_{k+1}) containing t (the last piece is closed)."""
    k = int(np.searchsorted(times, t, side="right")) - 1
    return min(max(k, 0), times.shape[0] - 2)


def phase_at(plan, t: float) -> Phase:
    """Return the :class:`Phase` of ``plan`` at time ``t`` in [0, 1].

    Pieces are half-open, ``[t_k, t_{k+1})``, and the last one is closed: at a waypoint time the
    phase that starts there is returned, and at t = 1 the last phase.

    Parameters
    ----------
    plan : pmplan.Plan
        A plan of the obstacle-line planner (two configurations or sequential), of the planar
        three-obstacle planner, or of any planner (then the phase is "piece k of K").
    t : float

    Examples
    --------
    >>> import pmplan
    >>> p = pmplan.plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    >>> ts = (0.0, 0.2, 0.4, 0.5, 0.6, 0.7, 0.9, 1.0)
    >>> [phase_at(p, t).name for t in ts]  # doctest: +NORMALIZE_WHITESPACE
    ['desingularization', 'projection to the line', 'lift', 'slide', 'descend',
     'projection reversed', 'desingularization reversed', 'desingularization reversed']
    >>> seq = pmplan.plan_sequence([[0, 0], [2, 0]], [[[0, 1]], [[1, -1]], [[3, 3]]])
    >>> phase_at(seq, 0.55).label()
    'leg 2/2 - phase 1/7: desingularization'
    """
    t = float(t)
    if not 0.0 <= t <= 1.0:
        raise InputError(f"the time t must lie in [0, 1], got {t}")
    times = np.asarray(plan.path.times, dtype=float)
    pieces = times.shape[0] - 1
    k = _piece_index(times, t)
    if plan.refined:  # the refinement moved every waypoint: no phase of the construction
        return Phase(REFINED_PHASE, k + 1, pieces, 1, 1,
                     f"piece {k + 1} of the refined path (pmplan.refine, docs/refinement.md)")
    p = REGISTRY.get(plan.planner)
    phases = display_for(p).phases if p is not None else ()
    nph = len(phases)
    if nph > 1 and pieces % nph == 0:  # named phases, every leg (pair of configurations)
        legs = pieces // nph
        name, desc = phases[k % nph]
        return Phase(name, k % nph + 1, nph, k // nph + 1, legs, desc)
    if nph == 1:  # every piece of one kind
        name, desc = phases[0]
        return Phase(name, k + 1, pieces, 1, 1, desc)
    return Phase("piece", k + 1, pieces, 1, 1, f"piece {k + 1} of the piecewise-linear path")


def frame_coordinates(plan, points: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Return the 2-D drawing coordinates of points of a plan, and the norm of the rest.

    Parameters
    ----------
    plan : pmplan.Plan
    points : ndarray, shape (..., P, d)
        Points in R^d (e.g. ``plan.path(t)``).

    Returns
    -------
    xy : ndarray, shape (..., P, 2)
        For d = 2 the points themselves. For d > 2 the planner's frame (:class:`pmplan.frame.Frame`
        of o1, o2): ``(s, h)`` with the column ``s = (y - o1) . e`` and ``h = (y - o1) . nu(e)``.
    rest : ndarray, shape (..., P), or None
        For d > 2, ``|r(y) - h nu(e)|``: the length of the part of y - o1 orthogonal to both e and
        nu(e), which the picture cannot show as a position. None for d = 2.

    Examples
    --------
    >>> import pmplan
    >>> p = pmplan.plan([[0, 0, 0], [0, 0, 2]], [[1, 2, 1]], [[0, 3, 1]])
    >>> xy, rest = frame_coordinates(p, p.path.waypoints[0])
    >>> xy  # o1 at the origin, o2 at (|w|, 0); the robot in column 1 (e = N: nu(e) = e_1)
    array([[0., 0.],
           [2., 0.],
           [1., 1.]])
    >>> rest
    array([0., 0., 2.])
    """
    pts = np.asarray(points, dtype=float)
    d = pts.shape[-1]
    if d == 2:
        return pts, None
    o = plan.obstacles
    fr = Frame(o[None, 0], o[None, 1])
    flat = pts.reshape(1, -1, d)
    s = fr.columns(flat)[0]
    r = fr.perpendicular(flat)[0]
    h = r @ fr.nu[0]
    rest_vec = r - h[:, None] * fr.nu[0][None, :]
    rest = np.sqrt((rest_vec * rest_vec).sum(-1))
    shape = pts.shape[:-1]
    return np.stack([s, h], axis=-1).reshape(shape + (2,)), rest.reshape(shape)




class _FrameArtists:
    """The artists of one animated plan, created once and moved by :meth:`update`."""

    def __init__(self, plan, ax, *, trails: bool = True, samples: int = 400):
        from .plotting import robot_colors

        self.plan = plan
        self.ax = ax
        d, n, m = plan.dims
        self.n, self.m, self.d = n, m, d
        self.trails = trails
        ts = np.union1d(np.linspace(0.0, 1.0, samples), plan.path.times)
        self.ts = ts
        self.xy, self.rest = frame_coordinates(plan, plan.path(ts))  # (S, P, 2), (S, P)
        self.rest_max = float(self.rest.max()) if self.rest is not None else 0.0
        colors = robot_colors(n)
        self.colors = colors

        obs_xy = self.xy[0, :m]
        obs_rest = self.rest[0, :m] if self.rest is not None else None
        ax.scatter(obs_xy[:, 0], obs_xy[:, 1], s=self._sizes(obs_rest, 70.0), marker="s",
                   color="black", zorder=5)
        for k in range(m):
            ax.annotate(f"o{k + 1}", obs_xy[k], xytext=(4, 4), textcoords="offset points",
                        fontsize=7)
        goal_xy = self.xy[-1, m:]
        ax.scatter(goal_xy[:, 0], goal_xy[:, 1], marker="*", color=colors, alpha=0.6, zorder=5.5,
                   s=self._sizes(self.rest[-1, m:] if self.rest is not None else None, 90.0))
        # the faint full path of every robot: where it is going
        for j in range(n):
            ax.plot(self.xy[:, m + j, 0], self.xy[:, m + j, 1], "-", color=colors[j], lw=0.8,
                    alpha=0.25)
        ticks = _BAR[0] + (_BAR[1] - _BAR[0]) * np.asarray(plan.path.times)
        ax.plot(ticks, np.full_like(ticks, _BAR[2]), "-", marker="|", ms=6, color="0.6", lw=0.8,
                transform=ax.transAxes, zorder=6)
        self.trail_lines = []
        if trails:
            for j in range(n):
                (line,) = ax.plot([], [], "-", color=colors[j], lw=1.8, alpha=0.95)
                self.trail_lines.append(line)
        self.robots = ax.scatter(self.xy[0, m:, 0], self.xy[0, m:, 1], s=60, color=colors,
                                 edgecolors="black", linewidths=0.8, zorder=6)
        # robots (moving) and obstacles (fixed) of a radius: discs of it, in data units (for
        # d > 2 the frame's axes are orthonormal, so a ball's shadow is a disc of its radius)
        from .plotting import draw_radii

        discs = draw_radii(plan, ax, self.xy[0], color="0.35", alpha=0.25, zorder=5.8)
        self.discs = discs[0] if plan.radius > 0 else None
        # the phase of the construction (text) and the time t (a progress bar along a timeline
        # whose ticks are the breakpoints of the path, e.g. 0, 1/6, 1/3, 4/9, 5/9, 2/3, 5/6, 1)
        self.text = ax.text(0.02, 0.98, "", transform=ax.transAxes, va="top", ha="left",
                            fontsize=7.5, family="monospace",
                            bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.85))
        self.progress = ax.plot([_BAR[0], _BAR[0]], [_BAR[2], _BAR[2]], "-", color="0.2", lw=2.5,
                                transform=ax.transAxes, solid_capstyle="butt", zorder=7)[0]
        #: the artists that move from frame to frame (the phase text changes only between phases)
        self.dynamic = [*self.trail_lines, self.robots, self.progress]
        if self.discs is not None:
            self.dynamic.insert(0, self.discs)
        lo = self.xy.reshape(-1, 2).min(axis=0)
        hi = self.xy.reshape(-1, 2).max(axis=0)
        pad = 0.12 * max(float((hi - lo).max()), 1e-9)
        top = 2.6 * pad  # room for the phase text
        bottom = 1.6 * pad  # room for the timeline
        if d > 2:
            ax.text(0.02, 0.045,
                    f"d = {d}: drawn in the planner's frame (axes);\n"
                    f"marker size grows with |rest|, the part\n"
                    f"off both axes (max {self.rest_max:.3g})",
                    transform=ax.transAxes, va="bottom", ha="left", fontsize=6.5, color="0.25")
            ax.set_xlabel("s = (y - o1) . e", fontsize=8)
            ax.set_ylabel("(y - o1) . nu(e)", fontsize=8)
            bottom = 4.6 * pad
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - bottom, hi[1] + top)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
        what = f"{plan.planner} refined, radius {plan.radius:g}" if plan.refined else plan.planner
        ax.set_title(f"$W_{{{plan.domain}}}$: ${plan.stratum}$  ({what}, d={d}, n={n}, m={m})",
                     fontsize=8)

    def _sizes(self, rest, base: float):
        if rest is None:
            return base
        if self.rest_max <= 0:
            return np.full(rest.shape, base)
        return base * (0.5 + 2.0 * rest / self.rest_max)

    def update(self, t: float):
        """Move the robots, trails and phase text to time t; return the changed artists."""
        m = self.m
        now = self.plan.path(float(t))
        xy, rest = frame_coordinates(self.plan, now)
        k = int(np.searchsorted(self.ts, t, side="right"))
        for j, line in enumerate(self.trail_lines):
            tr = np.vstack([self.xy[:k, m + j], xy[m + j][None]])
            line.set_data(tr[:, 0], tr[:, 1])
        self.robots.set_offsets(xy[m:])
        if self.discs is not None:
            self.discs.set_offsets(xy[m:])
        if rest is not None:
            self.robots.set_sizes(self._sizes(rest[m:], 60.0))
        self.text.set_text(self.label(t))
        self.progress.set_xdata([_BAR[0], _BAR[0] + (_BAR[1] - _BAR[0]) * float(t)])
        return self.dynamic

    def label(self, t: float) -> str:
        """Return the phase text at time t."""
        return phase_at(self.plan, t).label()


def draw_frame(plan, t: float, ax=None, *, trails: bool = True):
    """Draw the configuration of ``plan`` at time ``t``: one frame of its animation.

    Parameters
    ----------
    plan : pmplan.Plan
        Any plan (any d >= 2; d > 2 is drawn in the planner's frame, see :func:`frame_coordinates`).
    t : float
        Time in [0, 1].
    ax : matplotlib Axes, optional
        Axes to draw on (default: a new small figure).
    trails : bool
        Draw each robot's trail from t = 0 to t.

    Returns
    -------
    matplotlib Axes
        It holds, in this order of creation: ``ax.collections`` = [obstacles, goals (stars),
        robots at time t] (3); ``ax.lines`` = n faint full paths, the timeline (ticks at the
        path's breakpoints), n trails if ``trails``, the progress bar up to t; ``ax.texts`` =
        m obstacle labels, the phase text (:meth:`Phase.label`), and for d > 2 a note saying
        which frame is drawn and that marker size shows the norm of the rest. The title holds
        the domain and stratum.

    Examples
    --------
    >>> import pmplan
    >>> p = pmplan.plan([[0, 0], [2, 0]], [[0, 1], [1, 1]], [[1, -1], [2, 2]])
    >>> ax = draw_frame(p, 0.5)
    >>> len(ax.collections), len(ax.lines), len(ax.texts), ax.texts[-1].get_text()
    (3, 6, 3, 'phase 4/7: slide')
    """
    import matplotlib.pyplot as plt

    t = float(t)
    if not 0.0 <= t <= 1.0:
        raise InputError(f"the time t must lie in [0, 1], got {t}")
    if ax is None:
        _, ax = plt.subplots(figsize=_FIGSIZE)
    artists = _FrameArtists(plan, ax, trails=trails)
    artists.update(t)
    return ax


def _animation(plan, fig, frames: int, interval: float, trails: bool):
    from matplotlib.animation import FuncAnimation

    if int(frames) < 2:
        raise InputError(f"an animation needs at least 2 frames, got {frames}")
    ax = fig.add_subplot(1, 1, 1)
    artists = _FrameArtists(plan, ax, trails=trails)
    ts = np.linspace(0.0, 1.0, int(frames))
    fig.tight_layout()
    return FuncAnimation(fig, lambda i: artists.update(ts[i]), frames=int(frames),
                         interval=interval, blit=False, repeat=True)


def animate_plan(plan, *, frames: int = 120, interval: float = 1000.0 / 30.0,
                 trails: bool = True):
    """Return a ``matplotlib.animation.FuncAnimation`` of a plan (e.g. for a notebook).

    Each frame is :func:`draw_frame`'s picture at t = k/(frames - 1), k = 0..frames-1.

    Parameters
    ----------
    plan : pmplan.Plan
    frames : int
        Number of frames (>= 2), equally spaced in t.
    interval : float
        Delay between frames in milliseconds (default: 30 frames per second).
    trails : bool
        Draw the robots' trails.

    Examples
    --------
    >>> import pmplan
    >>> anim = animate_plan(pmplan.plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]]), frames=4)
    >>> type(anim).__name__, len(anim.to_jshtml()) > 1000
    ('FuncAnimation', True)

    In a notebook: ``from IPython.display import HTML; HTML(anim.to_jshtml())``.
    """
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=_FIGSIZE)
    return _animation(plan, fig, frames, interval, trails)


def render_frames(plan, *, frames: int = 120, trails: bool = True, dpi: int = _DPI):
    """Yield the frames of a plan's animation as RGBA arrays (height, width, 4) of uint8.

    The static part (axes, obstacles, goals, faint paths, timeline, and the phase text, which
    changes only between phases) is drawn once per phase; each frame restores it and draws only
    the moving artists of :func:`draw_frame` (Agg blitting), several times faster than
    redrawing whole figures.

    Examples
    --------
    >>> import pmplan
    >>> fr = list(render_frames(pmplan.plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]]), frames=3))
    >>> len(fr), fr[0].shape[2], fr[0].dtype.name, bool((fr[0] != fr[-1]).any())
    (3, 4, 'uint8', True)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    if int(frames) < 2:
        raise InputError(f"an animation needs at least 2 frames, got {frames}")
    fig = Figure(figsize=_FIGSIZE, dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    artists = _FrameArtists(plan, ax, trails=trails)
    fig.tight_layout()
    label, background = None, None
    for t in np.linspace(0.0, 1.0, int(frames)):
        if artists.label(t) != label:  # a new phase: redraw the static part with its text
            label = artists.label(t)
            artists.text.set_text(label)
            for a in artists.dynamic:
                a.set_visible(False)
            canvas.draw()
            background = canvas.copy_from_bbox(fig.bbox)
            for a in artists.dynamic:
                a.set_visible(True)
        canvas.restore_region(background)
        for a in artists.update(t):
            ax.draw_artist(a)
        yield np.array(canvas.buffer_rgba())


def animate_query(q: dict, out, *, frames: int = 120, fps: int = 30,
                  planner: str | None = None, refine: dict | None = None) -> Path:
    """Plan a query (and refine it) and write its animation to ``out`` (``.gif`` or ``.mp4``).

    Parameters
    ----------
    q : dict
        A query as returned by :func:`pmplan.io.read_query`: ``obstacles``, ``start``, ``goal``,
        optional ``via`` (sequential plan, Mathematics §4.3), ``lift``, ``planner``.
    out : str or path-like
        ``.gif`` (frames from :func:`render_frames`, written with Pillow) or ``.mp4``
        (``FuncAnimation.save`` with matplotlib's ffmpeg writer, when ffmpeg is installed).
    frames : int
        Number of frames, 2 to :data:`MAX_FRAMES`.
    fps : int
        Frames per second, 1 to :data:`MAX_FPS`.
    planner : str, optional
        Planner name; overrides ``q["planner"]``.
    refine : dict, optional
        Animate the refined motion: the keyword arguments of :func:`pmplan.refine` (``{}`` for
        its defaults, or e.g. ``{"radius": 0.2}``; robots with a radius are drawn as discs).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        For another suffix, or frames or fps out of range.
    UnsupportedError
        For ``.mp4`` when ffmpeg is not available.
    """
    import matplotlib.animation as manim
    from matplotlib.figure import Figure

    from .api import plan_query
    from .io import with_defaults

    out = Path(out)
    suffix = out.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InputError(f"cannot write an animation to {out.name!r}: use a .gif or .mp4 file name")
    for name, value, lo, hi in (("fps", fps, 1, MAX_FPS), ("frames", frames, 2, MAX_FRAMES)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                or not lo <= value <= hi:
            raise InputError(f"`{name}` must be an integer from {lo} to {hi:,}, got {value!r}")
    if suffix == ".mp4":
        if not manim.writers.is_available("ffmpeg"):
            raise UnsupportedError(
                "writing .mp4 needs ffmpeg, which was not found on this machine; "
                "install ffmpeg or write a .gif instead"
            )
        writer = manim.FFMpegWriter(fps=int(fps))
    else:
        from PIL import Image
    plan = plan_query(with_defaults(q, refine), planner)  # (the unit of a refined plan)
    if refine is not None:
        from .api import refine as refine_plan

        plan = refine_plan(plan, **refine)
    if suffix == ".gif":
        images = [Image.fromarray(rgba[..., :3]).quantize(
                      colors=64, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE)
                  for rgba in render_frames(plan, frames=frames)]
        images[0].save(out, save_all=True, append_images=images[1:],
                       duration=max(1, round(1000 / int(fps))), loop=0)
    else:
        fig = Figure(figsize=_FIGSIZE)
        anim = _animation(plan, fig, frames, 1000.0 / int(fps), True)
        anim.save(str(out), writer=writer, dpi=_DPI)
    return out
