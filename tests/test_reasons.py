"""Why a refined plan does not keep its radii (pmplan.reasons, issue 25 item 3): the reason
names the worst contact exactly as the exact measure finds it, at every magnitude, says when
the path crosses a gap of the scene narrower than a robot, and is None exactly when the radii
are kept."""

from __future__ import annotations

import json
import re
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pmplan
from pmplan import cli
from pmplan.certify import exact_segment_dist2, point_pairs
from pmplan.io import plan_to_dict
from pmplan.reasons import TIGHT, Gap, RadiusMiss, radius_miss, radius_reason

#: a room query (rounded from benchmarks/scenes.py's room family, seed 1, n = 4, query 4): in
#: the box [0, 10]^2 robot x4 crosses the gap between obstacle o6 and the wall y = 0, 0.17
#: wide; without the box the same refined plan keeps the radii
ROOM = {"obstacles": [[3.72, 5.76], [4.92, 8.49], [7.06, 1.15], [1.38, 8.68], [5.92, 8.13],
                      [8.8, 0.32]],
        "start": [[3.43, 1.62], [8.57, 1.76], [3.29, 8.75], [2.22, 0.57]],
        "goal": [[0.92, 9.06], [0.49, 2.08], [6.04, 3.95], [2.5, 8.29]]}
NUMBER = r"([0-9.e+-]+)"


def _quoted(reason: str) -> tuple[str, float, float]:
    """(who, distance, time) of the worst contact a reason names."""
    who = re.match(r"(robots x\d+ and x\d+|robot x\d+ comes [0-9.e+-]+ from (obstacle o\d+|the "
                   r"wall x\[\d\] = [0-9.e+-]+))", reason)
    dist = re.search(r"(?:come|comes) " + NUMBER, reason)
    when = re.search(r"at t = " + NUMBER, reason)
    assert who and dist and when, reason
    return re.sub(r"comes [0-9.e+-]+ from", "from", who.group(0)), float(dist.group(1)), \
        float(when.group(1))


def _exact_ratios(wp: np.ndarray, m: int, radius: Fraction, orad: Fraction) -> dict:
    """{name of the pair: its exact squared minimum distance / its squared need}, in rational
    arithmetic (the minimum over the pieces of the exact segment distances)."""
    pa, pb = point_pairs(wp.shape[1], m)
    out = {}
    for a, b in zip(pa, pb):
        need = 2 * radius if a >= m else radius + orad
        d2 = min(exact_segment_dist2(wp[k, a], wp[k, b], wp[k + 1, a], wp[k + 1, b])
                 for k in range(wp.shape[0] - 1))
        name = f"robots x{a - m + 1} and x{b - m + 1}" if a >= m else \
            f"robot x{b - m + 1} from obstacle o{a + 1}"
        out[name] = (d2 / (need * need), need)
    return out


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3]), st.integers(2, 3),
       st.integers(1, 3), st.sampled_from([-1000, -300, 300, 1000]))
def test_the_reason_names_the_worst_contact_at_every_magnitude(seed, d, m, n, e):
    """On random paths (integer waypoints, often exactly degenerate), the reason names a pair
    whose exact distance is the smallest against what it needs, quotes that distance to its
    six printed digits, and says the same, scaled, at every power-of-two magnitude."""
    rng = np.random.default_rng(seed)
    wp = rng.integers(-3, 4, size=(4, m + n, d)).astype(float)
    wp[:, :m] = wp[0, :m]  # the obstacles stay
    radius, orad = 0.25, 0.5
    ratios = _exact_ratios(wp, m, Fraction(radius), Fraction(orad))
    worst = min(r for r, _ in ratios.values())
    times = np.array([0.0, 0.25, 0.5, 1.0])
    reason = radius_reason(times, wp, m, radius, orad)
    who, dist, when = _quoted(reason)
    ratio, need = ratios[who]
    assert float(ratio) <= float(worst) * (1 + 1e-12)  # the worst (up to a tie)
    exact = float(np.sqrt(float(ratio))) * float(need)
    assert abs(dist - exact) <= 1e-5 * exact + 1e-300
    scaled = radius_reason(times, np.ldexp(wp, e), m, np.ldexp(radius, e), np.ldexp(orad, e))
    who_e, dist_e, when_e = _quoted(scaled)
    assert (who_e, when_e) == (who, when)
    assert abs(np.ldexp(dist_e, -e) - dist) <= 1e-5 * dist
    # the fields say what the sentence says, unrounded, and scale with the scene
    miss = radius_miss(times, wp, m, radius, orad)
    assert miss.sentence == str(miss) == reason
    names = re.findall(r"[xo]\d+", who)
    assert miss.contact == ("robots" if who.startswith("robots") else "obstacle")
    assert set(miss.between) == set(names)
    assert abs(miss.distance - exact) <= 1e-9 * exact + 1e-300
    assert miss.need == float(need) and f"{miss.t:.3f}" == f"{when:.3f}"
    assert miss.category in ("gap", miss.contact)
    big = radius_miss(times, np.ldexp(wp, e), m, np.ldexp(radius, e), np.ldexp(orad, e))
    assert (big.contact, big.between, big.t) == (miss.contact, miss.between, miss.t)
    assert big.distance == pytest.approx(np.ldexp(miss.distance, e), rel=1e-12)
    assert big.need == np.ldexp(miss.need, e)


def test_a_gap_between_two_obstacles_is_named_in_the_plane_only():
    """A robot crossing the segment between two obstacles whose discs leave less than its
    width: the plane's reason names the gap; in space (the same points, a third coordinate
    0) a path can go around, so the reason names the contact and the refinement's effort."""
    wp = np.array([[[0.0, 0.5], [0.0, -0.5], [-1.0, 0.0]],
                   [[0.0, 0.5], [0.0, -0.5], [1.0, 0.0]]])
    plane = radius_reason([0.0, 1.0], wp, 2, 0.2, 0.4)
    assert "crosses the gap between obstacles o1 and o2, whose discs leave 0.2" in plane
    miss = radius_miss([0.0, 1.0], wp, 2, 0.2, 0.4)
    assert (miss.gap.robot, miss.gap.between) == ("x1", ("o1", "o2"))
    assert miss.gap.width == pytest.approx(0.2) and miss.gap.robot_width == 0.4
    assert miss.gap.narrow and miss.gap.spare < 0 and miss.category == "gap"
    space = radius_reason([0.0, 1.0], np.concatenate([wp, np.zeros((2, 3, 1))], axis=-1), 2,
                          0.2, 0.4)
    assert "gap" not in space and "more effort" in space
    miss = radius_miss([0.0, 1.0], np.concatenate([wp, np.zeros((2, 3, 1))], axis=-1), 2, 0.2,
                       0.4)
    assert miss.gap is None and miss.category == "obstacle"
    # the same robot passing beside the pair, not between: no gap is claimed
    beside = wp.copy()
    beside[:, 2, 1] = 0.9
    assert "gap" not in radius_reason([0.0, 1.0], beside, 2, 0.2, 0.4)
    # nor moving along the pair's line beyond them (collinear, never between)
    along = np.array([[[0.0, 0.5], [0.0, -0.5], [0.0, 0.9]],
                      [[0.0, 0.5], [0.0, -0.5], [0.0, 2.0]]])
    assert "gap" not in radius_reason([0.0, 1.0], along, 2, 0.2, 0.4)


def test_a_gap_between_an_obstacle_and_a_wall_and_a_wall_contact():
    box = np.array([[0.0, 0.0], [10.0, 10.0]])
    wp = np.array([[[5.0, 0.3], [4.0, 0.2]], [[5.0, 0.3], [6.0, 0.2]]])  # under the obstacle
    reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert reason.startswith("robot x1 comes 0.1 from obstacle o1 at t = 0.500")
    assert "crosses the gap between obstacle o1 and the wall x[1] = 0, 0.15 wide" in reason
    miss = radius_miss([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert miss.gap == Gap("x1", ("o1", "x[1] = 0"), miss.gap.width, 0.3)
    assert miss.gap.width == pytest.approx(0.15) and miss.category == "gap"
    # without the box, nothing to cross
    assert "gap" not in radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15)
    # a robot too near a wall, far from every obstacle: the wall is the contact
    wp = np.array([[[5.0, 5.0], [1.0, 9.0]], [[5.0, 5.0], [1.0, 9.95]]])
    reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert reason.startswith("robot x1 comes 0.05 from the wall x[1] = 10 at t = 1.000")
    miss = radius_miss([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert (miss.contact, miss.between, miss.t, miss.need) == ("wall", ("x1", "x[1] = 10"),
                                                               1.0, 0.15)
    assert miss.distance == pytest.approx(0.05) and miss.category == "wall"


def test_a_contact_in_a_gap_with_room_for_one_robot_names_the_gap_and_the_effort():
    """An obstacle 0.458 from a wall leaves a gap of 0.308 (obstacle_radius 0.15) for robots
    0.3 wide: a motion through it may keep the radii, so the reason is the contact and the
    effort's knob, with the gap and what it leaves to spare; a gap as wide as two robots is not
    named, nor one the path does not pass through."""
    box = np.array([[0.0, 0.0], [10.0, 10.0]])
    wp = np.array([[[5.0, 0.458], [4.0, 0.2]], [[5.0, 0.458], [6.0, 0.2]]])
    reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert reason.startswith("robot x1 comes 0.258 from obstacle o1 at t = 0.500")
    assert ("its path passes through the gap between obstacle o1 and the wall x[1] = 0, 0.308 "
            "wide, room for one robot (2 radius = 0.3) with 0.008 to spare; the refinement's "
            "fixed steps did not clear it") in reason
    assert "crosses the gap" not in reason and "no motion" not in reason
    miss = radius_miss([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert miss.gap.between == ("o1", "x[1] = 0") and not miss.gap.narrow
    assert miss.gap.spare == pytest.approx(0.008) and miss.category == "obstacle"
    for y in (0.15 + TIGHT * 0.3 + 1e-9, 2.0):  # room for two robots side by side
        wp[:, 0] = [5.0, y]
        wp[:, 1, 1] = y - 0.25
        reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
        assert "gap" not in reason and "more effort" in reason, reason
        assert radius_miss([0.0, 1.0], wp, 1, 0.15, 0.15, box).gap is None
    # between two obstacles whose discs leave 0.45: named, the narrowest of those crossed
    wp = np.array([[[0.0, 0.375], [0.0, -0.375], [0.0, 5.0], [-1.0, 0.1]],
                   [[0.0, 0.375], [0.0, -0.375], [0.0, 5.0], [1.0, 0.1]]])
    reason = radius_reason([0.0, 1.0], wp, 3, 0.15, 0.15)
    assert reason.startswith("robot x1 comes 0.275 from obstacle o1")
    assert ("its path passes through the gap between obstacles o1 and o2, whose discs leave "
            "0.45, room for one robot (2 radius = 0.3) with 0.15 to spare") in reason


def test_two_robots_pressed_together_in_a_gap_no_robot_passes():
    """The worst contact is two robots, and one of them crosses a gap narrower than a robot:
    the reason names the contact and that robot's gap (more steps cannot help there)."""
    box = np.array([[0.0, 0.0], [10.0, 10.0]])
    wp = np.array([[[5.0, 0.3], [4.0, 0.2], [3.97, 0.2]],
                   [[5.0, 0.3], [6.0, 0.2], [5.97, 0.2]]])  # under the obstacle, x2 just behind
    reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert reason.startswith("robots x1 and x2 come 0.03 apart")
    assert ("robot x1's path crosses the gap between obstacle o1 and the wall x[1] = 0, 0.15 "
            "wide") in reason
    miss = radius_miss([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert (miss.contact, miss.between, miss.gap.robot) == ("robots", ("x1", "x2"), "x1")
    assert miss.category == "gap"
    # the obstacle lifted out of the way: the same contact, no gap, the effort's knob
    wp[:, 0] = [5.0, 3.0]
    reason = radius_reason([0.0, 1.0], wp, 1, 0.15, 0.15, box)
    assert reason.startswith("robots x1 and x2 come 0.03 apart") and "gap" not in reason
    assert "more effort" in reason


def test_a_plan_gives_its_reason_in_the_api_the_json_and_the_cli(capsys, tmp_path):
    """A room whose compact lanes cross the gap between o6 and the wall y = 0 (the default in
    the box, the wall side, passes on the side with room and keeps the radii)."""
    o, s, g = (np.array(ROOM[k]) for k in ("obstacles", "start", "goal"))
    assert pmplan.plan(o, s, g, bounds=(0, 10), refine=True, radius=0.15,
                       obstacle_radius=0.15).respects_radius
    kw = dict(refine=True, radius=0.15, obstacle_radius=0.15, planner="obstacle_line_compact")
    boxed = pmplan.plan(o, s, g, bounds=(0, 10), **kw)
    assert not boxed.respects_radius
    assert boxed.radius_reason == radius_reason(boxed.path.times, boxed.path.waypoints, 6,
                                                0.15, 0.15, boxed.bounds)
    assert "robot x4 comes" in boxed.radius_reason
    assert "crosses the gap between obstacle o6 and the wall x[1] = 0, 0.17 wide" \
        in boxed.radius_reason
    free = pmplan.plan(o, s, g, **kw)
    assert free.respects_radius and free.radius_reason is None
    # the batch's plans say the same; the JSON carries it; the CLI prints it
    batch = pmplan.plan_batch(o[None], s[None], g[None], bounds=(0, 10), **kw)
    assert batch[0].radius_reason == boxed.radius_reason
    assert plan_to_dict(boxed)["radius_reason"] == boxed.radius_reason
    assert plan_to_dict(free)["radius_reason"] is None
    # the same reason for a program: the fields, in the plan, the batch and the JSON
    miss = boxed.radius_miss
    assert isinstance(miss, RadiusMiss) and str(miss) == boxed.radius_reason
    assert miss.gap.robot == "x4" and miss.gap.between == ("o6", "x[1] = 0")
    assert miss.category == "gap" and free.radius_miss is None
    assert batch.radius_miss[0] == miss
    fields = plan_to_dict(boxed)["radius_miss"]
    assert json.loads(json.dumps(fields)) == fields
    assert fields["category"] == "gap" and fields["gap"]["between"] == ["o6", "x[1] = 0"]
    assert fields["between"] == list(miss.between) and fields["distance"] == miss.distance
    assert plan_to_dict(free)["radius_miss"] is None
    path = tmp_path / "room.json"
    path.write_text(json.dumps({**ROOM, "bounds": [0, 10], "planner": kw["planner"]}))
    assert cli.main(["plan", str(path), "--refine", "--radius", "0.15",
                            "--obstacle-radius", "0.15"]) == 0
    assert json.loads(capsys.readouterr().out)["radius_reason"] == boxed.radius_reason
    queries = tmp_path / "rooms.json"
    queries.write_text(json.dumps([{**ROOM, "bounds": [0, 10], "planner": kw["planner"]}] * 2))
    assert cli.main(["batch", str(queries), "--out", str(tmp_path / "out.npz"),
                            "--refine", "--radius", "0.15", "--obstacle-radius", "0.15",
                            "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert f"radii respected by 0 of 2 (query 0: {boxed.radius_reason})" in out
    with np.load(tmp_path / "out.npz") as res:  # every query's reason, in the npz
        assert res["radius_reason"].tolist() == [boxed.radius_reason] * 2
        assert res["radius_category"].tolist() == ["gap"] * 2
    # the batch's reasons: None where the radii are kept
    both = pmplan.plan_batch(np.stack([o, o]), np.stack([s, s]), np.stack([g, g]), **kw)
    assert both.respects_radius.all() and both.radius_reason.tolist() == [None, None]
    assert both.radius_miss.tolist() == [None, None]
    twice = pmplan.plan_batch(np.stack([o, o]), np.stack([s, s]), np.stack([g, g]),
                              bounds=(0, 10), **kw)
    assert twice.radius_reason.tolist() == [boxed.radius_reason] * 2


def test_the_reason_is_none_exactly_when_the_radii_are_kept():
    """Over the refined plans of random small queries: None iff respects_radius, and a reason
    that quotes a distance below what its pair needs (to the printed digits)."""
    rng = np.random.default_rng(5)
    seen = {True: 0, False: 0}
    for radius in [0.3, 0.45] * 60:
        o = rng.integers(-3, 4, size=(3, 2)).astype(float)
        s = rng.integers(-3, 4, size=(2, 2)).astype(float)
        g = rng.integers(-3, 4, size=(2, 2)).astype(float)
        try:
            p = pmplan.plan(o, s, g, refine=True, radius=radius, obstacle_radius=radius)
        except pmplan.PmplanError:
            continue
        seen[p.respects_radius] += 1
        assert (p.radius_reason is None) == p.respects_radius
        if p.radius_reason is not None:
            who, dist, when = _quoted(p.radius_reason)
            need = 2 * radius
            assert dist <= need * (1 + 1e-6) and 0 <= when <= 1
            assert str(p.radius_miss) == p.radius_reason
            assert p.radius_miss.distance <= p.radius_miss.need * (1 + 1e-12)
        else:
            assert p.radius_miss is None
    assert seen[False] > 0 and seen[True] > 0


def test_a_contact_within_rounding_of_the_bound_is_shown_with_every_digit():
    """A robot passing an obstacle at exactly 1 with radius + obstacle_radius one ulp above 1:
    the radii are not kept (decided exactly), and the reason shows both numbers in full, not
    "1 ... closer than ... = 1"."""
    wp = np.array([[[0.0, 0.0], [-1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0]]])
    orad = float(np.nextafter(0.5, 1))
    assert not pmplan.certify.radius_report(wp[None], 1, 0.5, orad)[2][0]
    reason = radius_reason([0.0, 1.0], wp, 1, 0.5, orad)
    assert reason.startswith("robot x1 comes 1 from obstacle o1 at t = 0.500, closer than "
                             "radius + obstacle_radius = 1.0000000000000001;")
    # far from the bound: six digits
    assert "comes 1 from obstacle o1 at t = 0.500, closer than radius + obstacle_radius = 1.2;" \
        in radius_reason([0.0, 1.0], wp, 1, 0.6, 0.6)


@pytest.mark.parametrize("planner", [None, "obstacle_line_compact", "obstacle_line"])
def test_a_continuous_planner_squeezes_past_an_obstacle_near_a_wall_at_one_end(planner):
    """Mathematics §8, the Proposition: o3 moves on the line x = 5 from 0.3 above the floor to
    0.3 below the ceiling (closer than 2 radius + obstacle_radius = 0.45), which changes no
    column, so both ends lie in one domain; the robot's start and goal are on opposite sides
    of that line. Whichever planner, one end's path crosses the narrow gap, and says so."""
    plans = []
    for y in (0.3, 9.7):
        o = np.array([[2.0, 5.0], [8.0, 5.0], [5.0, y]])
        plans.append(pmplan.plan(o, [[3.0, 2.0]], [[7.0, 8.0]], planner=planner, refine=True,
                                 radius=0.15, obstacle_radius=0.15, bounds=(0, 10)))
    assert plans[0].domain == plans[1].domain
    missed = [p for p in plans if not p.respects_radius]
    assert missed
    for p in missed:
        assert "crosses the gap between obstacle o3 and the wall x[1]" in p.radius_reason
