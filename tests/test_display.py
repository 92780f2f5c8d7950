"""pmplan.display: what the faces show of every planner, apart from its mathematics."""

from __future__ import annotations

import numpy as np
import pytest

from pmplan.display import DISPLAYS, DisplaySpec, ObstacleLineDisplay, PlanarDisplay, display_for
from pmplan.errors import UnsupportedError
from pmplan.planners.base import REGISTRY, Planner
from pmplan.strata import spec_for


def test_every_planner_has_a_display():
    for name, p in REGISTRY.items():
        own = next(DISPLAYS[c] for c in type(p).__mro__ if c in DISPLAYS)  # class or ancestor
        assert display_for(name) is display_for(p) is own
        assert display_for(p).domain_prefix == "W_"
    assert display_for("obstacle_line_compact") is display_for("obstacle_line")  # a subclass
    assert type(display_for("obstacle_line")) is ObstacleLineDisplay
    assert len(display_for("obstacle_line").phases) == 7
    assert type(display_for("planar_three")) is PlanarDisplay
    plain = type("Plain", (Planner,), {"name": "plain"})()
    assert type(display_for(plain)) is DisplaySpec and display_for(plain).phases == ()
    with pytest.raises(UnsupportedError, match="unknown planner 'nope'"):
        display_for("nope")
    assert not spec_for("obstacle_line").uses_heights and spec_for("planar_three").uses_heights


def test_map_boundaries_are_the_column_lines():
    o = np.array([[0.0, 0.0], [2.0, 0.0]])
    others = np.array([[1.0, 3.0], [1.0, -1.0], [3.0, 1.0]])  # two robots share a column
    lines = display_for("obstacle_line").map_boundaries(o, others)
    xs = sorted(float(p[0]) for p, _ in lines)
    assert xs == [0.0, 1.0, 2.0, 3.0]
    assert all(np.array_equal(direction, [0.0, 1.0]) for _, direction in lines)


def test_planar_boundaries_follow_the_family():
    on_line = np.array([[0.0, 0.0], [2.0, 0.0], [5.0, 0.0]])  # o3 on L_C: heights decide
    lines = display_for("planar_three").map_boundaries(on_line, np.empty((0, 2)))
    assert len(lines) == 1 and np.array_equal(lines[0][1], [1.0, 0.0])
    off = np.array([[0.0, 0.0], [2.0, 0.0], [5.0, 1.0]])  # columns decide
    lines = display_for("planar_three").map_boundaries(off, np.empty((0, 2)))
    assert sorted(float(p[0]) for p, _ in lines) == [0.0, 2.0, 5.0]
