"""Make the pictures and the recorded output of docs/tutorial.md.

Run from the repository root::

    python docs/tutorial/make_pictures.py

Writes, next to this file:

* ``domains.png``   two nearby queries in one domain (close paths) and two in different domains
                    (far paths);
* ``strip.png``     frames of the animation of one query, one per phase of the construction;
* ``motion.gif``    the animation itself (small);
* ``frame3d.png``   one frame of a query in R^3, drawn in the planner's frame;
* ``refined.png``   the query of ``strip.png`` raw and refined (radius 0.2), side by side;
* ``room.png``      the crowded room (8 robots, 6 obstacles, a box) raw and refined;
* ``refined.gif``   the refined motion, robots drawn as discs of radius 0.2;
* ``verify.txt``    the output of ``pmplan verify --d 2 --n 2 --m 2 --no-progress``;
* ``verify_refine.txt``  the same with ``--refine`` (the refined planner's moduli beside).
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pmplan  # noqa: E402
from pmplan.animation import draw_frame, render_frames  # noqa: E402
from pmplan.cli import main  # noqa: E402

HERE = Path(__file__).resolve().parent
OBSTACLES = np.array([[0.0, 0.0], [6.0, 0.0]])
#: the robots' radius of the refined pictures
RADIUS = 0.2


def _overlay(ax, plans, styles, labels, title):
    ts = np.union1d(np.linspace(0, 1, 400), np.concatenate([p.path.times for p in plans]))
    ax.plot(OBSTACLES[:, 0], OBSTACLES[:, 1], "s", color="black", ms=9, zorder=5)
    for k, o in enumerate(OBSTACLES):
        ax.annotate(f"$o_{k + 1}$", o, xytext=(4, 4), textcoords="offset points", fontsize=9)
    for p, (color, ls), label in zip(plans, styles, labels):
        tr = p.path(ts)[:, 2]
        ax.plot(tr[:, 0], tr[:, 1], ls, color=color, lw=2, label=label, alpha=0.9)
        ax.plot(*p.start[0], "o", color=color, mfc="white", mew=2, ms=7, zorder=6)
        ax.plot(*p.goal[0], "*", color=color, ms=11, zorder=6)
    ax.axvline(0.0, color="0.6", lw=0.8, ls=":")
    ax.set_aspect("equal")
    ax.set_xlim(-0.8, 6.8)
    ax.set_ylim(-1.8, 1.8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower left")
    ax.set_title(title, fontsize=9)


def domains_picture(out: Path) -> None:
    """Two nearby queries in one domain, and two nearby queries in different domains."""
    goal = [[3.0, -1.0]]
    q = pmplan.plan(OBSTACLES, [[0.0, 1.0]], goal)  # x on the column of o1: W_5
    same = pmplan.plan(OBSTACLES, [[0.0, 1.15]], goal)  # moved along the column: still W_5
    other = pmplan.plan(OBSTACLES, [[0.15, 1.0]], goal)  # moved off the column: W_6
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.3))
    def name(x, p):
        return f"x = {x}: $W_{{{p.domain}}}$, ${p.stratum}$"

    _overlay(axes[0], [q, same], [("tab:blue", "-"), ("tab:orange", "--")],
             [name("(0, 1)", q), name("(0, 1.15)", same)], "same domain: paths 0.15 apart")
    _overlay(axes[1], [q, other], [("tab:blue", "-"), ("tab:red", "--")],
             [name("(0, 1)", q), name("(0.15, 1)", other)], "different domains: paths ~2 apart")
    fig.suptitle("Moving the start by 0.15: along the column of $o_1$ (left), off it (right)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def strip_picture(plan, out: Path) -> None:
    """One frame per phase: the middle of each of the seven pieces, plus t = 1."""
    times = plan.path.times
    ts = list((times[:-1] + times[1:]) / 2) + [1.0]
    fig, axes = plt.subplots(2, 4, figsize=(16, 7.4))
    for ax, t in zip(axes.flat, ts):
        draw_frame(plan, float(t), ax=ax)
        ax.set_title(f"t = {t:.3f}", fontsize=9)
    fig.suptitle(f"$W_{{{plan.domain}}}$, ${plan.stratum}$: one frame per phase of the construction",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(out, dpi=65)
    plt.close(fig)


def gif(plan, out: Path, frames: int = 48, fps: int = 12) -> None:
    from PIL import Image

    images = [Image.fromarray(f[..., :3]).quantize(colors=32, method=Image.Quantize.FASTOCTREE,
                                                    dither=Image.Dither.NONE)
              for f in render_frames(plan, frames=frames, dpi=60)]
    images[0].save(out, save_all=True, append_images=images[1:], duration=1000 // fps, loop=0)


def frame3d_picture(out: Path) -> None:
    p = pmplan.plan([[0, 0, 0], [4, 0, 0], [2, 2, 1]], [[0, 1, 1], [2, -1, 0]],
                    [[3, -1, 2], [4, 2, 0]])
    fig, ax = plt.subplots(figsize=(5.5, 5))
    draw_frame(p, 0.5, ax=ax)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def refined_picture(plan, out: Path) -> None:
    """The same query raw and refined (radius 0.2): the same domain, a shorter motion."""
    from pmplan.plotting import plan_grid

    ref = pmplan.refine(plan, radius=RADIUS)
    fig = plan_grid([plan, ref], ncols=2, panel=4.2, same_axes=2,
                    titles=[f"raw: $W_{{{plan.domain}}}$, length {plan.path.length():.3g}",
                            f"refined, radius {RADIUS:g}: $W_{{{ref.domain}}}$, length "
                            f"{ref.path.length():.3g}"])
    fig.savefig(out, dpi=70)
    plt.close(fig)


def room_picture(out: Path) -> None:
    """The crowded room of ``pmplan demo`` raw and refined (radius 0.15) in its box."""
    from pmplan.examples import ROOM_GAP, crowded_room_plans
    from pmplan.plotting import plan_grid

    raw, ref = crowded_room_plans()  # the demo's own two plans
    fig = plan_grid([raw, ref], ncols=2, panel=4.6, same_axes=2,
                    titles=[f"raw, in the box: $W_{{{raw.domain}}}$, length "
                            f"{raw.path.length():.3g}",
                            f"refined, radius {ROOM_GAP / 2:g}: length {ref.path.length():.3g}"])
    fig.savefig(out, dpi=70)
    plt.close(fig)


def verify_output(out: Path, *extra: str) -> None:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        status = main(["verify", "--d", "2", "--n", "2", "--m", "2", "--no-progress", *extra])
    cmd = " ".join(["pmplan verify --d 2 --n 2 --m 2", *extra])
    out.write_text(f"$ {cmd}\n{buf.getvalue()}$ echo $?\n{status}\n")


def main_pictures() -> None:
    domains_picture(HERE / "domains.png")
    plan = pmplan.plan([[0, 0], [4, 0]], [[0, 1], [2, -1]], [[3, -1], [4, 2]])
    strip_picture(plan, HERE / "strip.png")
    gif(plan, HERE / "motion.gif")
    frame3d_picture(HERE / "frame3d.png")
    refined_picture(plan, HERE / "refined.png")
    gif(pmplan.refine(plan, radius=RADIUS), HERE / "refined.gif")
    room_picture(HERE / "room.png")
    verify_output(HERE / "verify.txt")
    verify_output(HERE / "verify_refine.txt", "--refine")
    for name in ("domains.png", "strip.png", "motion.gif", "frame3d.png", "refined.png",
                 "refined.gif", "room.png", "verify.txt", "verify_refine.txt"):
        print(f"wrote {HERE / name} ({(HERE / name).stat().st_size // 1024} KiB)")


if __name__ == "__main__":
    main_pictures()
