"""The closed sides of ``benchmarks/gap_bound.py`` (Mathematics §8, "How often") on hand-made
cases whose answer is known: an obstacle 0.4 from the floor of a 10 x 10 box, its vertical line
sampled, and robots that must pass it."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import gap_bound
import scenes

BOX = np.array([[0.0, 0.0], [10.0, 10.0]])
#: the vertical line x = 5, sampled; the obstacle at index J, (5, 0.4)
P = np.stack([np.full(1001, 5.0), np.linspace(0.0, 10.0, 1001)], axis=1)
J = np.array([40])


def test_a_robot_above_the_obstacle_cannot_pass_below_it():
    # from (2, 2.005) to (8, 2.005) (off the grid points of the line): passing below means
    # crossing the 0.4 gap to the floor
    plus, minus = gap_bound.closed_sides(P, J, np.array([2.0, 2.005]), np.array([8.0, 2.005]),
                                         BOX)
    assert minus.tolist() == [True] and plus.tolist() == [False]


def test_an_obstacle_near_the_ceiling_closes_the_upper_side():
    plus, minus = gap_bound.closed_sides(P, np.array([960]), np.array([2.0, 2.005]),
                                         np.array([8.0, 2.005]), BOX)
    assert plus.tolist() == [True] and minus.tolist() == [False]


def test_a_robot_in_the_gap_itself_is_still_blocked_below():
    # from (2, 0.205) to (8, 0.205): its straight path crosses sigma, and any path below the
    # obstacle does
    plus, minus = gap_bound.closed_sides(P, J, np.array([2.0, 0.205]), np.array([8.0, 0.205]),
                                         BOX)
    assert minus.tolist() == [True] and plus.tolist() == [False]


@pytest.mark.parametrize("height", [0.46, 1.0, 5.0])
def test_no_side_is_closed_when_the_gap_is_wide_enough(height):
    j = np.array([round(height * 100)])
    plus, minus = gap_bound.closed_sides(P, j, np.array([2.0, 2.005]), np.array([8.0, 2.005]),
                                         BOX)
    assert not plus.any() and not minus.any()


def test_the_bound_is_zero_when_obstacles_keep_away_from_the_walls():
    o, s, g = scenes.queries("room_walls", 4, 1, 3)[0]
    assert gap_bound.query_bound(o, s, g, BOX, scenes.WALL_GAP)["all"] == 0.0


def test_the_committed_report_is_its_json_rewritten(tmp_path):
    """``benchmarks/gap_bound.md`` is what ``--from-json`` writes from ``gap_bound.json``, byte
    for byte: every number in it comes from the run, and the rows kept from an earlier run name
    the command that wrote them."""
    here = Path(gap_bound.__file__).parent
    for ext in (".json", ".md"):
        (tmp_path / ("g" + ext)).write_bytes((here / ("gap_bound" + ext)).read_bytes())
    before = (tmp_path / "g.md").read_text()
    assert gap_bound.main(["--from-json", "--out", str(tmp_path / "g")]) == 0
    assert (tmp_path / "g.md").read_text() == before
    assert "(held out)" in before and "written by `python benchmarks/gap_bound.py" in before


def test_kept_rows_carry_their_file_and_command(tmp_path):
    """``--keep`` reads a bare list of rows (the runs before the JSON kept its command) and a
    run's ``{"argv", "rows"}``; a row kept twice keeps its first origin."""
    import json

    row = {"seed": 11, "family": "room", "n": 2}
    bare, full = tmp_path / "bare.json", tmp_path / "full.json"
    bare.write_text(json.dumps([row]))
    full.write_text(json.dumps({"argv": ["--seeds", "11"],
                                "rows": [row, dict(row, n=4, kept="old.json")]}))
    assert gap_bound._kept_rows(bare) == [dict(row, kept=str(bare), kept_argv=None)]
    got = gap_bound._kept_rows(full)
    assert got[0] == dict(row, kept=str(full), kept_argv=["--seeds", "11"])
    assert got[1] == dict(row, n=4, kept="old.json")
