"""The side of the lanes in a workspace box (pmplan.sides, Mathematics §8, "The side of the
lanes"): exact decisions, the mirror, the wall of sides and its labels, the guard, continuity."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan import sides
from pmplan import workspace as W
from pmplan.planners import REGISTRY, default_planner

BOX = np.array([[0.0, 0.0], [10.0, 10.0]])


def _exact_flags(o, zo, zc, box):
    """:func:`pmplan.sides.wall_sides` of one query from the rational decisions alone."""
    g = sides._g_exact(o, box)
    guard = sides._guard_exact(zo, zc)
    flip = g < 0 and guard > 0
    return flip, g <= 0 and guard >= 0 and not flip


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 9), st.integers(1, 9)), min_size=7, max_size=7,
                unique=True), st.integers(-60, 60))
def test_the_float_decisions_are_the_exact_ones_at_every_magnitude(pts, k):
    """Integer points (exact ties of the rooms on both sides, robots in obstacles' columns)
    scaled by 2**k: the batch's flip and wall flags are the rational decisions', and do not
    depend on the scale."""
    p = np.array(pts, dtype=float) * 2.0 ** k
    box = BOX * 2.0 ** k
    o, s, g = p[None, :3], p[None, 3:5], p[None, 5:]
    zo, zc = W.from_box_linear(o, box), [W.from_box_linear(c, box) for c in (s, g)]
    flip, wall = sides.wall_sides(o, zo, zc, box)
    want = _exact_flags(o[0], zo[0], [c[0] for c in zc], box)
    assert (bool(flip[0]), bool(wall[0])) == want
    unit = p / 2.0 ** k
    o1, s1, g1 = unit[None, :3], unit[None, 3:5], unit[None, 5:]
    z1 = W.from_box_linear(o1, BOX), [W.from_box_linear(c, BOX) for c in (s1, g1)]
    assert tuple(bool(x[0]) for x in sides.wall_sides(o1, *z1, BOX)) == want


def test_random_batches_decide_as_the_exact_rule():
    rng = np.random.default_rng(3)
    o = rng.uniform(0.5, 9.5, (300, 6, 2))
    s, g = rng.uniform(0.5, 9.5, (300, 4, 2)), rng.uniform(0.5, 9.5, (300, 4, 2))
    zo, zc = W.from_box_linear(o, BOX), [W.from_box_linear(c, BOX) for c in (s, g)]
    flip, wall = sides.wall_sides(o, zo, zc, BOX)
    assert 60 < flip.sum() < 240 and not wall.any()
    for i in range(0, 300, 7):
        assert (flip[i], wall[i]) == _exact_flags(o[i], zo[i], [c[i] for c in zc], BOX)


def test_the_side_with_the_most_room():
    """Obstacles on a line across the middle: as much room on each side (the wall of sides);
    moved toward the top wall, more room below, the side of -nu(e) = (0, -1)."""
    s, g = np.array([[[1.0, 1.0]]]), np.array([[[9.0, 9.0]]])
    for y, flip, wall in ((5.0, False, True), (7.0, True, False), (3.0, False, False)):
        o = np.array([[[4.0, y], [6.0, y], [5.0, 5.0]]])
        got = sides.wall_sides(o, W.from_box_linear(o, BOX),
                               [W.from_box_linear(c, BOX) for c in (s, g)], BOX)
        assert (bool(got[0][0]), bool(got[1][0])) == (flip, wall)


def test_the_mirror_is_exact_and_its_own_inverse():
    x = np.random.default_rng(0).normal(size=(5, 3, 4, 2))
    rows = np.array([True, False, True, False, False])
    y = sides.mirror(x, rows)
    assert np.array_equal(y[~rows], x[~rows]) and np.array_equal(y[rows, ..., 0], -x[rows, ..., 0])
    assert np.array_equal(sides.mirror(y, rows), x)


def test_defaults_take_the_wall_side_in_a_box_in_the_plane():
    """From 5 robots on (2 to 4 take a side per robot: tests/test_robot_sides.py)."""
    assert default_planner(2, 1, 6, refining=True, bounded=True) == "obstacle_line_compact"
    for n in (5, 8, 16):
        assert default_planner(2, n, 6, refining=True, bounded=True) == "obstacle_line_walls"
    assert default_planner(2, 8, 6, refining=True) == "obstacle_line_oneside"
    assert default_planner(2, 4, 6, refining=True) == "obstacle_line_compact"
    assert default_planner(2, 4, 6, bounded=True) == "obstacle_line_compact"
    assert default_planner(3, 8, 4, refining=True, bounded=True) == "obstacle_line_compact"
    rng = np.random.default_rng(1)
    o, s, g = rng.uniform(1, 9, (6, 2)), rng.uniform(1, 9, (5, 2)), rng.uniform(1, 9, (5, 2))
    assert pmplan.plan(o, s, g, bounds=(0, 10), refine=True, radius=0.05).planner == \
        "obstacle_line_walls"


def _queries(rng, b, n, m):
    o = rng.uniform(0.3, 9.7, (b, m, 2))
    s, g = rng.uniform(0.3, 9.7, (b, n, 2)), rng.uniform(0.3, 9.7, (b, n, 2))
    return o, s, g


def test_in_a_box_the_plan_is_the_one_side_plan_on_the_side_chosen():
    """A query the rule keeps on the side of nu(e) gets the one-side planner's plan in the box,
    bit for bit; a flipped one gets the mirror image of the one-side plan of the mirrored query
    (the planner with -nu(e)) mapped into the box, with the same label; without a box the
    planner is the one-side planner."""
    rng = np.random.default_rng(4)
    o, s, g = _queries(rng, 60, 4, 6)
    walls = pmplan.plan_batch(o, s, g, bounds=(0, 10), planner="obstacle_line_walls")
    one = pmplan.plan_batch(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    zo, zc = W.from_box_linear(o, BOX), [W.from_box_linear(c, BOX) for c in (s, g)]
    flip, wall = sides.wall_sides(o, zo, zc, BOX)
    assert 10 < flip.sum() < 50 and not wall.any()
    assert np.array_equal(walls.domain, one.domain)
    plane = pmplan.plan_batch(*(sides.mirror(x, flip) for x in (zo, *zc)),
                              planner="obstacle_line_oneside")
    t = np.linspace(0, 1, 101)
    for q in range(60):
        got, other = walls[q].path(t), one[q].path(t)
        if not flip[q]:
            assert np.abs(got - other).max() <= 1e-12 * 10
            continue
        want = W.into_box_linear(sides.mirror(plane[q].path(t)[None], np.array([True]))[0],
                                 BOX)
        assert np.abs(got - want).max() <= 1e-12 * 10
        assert np.abs(got - other).max() > 0.1
    free = (pmplan.plan_batch(o, s, g, planner=p) for p in ("obstacle_line_walls",
                                                           "obstacle_line_oneside"))
    a, b = free
    assert np.array_equal(a.waypoints, b.waypoints) and np.array_equal(a.domain, b.domain)


def test_on_the_wall_of_sides_the_label_is_one_less():
    """The obstacles on the line across the middle of the box: the rooms on the two sides are equal,
    the query lies on the wall of sides and its label is its stratum's minus one; moved off it
    by 1e-9 either way, the label is the stratum's, and the two sides' plans differ by O(1)
    (the wall is where the side changes)."""
    o = np.array([[4.0, 5.0], [6.0, 5.0], [7.5, 5.0]])  # on the middle line: equal rooms
    s, g = np.array([[2.5, 2.0], [3.0, 8.0]]), np.array([[8.0, 7.0], [7.0, 3.0]])
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    on = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_walls")
    low = min(REGISTRY["obstacle_line_walls"].domain_labels(2, 2, 3))
    assert on.domain == one.domain - 1 >= low
    assert np.array_equal(on.waypoints, one.waypoints)  # (on the wall: the side of nu(e))
    plans = []
    for dy in (1e-9, -1e-9):
        moved = o.copy()
        moved[:, 1] += dy
        p = pmplan.plan(moved, s, g, bounds=(0, 10), planner="obstacle_line_walls")
        assert p.domain == one.domain
        plans.append(p)
    assert np.abs(plans[0].waypoints - plans[1].waypoints).max() > 0.1


def test_the_guard_keeps_the_lowest_label():
    """Every robot in an obstacle's column (label 4, the lowest) with more room below the
    obstacles: the guard keeps the side of nu(e) and the label 4 (the wall of sides never meets
    the lowest label: Mathematics §8); one robot moved out of the columns by more than the
    guard, the side flips and the label is the stratum's."""
    o = np.array([[2.0, 7.0], [4.0, 7.0]])
    s, g = np.array([[2.0, 3.0]]), np.array([[4.0, 2.0]])
    one = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_oneside")
    walls = pmplan.plan(o, s, g, bounds=(0, 10), planner="obstacle_line_walls")
    assert one.domain == walls.domain == 4
    assert np.array_equal(walls.waypoints, one.waypoints)
    s2 = s + [[0.01, 0.0]]
    one, walls = (pmplan.plan(o, s2, g, bounds=(0, 10), planner=p)
                  for p in ("obstacle_line_oneside", "obstacle_line_walls"))
    assert walls.domain == one.domain == 5
    assert not np.allclose(walls.waypoints, one.waypoints)
    # inside the guard: no flip, whatever the rooms
    zo, zc = W.from_box_linear(o[None], BOX), [W.from_box_linear(c[None], BOX) for c in (s, g)]
    assert not sides.wall_sides(o[None], zo, zc, BOX)[0][0]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 7), st.integers(1, 7)), min_size=7, max_size=7,
                unique=True))
def test_integer_queries_keep_the_labels_of_the_planner(pts):
    """Exactly degenerate queries in [0, 8]^2 (ties of the rooms, robots in obstacles' columns,
    collinear points): every plan certified, inside the box, and its label one of the
    planner's (never below the lowest), one less than the one-side planner's exactly on the
    wall of sides."""
    p = np.array(pts, dtype=float)
    o, s, g = p[:3], p[3:5], p[5:]
    box = np.array([[0.0, 0.0], [8.0, 8.0]])
    walls = pmplan.plan(o, s, g, bounds=(0, 8), planner="obstacle_line_walls")
    one = pmplan.plan(o, s, g, bounds=(0, 8), planner="obstacle_line_oneside")
    assert walls.clearance > 0 and W.inside(walls.waypoints[None], box)[0]
    assert walls.domain in REGISTRY["obstacle_line_walls"].domain_labels(2, 2, 3)
    zo, zc = W.from_box_linear(o[None], box), [W.from_box_linear(c[None], box) for c in (s, g)]
    _, wall = sides.wall_sides(o[None], zo, zc, box)
    assert walls.domain == one.domain - int(wall[0])


def test_the_guard_boundary_is_decided_exactly_at_every_magnitude():
    """Queries on the guard's boundary G = 0 exactly (a robot's column GUARD |w| from the
    nearest obstacle's column, every other robot nearer) and one float either side of it, with
    more room below the obstacles (g < 0): on the boundary the query lies on the wall of sides
    (side of nu(e), label one less), just outside it the lanes flip, just inside they do not;
    the same at every scale 2**k (the box and the query scaled together)."""
    box0 = np.array([[0.0, 0.0], [8192.0, 8192.0]])  # inner box [1024, 7168]: the map is 1
    o0 = np.array([[2048.0, 6000.0], [3072.0, 6000.0], [4000.0, 5000.0]])  # |w| = 1024
    goal = np.array([[3072.0, 2000.0]])  # in o2's column
    for x, want in ((2049.0, (False, True)),  # GUARD |w| = 1 off o1's column: G = 0
                    (np.nextafter(2049.0, 3000.0), (True, False)),
                    (np.nextafter(2049.0, 0.0), (False, False))):
        for k in (-40, 0, 40):
            box, o = box0 * 2.0 ** k, o0 * 2.0 ** k
            s, g = np.array([[x, 1500.0]]) * 2.0 ** k, goal * 2.0 ** k
            zo = W.from_box_linear(o[None], box)
            zc = [W.from_box_linear(c[None], box) for c in (s, g)]
            assert np.array_equal(zo[0], o) and np.array_equal(zc[0][0], s)
            flip, wall = sides.wall_sides(o[None], zo, zc, box)
            assert (bool(flip[0]), bool(wall[0])) == want == _exact_flags(o, zo[0],
                                                                           [c[0] for c in zc],
                                                                           box)
    o, s, g = o0, np.array([[2049.0, 1500.0]]), goal
    one = pmplan.plan(o, s, g, bounds=(0, 8192), planner="obstacle_line_oneside")
    walls = pmplan.plan(o, s, g, bounds=(0, 8192), planner="obstacle_line_walls")
    assert walls.domain == one.domain - 1 and np.array_equal(walls.waypoints, one.waypoints)


def test_the_rooms_tie_is_decided_exactly_at_every_magnitude():
    """The obstacles on the box's middle line (equal rooms: the wall of sides) and one float above
    or below it (the room above smaller: flip; larger: keep), at every scale 2**k."""
    box0 = np.array([[0.0, 0.0], [8192.0, 8192.0]])
    s0, g0 = np.array([[2600.0, 1500.0]]), np.array([[3500.0, 6500.0]])
    for y, want in ((4096.0, (False, True)), (np.nextafter(4096.0, 9e3), (True, False)),
                    (np.nextafter(4096.0, 0.0), (False, False))):
        o0 = np.array([[2048.0, y], [3072.0, y], [4000.0, y]])
        for k in (-40, 0, 40):
            box, o, s, g = (a * 2.0 ** k for a in (box0, o0, s0, g0))
            zo = W.from_box_linear(o[None], box)
            zc = [W.from_box_linear(c[None], box) for c in (s, g)]
            flip, wall = sides.wall_sides(o[None], zo, zc, box)
            assert (bool(flip[0]), bool(wall[0])) == want == _exact_flags(o, zo[0],
                                                                           [c[0] for c in zc],
                                                                           box)
