"""Tests of the planar_three planner (paper Section 4, Mathematics §5).

The oracle for strata is an independent classification in exact rational arithmetic
(``fractions.Fraction``) written here from the paper's definitions; exact degenerate queries
are built here in the parametrisation ``o1 + U w + V rot90(w)`` (integer ``w``, half-integer
``U, V``), independently of the module's own generator ``stratum_queries``.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan.examples import planar_three_examples as demo_examples
from pmplan.generators import planar_stratum_queries as stratum_queries
from pmplan.planners.planar_three import (
    PLANAR_THREE,
    STRATA,
    WAYPOINTS,
    parse_stratum,
)

#: the numpy path (the reference; the production path of every query the kernel hands back)
#: gets the same independent checks as the default (numba) one
BACKENDS = [None, "numpy"]

# Mathematics §5 (paper (4.1)-(4.3)): the domains, written out again here on purpose
W_TABLE = {
    1: ("T1_11", "T22_33", "T23_44"),
    2: ("T1_22", "T22_22"),
    3: ("T1_12", "T1_21", "T22_23", "T22_32", "T23_33"),
    4: ("T23_34", "T23_43"),
}
DOMAIN = {s: a for a, names in W_TABLE.items() for s in names}
ALL_STRATA = sorted(DOMAIN)


# ---------------------------------------------------------------------------------------------
# independent exact oracle
# ---------------------------------------------------------------------------------------------
def fraction_memberships(o, x, xp) -> list[str]:
    """Names of all strata whose defining conditions (paper Section 4) hold, exactly."""
    pts = [[Fraction(float(c)) for c in p] for p in (*o, x, xp)]
    o1, o2 = pts[0], pts[1]
    w = (o2[0] - o1[0], o2[1] - o1[1])
    r = (-w[1], w[0])

    def col(p):
        return (p[0] - o1[0]) * w[0] + (p[1] - o1[1]) * w[1]

    def hgt(p):
        return (p[0] - o1[0]) * r[0] + (p[1] - o1[1]) * r[1]

    obs, X, XP = pts[:3], pts[3], pts[4]
    cpo_perp = len({hgt(p) for p in obs})
    cpo = len({col(p) for p in obs})

    def cp_perp(y):
        return len({hgt(p) for p in obs + [y]})

    def cp(y):
        return len({col(p) for p in obs + [y]})

    member = {}
    for i in (1, 2):
        for j in (1, 2):
            member[f"T1_{i}{j}"] = cpo_perp == 1 and cp_perp(X) == i and cp_perp(XP) == j
    for a in (2, 3):
        for b in (2, 3):
            member[f"T22_{a}{b}"] = cpo_perp == 2 and cpo == 2 and cp(X) == a and cp(XP) == b
    for a in (3, 4):
        for b in (3, 4):
            member[f"T23_{a}{b}"] = cpo_perp == 2 and cpo == 3 and cp(X) == a and cp(XP) == b
    return [name for name, ok in member.items() if ok]


def short(stratum: str) -> str:
    return parse_stratum(stratum)


def distinct(points: np.ndarray) -> bool:
    return len({tuple(p) for p in points.tolist()}) == len(points)


# ---------------------------------------------------------------------------------------------
# exact degenerate scenes, built here: o1 + U w + V rot90(w)
# ---------------------------------------------------------------------------------------------
HALF_U = st.integers(-8, 16).map(lambda k: k / 2)
HALF_V = st.integers(-8, 8).map(lambda k: k / 2)
NONZERO_V = st.integers(1, 8).flatmap(lambda k: st.sampled_from([k / 2, -k / 2]))


@st.composite
def scenes(draw, stratum: str):
    """Parameters of an exact query in ``stratum``: a dict, see :func:`realize`."""
    fam, ij = stratum[1:].split("_")
    fam, i, j = int(fam), int(ij[0]), int(ij[1])
    w = draw(st.tuples(st.integers(-3, 3), st.integers(-3, 3)).filter(lambda v: v != (0, 0)))
    o1 = draw(st.tuples(st.integers(-4, 4), st.integers(-4, 4)))
    u2 = float(draw(st.integers(1, 3)))
    if fam == 1:
        u3, v3 = draw(HALF_U.filter(lambda u: u not in (0, u2))), 0.0
    elif fam == 22:
        u3, v3 = draw(st.sampled_from([0.0, u2])), draw(NONZERO_V)
    else:
        u3, v3 = draw(HALF_U.filter(lambda u: u not in (0, u2))), draw(NONZERO_V)
    obs = [(0.0, 0.0), (u2, 0.0), (u3, v3)]
    cols = [0.0, u2] if fam == 22 else [0.0, u2, u3]

    def robot(c):
        if fam == 1 and c == 1:
            return ("free", draw(HALF_U.filter(lambda u: u not in (0, u2, u3))), 0.0)
        if fam == 1:
            return ("free", draw(HALF_U), draw(NONZERO_V))
        if (fam, c) in ((22, 2), (23, 3)):
            k = draw(st.integers(0, len(cols) - 1))
            v = draw(HALF_V.filter(lambda v: (cols[k], v) not in obs))
            return ("col", k, v)
        return ("free", draw(HALF_U.filter(lambda u: u not in cols)), draw(HALF_V))

    return dict(fam=fam, w=np.array(w, float), o1=np.array(o1, float), u2=u2, u3=u3, v3=v3,
                x=robot(i), xp=robot(j))


def realize(p):
    """Exact world coordinates (obstacles (3, 2), start (1, 2), goal (1, 2)) of a scene."""
    w, o1 = p["w"], p["o1"]
    rot = np.array([-w[1], w[0]])

    def at(u, v):
        return o1 + u * w + v * rot

    cols = [0.0, p["u2"]] + ([] if p["fam"] == 22 else [p["u3"]])

    def robot(spec):
        kind, a, v = spec
        return at(cols[a] if kind == "col" else a, v)

    obstacles = np.array([at(0.0, 0.0), at(p["u2"], 0.0), at(p["u3"], p["v3"])])
    return obstacles, robot(p["x"])[None], robot(p["xp"])[None]


def perturb(p, delta: float, k: np.ndarray):
    """Move every free parameter of a scene by ``delta * k_i`` (k: small integers).

    Rotation + scaling (w), translation (o1), o2 along L_C, o3 where its stratum allows, robots
    along their column line (V) and, when off the obstacle columns, across (U). Exact (dyadic).
    """
    q = dict(p)
    q["w"] = p["w"] + delta * k[0:2]
    q["o1"] = p["o1"] + delta * k[2:4]
    q["u2"] = p["u2"] + delta * k[4]
    if p["fam"] in (1, 23):
        q["u3"] = p["u3"] + delta * k[5]
    if p["fam"] in (22, 23):
        q["v3"] = p["v3"] + delta * k[6]
        if p["fam"] == 22 and p["u3"] != 0.0:
            q["u3"] = q["u2"]  # o3 stays on the column of o2
    for key, (a, b) in (("x", (7, 8)), ("xp", (9, 10))):
        kind, c, v = p[key]
        on_line = p["fam"] == 1 and v == 0.0
        if kind == "col":
            q[key] = (kind, c, v + delta * k[a])
        else:
            q[key] = (kind, c + delta * k[b], v if on_line else v + delta * k[a])
    return q


def strata_names(batch) -> list[str]:
    return [short(s) for s in batch.stratum]


# ---------------------------------------------------------------------------------------------
# frame helpers and the polylines of Mathematics §5.4 (written from that page)
# ---------------------------------------------------------------------------------------------
def frame_of(o):
    w = o[1] - o[0]
    length = float(np.hypot(*w))
    e = w / length
    return o[0], e, np.array([-e[1], e[0]]), length


def to_uh(points, o):
    o1, e, nu, _ = frame_of(o)
    rel = np.asarray(points) - o1
    return np.stack([rel @ e, rel @ nu], axis=-1)


def spec_polyline(name, o, x, xp):
    """The polyline of Mathematics §5.4 for a query in stratum ``name``, in (u, h) coordinates."""
    _, _, _, length = frame_of(o)
    (ux, hx), (ug, hg), (u3, h3) = to_uh(np.array([x, xp, o[2]]), o)
    if DOMAIN[name] == 1:
        big = 1 + max(0.0, h3)
        return [(ux, hx), (ux, big), (ug, big), (ug, hg)]
    if name in ("T1_12", "T1_21"):
        return [(ux, hx), (ug, hg)]
    if name in ("T1_22", "T22_22"):
        d = 0.5 * length if name == "T22_22" else 0.5 * min(length, float(np.hypot(*(o[2] - o[0]))))
        return [(ux, hx), (d, hx), (d, hg), (ug, hg)]
    if name == "T22_23":
        return [(ux, hx), (length / 2, hx), (length / 2, h3 / 2), (ug, h3 / 2), (ug, hg)]
    if name in ("T22_32", "T23_43"):
        return spec_polyline(name[:-2] + name[-1] + name[-2], o, xp, x)[::-1]
    cols = sorted([0.0, length, u3])
    s = [(cols[0] + cols[1]) / 2, (cols[1] + cols[2]) / 2, cols[2] + 1]
    sa = s[int(np.argmin([abs(c - ux) for c in cols]))]
    if name == "T23_33":
        sb = s[int(np.argmin([abs(c - ug) for c in cols]))]
        return [(ux, hx), (sa, hx), (sa, h3 / 2), (sb, h3 / 2), (sb, hg), (ug, hg)]
    assert name == "T23_34"
    return [(ux, hx), (sa, hx), (sa, h3 / 2), (ug, h3 / 2), (ug, hg)]


def dedupe(poly, tol):
    out = [np.asarray(poly[0], float)]
    for p in poly[1:]:
        if np.max(np.abs(np.asarray(p) - out[-1])) > tol:
            out.append(np.asarray(p, float))
    return np.array(out)


def sup_distance(pa, pb) -> float:
    """Exact sup over t of the distance between two piecewise-linear paths (robot row)."""
    ts = np.union1d(pa.times, pb.times)
    return float(np.max(np.hypot(*(pa.path(ts)[:, 3] - pb.path(ts)[:, 3]).T)))


# ---------------------------------------------------------------------------------------------
# the planner object
# ---------------------------------------------------------------------------------------------
def test_interface_and_registration():
    assert PLANAR_THREE.name == "planar_three"
    assert PLANAR_THREE.supports(2, 1, 3) is None
    for dims in [(2, 2, 3), (3, 1, 3), (2, 1, 2), (2, 1, 4)]:
        assert isinstance(PLANAR_THREE.supports(*dims), str)
    assert PLANAR_THREE.domain_labels(2, 1, 3) == [1, 2, 3, 4]
    assert pmplan.choose_planner(2, 1, 3).name == "planar_three"
    i = pmplan.info(2, 1, 3)
    assert (i.planner, i.domains, i.tc, i.optimal) == ("planar_three", 4, 4, True)
    assert PLANAR_THREE.stratum_name([1, 1, 2], 2, 1, 3) == "T^{1}_{1,2}"
    assert PLANAR_THREE.stratum_name([22, 3, 3], 2, 1, 3) == "T^{2,2}_{3,3}"
    assert PLANAR_THREE.stratum_name([23, 3, 4], 2, 1, 3) == "T^{2,3}_{3,4}"
    assert sorted(STRATA) == ALL_STRATA
    with pytest.raises(pmplan.UnsupportedError):
        pmplan.plan([[0, 0], [1, 0]], [[0, 1]], [[1, 1]], planner="planar_three")
    with pytest.raises(ValueError, match="unknown stratum"):
        parse_stratum("T3_11")


def test_demo_examples_one_per_domain():
    qs = demo_examples()
    assert len(qs) == 4
    for a, (o, s, g) in enumerate(qs, start=1):
        assert o.shape == (3, 2) and s.shape == (1, 2) and g.shape == (1, 2)
        (name,) = fraction_memberships(o, s[0], g[0])
        assert DOMAIN[name] == a
        p = pmplan.plan(o, s, g)
        assert p.domain == a and p.clearance > 0


# ---------------------------------------------------------------------------------------------
# strata: exact constructions, partition, domains
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("name", ALL_STRATA)
@settings(max_examples=8)
@given(data=st.data())
def test_exact_constructions_classify_and_certify(name, backend, data):
    """Exact scenes of every stratum (random orientation, o3 on both sides) are classified
    into that stratum and domain, and get a certified path with exact endpoints."""
    queries = [realize(data.draw(scenes(name))) for _ in range(4)]
    o = np.stack([q[0] for q in queries])
    s = np.stack([q[1] for q in queries])
    g = np.stack([q[2] for q in queries])
    for q in queries:
        assert fraction_memberships(q[0], q[1][0], q[2][0]) == [name]
    batch = pmplan.plan_batch(o, s, g, backend=backend)
    assert strata_names(batch) == [name] * 4
    assert batch.domain.tolist() == [DOMAIN[name]] * 4
    assert batch.waypoints.shape == (4, WAYPOINTS, 4, 2) and batch.times.shape == (4, WAYPOINTS)
    assert np.all(batch.clearance > 0)
    assert np.array_equal(batch.waypoints[:, 0], np.concatenate([o, s], axis=1))
    assert np.array_equal(batch.waypoints[:, -1], np.concatenate([o, g], axis=1))
    assert np.all(batch.waypoints[:, :, :3] == o[:, None])
    assert np.all(batch.times[:, 0] == 0) and np.all(batch.times[:, -1] == 1)
    assert np.all(np.diff(batch.times, axis=1) >= 0)


@pytest.mark.parametrize("name", ALL_STRATA)
@settings(max_examples=5)
@given(seed=st.integers(0, 2**32 - 1))
def test_stratum_queries_generator(name, seed):
    """The module's generator builds exact queries of the requested stratum (oracle check)."""
    o, s, g = stratum_queries(np.random.default_rng(seed), name, 12)
    assert o.shape == (12, 3, 2) and s.shape == (12, 1, 2) and g.shape == (12, 1, 2)
    sides = set()
    for b in range(12):
        assert fraction_memberships(o[b], s[b, 0], g[b, 0]) == [name]
        sides.add(np.sign(to_uh(o[b, 2], o[b])[1]))
    assert name.startswith("T1") or sides <= {-1.0, 1.0}
    batch = pmplan.plan_batch(o, s, g)
    assert set(strata_names(batch)) == {name}


def test_stratum_queries_paper_notation_and_both_sides():
    rng = np.random.default_rng(7)
    o, _, _ = stratum_queries(rng, "T^{2,3}_{3,4}", 200)
    h3 = np.array([to_uh(o[b, 2], o[b])[1] for b in range(200)])
    assert (h3 > 0).any() and (h3 < 0).any()


def _integer_queries(rng, size, lo=-2, hi=2):
    pts = rng.integers(lo, hi + 1, size=(size, 5, 2)).astype(float)
    keep = [distinct(p[:4]) and distinct(p[[0, 1, 2, 4]]) for p in pts]
    return pts[np.array(keep)]


def _near_degenerate_float_queries(rng, size):
    """Float scenes built by float arithmetic to lie *nearly or exactly* on the columns/heights."""
    o1 = rng.normal(size=(size, 2))
    o2 = o1 + rng.normal(size=(size, 2))
    w = o2 - o1
    rot = np.stack([-w[:, 1], w[:, 0]], axis=1)
    t = rng.choice([0.0, 0.5, 1.0, 0.3, 1 / 3, 2.0], size=(size, 3, 2))
    exact = rng.random(size=(size, 3, 2)) < 0.7
    coef_u = np.where(exact, t, rng.normal(size=(size, 3, 2)))
    pts = o1[:, None] + coef_u[..., :1] * w[:, None] + coef_u[..., 1:] * rot[:, None]
    return np.concatenate([o1[:, None], o2[:, None], pts], axis=1)


@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(["int", "float", "near"]))
def test_strata_partition_the_query_space(seed, kind):
    """Corollary 4.1: every query lies in exactly one of the 12 strata; the planner's exact
    classification agrees with the Fraction oracle; its domain is the one of the W table."""
    rng = np.random.default_rng(seed)
    if kind == "int":
        pts = _integer_queries(rng, 60)
    elif kind == "float":
        pts = rng.normal(scale=3.0, size=(30, 5, 2))
    else:
        pts = _near_degenerate_float_queries(rng, 60)
        pts = pts[[distinct(p[:4]) and distinct(p[[0, 1, 2, 4]]) for p in pts]]
    raw = PLANAR_THREE.plan(pts[:, :3], pts[:, 3:4], pts[:, 4:5])
    for b in range(len(pts)):
        names = fraction_memberships(pts[b, :3], pts[b, 3], pts[b, 4])
        assert len(names) == 1, (pts[b], names)
        got = short(PLANAR_THREE.stratum_name(raw.strata[b], 2, 1, 3))
        assert got == names[0], pts[b]
        assert raw.domain[b] == DOMAIN[names[0]]


def test_every_stratum_occurs_on_the_integer_grid():
    """The strata are all inhabited by integer queries, and all pass the certificate."""
    pts = _integer_queries(np.random.default_rng(3), 4000)
    batch = pmplan.plan_batch(pts[:, :3], pts[:, 3:4], pts[:, 4:5])
    assert set(strata_names(batch)) == set(ALL_STRATA)
    assert np.all(batch.clearance > 0)


# ---------------------------------------------------------------------------------------------
# paths: the construction of Mathematics §5.4, constant speed, reversal, zero length, batch = single
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("name", ALL_STRATA)
@settings(max_examples=8)
@given(data=st.data())
def test_paths_follow_spec_at_constant_speed(name, backend, data):
    o, s, g = realize(data.draw(scenes(name)))
    p = pmplan.plan(o, s, g, backend=backend)
    uh = to_uh(p.path.waypoints[:, 3], o)
    scale = 1 + np.abs(uh).max()
    want = dedupe(spec_polyline(name, o, s[0], g[0]), 1e-9 * scale)
    got = dedupe(uh, 1e-9 * scale)
    assert got.shape == want.shape and np.allclose(got, want, atol=1e-9 * scale)
    # legs are parallel to L_C or to L_C^perp, except the straight segments of Tstraight
    if name not in ("T1_12", "T1_21"):
        legs = np.diff(uh, axis=0)
        assert np.all(np.min(np.abs(legs), axis=1) <= 1e-9 * scale)
    # constant speed (arc length): every piece is run at speed = total length
    disp = np.hypot(*np.diff(p.path.waypoints[:, 3], axis=0).T)
    dt = np.diff(p.path.times)
    total = disp.sum()
    if total > 0:
        assert np.all(dt > 0)
        # (a leg of rounding size -- two waypoints of one exact point, ~1 ulp apart -- has a
        # duration of the same order and no meaningful speed: found on the numba and numpy
        # backends alike, e.g. T1_22 with o = (0, 0), (2, 3), (1, 1.5))
        real = disp > 1e-9 * scale
        assert np.allclose(disp[real] / dt[real], total, rtol=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("name", ["T22_32", "T23_43"])
@settings(max_examples=10)
@given(data=st.data())
def test_reversal_of_the_swapped_query(name, backend, data):
    """T22_32 (T23_43) is the reverse of the T22_23 (T23_34) path of (C', C)."""
    o, s, g = realize(data.draw(scenes(name)))
    forward = pmplan.plan(o, s, g, backend=backend)
    swapped = pmplan.plan(o, g, s, backend=backend)
    assert short(swapped.stratum) == name[:-2] + name[-1] + name[-2]
    assert forward.domain == swapped.domain == DOMAIN[name]
    assert np.array_equal(forward.path.waypoints, swapped.path.waypoints[::-1])
    assert np.allclose(forward.path.times, 1 - swapped.path.times[::-1], atol=1e-15)


@pytest.mark.parametrize("backend", BACKENDS)
@settings(max_examples=15)
@given(data=st.data())
def test_batch_equals_single(backend, data):
    names = data.draw(st.lists(st.sampled_from(ALL_STRATA), min_size=1, max_size=12))
    qs = [realize(data.draw(scenes(n))) for n in names]
    o, s, g = (np.stack([q[k] for q in qs]) for k in range(3))
    batch = pmplan.plan_batch(o, s, g, backend=backend)
    for b, q in enumerate(qs):
        single = pmplan.plan(*q, backend=backend)
        item = batch[b]
        assert (item.domain, item.stratum) == (single.domain, single.stratum)
        assert np.array_equal(item.path.waypoints, single.path.waypoints)
        assert np.array_equal(item.path.times, single.path.times)
        assert item.clearance == single.clearance


def test_zero_length_paths_are_constant():
    o = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 1.5]])  # T23: H = 1 + 1.5
    x = np.array([[2.0, 2.5]])
    p = pmplan.plan(o, x, x)
    assert short(p.stratum) == "T23_44" and p.domain == 1
    assert p.path.length() == 0
    assert np.all(p.path(np.linspace(0, 1, 11))[:, 3] == x[0])
    # T1_22 with x = x' on the vertical u = delta_1 = min(4, 1)/2
    o = np.array([[0.0, 0.0], [4.0, 0.0], [-1.0, 0.0]])
    x = np.array([[0.5, -3.0]])
    p = pmplan.plan(o, x, x)
    assert short(p.stratum) == "T1_22" and p.path.length() == 0
    assert np.all(p.path(np.linspace(0, 1, 11))[:, 3] == x[0])
    # in the batch the constant path is padded to WAYPOINTS waypoints, all equal
    batch = pmplan.plan_batch(o[None], x[None], x[None])
    assert np.all(batch.waypoints[0, :, 3] == x[0])


def test_same_start_and_goal_is_a_loop():
    """C = C' in a stratum with a detour (T22_22): a certified loop back to x."""
    o = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    x = np.array([[2.0, 1.0]])
    p = pmplan.plan(o, x, x)
    assert short(p.stratum) == "T22_22"
    assert p.path.length() > 0 and p.clearance > 0


# ---------------------------------------------------------------------------------------------
# continuity inside every domain
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ALL_STRATA)
@settings(max_examples=6)
@given(data=st.data())
def test_continuity_under_stratum_preserving_perturbations(name, data):
    """Rotating, scaling, translating the scene and moving o2, o3, x, x' along the lines
    their stratum allows by delta moves the path by O(delta) in sup norm."""
    p = data.draw(scenes(name))
    k = np.array(data.draw(st.lists(st.integers(-2, 2), min_size=11, max_size=11)), float)
    base = pmplan.plan(*realize(p))
    sups = []
    for delta in (2.0**-8, 2.0**-12):
        q = realize(perturb(p, delta, k))
        assert fraction_memberships(q[0], q[1][0], q[2][0]) == [name]
        moved = pmplan.plan(*q)
        assert moved.domain == base.domain
        sups.append(sup_distance(base, moved))
    # parameters move points by at most ~ 2 delta (|U| + |V| + 2) |w| <= 60 delta here
    assert sups[0] <= 100 * 2.0**-8
    assert sups[1] <= 100 * 2.0**-12
    assert sups[1] <= sups[0] / 4 + 1e-12  # O(delta): 16 times smaller delta, >= 4 times closer


@settings(max_examples=10)
@given(data=st.data())
def test_W1_is_continuous_across_its_strata(data):
    """W1 = T1_11 u T22_33 u T23_44 is one rule: the T23_44 path tends to the T1_11 path as
    o3 and x, x' approach L_C (heights delta), and to the T22_33 path as o3 approaches the
    column of o1 or o2."""
    p = data.draw(scenes("T1_11"))
    base = pmplan.plan(*realize(p))
    for delta in (2.0**-10, 2.0**-14):
        q = dict(p, fam=23, v3=delta, x=("free", p["x"][1], delta), xp=("free", p["xp"][1], -delta))
        near = realize(q)
        assert fraction_memberships(near[0], near[1][0], near[2][0]) == ["T23_44"]
        assert sup_distance(base, pmplan.plan(*near)) <= 20 * delta
    p = data.draw(scenes("T22_33"))
    base = pmplan.plan(*realize(p))
    delta = 2.0**-12
    q = dict(p, fam=23, u3=p["u3"] + delta)
    near = realize(q)
    assert fraction_memberships(near[0], near[1][0], near[2][0]) == ["T23_44"]
    scale = 1 + np.abs(base.path.waypoints).max()
    assert sup_distance(base, pmplan.plan(*near)) <= 20 * scale * delta
