"""Tests of pmplan.verify: the report, the failure rule, distances, and the CLI."""

import json

import numpy as np
import pytest

import pmplan
from pmplan import generators as gen
from pmplan.cli import main
from pmplan.path import PiecewiseLinearPath
from pmplan.planners.base import REGISTRY, Planner
from pmplan.strata import ColumnStrata
from pmplan.verify import (
    DELTA,
    RHO_MIN,
    Report,
    degeneracy_ratio,
    path_distance,
    query_distance,
    verify,
)

CASES = [("obstacle_line", 2, 2, 2), ("obstacle_line", 3, 1, 2), ("planar_three", 2, 1, 3)]


@pytest.fixture(scope="module")
def reports():
    out = {}
    for planner, d, n, m in CASES:
        if planner not in REGISTRY:
            continue
        out[(planner, d, n, m)] = verify(planner=planner, d=d, n=n, m=m, queries=80, seed=1,
                                         progress=False)
    return out


def _report(reports, case):
    if case not in reports:
        pytest.skip(f"planner {case[0]} is not available")
    return reports[case]


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[0]}-{c[1]}{c[2]}{c[3]}")
def test_verify_is_ok_and_realises_every_label(reports, case):
    r = _report(reports, case)
    planner, d, n, m = case
    assert r.ok, r.to_text()
    assert r.problems == [] and r.failures == []
    assert r.planner == planner and r.dims == [d, n, m]
    labels = list(pmplan.info(d, n, m, planner=planner).labels)
    assert r.labels == labels
    assert r.realised == labels
    assert [dr.label for dr in r.domains] == labels
    for dr in r.domains:
        assert dr.queries > 0 and dr.strata
        assert dr.min_clearance is not None and dr.min_clearance > 0
    # families: all exact and random queries are planned; nothing is counted as failed
    assert r.families["exact"]["planned"] == r.families["exact"]["queries"]
    assert r.families["random"]["planned"] == r.families["random"]["queries"]
    assert all(f["failed"] == 0 for f in r.families.values())


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[0]}-{c[1]}{c[2]}{c[3]}")
def test_continuity_modulus_is_small_and_jumps_are_large(reports, case):
    """Inside a domain paths move by O(delta); across labels by O(1): a clear separation."""
    r = _report(reports, case)
    mods = [dr.modulus for dr in r.domains]
    jumps = [dr.jump for dr in r.domains]
    assert all(x is not None and np.isfinite(x) and x > 0 for x in mods)
    assert all(dr.perturbations > 0 for dr in r.domains)
    assert all(x is not None for x in jumps)
    # a jump is a path change of size O(1) for a query change of size ~delta
    assert min(jumps) > 100 * max(mods)
    assert min(jumps) > 1e-3 / DELTA
    assert r.separation == min(jumps) / max(mods)


def test_strata_are_covered(reports):
    r = _report(reports, ("obstacle_line", 2, 2, 2))
    met = {s for dr in r.domains for s in dr.strata}
    assert met == {f"T_{{{s.cp_start},{s.cp_goal}}}" for s in gen.strata(2, 2, 2)}
    r3 = _report(reports, ("obstacle_line", 3, 1, 2))
    met3 = {s for dr in r3.domains for s in dr.strata}
    assert any("e=N" in s for s in met3) and any("e=N" not in s for s in met3)
    for dr in r3.domains:  # at the pole e == N the label drops by one (Mathematics §4.1)
        for s in dr.strata:
            i, j = (int(c) for c in s[s.index("{") + 1: s.index("}")].split(","))
            assert dr.label == i + j - ("e=N" in s)


def test_planar_three_strata_are_all_covered(reports):
    r = _report(reports, ("planar_three", 2, 1, 3))
    met = sorted(s for dr in r.domains for s in dr.strata)
    assert len(met) == 12


def test_report_json_round_trip(reports):
    for r in reports.values():
        text = r.to_json()
        data = json.loads(text)  # strict JSON: no NaN / Infinity
        assert data["ok"] is True and data["dims"] == r.dims
        assert Report.from_json(text) == r
        assert Report.from_json(text).to_text() == r.to_text()


def test_report_text_mentions_every_domain(reports):
    r = _report(reports, ("obstacle_line", 2, 2, 2))
    text = r.to_text()
    for dr in r.domains:
        assert f"W_{dr.label} " in text
    assert text.splitlines()[-1] == "OK"
    assert "labels realised: 5/5" in text


def test_verify_is_reproducible():
    a = verify(d=2, n=1, m=2, queries=20, seed=3, progress=False)
    b = verify(d=2, n=1, m=2, queries=20, seed=3, progress=False)
    assert a == b


# --------------------------------------------------------------------------------------------
# the failure rule and a broken planner


class _BrokenLine(Planner):
    """The obstacle-line planner with a bug: in even domains robot 1 visits o1 mid-way (the
    required members of the planner protocol only: no kernel, no fast path)."""

    name = "broken_line"
    summary = "obstacle_line with a collision in even domains (test double)"

    def __init__(self):
        self.base = REGISTRY["obstacle_line"]

    def supports(self, d, n, m):
        return self.base.supports(d, n, m)

    def domain_labels(self, d, n, m, r=2):
        return self.base.domain_labels(d, n, m, r)

    def stratum_name(self, row, d, n, m):
        return self.base.stratum_name(row, d, n, m)

    def allocate(self, b, r, m, n, d):
        return self.base.allocate(b, r, m, n, d)

    def reference(self, obstacles, configs, lift):
        raw = self.base.reference(obstacles, configs, lift)
        wp = raw.path.waypoints.copy()
        m = np.asarray(obstacles).shape[1]
        bad = raw.domain % 2 == 0
        wp[bad, 4, m] = wp[bad, 4, 0]  # robot 1 on o1 at tau = 5/9: a collision
        raw.path = PiecewiseLinearPath(raw.path.times, wp)
        return raw


@pytest.fixture
def broken(monkeypatch):
    monkeypatch.setitem(REGISTRY, "broken_line", _BrokenLine())
    return "broken_line"


def test_broken_planner_is_not_ok(broken):
    r = verify(planner=broken, d=2, n=2, m=2, queries=40, progress=False)
    assert not r.ok
    assert r.failures and all(f["rho"] >= RHO_MIN for f in r.failures)
    assert r.families["exact"]["failed"] > 0
    assert "certificate failure" in r.problems[0]
    assert r.to_text().splitlines()[-1] == "NOT OK"
    # every query of an even domain was refused, the odd domains are untouched
    assert r.realised == [5, 7]
    assert any("never realised: [4, 6, 8]" in p for p in r.problems)


def test_cli_verify_exit_status(broken, capsys):
    assert main(["verify", "--planner", broken, "--queries", "30", "--no-progress"]) == 1
    assert "NOT OK" in capsys.readouterr().out
    assert main(["verify", "--d", "2", "--n", "1", "--m", "2", "--queries", "30", "--json",
                 "--no-progress"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["ok"] is True and data["realised"] == data["labels"] == [4, 5, 6]


def test_degeneracy_ratio_separates_exact_and_nearly_degenerate_queries():
    rng = np.random.default_rng(0)
    exact = [gen.column_query(rng, 2, 2, 2, 2, 3) for _ in range(10)]
    q = tuple(np.stack(a) for a in zip(*exact))
    assert np.all(degeneracy_ratio(*q) >= RHO_MIN)  # exact ties are not near-degenerate
    near = gen.near_degenerate_queries(rng, 2, 2, 2, 20, 1e-15)
    rho = degeneracy_ratio(*near)
    # a tie broken at ~1e-15 of the scene is far below 2^-26 (strata without ties are not)
    assert np.any(rho < RHO_MIN)
    assert np.all((rho < 1e-12) | (rho >= RHO_MIN))


def test_nearly_degenerate_refusals_are_excused():
    # the paper's lanes: with this seed some ties at 1e-15 cannot be planned in floats (its
    # projection puts robots of columns 1e-15 apart that close on the line, Mathematics §6.2)
    r = verify(planner="obstacle_line", d=2, n=3, m=2, queries=200, seed=0, progress=False)
    near = r.families["near-degenerate"]
    assert near["planned"] + near["excused"] + near["failed"] == near["queries"]
    assert near["excused"] > 0
    assert near["failed"] == 0 and r.ok
    # the compact lanes (the default) keep those robots apart: nothing fails there either
    r = verify(d=2, n=3, m=2, queries=200, seed=0, progress=False)
    near = r.families["near-degenerate"]
    assert near["planned"] + near["excused"] == near["queries"]
    assert near["failed"] == 0 and r.ok


# --------------------------------------------------------------------------------------------
# distances


def test_path_distance_is_the_supremum():
    rng = np.random.default_rng(0)
    b, p, d = 6, 3, 2
    ta = np.sort(np.concatenate([np.zeros((b, 1)), rng.random((b, 3)), np.ones((b, 1))], 1), 1)
    tb = np.linspace(0, 1, 4)
    a = PiecewiseLinearPath(ta, rng.normal(size=(b, 5, p, d)))
    c = PiecewiseLinearPath(tb, rng.normal(size=(b, 4, p, d)))
    exact = path_distance(a, c)
    t = np.linspace(0, 1, 2001)
    sampled = np.stack([np.linalg.norm(a[i](t) - c[i](t), axis=-1).max() for i in range(b)])
    assert np.all(sampled <= exact + 1e-12)
    assert np.all(exact - sampled < 0.02 * exact)
    assert np.all(path_distance(a, a) == 0)


def test_query_distance_is_the_largest_displacement():
    o = np.zeros((2, 2, 2))
    o[:, 1, 0] = 1.0
    x = np.ones((2, 2, 2))
    y = x.copy()
    y[0, 1] += [3.0, 4.0]
    y[1, 0] += [0.0, -2.0]
    np.testing.assert_allclose(query_distance((o, x, x), (o, y, x)), [5.0, 2.0])


# --------------------------------------------------------------------------------------------
# the branches of the continuity step: perturbed queries refused, labels changed


def _leave_the_stratum(planner, rng, q, delta):
    """A wrong "stratum-preserving" move: every robot off its column by ~delta (generic)."""
    o, s, g = (np.array(a, dtype=float) for a in q)
    return o, s + delta * rng.normal(size=s.shape), g + delta * rng.normal(size=g.shape)


def test_a_label_change_under_perturbation_is_a_problem(monkeypatch):
    """Perturbations that leave the stratum change the label of degenerate queries: verify must
    say so (and not count them in the continuity modulus)."""
    monkeypatch.setattr(ColumnStrata, "perturb_within_stratum", _leave_the_stratum)
    r = verify(d=2, n=2, m=2, queries=40, seed=0, progress=False)
    assert not r.ok
    (problem,) = [p for p in r.problems if "changed the label" in p]
    count, rest = problem.split(" ", 1)
    a, b = (int(x) for x in rest.split("(e.g. ")[1].rstrip(")").split(" -> "))
    assert int(count) > 0 and a != b and {a, b} <= set(r.labels)
    assert r.to_text().splitlines()[-1] == "NOT OK"
    assert f"problem: {problem}" in r.to_text()


def test_refused_perturbations_that_double_precision_can_represent_are_failures(broken,
                                                                                monkeypatch):
    """The broken planner refuses even domains; moved off their strata, queries of odd domains
    land in the even domain 8 (generic), so the perturbed family is refused: failures."""
    monkeypatch.setattr(ColumnStrata, "perturb_within_stratum", _leave_the_stratum)
    r = verify(planner=broken, d=2, n=2, m=2, queries=40, seed=0, progress=False)
    perturbed = [f for f in r.failures if f["family"] == "perturbed"]
    assert perturbed and all(f["rho"] >= RHO_MIN for f in perturbed)
    assert all(f["error"] == "CertificationError" for f in perturbed)
    assert all(f["stratum"] == "T_{4,4}" for f in perturbed)  # generic: the domain W_8
    assert not r.ok and "certificate failure" in r.problems[0]
    text = r.to_text()
    assert sum(line.startswith("FAILED: ") for line in text.splitlines()) == min(10, len(r.failures))
    assert len(r.failures) <= 10 or f"and {len(r.failures) - 10} more failures" in text


def test_refused_nearly_degenerate_perturbations_are_excused(monkeypatch):
    """A perturbed query that double precision cannot represent (rho < 2^-26) may be refused:
    not a failure, and no modulus is computed from it."""
    near = (np.array([[0.0, 0.0], [1.0, 2.0]]), np.array([[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]]),
            np.array([[5.0, 5.0], [6.0, -7.0]]))
    assert degeneracy_ratio(*(a[None] for a in near))[0] < RHO_MIN
    with pytest.raises(pmplan.CertificationError):  # (the paper's projection, Mathematics §6.2)
        pmplan.plan(*near, planner="obstacle_line")
    monkeypatch.setattr(ColumnStrata, "perturb_within_stratum", lambda planner, rng, q, delta: near)
    r = verify(planner="obstacle_line", d=2, n=2, m=2, queries=40, seed=0, progress=False)
    assert r.ok, r.problems
    assert not [f for f in r.failures if f["family"] in ("perturbed", "exact+random")]
    assert all(d.perturbations == 0 and d.modulus is None for d in r.domains)


# --------------------------------------------------------------------------------------------
# odd d: the note on the pole, and the figures it states


def test_odd_d_report_carries_the_pole_note(reports):
    from pmplan.verify import POLE_NOTE

    odd = _report(reports, ("obstacle_line", 3, 1, 2))
    assert odd.notes == [POLE_NOTE]
    assert f"note: {POLE_NOTE}" in odd.to_text()
    assert json.loads(odd.to_json())["notes"] == [POLE_NOTE]
    assert Report.from_json(odd.to_json()) == odd
    even = _report(reports, ("obstacle_line", 2, 2, 2))
    assert even.notes == [] and "note:" not in even.to_text()


def _pole_modulus(angle, eps=1e-9, lift=1.0):
    """sup |path - path'| when o2 turns by eps about N at ``angle`` from N (d = 3, n = 2)."""
    start = np.array([[0.6, -1.3, 0.4], [-0.9, 0.5, 1.7]])
    goal = np.array([[1.1, 0.8, -0.6], [-0.4, -1.5, 0.9]])
    o = np.array([[0.0, 0.0, 0.0], [np.sin(angle), 0.0, np.cos(angle)]])
    o2 = o.copy()
    o2[1, 1] = eps
    a, b = (pmplan.plan(obs, start, goal, lift=lift, planner="obstacle_line") for obs in (o, o2))
    assert a.domain == b.domain  # one domain: this is continuity inside it, not a jump
    return path_distance(*(PiecewiseLinearPath(p.path.times, p.path.waypoints[None])
                           for p in (a, b)))[0]


def test_odd_d_modulus_near_the_pole_grows_like_one_over_the_angle():
    """The figures of POLE_NOTE (Mathematics §4.1, the tutorial): about 2 n lambda / angle; 0.4 at 1e-8 rad."""
    for angle in (1e-2, 1e-4, 1e-6, 1e-8):
        ratio = _pole_modulus(angle) / 1e-9
        assert 3.9 < angle * ratio < 4.1, (angle, ratio)  # 2 n lambda = 2 * 2 * 1
    assert 0.35 < _pole_modulus(1e-8) < 0.45
    assert 7.8 < 1e-6 * _pole_modulus(1e-6, lift=2.0) / 1e-9 < 8.2  # lambda = lift here


def test_verify_refuses_bad_sizes():
    with pytest.raises(pmplan.InputError, match="`queries` must be an integer from 10 to 100,000"):
        verify(queries=5, progress=False)
    with pytest.raises(pmplan.InputError, match="`seed` must be an integer at least 0"):
        verify(seed=-1, progress=False)
    with pytest.raises(pmplan.InputError, match="more than 200,000,000"):
        verify(d=40, n=40, m=40, progress=False)


# --------------------------------------------------------------------------------------------
# verify asks the planner (planners/base.py), never its name


@pytest.mark.parametrize("name, dims", [("planar_three", (2, 1, 3)), ("obstacle_line", (3, 2, 2))])
def test_verify_does_not_branch_on_a_planner_name(monkeypatch, name, dims):
    """A planner registered under another name gets the same report: its query families, moves
    inside a stratum, stratum names and notes come from its protocol, not from its name."""
    cls = type(REGISTRY[name])
    twin = type("Twin", (cls,), {"name": "twin_under_another_name"})()
    monkeypatch.setitem(REGISTRY, twin.name, twin)
    d, n, m = dims
    a = json.loads(verify(planner=name, d=d, n=n, m=m, queries=40, progress=False).to_json())
    b = json.loads(verify(planner=twin.name, d=d, n=n, m=m, queries=40, progress=False).to_json())
    assert a.pop("planner") == name and b.pop("planner") == twin.name
    assert a == b
    assert a["ok"] and a["realised"] == a["labels"]
    assert bool(a["notes"]) == (name == "obstacle_line" and d % 2 == 1)


# --------------------------------------------------------------------------------------------
# verify(refine=True) refines every plan once: the continuity pass reuses the family pass's
# refined plans of the base queries Q and refines only the moved queries Q'


def _row_keys(batch) -> list[bytes]:
    """One key per plan of a batch: the bytes of its breakpoints and waypoints."""
    times = np.broadcast_to(batch.times, (len(batch), batch.times.shape[-1]))
    return [t.tobytes() + w.tobytes() for t, w in zip(times, batch.waypoints)]


def _refusing_refine(monkeypatch, log: list | None = None) -> None:
    """Make ``pmplan.api.refine`` refuse (CertificationError naming them) the plans whose key
    hashes to 0 mod 4 -- a rule of the plan alone, as a certificate is -- and log the keys of
    the plans it refines."""
    import hashlib
    import sys

    from pmplan.errors import CertificationError

    api = sys.modules["pmplan.api"]
    real = api.refine

    def refine(batch, **kwargs):
        keys = _row_keys(batch)
        bad = [i for i, k in enumerate(keys) if hashlib.sha256(k).digest()[0] % 4 == 0]
        if bad:
            raise CertificationError("refused by the test", indices=np.array(bad))
        if log is not None:
            log.append(keys)
        return real(batch, **kwargs)

    monkeypatch.setattr(api, "refine", refine)


@pytest.mark.parametrize("planner, d, n, m", [("obstacle_line", 2, 2, 2),
                                              ("planar_three", 2, 1, 3)])
def test_reused_refined_plans_are_what_refining_again_gives(monkeypatch, planner, d, n, m):
    """The reuse is exact: planning rows of a family again gives the family's plans bit for
    bit, and the refined plans ``_refined_rows`` takes from the family pass (refused ones
    left out) are those that refining the plans again gives, in the order asked."""
    from pmplan.verify import _plan_each, _refine_each, _refined_rows

    _refusing_refine(monkeypatch)
    rng = np.random.default_rng(7)
    planned, refined = {}, {}
    for name in ("exact", "random"):
        q = tuple(gen.random_queries(rng, d, n, m, 16))
        batch, kept, _ = _plan_each(q, planner)
        rb, rk, refused = _refine_each(batch)
        assert refused and rk.size  # some refused, some refined
        planned[name], refined[name] = (q, batch, kept), (rb, rk)
    # rows as the continuity pass asks them: exact ones first, refused ones among them
    fams = np.array(["exact"] * 10 + ["random"] * 9)
    rows = np.concatenate([np.arange(10), np.arange(3, 12)])
    paths, at = _refined_rows(refined, fams, rows)
    base = tuple(np.concatenate([np.asarray(planned[f][0][k])[planned[f][2][rows[fams == f]]]
                                 for f in ("exact", "random")]) for k in range(3))
    b0, k0, _ = _plan_each(base, planner)
    assert k0.size == rows.size
    for f in ("exact", "random"):
        same = planned[f][1][rows[fams == f]]
        assert np.array_equal(b0.waypoints[fams == f], same.waypoints)
        assert np.array_equal(b0.clearance[fams == f], same.clearance)
    r0, k0r, refused = _refine_each(b0)
    assert refused and 0 < at.size < rows.size
    assert np.array_equal(at, k0r)
    assert np.array_equal(paths.waypoints, r0.waypoints)
    assert np.array_equal(paths.times, np.broadcast_to(r0.times, paths.times.shape))


def test_verify_refine_refines_each_plan_once(monkeypatch):
    """The plans the continuity pass refines (those of the moved queries Q', one batch per
    perturbation size) are none of the plans the family pass refined: the base queries' refined
    plans are reused, not refined again; with refusals among them, the report still counts
    them as refused."""
    from pmplan.verify import REFINE_DELTAS

    log: list = []
    _refusing_refine(monkeypatch, log)
    r = verify(d=2, n=2, m=2, queries=30, seed=2, progress=False, refine=True)
    families = [k for k in r.families if k.startswith("refined ")]
    # one refinement per family, one of Q' per perturbation size
    assert len(families) == 3 and len(log) == 3 + len(REFINE_DELTAS)
    family_keys = set().union(*log[:3])
    assert sum(r.families[k]["planned"] for k in families) == len(family_keys)
    for moved in log[3:]:
        assert moved and family_keys.isdisjoint(moved)
    assert any(r.families[k]["failed"] for k in families)  # refusals met
    assert any(dr.refined_perturbations for dr in r.domains)
