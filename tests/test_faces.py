"""The faces are tested for what they produce: pictures (size, content, legend, layout), an .mp4
(frames counted by ffprobe), the Section 4 figures through the command line."""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from PIL import Image  # noqa: E402

import pmplan  # noqa: E402
from pmplan.cli import main  # noqa: E402
from pmplan.plotting import legend_handles, plan_grid, plan_title, robot_colors  # noqa: E402

TAB_BLUE = np.array([31, 119, 180])  # the path colour of the Section 4 figures


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _rgb(path) -> np.ndarray:
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def _near(rgb: np.ndarray, color, tol: int = 40) -> int:
    """Number of pixels within ``tol`` (max channel difference) of ``color``."""
    return int((np.abs(rgb - np.asarray(color)[:3]).max(-1) <= tol).sum())


def _ink(rgb: np.ndarray) -> float:
    """Fraction of pixels that are not (nearly) white."""
    return float((rgb.min(-1) < 235).mean())


# --------------------------------------------------------------------------------------------
# pmplan figures: 13 pictures of the right size, each with the path drawn in it


def test_cli_figures_writes_13_pictures_with_content(tmp_path, capsys):
    from pmplan.planners.planar_three import STRATA

    out_dir = tmp_path / "figs"
    assert main(["figures", "--out", str(out_dir)]) == 0
    printed = capsys.readouterr().out.split()
    expected = [out_dir / f"{name}.png" for name in STRATA] + [out_dir / "overview.png"]
    assert printed == [str(p.resolve()) for p in expected]  # the paths written, in order
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(p.name for p in expected)
    for p in expected:
        rgb = _rgb(p)
        # 5.2 x 4.2 in at 100 dpi per stratum; the 25 x 17 in overview at 80 dpi
        assert rgb.shape[:2] == ((1360, 2000) if p.name == "overview.png" else (420, 520)), p
        assert 0.02 < _ink(rgb) < 0.6, p  # drawn on, and not a solid block
        assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 20, p
        assert _near(rgb, TAB_BLUE) > (400 if p.name == "overview.png" else 40), p  # the path


def test_cli_figures_into_a_file_is_one_line_error(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    assert main(["figures", "--out", str(blocker)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and "error:" in err


# --------------------------------------------------------------------------------------------
# the demo picture: legend, mathematical titles, no overlaps, time along the motions


@pytest.fixture(scope="module")
def demo_plans():
    from pmplan.examples import obstacle_line_examples
    from pmplan.examples import planar_three_examples as demo_examples

    plans = [pmplan.plan(*q) for q in obstacle_line_examples(3)]
    return plans + [pmplan.plan(*q) for q in demo_examples()]


def _extent(artist, renderer):
    return artist.get_window_extent(renderer)


def test_demo_grid_has_legend_mathtext_titles_and_robot_colours(demo_plans):
    fig = plan_grid(demo_plans, ncols=4, suptitle="pmplan demo\nsecond line")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    # the legend names every marker, the time channel and the colour of every robot
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    assert [lab.split()[0] for lab in labels] == ["obstacle", "start", "goal", "time:", "robot",
                                                  "robot", "robot"]
    assert labels[4:] == ["robot 1", "robot 2", "robot 3"]
    # titles are mathtext (dollar signs around W_l and the stratum), rendered, not raw
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert len(panels) == len(demo_plans)
    for ax, p in zip(panels, demo_plans):
        assert ax.get_title() == plan_title(p) == f"{p.planner}  $W_{{{p.domain}}}$: ${p.stratum}$"
    # time is not a colour any more: no colourbar
    assert not [ax for ax in fig.axes if "time" in ax.get_ylabel()]
    # nothing overlaps: the suptitle, every panel title, the legend
    boxes = [("suptitle", _extent(fig._suptitle, renderer)), ("legend", _extent(legend, renderer))]
    boxes += [(ax.get_title(), _extent(ax.title, renderer)) for ax in panels]
    boxes += [(f"panel {k}", ax.get_window_extent(renderer)) for k, ax in enumerate(panels)]
    for i, (na, a) in enumerate(boxes):
        for nb, b in boxes[i + 1:]:
            if na.startswith("panel") and nb.startswith("panel"):
                continue
            if (na, nb) in {(t, f"panel {k}") for k, t in enumerate(p_.get_title() for p_ in panels)}:
                continue
            assert not a.overlaps(b), f"{na!r} overlaps {nb!r}"
    _assert_labels_apart_and_inside(fig, demo_plans)
    # every box lies inside the figure
    fig_box = fig.bbox
    for name, box in boxes:
        assert box.x0 >= fig_box.x0 - 1 and box.x1 <= fig_box.x1 + 1, name
        assert box.y0 >= fig_box.y0 - 1 and box.y1 <= fig_box.y1 + 1, name


def _assert_labels_apart_and_inside(fig, plans):
    """The labels of obstacles, starts and goals neither overlap each other nor leave their
    panel (one label per obstacle, start and goal)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax, p in zip(fig.axes, plans):
        texts = [t for t in ax.texts if t.get_text()]
        assert len(texts) == 2 * p.dims[1] + p.dims[2]
        inner = ax.get_window_extent(renderer)
        tb = [t.get_window_extent(renderer) for t in texts]
        for i, a in enumerate(tb):
            assert inner.x0 <= a.x0 and a.x1 <= inner.x1 and inner.y0 <= a.y0 and a.y1 <= inner.y1, \
                (ax.get_title(), texts[i].get_text())
            for k in range(i + 1, len(tb)):
                assert not a.overlaps(tb[k]), (ax.get_title(), texts[i].get_text(),
                                               texts[k].get_text())


@pytest.mark.parametrize("n", [1, 2, 5, 6])
def test_demo_labels_do_not_collide(n):
    from pmplan.examples import obstacle_line_examples

    plans = [pmplan.plan(*q) for q in obstacle_line_examples(n)]
    _assert_labels_apart_and_inside(plan_grid(plans, ncols=4), plans)


def test_each_robot_has_its_colour_and_time_is_width_and_opacity(demo_plans):
    """Robot j's line is one LineCollection in robot j's colour (its start circle and goal star
    too); along it width and opacity grow with time from t = 0 to t = 1; a dot marks it at
    t = 1/4, 1/2, 3/4."""
    from matplotlib.collections import LineCollection
    from matplotlib.colors import to_rgb

    from pmplan.plotting import TIME_TICKS, time_style

    p = demo_plans[0]
    fig = plan_grid([p], ncols=1)
    ax = fig.axes[0]
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    n = p.dims[1]
    assert len(lines) == n
    colors = robot_colors(n)
    assert len({tuple(np.round(c, 3)) for c in colors}) == n
    for j, lc in enumerate(lines):
        rgba = lc.get_colors()
        np.testing.assert_allclose(rgba[:, :3], np.tile(to_rgb(colors[j]), (len(rgba), 1)))
        alpha, width = rgba[:, 3], np.asarray(lc.get_linewidths())
        assert alpha[0] < 0.35 and alpha[-1] > 0.95 and np.all(np.diff(alpha) > 0)
        assert width[0] < 1.0 and width[-1] > 3.0 and np.all(np.diff(width) > 0)
        segs = lc.get_segments()
        # the line starts at the robot's start and ends at its goal
        np.testing.assert_array_equal(segs[0][0], p.start[j])
        np.testing.assert_array_equal(segs[-1][-1], p.goal[j])
        # start circle, goal star and the time dots are in the robot's colour
        mine = [ln for ln in ax.lines if np.allclose(to_rgb(ln.get_color()), to_rgb(colors[j]))]
        markers = sorted(ln.get_marker() for ln in mine)
        assert markers == ["*", "o", "o"], markers
        dots = next(ln for ln in mine if len(ln.get_xdata()) == len(TIME_TICKS))
        np.testing.assert_allclose(np.c_[dots.get_xdata(), dots.get_ydata()],
                                   p.path(np.array(TIME_TICKS))[:, p.dims[2] + j])
    np.testing.assert_allclose(time_style([0, 0.5, 1])[0], [0.8, 2.1, 3.4])
    assert len(legend_handles()) == 4 and len(legend_handles(3)) == 7


def test_raw_and_refined_panels_share_their_axes(demo_plans):
    """plan_grid(..., same_axes=2): the two panels of one query show the same ranges."""
    pairs = [q for p in demo_plans for q in (p, pmplan.refine(p))]
    fig = plan_grid(pairs, ncols=4, same_axes=2)
    fig.canvas.draw()
    panels = [ax for ax in fig.axes if ax.get_title()]
    for left, right in zip(panels[::2], panels[1::2]):
        assert left.get_xlim() == right.get_xlim() and left.get_ylim() == right.get_ylim()
    # without it each panel fits its own plan: a raw staircase is wider than its refined motion
    alone = [ax for ax in plan_grid(pairs[:2], ncols=2).axes if ax.get_title()]
    alone[0].figure.canvas.draw()
    assert alone[0].get_xlim() != alone[1].get_xlim() or alone[0].get_ylim() != alone[1].get_ylim()


def test_cli_demo_picture(tmp_path, capsys):
    """``pmplan demo`` writes the file it names; the colours of robots 1, 2 and 3 appear in it;
    no suffix means .png; an unknown suffix is one clear error."""
    assert main(["demo", "--out", str(tmp_path / "demo")]) == 0
    out = capsys.readouterr().out
    written = tmp_path / "demo.png"
    assert f"wrote {written.resolve()}" in out
    rgb = _rgb(written)
    assert rgb.shape[0] > 900 and rgb.shape[1] > 1200
    for color in robot_colors(3):
        assert _near(rgb, np.round(np.array(color[:3]) * 255), 25) > 100
    # the table's headings: raw and refined motion, each a length and a clearance
    head = [line for line in out.splitlines() if line.startswith("planner")]
    assert head and head[0].split() == ["planner", "domain", "stratum", "length", "clearance",
                                        "length", "clearance"]
    above = out.splitlines()[out.splitlines().index(head[0]) - 1].split()
    assert above == ["raw", "motion", "refined", "motion"]
    assert main(["demo", "--out", str(tmp_path / "demo.xyz")]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "use a file name ending in .png, .pdf, .svg" in err
    assert len(err.strip().splitlines()) == 1


# --------------------------------------------------------------------------------------------
# an .mp4 really written: ffprobe counts its frames


def _need_ffmpeg():
    if shutil.which("ffmpeg") and shutil.which("ffprobe"):
        return
    if os.environ.get("CI"):
        pytest.fail("ffmpeg/ffprobe not found although CI is set: .ci/run installs ffmpeg with "
                    "apt-get when it is missing; install it (apt-get install -y ffmpeg)")
    pytest.skip("ffmpeg not installed (outside CI only; CI installs it)")


def test_cli_animate_writes_a_real_mp4(tmp_path, capsys):
    _need_ffmpeg()
    q = tmp_path / "q.json"
    q.write_text(json.dumps({"obstacles": [[0, 0], [4, 0]], "start": [[0, 1], [2, -1]],
                             "goal": [[3, -1], [4, 2]]}))
    out = tmp_path / "m.mp4"
    assert main(["animate", str(q), "--out", str(out), "--frames", "24", "--fps", "12"]) == 0
    assert f"wrote {out.resolve()}" in capsys.readouterr().out
    head = out.read_bytes()[:12]
    assert head[4:8] == b"ftyp"  # an ISO media file
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
         "stream=codec_type,nb_read_frames,width,height,avg_frame_rate", "-of", "json", str(out)],
        capture_output=True, text=True, timeout=120, check=True)
    (stream,) = json.loads(probe.stdout)["streams"]
    assert stream["codec_type"] == "video"
    assert int(stream["nb_read_frames"]) == 24
    assert stream["avg_frame_rate"] == "12/1"
    assert int(stream["width"]) > 100 and int(stream["height"]) > 100
