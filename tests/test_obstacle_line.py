"""The obstacle-line planner (Mathematics §3, §4.1, §4.2) against the independent reference ``reference.py``.

What is checked, and why it can fail:

* waypoint by waypoint, the library equals the high-precision reference up to a few ulps of the
  scene's scale; labels and stratum records equal exactly (random, hypothesis-degenerate and
  exactly constructed queries, d = 2..5, m = 2..5, n in {1, 2, 3, 8}, several lifts);
* every stratum is realised and its label is the one the exact classification predicts; the
  set of labels has exactly TC elements (``parametrised_tc``, ``info``);
* odd d: the pole ``e == N`` (label - 1), ``nu`` near N, -N and at N;
* lambda = lift + max |r(o_k)| is needed (the example of Mathematics §4.2);
* continuity inside a piece (O(delta)) and jumps across labels (not o(1));
* m = 2, even d: the paper's Section 3 construction, written separately;
* certificates and batch == single everywhere.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import SHARING, TIMES, nu_exact, paper_plan_m2, reference_plan
from strategies import queries

import pmplan
from pmplan.certify import clearance
from pmplan.frame import nu as library_nu
from pmplan.path import DIRECT_AT
from pmplan.generators import (
    column_query,
    perturb_within_stratum,
    piece_of,
    strata,
    stratum_of,
)

#: waypoints agree with the reference to this many ulps of the scene's scale (observed: <= 5)
ULPS = 16
_TIMES = np.array([float(t) for t in TIMES])


#: both backends are held against the independent reference (tests/reference.py), not only
#: against each other: the numpy one is the production path for d > 7 and for every query the
#: kernel hands back
BACKENDS = [None, "numpy"]


#: the paper's lanes, the compact ones, the shared ones and the shared ones on one side
#: (Mathematics §4.4): one construction, four sections
PLANNERS = ["obstacle_line", "obstacle_line_compact", "obstacle_line_shared",
            "obstacle_line_oneside"]


def _plan(q, lift=1.0, backend=None, planner="obstacle_line"):
    return pmplan.plan(*q, planner=planner, lift=lift, backend=backend)


def _batch(qs, lift=1.0, backend=None, planner="obstacle_line"):
    return pmplan.plan_batch(*(np.stack(a) for a in zip(*qs)), planner=planner, lift=lift,
                             backend=backend)


def assert_matches_reference(q, plan, record, lift=1.0):
    """Compare one library plan (and its stratum record) with the reference, and certify it."""
    ref = reference_plan(*q, lift=lift, compact=plan.planner != "obstacle_line",
                         shared=SHARING.get(plan.planner, 0))
    assert plan.domain == ref.label
    assert tuple(int(v) for v in record) == ref.record
    assert plan.waypoints.shape == (8,) + (q[0].shape[0] + q[1].shape[0], q[0].shape[1])
    assert np.abs(plan.times - _TIMES).max() <= 2.0**-52  # breakpoints, within an ulp
    want = np.array(ref.waypoints)
    scale = np.abs(want).max()
    err = np.abs(plan.waypoints - want).max()
    assert err <= ULPS * np.spacing(scale), (err / np.spacing(scale), q)
    # certificate: endpoints, fixed obstacles, clearance > 0 and equal to the closed form
    np.testing.assert_array_equal(plan.waypoints[0], np.concatenate([q[0], q[1]]))
    np.testing.assert_array_equal(plan.waypoints[-1], np.concatenate([q[0], q[2]]))
    assert plan.clearance > 0
    assert plan.clearance == clearance(plan.waypoints[None], q[0].shape[0])[0]
    return ref


def check_queries(qs, lift=1.0, backend=None, planner="obstacle_line"):
    """Plan ``qs`` singly and as a batch; compare each with the reference; batch == single."""
    batch = _batch(qs, lift, backend, planner)
    for i, q in enumerate(qs):
        single = _plan(q, lift, backend, planner)
        assert single.planner == planner
        assert_matches_reference(q, single, batch.strata[i], lift)
        assert batch.domain[i] == single.domain
        assert batch.stratum[i] == single.stratum
        np.testing.assert_array_equal(batch.waypoints[i], single.waypoints)
        assert batch.clearance[i] == single.clearance
    return batch


# --------------------------------------------------------------------------------------------
# waypoint-by-waypoint comparison with the reference


@settings(max_examples=40)
@given(
    d=st.sampled_from([2, 3, 4, 5]),
    m=st.sampled_from([2, 3, 4, 5]),
    n=st.sampled_from([1, 2, 3, 8]),
    lift=st.sampled_from([1.0, 0.25, 3.0]),
    degenerate=st.booleans(),
    data=st.data(),
)
@pytest.mark.parametrize("planner", PLANNERS)
@pytest.mark.parametrize("backend", BACKENDS)
def test_matches_reference_hypothesis(backend, planner, d, m, n, lift, degenerate, data):
    q = data.draw(queries(d, m, n, degenerate=degenerate))
    check_queries([q], lift, backend, planner)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("d, m, n", [(d, m, n) for d in (2, 3, 4, 5) for m in (2, 3, 4, 5)
                                     for n in (1, 2, 3, 8)]
                         + [(d, m, n) for d in (8, 9) for m in (2, 4) for n in (1, 3)])
@pytest.mark.parametrize("planner", PLANNERS)
def test_matches_reference_exact_strata(backend, planner, d, m, n):
    """Exactly constructed queries of random strata (both poles for odd d), as one batch."""
    rng = np.random.default_rng(1000 * d + 100 * m + n)
    table = strata(d, n, m)
    picks = rng.choice(len(table), size=3, replace=False)
    qs = [column_query(rng, d, n, m, table[i].cp_start, table[i].cp_goal, cp_o=table[i].cp_o,
                       pole=table[i].pole, integer=bool(i % 2)) for i in picks]
    lift = float(rng.choice([1.0, 0.5, 2.0]))
    batch = check_queries(qs, lift, backend, planner)
    for i, q in zip(picks, qs):
        assert stratum_of(q).label == table[i].label
    assert list(batch.domain) == [table[i].label for i in picks]


# --------------------------------------------------------------------------------------------
# strata and labels


@pytest.mark.parametrize("d, n", [(2, 1), (2, 3), (4, 2), (4, 8), (6, 2), (2, 8)])
def test_all_strata_m2_even(d, n):
    """Every T_{ij} (2 <= i, j <= n+2) built exactly has label i + j; 2n+1 labels, = TC."""
    rng = np.random.default_rng(d * 31 + n)
    qs, want = [], []
    for i in range(2, n + 3):
        for j in range(2, n + 3):
            q = column_query(rng, d, n, 2, i, j)
            qs.append(q)
            want.append((i, j))
    batch = _batch(qs)
    assert [tuple(r[:2]) for r in batch.strata] == want
    assert list(batch.domain) == [i + j for i, j in want]
    assert set(batch.domain) == set(range(4, 2 * n + 5))
    assert len(set(batch.domain)) == 2 * n + 1 == pmplan.parametrised_tc(d, n, 2)
    assert (batch.clearance > 0).all()
    assert list(batch.stratum[:2]) == ["T_{2,2}", "T_{2,3}"]


@pytest.mark.parametrize("d", [2, 3, 4])
@pytest.mark.parametrize("m", [3, 4, 5])
@pytest.mark.parametrize("n", [1, 2])
def test_every_label_realised(d, m, n):
    """For every stratum (cps, cp_o, pole) a query is built exactly; the planner's label is the
    exact one, and the labels realised are exactly info(d, n, m).labels, TC of them."""
    rng = np.random.default_rng(7 * d + 11 * m + n)
    table = strata(d, n, m)
    qs = [column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole)
          for s in table]
    batch = _batch(qs)
    assert list(batch.domain) == [s.label for s in table]
    assert [tuple(r) for r in batch.strata] == [s.record() for s in table]
    realised = sorted(set(batch.domain.tolist()))
    low = 4 if d % 2 == 0 else 3
    assert realised == list(range(low, 2 * n + m + 3))
    info = pmplan.info(d, n, m, planner="obstacle_line")
    assert len(realised) == pmplan.parametrised_tc(d, n, m) == info.domains
    assert tuple(realised) == info.labels
    assert (batch.clearance > 0).all()


# --------------------------------------------------------------------------------------------
# odd d: the pole e == N


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("d", [3, 5, 9])
def test_pole_label_shifted(d, backend):
    """At e == N the label is cp + cp' - cp_o + 1; the same robots with o2 - o1 = -N: + 2."""
    rng = np.random.default_rng(d)
    for s in strata(d, 2, 3):
        if not s.pole:
            continue
        q = column_query(rng, d, 2, 3, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=True)
        p = _plan(q, backend=backend)
        assert p.domain == s.cp_start + s.cp_goal - s.cp_o + 1
        # reflect everything through the hyperplane x_d = 0: e becomes -N, not the pole; the
        # columns (hence cp, cp_o) are unchanged, so the label goes up by exactly one
        flip = np.ones(d)
        flip[-1] = -1.0
        p2 = _plan(tuple(a * flip for a in q), backend=backend)
        assert p2.domain == p.domain + 1
        check_queries([q, tuple(a * flip for a in q)], backend=backend)


def _w_near(d, kind, t):
    """``o2 - o1`` exactly N, exactly -N, or (t, -t/2, 0, ..., +-1) near N / -N."""
    w = np.zeros(d)
    if kind == "N":
        w[-1] = 2.0
    elif kind == "-N":
        w[-1] = -3.0
    else:
        w[0], w[1] = t, -0.5 * t
        w[-1] = 1.0 if kind == "nearN" else -1.0
    return w


@pytest.mark.parametrize("d", [3, 5])
@pytest.mark.parametrize("kind, t", [("N", 0), ("-N", 0), ("nearN", 1e-3), ("nearN", 1e-9),
                                     ("nearN", 1e-200), ("near-N", 1e-9)])
def test_nu_near_pole(d, kind, t):
    """nu(e) is a unit vector orthogonal to e near N, near -N and at N (exactly a there), equals
    the reference field, and is what the planner lifts the robots along."""
    w = _w_near(d, kind, t)
    v, pole = library_nu(w)
    assert bool(pole) == (kind == "N")
    e = w / np.linalg.norm(w)
    assert abs(np.dot(v, v) - 1.0) <= 4e-16
    assert abs(np.dot(v, e)) <= 4e-16
    ref, ref_pole = nu_exact([Fraction(c) for c in w])
    assert ref_pole == bool(pole)
    np.testing.assert_allclose(v, [float(c) for c in ref], rtol=0, atol=4e-16)
    if kind == "N":
        np.testing.assert_array_equal(v, np.eye(d)[0])
    # the planner: o1 = 0, o2 = w, one robot off L; lifted waypoint - projected = lambda nu(e)
    rng = np.random.default_rng(0)
    x = rng.normal(size=(1, d))
    xg = rng.normal(size=(1, d))
    q = (np.stack([np.zeros(d), w]), x, xg)
    p = _plan(q)
    lifted = p.waypoints[3, 2] - p.waypoints[2, 2]
    np.testing.assert_allclose(lifted, v, rtol=0, atol=1e-15)
    check_queries([q])


# --------------------------------------------------------------------------------------------
# m >= 3: columns shared, obstacles far from L, lambda


def test_lambda_example_from_spec():
    """Mathematics §4.2: O = (0,0),(1,0),(5,1), x = (2,3), x' = (10,-3), lift 1 is certified; with
    lambda = lift alone the reference path would slide robot 1 through o3 (clearance 0)."""
    q = (np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 1.0]]), np.array([[2.0, 3.0]]),
         np.array([[10.0, -3.0]]))
    p = _plan(q)
    batch = check_queries([q])
    assert p.clearance > 0
    good = reference_plan(*q, lift=1.0)
    assert good.lam == 2  # lift + |r(o3)| = 1 + 1
    bad = reference_plan(*q, lift=1.0, lam=1.0)
    wp = np.array(bad.waypoints)[None]
    assert clearance(wp, 3)[0] == 0.0
    assert batch.clearance[0] == p.clearance


def test_shared_columns_hand_built():
    """o3 in o1's column, o4 on L beyond o2, o5 far from L in o2's column; robots on obstacle
    columns, two robots sharing a column, a robot on L; d = 2 and the same scene in R^3, R^4."""
    obs2 = np.array([[0, 0], [2, 0], [0, 3], [5, 0], [2, -40]], dtype=float)
    start2 = np.array([[0, -1], [2, 1], [7, 2], [7, -2], [3, 0]], dtype=float)
    goal2 = np.array([[5, 1], [1, 1], [1, 3], [-1, 0], [0, 1]], dtype=float)
    qs = []
    for d in (2, 3, 4):
        pad = lambda a: np.concatenate([a, np.zeros((a.shape[0], d - 2))], axis=1)  # noqa: E731
        qs.append((pad(obs2), pad(start2), pad(goal2)))
    for q in qs:
        s = stratum_of(q)
        assert s.cp_o == 3 and s.cps == (5, 5)
        batch = check_queries([q], lift=0.5)
        assert batch.domain[0] == 5 + 5 - 3 + 2 - int(s.pole)
        ref = reference_plan(*q, lift=0.5)
        assert ref.lam == Fraction(1, 2) + 40


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3, 4]),
       m=st.sampled_from([3, 4, 5]), n=st.sampled_from([1, 2, 3]))
def test_column_queries_m_ge_3(seed, d, m, n):
    rng = np.random.default_rng(seed)
    table = strata(d, n, m)
    s = table[int(rng.integers(len(table)))]
    q = column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole,
                     integer=bool(rng.integers(2)))
    check_queries([q], lift=float(rng.choice([1.0, 0.1, 4.0])))


# --------------------------------------------------------------------------------------------
# m = 2, even d: the paper's Section 3 construction


@settings(max_examples=30)
@given(d=st.sampled_from([2, 4, 6]), n=st.sampled_from([1, 2, 3, 5]),
       lift=st.sampled_from([1.0, 0.5]), degenerate=st.booleans(), data=st.data())
def test_m2_is_the_papers_planner(d, n, lift, degenerate, data):
    """For m = 2 the m-obstacle construction (Mathematics §4.2) IS the paper's (Mathematics §3): the two
    independent references agree exactly, and the library agrees with them up to ulps."""
    q = data.draw(queries(d, 2, n, degenerate=degenerate))
    label, exact = paper_plan_m2(*q, lift=lift)
    ref = reference_plan(*q, lift=lift)
    assert label == ref.label
    assert exact == ref.exact
    assert ref.lam == Fraction(lift)
    check_queries([q], lift)


# --------------------------------------------------------------------------------------------
# continuity inside a piece, jumps across labels


def _sup_distance(p, q):
    assert p.waypoints.shape == q.waypoints.shape
    np.testing.assert_array_equal(p.times, q.times)
    return float(np.sqrt(((p.waypoints - q.waypoints) ** 2).sum(-1)).max())


def lipschitz_bound(q, lift=1.0) -> float:
    """A crude Lipschitz constant of the planner's waypoints in a piece, at the query q.

    If every point moves by at most D (obstacles included), then with R = max |y - o1| and
    rho = |w|: w moves by 2D and e by 4D/rho; a column s(y) by a D, a = 2 + 4 R/rho; eps by
    2 a D/(n+m); the desingularized robots by D(1 + 2a + 8R/rho); their projections by
    D(1 + 3a + 20R/rho); lambda by a D; and i lambda nu(e) by n(a D + lambda L_nu 4D/rho) with
    L_nu = 1 for even d (nu is linear) and L_nu = 2 + 8/sqrt(1 - e_d) for odd d (nu blows up
    only at N, where the perturbations keep e == N fixed). Summing with slack:
    C = 8 (n + 1)(1 + a + 20 R/rho) + 4 n lambda L_nu / rho.
    """
    obs = q[0]
    n, m, d = q[1].shape[0], obs.shape[0], obs.shape[1]
    o1, w = obs[0], obs[1] - obs[0]
    rho = np.linalg.norm(w)
    big_r = max(np.linalg.norm(a - o1, axis=1).max() for a in q)
    a = 2 + 4 * big_r / rho
    lam = lift + max(np.linalg.norm((o - o1) - np.dot(o - o1, w) / rho**2 * w) for o in obs)
    e = w / rho
    l_nu = 1.0 if d % 2 == 0 else 2 + 8 / np.sqrt(max(1 - e[-1], 1e-300))
    if stratum_of(q).pole:
        l_nu = 0.0
    return 8 * (n + 1) * (1 + a + 20 * big_r / rho) + 4 * n * lam * l_nu / rho


@pytest.mark.parametrize("d, n, m", [(2, 3, 2), (2, 2, 4), (3, 2, 3), (4, 3, 3), (5, 1, 2),
                                     (3, 3, 5)])
def test_continuity_inside_a_piece(d, n, m):
    """Stratum-preserving perturbations of size delta move every waypoint by <= C delta, with C
    from :func:`lipschitz_bound`; and the ratio sup/delta does not grow as delta -> 0."""
    rng = np.random.default_rng(d * 100 + n * 10 + m)
    table = strata(d, n, m)
    for trial in range(4):
        s = table[int(rng.integers(len(table)))]
        q = column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole)
        base = _plan(q)
        c_bound = lipschitz_bound(q)
        seed = int(rng.integers(2**32))
        ratios = []
        for delta in (1e-3, 1e-5, 1e-7):
            q2 = perturb_within_stratum(np.random.default_rng(seed), q, delta)
            assert piece_of(q2) == piece_of(q)
            moved = max(float(np.abs(a - b).max()) for a, b in zip(q, q2))
            assert 0 < moved <= delta
            p2 = _plan(q2)
            assert p2.domain == base.domain
            sup = _sup_distance(base, p2)
            assert sup <= c_bound * delta, (sup / delta, c_bound)
            ratios.append(sup / moved)
        # the path is piecewise smooth in the query: the difference quotient stays bounded
        assert ratios[-1] <= 4 * ratios[0] + 1e-6 * c_bound


@pytest.mark.parametrize("d, n, m", [(2, 1, 2), (2, 3, 3), (3, 2, 2), (4, 2, 4)])
def test_jump_across_labels(d, n, m):
    """Moving robot 1 off an obstacle column by delta changes the label, and the waypoint at
    tau = 1/6 jumps by about eps (the desingularization is switched off): no convergence."""
    rng = np.random.default_rng(d + n + m)
    obs = np.zeros((m, d))
    obs[1, 0] = 2.0
    for k in range(2, m):
        obs[k] = rng.integers(-3, 4, size=d)
        obs[k, 0] = 2.0 * k  # its own column
    start = np.zeros((n, d))
    start[:, 1] = np.arange(1, n + 1)  # robot j at column 0 (o1's), height j
    start[1:, 0] = -np.arange(1, n) * 0.5 - 0.25  # other robots alone in their columns
    goal = start + 0.0
    goal[:, -1] += 1.0
    q = (obs, start, goal)
    base = _plan(q)
    sups = []
    for delta in (1e-3, 1e-5, 1e-7):
        moved = tuple(a.copy() for a in q)
        moved[1][0, 0] += delta  # robot 1 leaves o1's column
        assert stratum_of(moved).label == stratum_of(q).label + 1
        p = _plan(moved)
        assert p.domain == base.domain + 1
        sups.append(_sup_distance(base, p))
    eps = base.waypoints[1, m, 0] - base.waypoints[0, m, 0]  # robot 1 moved by 1 * eps along e
    assert eps >= 0.5 / (n + m) * (1 - 1e-12)  # min column gap 0.5 over n + m
    assert min(sups) >= 0.5 * eps


# --------------------------------------------------------------------------------------------
# compact lanes (Mathematics §4.4): the default planner's section


@settings(max_examples=60)
@given(d=st.sampled_from([2, 3, 4]), m=st.sampled_from([2, 3, 5]), n=st.sampled_from([1, 2, 5]),
       lift=st.sampled_from([1.0, 0.3, 0.01]), data=st.data())
def test_compact_lanes_are_a_unit_apart_and_clear_the_obstacles(d, m, n, lift, data):
    """During the slide (waypoints 3 and 4) the robots' nu-components are their lanes h_i:
    odd robots above the line, even ones below, any two at least u apart, every lane at least
    u from every obstacle's nu-component (the reference's rational waypoints, each rounded to a
    double: up to a relative 1e-12)."""
    q = data.draw(queries(d, m, n, degenerate=data.draw(st.booleans())))
    ref = reference_plan(*q, lift=lift, compact=True)
    nu, o1 = ref.nu, ref.exact[0][0]
    scale = max(abs(c) for conf in ref.exact for p in conf for c in p)
    u = Fraction(lift) - Fraction(1, 10**12) * scale

    def height(p):
        return sum((a - b) * c for a, b, c in zip(p, o1, nu))

    ts = [height(o) for o in ref.exact[0][:m]]
    hs = [height(x) for x in ref.exact[3][m:]]  # (the lanes pass through the line's feet)
    for i, h in enumerate(hs):
        assert (h > 0) == (i % 2 == 0)
        assert all(abs(h - t) >= u for t in ts)  # (t = 0 for o_1, o_2)
        assert all(abs(h - g) >= u for g in hs[:i])
        if m == 2:  # no obstacle off the line: +-k u
            assert abs(abs(h) - lift * (i // 2 + 1)) <= 1e-12 * scale


@settings(max_examples=60)
@given(d=st.sampled_from([2, 3, 4]), m=st.sampled_from([2, 3, 5]), n=st.sampled_from([1, 2, 5, 9]),
       lift=st.sampled_from([1.0, 0.3, 0.01]), sides=st.sampled_from([2, 1]), data=st.data())
def test_shared_lanes_are_a_unit_apart_and_clear_the_obstacles(d, m, n, lift, sides, data):
    """The shared lanes (obstacle_line_shared, and with one side obstacle_line_oneside): during
    the slide (waypoints 3 and 4) the robots' nu-components are their lanes h_i: odd robots
    above the line, even ones below (one side: every robot above); two robots
    share a lane only if their columns
    are in the same order at both ends of the slide (so they never share a column on it: the
    chains of Mathematics §4.4), other pairs are at least u apart; every lane is at least u
    from every obstacle's nu-component; a side's lanes are 1, 2, ... units beyond its
    obstacles, none skipped (the reference's rational waypoints, each rounded to a double: up
    to a relative 1e-12)."""
    q = data.draw(queries(d, m, n, degenerate=data.draw(st.booleans())))
    ref = reference_plan(*q, lift=lift, compact=True, shared=sides)
    nu, o1 = ref.nu, ref.exact[0][0]
    o2 = ref.exact[0][1]
    scale = max(abs(c) for conf in ref.exact for p in conf for c in p)
    u = Fraction(lift) - Fraction(1, 10**12) * scale

    def height(p):
        return sum((a - b) * c for a, b, c in zip(p, o1, nu))

    def column(p):
        return sum((a - b) * (c - b) for a, b, c in zip(p, o1, o2))

    ts = [height(o) for o in ref.exact[0][:m]]
    hs = [height(x) for x in ref.exact[3][m:]]  # (the lanes pass through the line's feet)
    ends = [[column(x) for x in ref.exact[t][m:]] for t in (3, 4)]
    for i, h in enumerate(hs):
        assert (h > 0) == (i % 2 == 0 or sides == 1)
        assert all(abs(h - t) >= u for t in ts)  # (t = 0 for o_1, o_2)
        for j, g in enumerate(hs[:i]):
            if abs(h - g) < u:  # one lane: the same order at both ends, never one column
                assert abs(h - g) <= Fraction(1, 10**12) * scale
                assert (ends[0][i] - ends[0][j]) * (ends[1][i] - ends[1][j]) > 0
    tol = Fraction(1, 10**12) * scale
    for side in range(sides):
        base = max([0] + [t if side == 0 else -t for t in ts])
        ks = []
        for h in hs[side::sides]:  # lane k: k units beyond the side's obstacles
            k = round((abs(h) - base) / Fraction(lift))
            assert abs(abs(h) - base - k * Fraction(lift)) <= tol
            ks.append(k)
        assert sorted(set(ks)) == list(range(1, len(set(ks)) + 1))  # none skipped


def test_compact_lanes_pass_where_the_papers_climb():
    """The example of Mathematics §4.2 (o_3 far off the line): the paper's lanes climb by
    lambda = lift + |r(o_3)| per robot, the compact ones by the unit; both are certified."""
    o = [[0.0, 0.0], [1.0, 0.0], [5.0, 4.0]]
    s, g = [[2.0, 3.0], [3.0, -1.0], [4.0, 1.0]], [[10.0, -3.0], [-2.0, 2.0], [6.0, -2.0]]
    paper = pmplan.plan(o, s, g, planner="obstacle_line")
    compact = pmplan.plan(o, s, g)
    assert compact.planner == "obstacle_line_compact" and compact.domain == paper.domain
    lanes = lambda p: p.path.waypoints[3, 3:, 1]  # noqa: E731 (the line is y = 0)
    np.testing.assert_array_equal(lanes(paper), [5.0, 10.0, 15.0])  # i (1 + 4)
    np.testing.assert_array_equal(lanes(compact), [5.0, -1.0, 6.0])  # 4 + 1, -(0 + 1), 4 + 2
    assert compact.path.length() < 0.6 * paper.path.length()
    assert compact.clearance > 0 and paper.clearance > 0


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_shared_lanes_are_those_of_robots_that_keep_their_order(backend):
    """Mathematics §4.4, the shared lanes: robots 1 and 3 (one side) whose columns are in the
    same order at the start and the goal share the first lane (the compact planner, the
    default, gives every robot its own); when robot 3's goal passes robot 1's
    they take lanes 1 and 2; robots in one start column (one above the other) are ordered by
    their index, as the desingularization orders them; a sequence shares a lane only if the
    order holds in every configuration. The domain is the same, every plan is certified, and
    both backends agree bit for bit."""
    o = [[0.0, 0.0], [1.0, 0.0]]
    lanes = lambda p, k=0: p.path.waypoints[7 * k + 3, 2:, 1]  # noqa: E731 (the line y = 0)
    s = [[2.0, 1.0], [3.0, 2.0], [4.0, -1.0]]
    planner = "obstacle_line_shared"
    kept = pmplan.plan(o, s, [[5.0, 1.0], [-3.0, 1.0], [7.0, 2.0]], backend=backend,
                       planner=planner)
    np.testing.assert_array_equal(lanes(pmplan.plan(o, s, [[5.0, 1.0], [-3.0, 1.0], [7.0, 2.0]],
                                                    backend=backend)), [1.0, -1.0, 2.0])
    np.testing.assert_array_equal(lanes(kept), [1.0, -1.0, 1.0])
    crossed = pmplan.plan(o, s, [[5.0, 1.0], [-3.0, 1.0], [3.0, 2.0]], backend=backend,
                          planner=planner)
    np.testing.assert_array_equal(lanes(crossed), [1.0, -1.0, 2.0])
    assert kept.domain == crossed.domain and min(kept.clearance, crossed.clearance) > 0
    # one side: robot 2 (index 1) goes before robot 1 at the goal, so it opens lane 2; robot 3
    # joins robot 1's chain when it stays after it, robot 2's when it passes robot 1
    ones = [pmplan.plan(o, s, [[5.0, 1.0], [-3.0, 1.0], [x, 2.0]], backend=backend,
                        planner="obstacle_line_oneside") for x in (7.0, 3.0)]
    np.testing.assert_array_equal(lanes(ones[0]), [1.0, 2.0, 1.0])
    np.testing.assert_array_equal(lanes(ones[1]), [1.0, 2.0, 2.0])
    assert ones[0].domain == kept.domain and min(p.clearance for p in ones) > 0
    # one start column: robot 3 is after robot 1 in H(C, 1), whatever their heights
    tied = [[2.0, 1.0], [3.0, 2.0], [2.0, -1.0]]
    after = pmplan.plan(o, tied, [[5.0, 1.0], [-3.0, 1.0], [7.0, 2.0]], backend=backend,
                        planner=planner)
    before = pmplan.plan(o, tied, [[7.0, 1.0], [-3.0, 1.0], [5.0, 2.0]], backend=backend,
                         planner=planner)
    np.testing.assert_array_equal(lanes(after), [1.0, -1.0, 1.0])
    np.testing.assert_array_equal(lanes(before), [1.0, -1.0, 2.0])
    assert min(after.clearance, before.clearance) > 0
    seq = pmplan.plan_sequence(o, [s, [[5.0, 1.0], [-3.0, 1.0], [7.0, 2.0]],
                                   [[5.0, 1.0], [-3.0, 1.0], [3.0, 2.0]]], backend=backend,
                               planner=planner)
    np.testing.assert_array_equal(lanes(seq, 0), [1.0, -1.0, 2.0])
    np.testing.assert_array_equal(lanes(seq, 1), [1.0, -1.0, 2.0])
    assert seq.clearance > 0
    for p in (kept, crossed, after, before, seq, *ones):
        ref = pmplan.plan_sequence(o, [p.path.waypoints[7 * k][2:] for k in
                                       range(len(p.path.times) // 7 + 1)], backend="numpy",
                                   planner=p.planner)
        np.testing.assert_array_equal(ref.path.waypoints, p.path.waypoints)


@settings(max_examples=60)
@given(d=st.sampled_from([2, 3, 4, 5]), m=st.sampled_from([2, 3, 5]),
       n=st.sampled_from([1, 2, 5]), data=st.data())
def test_compact_lanes_keep_the_offsets_in_space(d, m, n, data):
    """Mathematics §4.4, offsets: at the end of the projection (waypoints 2 and 5) a robot of
    the compact planner has the column and the offset of its desingularized position
    (waypoints 1 and 6) and no component along nu: in d >= 3 the offset is kept (the rational
    reference, within a relative 1e-12), so the robots are not all on the line, unless every
    offset is 0. In the plane (the direct lift) waypoints 2 and 5 are 3/5 of the way from
    waypoints 1 and 6 to the lanes (waypoints 3 and 4), bit for bit the float formula, and the
    desingularization is the paper's."""
    q = data.draw(queries(d, m, n, degenerate=data.draw(st.booleans())))
    compact = pmplan.plan(*q, planner="obstacle_line_compact")
    paper = pmplan.plan(*q, planner="obstacle_line")
    w = compact.path.waypoints
    assert compact.domain == paper.domain and compact.stratum == paper.stratum
    if d == 2:
        np.testing.assert_array_equal(w[[1, 6]], paper.path.waypoints[[1, 6]])
        np.testing.assert_array_equal(w[2, m:], w[1, m:] + DIRECT_AT * (w[3, m:] - w[1, m:]))
        np.testing.assert_array_equal(w[5, m:], w[6, m:] + DIRECT_AT * (w[4, m:] - w[6, m:]))
        return
    ref = reference_plan(*q, compact=True)
    nu, o1 = ref.nu, ref.exact[0][0]
    o2 = ref.exact[0][1]
    e = [b - a for a, b in zip(o1, o2)]
    ee = sum(c * c for c in e)
    scale = max(abs(c) for conf in ref.exact for p in conf for c in p)

    def parts(p):  # column (times |w|), nu-component, offset
        rel = [a - b for a, b in zip(p, o1)]
        s = sum(a * b for a, b in zip(rel, e))
        r = [a - s / ee * b for a, b in zip(rel, e)]
        t = sum(a * b for a, b in zip(r, nu))
        return s, t, [a - t * b for a, b in zip(r, nu)]

    tol = Fraction(1, 10**12) * scale
    for k_des, k_proj in ((1, 2), (6, 5)):
        for x, y, yf in zip(ref.exact[k_des][m:], ref.exact[k_proj][m:], w[k_proj, m:]):
            (s1, _, p1), (s2, t2, p2) = parts(x), parts(y)
            assert abs(s1 - s2) <= tol * ee ** 0.5 and abs(t2) <= tol
            assert max(abs(a - b) for a, b in zip(p1, p2)) <= tol
            assert np.abs(yf - np.array([float(c) for c in y])).max() <= 1e-12 * float(scale)


def test_the_direct_lift_keeps_robots_of_close_columns_apart():
    """Mathematics §4.4, the direct lift: in the plane two robots whose columns differ by 1e-6
    and which need not pass each other (the first below the line goes to its lane below, the
    second above to its lane above) never come near: the paper's projection puts both on the
    line at tau = 1/3 (clearance < 2e-6), the compact lanes keep them more than 1 apart."""
    o = [[0.0, 0.0], [10.0, 0.0]]
    s = [[3.0, 2.0], [3.0 + 1e-6, -2.0]]  # robot 1 (lane above) above, robot 2 (below) below
    g = [[7.0, 2.0], [7.0 + 1e-6, -2.0]]
    paper = pmplan.plan(o, s, g, planner="obstacle_line")
    compact = pmplan.plan(o, s, g)
    assert compact.domain == paper.domain
    assert paper.clearance < 2e-6 and compact.clearance > 1.0


def test_compact_lanes_plan_the_precision_case():
    """The query of Mathematics §6.2, whose columns are 2**-51 apart: the paper's projection
    puts both robots in one float point of the line (CertificationError); the compact lanes in
    the plane move x1 up to its lane and x2 down to its own without a common point, and both
    backends certify the same path."""
    o, s, g = [[0.0, 0.0], [1.0, 2.0]], [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]], [[5.0, 5.0],
                                                                                [6.0, -7.0]]
    with pytest.raises(pmplan.CertificationError):
        pmplan.plan(o, s, g, planner="obstacle_line")
    fast, ref = pmplan.plan(o, s, g), pmplan.plan(o, s, g, backend="numpy")
    np.testing.assert_array_equal(fast.path.waypoints, ref.path.waypoints)
    assert fast.clearance == ref.clearance > 0.5


def test_offsets_keep_robots_of_close_columns_apart():
    """Two robots whose columns differ by 1e-6 but whose offsets differ by 2 (d = 3): the
    paper's projection brings them 1e-6 apart on the obstacle line at tau = 1/3; with the
    offsets (the default planner, Mathematics §4.4) they stay about 2 apart, and the plan's
    clearance is that of its lanes, not that of the columns."""
    o = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    nu = pmplan.frame.nu(np.array([[1.0, 0.0, 0.0]]))[0][0]
    off = np.cross([1.0, 0.0, 0.0], nu)  # orthogonal to e and to nu
    s = [np.array([0.5, 0.0, 0.0]) + off + 0.5 * nu, np.array([0.5 + 1e-6, 0, 0]) - off - 0.5 * nu]
    g = [np.array([3.0, 0.0, 0.0]) + off, np.array([-2.0, 0.0, 0.0]) - off]
    paper = pmplan.plan(o, s, g, planner="obstacle_line")
    compact = pmplan.plan(o, s, g)
    assert compact.domain == paper.domain
    assert paper.clearance < 2e-6
    assert compact.clearance > 0.5
    at_line = compact.path.waypoints[2]  # tau = 1/3: the projection's end
    np.testing.assert_allclose(np.linalg.norm(at_line[2] - at_line[3]), 2.0, rtol=1e-6)


@pytest.mark.parametrize("radius, obstacle_radius, unit", [(0.1, 0.1, 0.2), (0.1, 0.3, 0.4),
                                                           (0.2, 0.0, 0.4)])
def test_the_default_unit_of_a_refined_plan_is_the_robots_diameter(radius, obstacle_radius,
                                                                   unit):
    """lift=None (the default): max(2 radius, radius + obstacle_radius) for a refined plan,
    the paper's 1 for a raw one (pmplan.configuration.default_lift); a query scaled by a power
    of two, radii with it, gives the scaled refined plan, bit for bit."""
    o, s, g = [[0.0, 0.0], [4.0, 0.0], [2.0, 1.5]], [[1.0, 1.0], [3.0, -1.0]], [[3.0, -1.0],
                                                                               [0.5, 2.0]]
    kw = dict(refine=True, radius=radius, obstacle_radius=obstacle_radius)
    auto = pmplan.plan(o, s, g, **kw)
    same = pmplan.plan(o, s, g, lift=unit, **kw)
    np.testing.assert_array_equal(auto.path.waypoints, same.path.waypoints)
    paper_unit = pmplan.plan(o, s, g, lift=1.0, **kw)
    assert not np.array_equal(auto.path.waypoints, paper_unit.path.waypoints)
    np.testing.assert_array_equal(pmplan.plan(o, s, g).path.waypoints,
                                  pmplan.plan(o, s, g, lift=1.0).path.waypoints)
    k = 2.0**-7
    small = pmplan.plan(np.multiply(o, k), np.multiply(s, k), np.multiply(g, k), refine=True,
                        radius=radius * k, obstacle_radius=obstacle_radius * k)
    np.testing.assert_array_equal(small.path.waypoints, auto.path.waypoints * k)
    batch = pmplan.plan_batch(*(np.array(a)[None] for a in (o, s, g)), **kw)
    np.testing.assert_array_equal(batch.waypoints[0], auto.path.waypoints)
