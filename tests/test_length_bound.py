"""The lower bound on length of ``benchmarks/length_bound.py`` (Mathematics §8, "How long"):
its hull perimeters, the obstacles the mirror move carries through a robot's segment, the
bound of a hand-made query whose value is known in closed form, and the bound holding for
pmplan's own plans in the box (a planner continuous on these domains) on the scene queries."""

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import length_bound as lb
import scenes

import pmplan

#: a box so large that its map is the identity on every point used here (the plane)
FAR = np.array([[-1e4, -1e4], [1e4, 1e4]])


def test_hull_perimeter_of_known_sets():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.2, 0.9]], float)
    assert lb.hull_perimeter(square) == pytest.approx(4.0, abs=1e-15)
    assert lb.hull_perimeter(np.array([[0, 0], [3, 4]], float)) == pytest.approx(10.0)
    assert lb.hull_perimeter(np.array([[0, 0], [1, 1], [3, 3]], float)) == \
        pytest.approx(6 * np.sqrt(2))
    assert lb.hull_perimeter(np.array([[2.0, 2.0]])) == 0.0


coords = st.floats(-100, 100, allow_nan=False)


@settings(max_examples=100, deadline=None)
@given(pts=st.lists(st.tuples(coords, coords), min_size=2, max_size=8),
       extra=st.tuples(coords, coords), angle=st.floats(0, 6.3))
def test_hull_perimeter_grows_with_the_set_and_ignores_rigid_motions(pts, extra, angle):
    p = np.array(pts)
    q = np.vstack([p, extra])
    assert lb.hull_perimeter(q) >= lb.hull_perimeter(p) - 1e-9 * (1 + np.abs(q).max())
    c, s = np.cos(angle), np.sin(angle)
    rot = p @ np.array([[c, -s], [s, c]]).T + np.array([3.0, -7.0])
    assert lb.hull_perimeter(rot) == pytest.approx(lb.hull_perimeter(p), rel=1e-9, abs=1e-9)


def test_in_the_plane_the_move_carries_exactly_the_obstacles_between_the_columns():
    """With the identity map, the obstacles with an odd number of crossings are those whose
    column lies strictly between the start's and the goal's (each crossed once, at t = 1/2)."""
    checked = 0
    for fam, n in (("room", 2), ("swap", 4), ("room", 8)):
        for o, s, g in scenes.queries(fam, n, 10, 3):
            move = lb.mirror_move(o, s, g, box=FAR)
            odd = lb.crossing_parity(move, len(o), n)
            for i in range(n):
                assert odd[i].tolist() == lb.in_strip(o, s[i], g[i]).tolist()
                checked += int(odd[i].sum())
    assert checked > 20


def test_the_mirror_move_ends_at_the_mirror_image():
    o = np.array([[0.0, 0.0], [1.0, 1.0], [3.0, -1.0]])
    s, g = np.array([[2.0, 0.0]]), np.array([[0.0, 4.0]])
    end = lb.mirror_move(o, s, g, box=FAR)[-1]
    # the mirror in the diagonal y = x swaps the coordinates
    assert np.allclose(end, np.concatenate([o, s, g])[:, ::-1], atol=1e-12)


def test_the_bound_of_one_robot_past_one_obstacle():
    """One robot from (0, 0) to (4, 0); o_1 = (-5, -3) and o_2 = (9, -3) put the line at y = -3
    and the columns at x, so o_3 = (2, 1) is the one obstacle between the robot's columns. The
    mirror image has the robot from (0, -6) to (4, -6) and o_3 at (2, -7), again 1 from the
    segment: whichever of q, q* goes round o_3 is at least 2 sqrt(5) long, the other at least
    4, so the pair's mean len/LB is at least (2 sqrt(5) / 4 + 1) / 2."""
    o = np.array([[-5.0, -3.0], [9.0, -3.0], [2.0, 1.0]])
    s, g = np.array([[0.0, 0.0]]), np.array([[4.0, 0.0]])
    move = lb.mirror_move(o, s, g, box=FAR)
    odd = lb.crossing_parity(move, 3, 1)
    # o_1 and o_2 lie outside the robot's columns, o_3 between them
    assert odd.tolist() == [[False, False, True]]
    end = move[-1]
    q_star = (end[:3], end[3:4], end[4:5])
    assert np.allclose(q_star[0][2], [2.0, -7.0]) and np.allclose(q_star[1], [[0.0, -6.0]])
    # round o_3 at q: 2 sqrt(5); at q*: o_3 is 1 below the segment there too (mirror image)
    expect = (2 * np.sqrt(5) / 4 + 4 / 4) / 2
    assert lb.pair_bound((o, s, g), q_star, odd) == pytest.approx(expect, rel=1e-12)
    # nothing to go round: the straight lines
    assert lb.pair_bound((o, s, g), q_star, np.zeros((1, 3), bool)) == pytest.approx(1.0)


@pytest.mark.parametrize("fam, n", [("room", 2), ("swap", 4), ("room_walls", 8)])
def test_pmplan_in_the_plane_keeps_the_bound(fam, n):
    """pmplan's default plan without a box is continuous on these domains: on every query and
    its mirror image its mean len/LB, refined, is at least the bound (which a wrong count of
    crossings or a wrong perimeter would break), and the bound exceeds the straight lines on
    most queries. (In the box the returned polylines follow chords, Mathematics §8, and may
    pass below it: test_workspace.py.)"""
    above = 0
    for o, s, g in scenes.queries(fam, n, 12, 5):
        q, q_star, bound = lb.mirror_pair(o, s, g, lb.PLANE)
        lens = []
        for oo, ss, gg in (q, q_star):
            p = pmplan.plan(oo, ss, gg, refine=True, radius=scenes.R / 2,
                            obstacle_radius=scenes.R / 2)
            lens.append(p.path.length() / np.linalg.norm(gg - ss, axis=1).sum())
        assert (lens[0] + lens[1]) / 2 >= bound - 1e-9
        above += bound > 1.0 + 1e-9
    assert above >= 8
