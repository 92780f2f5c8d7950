"""A side per robot in a workspace box (pmplan.sides.robot_sides, the planner
obstacle_line_robots, Mathematics §8, "A side per robot"): exact decisions at every magnitude,
each robot's side, the walls and their labels, the guard, continuity, the defaults."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan import sides
from pmplan import workspace as W
from pmplan.planners import REGISTRY, default_planner

BOX = np.array([[0.0, 0.0], [10.0, 10.0]])
ROBOTS = "obstacle_line_robots"


def _z(o, configs, box=BOX):
    return W.from_box_linear(o, box), [W.from_box_linear(c, box) for c in configs]


def _exact(o, configs, box=BOX, lift=1.0):
    """:func:`pmplan.sides.robot_sides` of one query (unbatched) from the rational decisions
    alone: (down, walls)."""
    zo, zc = _z(o[None], [c[None] for c in configs], box)
    f = sides._f_exact(o, configs, box, lift)
    g = sides._robot_guard_exact(zo[0], [c[0] for c in zc])
    down = [a < 0 and b > 0 for a, b in zip(f, g)]
    wall = [not d and ((a == 0 and b >= 0) or (b == 0 and a <= 0))
            for d, a, b in zip(down, f, g)]
    return down, sum(wall)


def _decide(o, configs, box=BOX, lift=1.0):
    """:func:`pmplan.sides.robot_sides` of one query (unbatched; the unit of a raw plan by
    default): (down, walls)."""
    zo, zc = _z(o[None], [c[None] for c in configs], box)
    down, walls = sides.robot_sides(o[None], [c[None] for c in configs], zo, zc, box, lift)
    return [bool(x) for x in down[0]], int(walls[0])


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 9), st.integers(1, 9)), min_size=9, max_size=9,
                unique=True), st.integers(-60, 60), st.sampled_from([0.0, 0.25, 1.0, 1.5]))
def test_the_float_decisions_are_the_exact_ones_at_every_magnitude(pts, k, lift):
    """Integer points (ties of heights and rooms, narrow rooms at the edge of the unit's gap,
    robots in obstacles' and each other's columns, obstacles at the columns' ends) scaled by
    2**k, with the unit scaled alike (0: the scene's): every robot's side and the count of
    walls are the rational decisions', and do not depend on the scale."""
    p = np.array(pts, dtype=float)
    o, s, g = p[:3], p[3:6], p[6:]
    want = _exact(o, [s, g], BOX, lift)
    assert _decide(o, [s, g], BOX, lift) == want
    c = 2.0 ** k
    assert _decide(o * c, [s * c, g * c], BOX * c, lift * c) == want


def test_random_batches_decide_as_the_exact_rule():
    rng = np.random.default_rng(5)
    o = rng.uniform(0.5, 9.5, (300, 6, 2))
    s, g = rng.uniform(0.5, 9.5, (300, 4, 2)), rng.uniform(0.5, 9.5, (300, 4, 2))
    zo, zc = _z(o, [s, g])
    down, walls = sides.robot_sides(o, [s, g], zo, zc, BOX)
    assert 0.2 < down.mean() < 0.8 and not walls.any()
    for q in range(0, 300, 7):
        assert ([bool(x) for x in down[q]], int(walls[q])) == _exact(o[q], [s[q], g[q]])
    # and with a unit whose gap (ROBOT_GAP units) makes some rooms narrow
    down, walls = sides.robot_sides(o, [s, g], zo, zc, BOX, 0.3)
    for q in range(0, 300, 7):
        assert ([bool(x) for x in down[q]], int(walls[q])) == _exact(o[q], [s[q], g[q]],
                                                                     lift=0.3)


def _middle():
    """Obstacles on the middle line of the box (the walls leave them as much room on each
    side, so ``f_i`` is robot i's heights alone), robot 1 above, robot 2 below."""
    o = np.array([[4.0, 5.0], [6.0, 5.0], [7.5, 5.0]])
    s, g = np.array([[2.5, 8.0], [3.0, 2.0]]), np.array([[8.5, 7.0], [7.0, 3.0]])
    return o, s, g


def test_each_robot_takes_the_side_of_its_own_positions():
    """Robot 1 slides above the obstacles' line, robot 2 below it (the one-side lanes put both
    above); the label is the stratum's; without a box the planner is the one-side planner."""
    o, s, g = _middle()
    assert _decide(o, [s, g]) == ([False, True], 0)
    mine = pmplan.plan(o, s, g, bounds=(0, 10), planner=ROBOTS)
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    assert mine.domain == one.domain
    m = o.shape[0]
    lanes = mine.waypoints[3:5, m:, 1]  # the slide (tau = 4/9, 5/9), heights in the box
    assert (lanes[:, 0] > 5.0).all() and (lanes[:, 1] < 5.0).all()
    assert (one.waypoints[3:5, m:, 1] > 5.0).all()
    free = [pmplan.plan_batch(o[None], s[None], g[None], planner=p)
            for p in (ROBOTS, "obstacle_line_oneside")]
    assert np.array_equal(free[0].waypoints, free[1].waypoints)
    assert np.array_equal(free[0].domain, free[1].domain)


def test_a_query_no_robot_of_which_goes_down_is_planned_as_the_one_side_lanes():
    """Every robot above the middle line: the side per robot plans the one-side plan, bit for
    bit, by the numba kernel and by the numpy reference alike."""
    o, s, g = _middle()
    s, g = s.copy(), g.copy()
    s[1, 1], g[1, 1] = 9.0, 6.0
    assert _decide(o, [s, g]) == ([False, False], 0)
    for backend in ("numba", "numpy"):
        mine = pmplan.plan(o, s, g, bounds=(0, 10), planner=ROBOTS, backend=backend)
        one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside",
                          backend=backend)
        assert np.array_equal(mine.waypoints, one.waypoints) and mine.domain == one.domain


def test_on_the_walls_of_k_robots_the_label_is_k_less():
    """Robots whose heights add up to 0 (the rooms equal): each lies on its wall, the label is
    the stratum's minus the number of robots on a wall; moved off a wall by 1e-9 either way,
    that robot's side changes (the plans differ by O(1)) and the label goes up by one."""
    o = np.array([[4.0, 5.0], [6.0, 5.0], [7.5, 5.0]])
    s, g = np.array([[2.5, 8.0], [3.0, 2.0]]), np.array([[8.5, 2.0], [7.0, 8.0]])
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    low = min(REGISTRY[ROBOTS].domain_labels(2, 2, 3))
    assert _decide(o, [s, g]) == ([False, False], 2)
    on = pmplan.plan(o, s, g, bounds=(0, 10), planner=ROBOTS)
    assert on.domain == one.domain - 2 >= low
    plans = []
    for dy, side in ((1e-9, False), (-1e-9, True)):
        moved = g.copy()
        moved[0, 1] += dy
        assert _decide(o, [s, moved]) == ([side, False], 1)
        p = pmplan.plan(o, s, moved, bounds=(0, 10), planner=ROBOTS)
        assert p.domain == one.domain - 1
        plans.append(p)
    assert np.abs(plans[0].waypoints - plans[1].waypoints).max() > 0.1


def test_the_guard_keeps_the_lowest_label():
    """Every robot in an obstacle's column (label 4, the lowest) and below the obstacles: the
    guards keep the side of nu(e) and the label 4 (no wall meets the lowest label: Mathematics
    §8); a robot in no other point's column in its start, on its wall, takes one label off;
    the other, in obstacles' columns, is never on a wall."""
    o = np.array([[2.0, 7.0], [4.0, 7.0]])
    s, g = np.array([[2.0, 3.0], [4.0, 2.0]]), np.array([[4.0, 2.5], [2.0, 1.0]])
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    mine = pmplan.plan(o, s, g, bounds=(0, 10), planner=ROBOTS)
    assert one.domain == mine.domain == 4 and _decide(o, [s, g]) == ([False, False], 0)
    assert np.array_equal(mine.waypoints, one.waypoints)
    # on the middle line (f_i = robot i's heights): robot 1 in columns of its own, its
    # heights +3 and -3, on its wall; robot 2 in obstacles' columns, heights +2 and -2
    o = np.array([[2.0, 5.0], [4.0, 5.0]])
    s, g = np.array([[3.0, 8.0], [2.0, 7.0]]), np.array([[3.5, 2.0], [4.0, 3.0]])
    assert sides._f_exact(o, [s, g], BOX, 1.0) == [0, 0]
    assert _decide(o, [s, g]) == ([False, False], 1)
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    mine = pmplan.plan(o, s, g, bounds=(0, 10), planner=ROBOTS)
    assert mine.domain == one.domain - 1 == 5


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 7), st.integers(1, 7)), min_size=9, max_size=9,
                unique=True))
def test_integer_queries_keep_the_labels_of_the_planner(pts):
    """Exactly degenerate queries in [0, 8]^2 (ties, robots in obstacles' and each other's
    columns, collinear points): every plan certified, inside the box, its label one of the
    planner's (never below the lowest) and the one-side planner's less the walls."""
    p = np.array(pts, dtype=float)
    o, s, g = p[:3], p[3:6], p[6:]
    box = np.array([[0.0, 0.0], [8.0, 8.0]])
    mine = pmplan.plan(o, s, g, bounds=(0, 8), planner=ROBOTS)
    one = pmplan.plan(o, s, g, bounds=(0, 8), planner="obstacle_line_oneside")
    assert mine.clearance > 0 and W.inside(mine.waypoints[None], box)[0]
    assert mine.domain in REGISTRY[ROBOTS].domain_labels(2, 3, 3)
    assert mine.domain == one.domain - _decide(o, [s, g], box)[1]


def test_sequences_through_a_via_take_a_side_per_robot():
    """A query through a via configuration in a box: certified, inside the box, its label one
    of the planner's for r = 3, the robots' sides from all three configurations."""
    rng = np.random.default_rng(8)
    for _ in range(10):
        o = rng.uniform(1, 9, (4, 2))
        cs = [rng.uniform(1, 9, (3, 2)) for _ in range(3)]
        p = pmplan.plan_sequence(o, cs, bounds=(0, 10), planner=ROBOTS)
        assert p.clearance > 0 and W.inside(p.waypoints[None], BOX)[0]
        assert p.domain in REGISTRY[ROBOTS].domain_labels(2, 3, 4, 3)


def test_the_backends_plan_alike():
    rng = np.random.default_rng(9)
    o = rng.uniform(0.5, 9.5, (40, 5, 2))
    s, g = rng.uniform(0.5, 9.5, (40, 3, 2)), rng.uniform(0.5, 9.5, (40, 3, 2))
    a, b = (pmplan.plan_batch(o, s, g, bounds=(0, 10), planner=ROBOTS, backend=be)
            for be in ("numba", "numpy"))
    assert np.array_equal(a.domain, b.domain)
    assert np.abs(a.waypoints - b.waypoints).max() <= 1e-12 * 10


def test_plans_are_continuous_off_the_walls():
    """Refined plans in a box moved by 1e-6, 1e-9 and 1e-12 (every point, a uniform direction):
    where the label stays, the sup change over the path is at most 1e3 delta."""
    rng = np.random.default_rng(10)
    t = np.linspace(0, 1, 401)
    for _ in range(6):
        o = rng.uniform(0.5, 9.5, (6, 2))
        s, g = rng.uniform(0.5, 9.5, (4, 2)), rng.uniform(0.5, 9.5, (4, 2))
        base = pmplan.plan(o, s, g, bounds=(0, 10), refine=True, radius=0.15,
                           obstacle_radius=0.15)
        assert base.planner == ROBOTS
        for delta in (1e-6, 1e-9, 1e-12):
            mv = [x + delta * rng.uniform(-1, 1, x.shape) for x in (o, s, g)]
            p = pmplan.plan(*mv, bounds=(0, 10), refine=True, radius=0.15, obstacle_radius=0.15)
            if p.domain == base.domain:
                assert np.abs(p.path(t) - base.path(t)).max() <= 1e3 * delta


def test_defaults_take_a_side_per_robot_for_two_to_four_robots_in_a_box():
    for n in (2, 3, 4):
        assert default_planner(2, n, 6, refining=True, bounded=True) == ROBOTS
        assert default_planner(2, n, 6, refining=True) == "obstacle_line_compact"
        assert default_planner(3, n, 4, refining=True, bounded=True) == "obstacle_line_compact"
    assert default_planner(2, 5, 6, refining=True, bounded=True) == "obstacle_line_walls"
    assert default_planner(2, 1, 6, refining=True, bounded=True) == "obstacle_line_compact"
    rng = np.random.default_rng(1)
    o, s, g = rng.uniform(1, 9, (6, 2)), rng.uniform(1, 9, (3, 2)), rng.uniform(1, 9, (3, 2))
    assert pmplan.plan(o, s, g, bounds=(0, 10), refine=True, radius=0.05).planner == ROBOTS
