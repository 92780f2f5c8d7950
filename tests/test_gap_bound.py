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
