"""pmplan.strata: what ``pmplan verify`` needs of every registered planner."""

from __future__ import annotations

import numpy as np
import pytest

from pmplan.errors import UnsupportedError
from pmplan.planners.base import REGISTRY, Planner
from pmplan.strata import SPECS, ColumnStrata, StrataSpec, spec_for

CASES = [("obstacle_line", (2, 2, 2)), ("obstacle_line", (3, 2, 3)), ("obstacle_line", (2, 1, 4)),
         ("planar_three", (2, 1, 3))]


def test_every_planner_has_a_spec():
    for name, p in REGISTRY.items():
        assert isinstance(spec_for(p), StrataSpec) and spec_for(name) is spec_for(p)
        assert spec_for(p) is next(SPECS[c] for c in type(p).__mro__ if c in SPECS)
    assert spec_for("obstacle_line_compact") is spec_for("obstacle_line")  # a subclass
    twin = type("Twin", (type(REGISTRY["planar_three"]),), {"name": "twin"})()
    assert spec_for(twin) is spec_for("planar_three")  # a subclass: its ancestor's
    plain = type("Plain", (Planner,), {"name": "plain"})()
    assert type(spec_for(plain)) is ColumnStrata  # any planner: the column strata
    with pytest.raises(UnsupportedError, match="unknown planner 'no_such_planner'"):
        spec_for("no_such_planner")


@pytest.mark.parametrize("name, dims", CASES)
def test_exact_queries_meet_every_stratum_first(name, dims):
    spec, p = spec_for(name), REGISTRY[name]
    d, n, m = dims
    rng = np.random.default_rng(5)
    k = spec.stratum_count(d, n, m)
    o, s, g = spec.exact_queries(rng, d, n, m, 2 * k)
    assert o.shape[1:] == (m, d) and s.shape[1:] == (n, d) == g.shape[1:] and len(o) >= 2 * k
    rows = {tuple(spec.stratum_row(o[i], s[i], g[i]).tolist()) for i in range(k)}
    assert len(rows) == k  # the first stratum_count queries: one in every stratum
    names = {p.stratum_name(np.asarray(r), d, n, m) for r in rows}
    assert len(names) == k


@pytest.mark.parametrize("name, dims", CASES)
def test_moves_stay_in_the_stratum(name, dims):
    spec = spec_for(name)
    d, n, m = dims
    rng = np.random.default_rng(6)
    o, s, g = spec.exact_queries(rng, d, n, m, 12)
    moved_some = 0
    for i in range(12):
        q = (o[i], s[i], g[i])
        moved = spec.perturb_within_stratum(rng, q, 1e-6)
        if moved is None:
            continue
        moved_some += 1
        assert np.array_equal(spec.stratum_row(*moved), spec.stratum_row(*q))
        assert 0 < max(float(np.abs(a - b).max()) for a, b in zip(moved, q)) <= 1e-5
    assert moved_some >= 6
    near = spec.near_degenerate_queries(rng, d, n, m, 5, 1e-9)
    assert [a.shape for a in near] == [(5, m, d), (5, n, d), (5, n, d)]


def test_notes():
    assert spec_for("obstacle_line").notes(3, 2, 2) and not spec_for("obstacle_line").notes(2, 2, 2)
    assert spec_for("planar_three").notes(2, 1, 3) == []
