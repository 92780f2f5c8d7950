"""The fused numba kernel of the planar three-obstacle planner against its numpy reference.

``backend="numba"`` (:mod:`pmplan.kernels.planar`) must reproduce ``backend="numpy"`` (the
reference code of :mod:`pmplan.planners.planar_three` with :mod:`pmplan.predicates`,
:mod:`pmplan.frame`, :mod:`pmplan.path`, :mod:`pmplan.certify`) exactly. What is checked, and
why it can fail:

* waypoints, breakpoints (per query, padded to WAYPOINTS = 6 points), domains, stratum records
  and certified clearances are *equal* (``==``, no tolerance: the kernel does the reference's floating-point
  operations in the reference's order) on the exact constructions of all 12 strata (which the
  kernel decides alone: no flag, otherwise the comparison would be vacuous), on generic floats,
  on exactly degenerate grid queries, on near-degenerate and rescaled mixed batches (also
  those of :mod:`pmplan.generators`);
* the exact constructions land in the stratum and domain they were built for (paper Section 4,
  (4.1)-(4.3)), start and end exactly at the query, at breakpoints 0 and 1;
* each re-decision route is taken where it must be: an exact tie only fractions can see
  (``FALLBACK``), a clearance ~1e-10 of the scene (``SUSPECT``), an overflowing ``o2 - o1``;
* the same queries fail their certificate, with the same indices (``CertificationError``);
* the single-query fast path (the numba backend's ``single_query``) gives the reference
  :class:`pmplan.Plan` and the reference errors; chunked planning equals unchunked planning;
* the SIMD path (:func:`pmplan.kernels.planar._plan_lanes`, generic queries LANES at a time)
  gives bit for bit what the scalar kernel gives (waypoints, breakpoints, domains, strata,
  clearances, flags) on random, exactly degenerate (integer) and mixed batches of every size
  around the lane width, and which path plans a query never shows (a query planned inside a
  batch is the query planned alone);
* the kernel is compiled for one signature only.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import backends, planar_strata, running
from pmplan.errors import CertificationError, PmplanError
from pmplan.generators import near_degenerate_queries, random_queries
from pmplan.generators import planar_stratum_queries as stratum_queries
from pmplan.kernels import planar as kernels_planar
from pmplan.planners import planar_three
from pmplan.planners.base import SCENE_CODE
from pmplan.planners.planar_three import (
    DOMAIN_OF,
    PLANAR_THREE,
    STRATA,
    WAYPOINTS,
    stratum_short_name,
)


def _kernel(o, s, g, lift=1.0, validate=False, path="chunk"):
    """Run the kernel alone on a batch; return (flags (B,), outputs dict). ``path``: "chunk"
    (:func:`plan_chunk`: the SIMD path, then the scalar kernel) or "scalar" (the scalar kernel
    on every row). Outputs start as NaN (flags as 255), so rows a kernel leaves alone compare
    equal too."""
    o, s, g = (np.ascontiguousarray(a, dtype=float) for a in (o, s, g))
    b = o.shape[0]
    out = {k: np.full_like(v, np.nan if v.dtype.kind == "f" else -1)
           for k, v in PLANAR_THREE.allocate(b, 2, 3, 1, 2).items()}
    flags = np.full(b, 255, np.uint8)
    args = (o, s, g, planar_strata.EVEN, lift, validate, out["times"], out["waypoints"], out["domain"],
            out["strata"], out["clearance"], flags)
    if path == "chunk":
        kernels_planar.plan_chunk(*args)
    else:
        sel = np.arange(b, dtype=np.int64)
        kernels_planar.plan_planar(*args, sel, b)
    return flags, out


def _outcome(fn, *args, **kwargs):
    """The result, or the (type, message, indices) of the pmplan error raised."""
    try:
        return fn(*args, **kwargs)
    except PmplanError as exc:
        idx = getattr(exc, "indices", None)
        return type(exc), str(exc), None if idx is None else tuple(np.asarray(idx).tolist())


def _both(o, s, g):
    fast = _outcome(pmplan.plan_batch, o, s, g, backend="numba")
    ref = _outcome(pmplan.plan_batch, o, s, g, backend="numpy")
    assert_same_batch(fast, ref)
    return fast


def assert_same_batch(a, b):
    if isinstance(a, tuple) or isinstance(b, tuple):
        assert a == b
        return
    assert a.waypoints.shape == b.waypoints.shape == (len(b), WAYPOINTS, 4, 2)
    assert np.array_equal(a.waypoints, b.waypoints)
    assert np.array_equal(a.times, b.times)
    assert np.array_equal(a.domain, b.domain)
    assert np.array_equal(a.strata, b.strata)
    assert np.array_equal(a.clearance, b.clearance)
    assert (a.planner, a.dims) == (b.planner, b.dims) == ("planar_three", (2, 1, 3))


def _mixed(rng, names, count, exponent=0, noise=0.0):
    """``count`` exact queries of every stratum in ``names``, shuffled, scaled by 2**exponent
    and translated by a dyadic vector (still exact); then ``noise`` relative perturbation."""
    parts = [stratum_queries(rng, name, count) for name in names]
    o, s, g = (np.concatenate(a) for a in zip(*parts))
    perm = rng.permutation(o.shape[0])
    shift = rng.integers(-64, 65, size=2) / 8.0
    o, s, g = (a[perm] * 2.0**exponent + shift for a in (o, s, g))
    if noise:
        o, s, g = (a + noise * (1 + np.abs(a)) * rng.normal(size=a.shape) for a in (o, s, g))
    return o, s, g


def test_tables_agree_with_the_planner():
    """The kernel's stratum codes and domains are the planner's (paper (4.1)-(4.3))."""
    assert kernels_planar.WAYPOINTS is planar_three.WAYPOINTS is WAYPOINTS == 6  # one source
    assert np.array_equal(kernels_planar.CODE_LUT, planar_strata.LUT)
    assert np.array_equal(kernels_planar._DOMAIN, [DOMAIN_OF[name] for name in STRATA])
    assert planar_strata.EVEN.shape == (WAYPOINTS + 1, WAYPOINTS)
    for k in range(2, WAYPOINTS + 1):
        assert np.array_equal(planar_strata.EVEN[k, :k], np.linspace(0.0, 1.0, k))


@pytest.mark.parametrize("name", STRATA)
def test_exact_constructions_equal_reference(name):
    """Every stratum's exact queries (also rescaled by powers of two): identical to the
    reference, decided by the kernel alone, in the right stratum and domain, exact ends."""
    rng = np.random.default_rng(sum(map(ord, name)))
    o, s, g = _mixed(rng, [name], 40, exponent=int(rng.integers(-20, 21)))
    flags, _ = _kernel(o, s, g)
    assert not flags.any()  # the float filter and the error-free stage decide everything
    fast = _both(o, s, g)
    assert {stratum_short_name(row) for row in fast.strata} == {name}
    assert (fast.domain == DOMAIN_OF[name]).all()
    assert np.array_equal(fast.waypoints[:, 0, 3], s[:, 0])
    assert np.array_equal(fast.waypoints[:, -1, 3], g[:, 0])
    assert (fast.waypoints[:, :, :3] == o[:, None]).all()
    assert (fast.times[:, 0] == 0).all() and (fast.times[:, -1] == 1).all()
    assert (np.diff(fast.times, axis=1) >= 0).all()
    assert (fast.clearance > 0).all()


@settings(max_examples=40)
@given(st.booleans().flatmap(
    lambda degenerate: st.tuples(
        st.just(degenerate),
        st.lists(queries(2, 3, 1, degenerate=degenerate), min_size=1, max_size=6))))
def test_random_batches_equal_reference(case):
    """Generic floats and exactly degenerate grid queries (hypothesis strategies)."""
    degenerate, qs = case
    o, s, g = (np.stack(a) for a in zip(*qs))
    _both(o, s, g)
    if not degenerate:  # generic queries are decided by the kernel alone
        flags, _ = _kernel(o, s, g)
        assert not (flags & kernels_planar.FALLBACK).any()


@settings(max_examples=30)
@given(st.integers(0, 2**32 - 1), st.lists(st.sampled_from(STRATA), min_size=1, max_size=12),
       st.integers(-40, 40), st.sampled_from([0.0, 1e-9, 1e-12, 1e-15]))
def test_mixed_near_degenerate_batches_equal_reference(seed, names, exponent, noise):
    """Mixed strata, rescaled, with ties broken by relative noise down to 1e-15 (where some
    queries need the exact stages, and some paths fail their certificate): same outcome."""
    rng = np.random.default_rng(seed)
    o, s, g = _mixed(rng, names, 3, exponent=exponent, noise=noise)
    _both(o, s, g)


@pytest.mark.parametrize("scale", [1e-9, 1e-13, 1e-15])
def test_generator_queries_equal_reference(scale):
    """pmplan.generators: generic normal queries and near-degenerate column queries of the
    (d, n, m) = (2, 1, 3) strata with ties broken at ``scale`` (at 1e-15 some paths fail)."""
    rng = np.random.default_rng(int(-np.log10(scale)))
    generic = random_queries(rng, 2, 1, 3, 200)
    flags, _ = _kernel(*generic)
    assert not flags.any()
    _both(*generic)
    near = near_degenerate_queries(rng, 2, 1, 3, 60, scale=scale)
    _both(near.obstacles, near.start, near.goal)


def test_certificate_failures_agree():
    """Scenes of size ~2**60, where the paper's unit (H = 1 + max(0, h3), s3 = c3 + 1) is below
    the resolution of the coordinates, fail their certificate in both backends, with the same
    indices; the rescaled queries around them are planned."""
    rng = np.random.default_rng(4)
    o, s, g = _mixed(rng, STRATA, 4)
    big = np.zeros(o.shape[0], dtype=bool)
    big[rng.choice(o.shape[0], size=12, replace=False)] = True
    o, s, g = (np.where(big[:, None, None], a * 2.0**60, a) for a in (o, s, g))
    fast = _both(o, s, g)
    assert fast[0] is CertificationError
    assert 0 < len(fast[2]) <= 12 and big[list(fast[2])].all()


def test_tiny_clearance_is_decided_exactly():
    """T1_12: x on L_C, 1e-10 from o2, goes straight to x'. The clearance is below certify's
    float threshold: the kernel flags SUSPECT and certify.clearance decides it exactly."""
    o = np.array([[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]])
    s = np.array([[[1.0 + 1e-10, 0.0]]])
    g = np.array([[[2.0, 1.0]]])
    flags, _ = _kernel(o, s, g)
    assert flags[0] == kernels_planar.SUSPECT
    fast = _both(o, s, g)
    assert stratum_short_name(fast.strata[0]) == "T1_12"
    assert 0.9e-10 < fast.clearance[0] < 1.1e-10


def test_exact_tie_only_fractions_see_goes_to_the_reference():
    """(0.3, -0.1) . (0.1, 0.3) == 0 exactly, but its products are inexact: the error-free stage
    cannot decide, the kernel flags FALLBACK and the numpy reference decides (x on the column
    of o1: cp(C) = 3, stratum T23_34)."""
    o = np.array([[[0.0, 0.0], [0.1, 0.3], [2.0, 0.0]], [[0.0, 0.0], [4.0, 0.0], [2.5, 1.5]]])
    s = np.array([[[0.3, -0.1]], [[0.0, -2.0]]])
    g = np.array([[[3.0, 3.0]], [[6.0, 2.5]]])
    flags, _ = _kernel(o, s, g)
    assert flags.tolist() == [kernels_planar.FALLBACK, 0]
    fast = _both(o, s, g)
    assert fast.strata.tolist() == [[23, 3, 4], [23, 3, 4]]
    raw = PLANAR_THREE.plan(o, s, g, backend="numba")
    ref = PLANAR_THREE.plan(o, s, g, backend="numpy")
    assert np.array_equal(raw.path.waypoints, ref.path.waypoints)
    assert np.array_equal(raw.path.times, ref.path.times)
    assert np.array_equal(raw.strata, ref.strata) and np.array_equal(raw.domain, ref.domain)
    one = pmplan.plan(o[0], s[0], g[0])  # flagged: the fast path hands over to the reference
    assert one.stratum == "T^{2,3}_{3,4}" and one.clearance == fast.clearance[0]


def test_overflowing_direction_goes_to_the_reference():
    """o2 - o1 overflows: the kernel flags FALLBACK; both backends give the same outcome."""
    o = np.array([[[-1e308, 0.0], [1e308, 0.0], [0.0, 1.0]]])
    s = np.array([[[5.0, 5.0]]])
    g = np.array([[[7.0, -3.0]]])
    with np.errstate(all="ignore"):
        flags, _ = _kernel(o, s, g)
        assert flags[0] & kernels_planar.FALLBACK
        _both(o, s, g)


@settings(max_examples=30)
@given(st.booleans().flatmap(lambda degenerate: queries(2, 3, 1, degenerate=degenerate)))
def test_single_plan_equals_reference(q):
    """The lean single-query path gives the reference Plan (compacted breakpoints)."""
    fast = pmplan.plan(*q)
    ref = pmplan.plan(*q, backend="numpy")
    assert (fast.domain, fast.stratum, fast.clearance, fast.planner, fast.dims) == (
        ref.domain, ref.stratum, ref.clearance, ref.planner, ref.dims)
    assert np.array_equal(fast.path.times, ref.path.times)
    assert np.array_equal(fast.path.waypoints, ref.path.waypoints)
    assert (np.diff(fast.path.times) > 0).all()


@pytest.mark.parametrize("name", STRATA)
def test_single_plan_of_every_stratum_uses_the_kernel(name):
    o, s, g = stratum_queries(np.random.default_rng(3), name, 4)
    for q in zip(o, s, g):
        res = backends.select("numba").single_query(PLANAR_THREE, 3, 1, 2)(*q, 1.0)
        assert res is not None  # decided and certified by the kernel
        times, wp, domain, row, clearance = res
        ref = pmplan.plan(*q, backend="numpy")
        assert (domain, stratum_short_name(row), clearance) == (
            ref.domain, name, ref.clearance)
        assert np.array_equal(times, ref.path.times)
        assert np.array_equal(wp, ref.path.waypoints)
        assert pmplan.plan(*q).stratum == ref.stratum


O = [[0.0, 0.0], [4.0, 0.0], [2.5, 1.5]]


@pytest.mark.parametrize("args, kwargs", [
    ((O, [[0.0, -2.0]], [[6.0, 2.5]]), {}),
    ((O, [[0.0, -2.0]], [[6.0, 2.5]]), {"lift": -1.0}),
    ((O, [[0.0, -2.0]], [[6.0, 2.5]]), {"backend": "cuda"}),
    ((O, [[np.nan, -2.0]], [[6.0, 2.5]]), {}),
    ((O, [[0.0, -2.0]], [[np.inf, 2.5]]), {}),
    ((O, [[2.5, 1.5]], [[6.0, 2.5]]), {}),
    ((O, [[0.0, -2.0]], [[0.0, 0.0]]), {}),
    (([[0.0, 0.0], [0.0, 0.0], [2.5, 1.5]], [[0.0, -2.0]], [[6.0, 2.5]]), {}),
    (([[0.0, 0.0], [4.0, 0.0], [4.0, 0.0]], [[0.0, -2.0]], [[6.0, 2.5]]), {}),
    ((O, [[0.0, -2.0]], [[6.0, 2.5, 1.0]]), {}),
    ((O, [[0.0, -2.0]], [[6.0, 2.5]]), {"planner": "obstacle_line"}),
])
def test_fast_path_errors_are_the_reference_errors(args, kwargs):
    fast = _outcome(pmplan.plan, *args, **kwargs)
    if kwargs.get("backend") is not None:
        assert isinstance(fast, tuple) and issubclass(fast[0], PmplanError)
        return
    ref = _outcome(pmplan.plan, *args, **kwargs, backend="numpy")
    if isinstance(ref, tuple):
        assert fast == ref
    else:
        assert (fast.domain, fast.stratum, fast.clearance) == (ref.domain, ref.stratum,
                                                               ref.clearance)
        assert np.array_equal(fast.path.waypoints, ref.path.waypoints)


def test_chunks(monkeypatch):
    """Chunk boundaries change nothing (CHUNK = 7 on a mixed batch of 36)."""
    o, s, g = _mixed(np.random.default_rng(8), STRATA, 3)
    whole = pmplan.plan_batch(o, s, g)
    monkeypatch.setattr(running, "CHUNK", 7)
    assert_same_batch(pmplan.plan_batch(o, s, g), whole)
    assert_same_batch(pmplan.plan_batch(o, s, g, backend="numpy"), whole)


def test_one_specialisation():
    """Batches, single queries and other input dtypes/layouts reuse one compiled kernel."""
    o, s, g = _mixed(np.random.default_rng(9), STRATA, 2)
    pmplan.plan_batch(o.astype(np.float32), s, g[::1])
    pmplan.plan_batch(np.asfortranarray(o), s, g)
    pmplan.plan(o[0].tolist(), s[0], g[0])
    PLANAR_THREE.plan(o, s, g)
    frozen = [a.copy() for a in (o, s, g)]
    for a in frozen:  # read-only input (a memory map, say) is copied, not compiled for
        a.flags.writeable = False
    pmplan.plan_batch(*frozen)
    PLANAR_THREE.plan(*frozen)
    o, s, g = (np.repeat(a, 40, axis=0) for a in (o, s, g))  # > LANES queries: the SIMD path
    pmplan.plan_batch(o, s, g)
    pmplan.plan_batch(o, s, g, workers=2)
    assert len(kernels_planar.plan_planar.signatures) == 1
    assert len(kernels_planar._plan_lanes.signatures) == 1
    assert len(kernels_planar.plan_planar_one.signatures) == 1


# --- the SIMD path (_plan_lanes) against the scalar kernel, bit for bit ----------------------
SIZES = [0, 1, 15, 16, 63, 64, 65, 200]


def _bits(out: dict, flags: np.ndarray) -> dict:
    """Every output as raw bytes (so -0.0 and +0.0, and NaN payloads, differ)."""
    res = {k: v.view(np.uint8).tobytes() for k, v in out.items()}
    res["flags"] = flags.tobytes()
    return res


def _batch(rng, b: int, kind: str, extra: list):
    """A batch of b queries: ``generic`` (standard normal, scaled by a power of two),
    ``integer`` (small integer coordinates: exact ties, coincident points, o1 == o2), ``mixed``
    (both, and exact constructions of every stratum, shuffled); ``extra`` (hypothesis queries)
    is put at random rows."""
    scale = 2.0 ** int(rng.integers(-30, 31))
    gen = tuple(scale * rng.standard_normal((b, k, 2)) for k in (3, 1, 1))
    ints = tuple(rng.integers(-3, 4, size=(b, k, 2)).astype(float) for k in (3, 1, 1))
    if kind == "generic":
        o, s, g = gen
    elif kind == "integer":
        o, s, g = ints
    else:
        cons = _mixed(rng, STRATA, b // len(STRATA) + 1)
        pick = rng.integers(0, 3, size=b)
        o, s, g = (np.where((pick == 0)[:, None, None], a, np.where(
            (pick == 1)[:, None, None], c, k[:b])) for a, c, k in zip(gen, ints, cons))
    o, s, g = (a.copy() for a in (o, s, g))
    for q in extra:
        if b:
            row = int(rng.integers(0, b))
            o[row], s[row], g[row] = q
    return o, s, g


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(SIZES), st.sampled_from(["generic", "integer", "mixed"]),
       st.integers(0, 2**32 - 1), st.booleans(), st.sampled_from([1.0, 0.5, SCENE_CODE]),
       st.lists(st.booleans().flatmap(lambda degenerate: queries(2, 3, 1, degenerate=degenerate)),
                max_size=3))
def test_simd_path_equals_scalar_kernel(b, kind, seed, validate, lift, extra):
    """plan_chunk (SIMD path + scalar kernel) == the scalar kernel on every row, bit for bit:
    waypoints, times, domain, strata, clearance and flags (also the rows left unwritten)."""
    rng = np.random.default_rng(seed)
    o, s, g = _batch(rng, b, kind, extra)
    with np.errstate(all="ignore"):
        fast = _kernel(o, s, g, lift, validate)
        slow = _kernel(o, s, g, lift, validate, path="scalar")
    assert _bits(*fast[::-1]) == _bits(*slow[::-1])


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(SIZES[1:]), st.sampled_from(["generic", "integer", "mixed"]),
       st.integers(0, 2**32 - 1))
def test_which_path_plans_a_query_never_shows(b, kind, seed):
    """A query planned inside a batch (SIMD path for the generic ones) is bit for bit the query
    planned alone (the scalar kernel) and by pmplan.plan_batch at any position."""
    rng = np.random.default_rng(seed)
    o, s, g = _batch(rng, b, kind, [])
    flags, out = _kernel(o, s, g, validate=True)
    for i in rng.choice(b, size=min(b, 12), replace=False):
        one_flags, one = _kernel(o[i:i + 1], s[i:i + 1], g[i:i + 1], validate=True)
        assert _bits(one, one_flags) == _bits({k: v[i:i + 1] for k, v in out.items()},
                                              flags[i:i + 1])
    perm = rng.permutation(b)
    pflags, pout = _kernel(o[perm], s[perm], g[perm], validate=True)
    assert _bits(pout, pflags) == _bits({k: v[perm] for k, v in out.items()}, flags[perm])


def test_simd_path_decides_the_generic_queries():
    """Not vacuous: the SIMD path plans every generic query of the full blocks (T23_44) and
    leaves the degenerate ones to the scalar kernel (and the last B mod LANES: plan_chunk)."""
    L = kernels_planar.LANES
    rng = np.random.default_rng(11)
    for b in (L, 3 * L + 5):
        o, s, g = (rng.standard_normal((b, k, 2)) for k in (3, 1, 1))
        out = PLANAR_THREE.allocate(b, 2, 3, 1, 2)
        flags = np.empty(b, np.uint8)
        todo = np.empty(b, np.int64)
        nt = kernels_planar._plan_lanes(o, s, g, planar_strata.EVEN, 1.0, out["times"], out["waypoints"],
                                        out["domain"], out["strata"], out["clearance"], flags,
                                        todo)
        assert nt == 0
        done = slice(0, b - b % L)
        assert not flags[done].any()
        assert (out["strata"][done] == [23, 4, 4]).all() and (out["domain"][done] == 1).all()
    # one query exactly on the column of o2 (x - o2 orthogonal to o2 - o1), one coincident with
    # o3, one not finite: the scalar kernel decides them, the rest of their block stays here
    o, s, g = (rng.standard_normal((L, k, 2)) for k in (3, 1, 1))
    o[5] = [[0.0, 0.0], [2.0, 1.0], [-1.0, 3.0]]
    s[5] = [[1.0, 3.0]]
    s[9] = o[9, 2]
    g[17, 0, 1] = np.nan
    out = PLANAR_THREE.allocate(L, 2, 3, 1, 2)
    flags = np.zeros(L, np.uint8)
    todo = np.empty(L, np.int64)
    nt = kernels_planar._plan_lanes(o, s, g, planar_strata.EVEN, 1.0, out["times"], out["waypoints"],
                                    out["domain"], out["strata"], out["clearance"], flags, todo)
    assert todo[:nt].tolist() == [5, 9, 17]
    with np.errstate(all="ignore"):
        chunk_flags, chunk = _kernel(o, s, g, validate=True)
    assert chunk_flags.tolist() == [kernels_planar.INVALID if i in (9, 17) else 0
                                    for i in range(L)]
    assert stratum_short_name(chunk["strata"][5]) == "T23_34"


def test_poor_blocks_are_skipped_and_planned_the_same():
    """After a block with few generic queries the next 1, 2, 4, ... blocks go to the scalar
    kernel untried; a good block resets that. The results are the scalar kernel's, bit for bit."""
    L = kernels_planar.LANES
    rng = np.random.default_rng(12)
    o, s, g = (rng.standard_normal((12 * L, k, 2)) for k in (3, 1, 1))
    ints = [rng.integers(-3, 4, size=(L, k, 2)).astype(float) for k in (3, 1, 1)]
    ints[0][:, 1] = ints[0][:, 0] + [1.0, 2.0]
    ints[0][:, 2] = ints[0][:, 0] + [3.0, 6.0]  # o3 on L_C: family T1, never generic
    for blk in (0, 2, 5):  # poor blocks: 0 (skip 1), 2 (skip 2: 3, 4), 5 (skip 4: 6..9)
        o[blk * L:(blk + 1) * L], s[blk * L:(blk + 1) * L], g[blk * L:(blk + 1) * L] = ints
    out = PLANAR_THREE.allocate(12 * L, 2, 3, 1, 2)
    flags = np.empty(12 * L, np.uint8)
    todo = np.empty(12 * L, np.int64)
    nt = kernels_planar._plan_lanes(o, s, g, planar_strata.EVEN, 1.0, out["times"], out["waypoints"],
                                    out["domain"], out["strata"], out["clearance"], flags, todo)
    blocks = sorted(set((todo[:nt] // L).tolist()))
    assert blocks == [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]
    assert (todo[:nt] // L >= 10).sum() == 0  # 10, 11: tried again, generic, decided here
    with np.errstate(all="ignore"):
        fast = _kernel(o, s, g, validate=True)
        slow = _kernel(o, s, g, validate=True, path="scalar")
    assert _bits(*fast[::-1]) == _bits(*slow[::-1])



@pytest.mark.parametrize("b", [5, 200])
@pytest.mark.parametrize("which, index, value", [
    (0, (2, 1), np.nan),  # a NaN coordinate of o3
    (2, (0, 0), -np.inf),  # an infinite coordinate of the goal
    (1, (0,), "o3"),  # the start on o3
    (0, (1,), "o1"),  # o2 == o1
    (2, (0,), "o1"),  # the goal on o1
])
def test_batch_errors_validated_in_the_kernel_are_the_reference_errors(b, which, index, value):
    """The planar kernel validates the batch itself (no separate pass): an invalid query at
    any row (in a block of the SIMD path or not) gives the reference's error."""
    rng = np.random.default_rng(b)
    q = [rng.standard_normal((b, k, 2)) for k in (3, 1, 1)]
    row = b - 3 if b > 64 else 1
    point = {"o1": q[0][row, 0], "o3": q[0][row, 2]}
    q[which][(row, *index)] = point[value] if isinstance(value, str) else value
    fast = _outcome(pmplan.plan_batch, *q)
    assert isinstance(fast, tuple) and issubclass(fast[0], PmplanError)
    assert fast == _outcome(pmplan.plan_batch, *q, backend="numpy")
