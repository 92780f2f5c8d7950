"""Tests of pmplan.animation: phases, frame coordinates, frames, GIF output, CLI."""

import json

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import pmplan  # noqa: E402
from pmplan import generators as gen  # noqa: E402
from pmplan.animation import (  # noqa: E402
    OBSTACLE_LINE_PHASES,
    animate_plan,
    animate_query,
    draw_frame,
    frame_coordinates,
    phase_at,
    render_frames,
)
from pmplan.cli import main  # noqa: E402
from pmplan.examples import planar_three_examples  # noqa: E402
from pmplan.errors import InputError, UnsupportedError  # noqa: E402
from pmplan.frame import Frame  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _plan(seed, d, n, m, cps=(2, 3)):
    q = gen.column_query(np.random.default_rng(seed), d, n, m, *cps, cp_o=2)
    return pmplan.plan(*q, planner="obstacle_line")


# --------------------------------------------------------------------------------------------
# phases: names at the waypoint times, and the motion each name promises


@pytest.mark.parametrize("d", [2, 3, 4])
def test_phase_names_at_waypoint_times(d):
    p = _plan(d, d, 2, 3)
    times = p.path.times
    assert times.shape == (8,)
    names = [name for name, _ in OBSTACLE_LINE_PHASES]
    for k in range(7):
        # a phase starts at its waypoint time and lasts until the next one
        assert phase_at(p, times[k]).name == names[k]
        assert phase_at(p, (times[k] + times[k + 1]) / 2).name == names[k]
        assert phase_at(p, times[k]).index == k + 1
    assert phase_at(p, 1.0).name == "desingularization reversed"
    assert phase_at(p, 0.0).label() == "phase 1/7: desingularization"


@pytest.mark.parametrize("d,n,m,seed", [(2, 3, 2, 0), (3, 2, 3, 1), (4, 2, 4, 2), (5, 1, 2, 3)])
def test_phase_names_describe_the_motion(d, n, m, seed):
    """Each named phase moves the robots the way its name says (Mathematics §3, paper (3.8))."""
    p = _plan(seed, d, n, m, cps=(2, 2))  # degenerate: the desingularization really moves
    o = p.obstacles
    fr = Frame(o[None, 0], o[None, 1])
    wp = p.path.waypoints[:, m:]  # robots (8, n, d)
    s = fr.columns(wp.reshape(1, -1, d)).reshape(8, n)
    r = fr.perpendicular(wp.reshape(1, -1, d)).reshape(8, n, d)
    by_name = {phase_at(p, (p.path.times[k] + p.path.times[k + 1]) / 2).name: k for k in range(7)}
    k = by_name["desingularization"]  # moves along e only: perpendicular parts unchanged
    np.testing.assert_allclose(r[k + 1], r[k], atol=1e-12)
    assert np.any(s[k + 1] != s[k])
    k = by_name["projection to the line"]  # ends on L_C: perpendicular parts vanish
    np.testing.assert_allclose(r[k + 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(s[k + 1], s[k], atol=1e-12)
    for name in ("lift", "descend"):  # vertical moves along nu(e): columns unchanged
        k = by_name[name]
        np.testing.assert_allclose(s[k + 1], s[k], atol=1e-12)
        dr = r[k + 1] - r[k]
        np.testing.assert_allclose(np.abs(dr @ fr.nu[0]), np.linalg.norm(dr, axis=-1), atol=1e-12)
    k = by_name["slide"]  # parallel to L_C: perpendicular parts unchanged (robot i at i*lambda)
    np.testing.assert_allclose(r[k + 1], r[k], atol=1e-12)
    k = by_name["projection reversed"]  # leaves L_C
    np.testing.assert_allclose(r[k], 0.0, atol=1e-12)


def test_phase_of_sequential_plan_names_the_leg():
    p = pmplan.plan_sequence([[0, 0], [2, 0]], [[[0, 1]], [[1, -1]], [[3, 3]], [[0, -2]]])
    legs = 3
    assert p.path.times.shape == (7 * legs + 1,)
    for leg in range(legs):
        mid = (leg + 0.5) / legs  # the middle of a leg is in its slide
        ph = phase_at(p, mid)
        assert (ph.leg, ph.legs, ph.name) == (leg + 1, legs, "slide")
        assert ph.label().startswith(f"leg {leg + 1}/{legs} - ")


def test_phase_of_planar_three_plan_is_its_polyline_leg():
    p3 = pytest.importorskip("pmplan.planners.planar_three")
    for o, s, g in planar_three_examples():
        p = pmplan.plan(o, s, g)
        assert p.planner == "planar_three"
        pieces = p.path.times.shape[0] - 1
        for k in range(pieces):
            t = (p.path.times[k] + p.path.times[k + 1]) / 2
            assert phase_at(p, t).label() == f"polyline leg {k + 1} of {pieces}"


def test_phase_at_rejects_times_outside_the_interval():
    p = _plan(0, 2, 1, 2)
    with pytest.raises(InputError, match=r"\[0, 1\]"):
        phase_at(p, 1.5)


# --------------------------------------------------------------------------------------------
# frame coordinates for d > 2


@pytest.mark.parametrize("d", [3, 4, 6])
def test_frame_coordinates_are_the_planners_frame(d):
    p = _plan(10 + d, d, 2, 3)
    pts = p.path(np.linspace(0, 1, 9))  # (9, P, d)
    xy, rest = frame_coordinates(p, pts)
    assert xy.shape == pts.shape[:-1] + (2,) and rest.shape == pts.shape[:-1]
    o1, o2 = p.obstacles[0], p.obstacles[1]
    e = (o2 - o1) / np.linalg.norm(o2 - o1)
    rel = pts - o1
    np.testing.assert_allclose(xy[..., 0], rel @ e, atol=1e-12)  # s = (y - o1).e
    # Pythagoras: s^2 + h^2 + |rest|^2 = |y - o1|^2, and h is along a unit normal of e
    np.testing.assert_allclose((xy**2).sum(-1) + rest**2, (rel**2).sum(-1), atol=1e-9)
    np.testing.assert_allclose(xy[:, 1, :], [[np.linalg.norm(o2 - o1), 0.0]] * 9, atol=1e-12)
    # during the slide robot i is at height i*lambda along nu(e), and its rest is 0
    mid = p.path((p.path.times[3] + p.path.times[4]) / 2)
    mxy, mrest = frame_coordinates(p, mid)
    heights = mxy[3:, 1]
    np.testing.assert_allclose(heights / heights[0], [1.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(mrest[3:], 0.0, atol=1e-9)


def test_frame_coordinates_in_the_plane_are_the_points():
    p = _plan(5, 2, 2, 2)
    pts = p.path(0.3)
    xy, rest = frame_coordinates(p, pts)
    assert rest is None and np.array_equal(xy, pts)


# --------------------------------------------------------------------------------------------
# draw_frame


@pytest.mark.parametrize("d,n,m", [(2, 1, 2), (2, 3, 2), (2, 2, 4), (3, 2, 3), (4, 3, 2)])
@pytest.mark.parametrize("trails", [True, False])
def test_draw_frame_artists(d, n, m, trails):
    p = _plan(d + n + m, d, n, m)
    ax = draw_frame(p, 0.5, trails=trails)
    assert len(ax.collections) == 3  # obstacles, goals, robots
    assert len(ax.lines) == n + 1 + (n if trails else 0) + 1  # paths, timeline, trails, bar
    assert len(ax.texts) == m + 1 + (1 if d > 2 else 0)
    obstacles, goals, robots = ax.collections
    assert obstacles.get_offsets().shape == (m, 2)
    assert robots.get_offsets().shape == (n, 2)
    # the robots are drawn where the path says, in the drawing coordinates
    xy, _ = frame_coordinates(p, p.path(0.5))
    np.testing.assert_allclose(np.asarray(robots.get_offsets()), xy[m:])
    goal_xy = frame_coordinates(p, p.path(1.0))[0][m:]
    np.testing.assert_allclose(np.asarray(goals.get_offsets()), goal_xy)
    assert ax.texts[m].get_text() == phase_at(p, 0.5).label() == "phase 4/7: slide"
    title = ax.get_title()
    assert f"$W_{{{p.domain}}}$: ${p.stratum}$" in title  # mathtext, not raw TeX
    if d > 2:
        assert "planner's frame" in ax.texts[-1].get_text()
        assert "marker size" in ax.texts[-1].get_text()


def test_draw_frame_trails_end_at_the_robots():
    p = _plan(3, 2, 2, 2)
    for t in (0.0, 0.37, 1.0):
        ax = draw_frame(p, t)
        trails = ax.lines[3:5]
        for j, line in enumerate(trails):
            x, y = line.get_data()
            np.testing.assert_allclose([x[-1], y[-1]], p.path(t)[2 + j])
            np.testing.assert_allclose([x[0], y[0]], p.path(0.0)[2 + j])
        plt.close("all")


def test_draw_frame_uses_given_axes():
    _, ax = plt.subplots()
    out = draw_frame(_plan(1, 2, 1, 2), 0.2, ax=ax)
    assert out is ax


# --------------------------------------------------------------------------------------------
# frames, animations, files


def test_render_frames_change_during_the_motion():
    p = _plan(4, 2, 2, 2)
    frames = list(render_frames(p, frames=4))
    assert len(frames) == 4
    assert all(f.shape == frames[0].shape and f.dtype == np.uint8 for f in frames)
    assert all(np.any(a != b) for a, b in zip(frames[:-1], frames[1:]))


def test_animate_plan_is_a_funcanimation():
    from matplotlib.animation import FuncAnimation

    anim = animate_plan(_plan(2, 2, 1, 2), frames=3)
    assert isinstance(anim, FuncAnimation)
    anim._draw_was_started = True  # not rendered here: silence the "deleted without rendering"


def _query(tmp_path, **extra):
    q = {"obstacles": [[0, 0], [4, 0]], "start": [[0, 1], [2, -1]], "goal": [[3, -1], [4, 2]]}
    q.update(extra)
    path = tmp_path / "q.json"
    path.write_text(json.dumps(q))
    return path


def test_animate_query_writes_a_gif(tmp_path):
    from PIL import Image

    from pmplan.io import read_query

    out = animate_query(read_query(_query(tmp_path)), tmp_path / "m.gif", frames=5, fps=10)
    assert out == tmp_path / "m.gif" and out.stat().st_size > 0
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == 5


def test_animate_query_sequential(tmp_path):
    from PIL import Image

    from pmplan.io import read_query

    q = read_query(_query(tmp_path, via=[[[1, 2], [3, 2]]]))
    out = animate_query(q, tmp_path / "s.gif", frames=3)
    with Image.open(out) as im:
        assert im.n_frames == 3


def test_animate_query_rejects_other_suffixes(tmp_path):
    from pmplan.io import read_query

    q = read_query(_query(tmp_path))
    with pytest.raises(InputError, match=r"\.gif or \.mp4"):
        animate_query(q, tmp_path / "m.png", frames=3)
    with pytest.raises(InputError, match="`frames` must be an integer from 2 to 1,000"):
        animate_query(q, tmp_path / "m.gif", frames=1)


def test_animate_query_mp4_without_ffmpeg(tmp_path, monkeypatch):
    import matplotlib.animation as manim

    from pmplan.io import read_query

    monkeypatch.setattr(manim.writers, "is_available", lambda name: False)
    with pytest.raises(UnsupportedError, match="ffmpeg"):
        animate_query(read_query(_query(tmp_path)), tmp_path / "m.mp4", frames=3)


def test_cli_animate(tmp_path, capsys):
    out = tmp_path / "cli.gif"
    assert main(["animate", str(_query(tmp_path)), "--out", str(out), "--frames", "3"]) == 0
    assert out.stat().st_size > 0
    assert "wrote" in capsys.readouterr().out
    assert main(["animate", str(_query(tmp_path)), "--out", str(tmp_path / "x.txt")]) == 2
    assert ".gif or .mp4" in capsys.readouterr().err
