"""What the numba kernels share: the numba import, the flag bits, the thresholds, the
error-free transformations and the distance of a piece.

One source for each: the flag bits a kernel returns for every query (:data:`FALLBACK`,
:data:`SUSPECT`, :data:`NONFINITE`, :data:`BROKEN`, :data:`INVALID`; what the caller does with
each: :func:`pmplan.planners.base.redecide`), the constants of the float filter and of the
certificate (read from :mod:`pmplan.predicates` and :mod:`pmplan.certify`, whose values numba
compiles in as constants), the compile options (:data:`OPTS`), TwoSum / TwoProduct
(:func:`two_sum`, :func:`two_prod`), the closed-form squared distance of a piece in the
plane (:func:`segment_dist2_plane`) and the write of a block of lanes into the caller's rows
(:func:`write_lanes`, :func:`read_lanes`). Without numba, :data:`AVAILABLE` is False, ``njit`` leaves
the functions as Python, and the numpy references plan everything (:mod:`pmplan.backends`).
"""

from __future__ import annotations

# one source: the unit roundoff and the underflow bound of pmplan.predicates' filter, and the
# thresholds of pmplan.certify (numba reads these module globals as compile-time constants)
from ..certify import (  # noqa: F401 (the kernels import them here)
    BAND_ABS,
    BAND_REL,
    MAXF,
    OBSTACLE_TINY2,
    REL,
    SURE,
    TINY_DIST,
)
from ..path import DIRECT_AT  # noqa: F401 (the direct lift, Mathematics §4.4)
from ..predicates import TINY, U  # noqa: F401

try:
    from llvmlite import ir as _ir
    from numba import njit
    from numba import types as _nbt
    from numba.core.extending import intrinsic, overload

    NoneType = _nbt.NoneType
    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; keep the numpy path usable
    AVAILABLE = False

    def njit(*args, **kwargs):
        return lambda f: f

    def intrinsic(f):
        return f

    def overload(f):
        return lambda impl: impl

    NoneType = type(None)

__all__ = ["AVAILABLE", "BROKEN", "FALLBACK", "INVALID", "NONFINITE", "SUSPECT"]

FALLBACK = 1
SUSPECT = 2
NONFINITE = 4
BROKEN = 8
INVALID = 16

BIG = 2.0**900  # TwoProduct's split overflows beyond this (as in pmplan.predicates)
SMALL = 2.0**-900  # below this TwoProduct's error term may underflow (as in pmplan.predicates)
# an obstacle pair whose squared distance is below OBSTACLE_TINY2 (pmplan.certify's) is
# SUSPECT: the square may have underflowed; pmplan.certify.clearance decides it exactly

OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}
#: the small helpers: compiled once each and inlined by LLVM where it pays. Not numba's
#: ``inline="always"``, which copies them into every caller before typing and cost about three
#: seconds of every first run's compilation, with the same machine code speed (docs/install.md, "The first
#: run compiles the kernels"; the floating-point operations are the same either way: no fast-math, no contraction)
INLINE = OPTS


@njit(**INLINE)
def two_sum(a, b):  # pragma: no cover - compiled
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(**INLINE)
def two_prod(a, b):  # pragma: no cover - compiled
    p = a * b
    c = 134217729.0 * a
    ah = c - (c - a)
    al = a - ah
    c = 134217729.0 * b
    bh = c - (c - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl



@njit(**INLINE)
def segment_param(num, vv):  # pragma: no cover - compiled
    """The parameter of the point of a piece closest to the origin, as
    :func:`pmplan.certify.segment_clearance` computes it: ``num / vv`` (``num = -r0.v``,
    ``vv = |v|^2``) clipped to [0, 1], and 0 when ``vv`` is not positive. Branch-free (selects),
    so that the loops calling it vectorise."""
    q = num / vv
    q = 1.0 if num >= vv else q
    q = 0.0 if num <= 0 else q
    return q if vv > 0 else 0.0


@njit(**INLINE)
def segment_dist2_plane(rx, ry, r1x, r1y):  # pragma: no cover - compiled
    """Squared minimum distance to the origin of the plane piece r0 -> r1 (relative
    positions), in :func:`pmplan.certify.segment_clearance`'s arithmetic and order."""
    vx = r1x - rx
    vy = r1y - ry
    vv = (0.0 + vx * vx) + vy * vy
    q = segment_param(-((0.0 + rx * vx) + ry * vy), vv)
    qx = rx + q * vx
    qy = ry + q * vy
    return (0.0 + qx * qx) + qy * qy


def _shuffle(builder, a, b, mask):  # pragma: no cover - compiled (runs when numba compiles)
    """LLVM ``shufflevector`` of the vectors a, b (elements of b numbered from len(a) on)."""
    return builder.shuffle_vector(a, b, _ir.Constant(_ir.VectorType(_ir.IntType(32), 8), mask))


@intrinsic
def _transpose8(typingctx, S, si, sj, out, oi, oj):  # pragma: no cover - compiled
    """``out[oi + j, oj + i] = S[si + i, sj + j]`` for i, j < 8: an 8 x 8 block of float64
    transposed in registers (8 vector loads, three rounds of 8 shuffles, 8 vector stores).

    ``S`` and ``out`` are C-contiguous 2-D float64 arrays; the caller guarantees the block is
    inside both (numba checks no bounds). A pure move: the values are copied bit for bit. LLVM
    lowers the 8-wide vectors to what the machine has (one AVX-512 register, two AVX ones...).
    """
    f64 = _nbt.Array(_nbt.float64, 2, "C")
    if S != f64 or out != f64 or not all(isinstance(a, _nbt.Integer) for a in (si, sj, oi, oj)):
        return None
    sig = _nbt.void(S, _nbt.intp, _nbt.intp, out, _nbt.intp, _nbt.intp)

    def codegen(context, builder, signature, args):
        s = context.make_array(signature.args[0])(context, builder, args[0])
        w = context.make_array(signature.args[3])(context, builder, args[3])
        si, sj, oi, oj = args[1], args[2], args[4], args[5]
        i64 = _ir.IntType(64)
        vec = _ir.VectorType(_ir.DoubleType(), 8).as_pointer()
        s0 = builder.ptrtoint(s.data, i64)
        w0 = builder.ptrtoint(w.data, i64)
        sstride = builder.extract_value(s.strides, 0)
        wstride = builder.extract_value(w.strides, 0)

        def at(base, i, stride, j):  # &A[i, j] as a pointer to 8 doubles
            off = builder.add(builder.mul(i, stride), builder.mul(j, _ir.Constant(i64, 8)))
            return builder.inttoptr(builder.add(base, off), vec)

        rows = [builder.load(at(s0, builder.add(si, _ir.Constant(i64, i)), sstride, sj), align=8)
                for i in range(8)]
        # round 1: t[2h], t[2h + 1] = lanes 0, 2, 4, 6 / 1, 3, 5, 7 of rows 2h, 2h + 1
        t = []
        for h in range(0, 8, 2):
            t.append(_shuffle(builder, rows[h], rows[h + 1], [0, 8, 2, 10, 4, 12, 6, 14]))
            t.append(_shuffle(builder, rows[h], rows[h + 1], [1, 9, 3, 11, 5, 13, 7, 15]))
        # round 2: u[4g + 2h], u[4g + 2h + 1] = rows 4g .. 4g + 3 at lanes (0, 4) / (2, 6)
        # (h = 0) and (1, 5) / (3, 7) (h = 1)
        u = []
        for g in range(0, 8, 4):
            for h in range(2):
                u.append(_shuffle(builder, t[g + h], t[g + 2 + h], [0, 1, 8, 9, 4, 5, 12, 13]))
                u.append(_shuffle(builder, t[g + h], t[g + 2 + h], [2, 3, 10, 11, 6, 7, 14, 15]))
        # round 3: rows 0-3 and 4-7 of one lane
        col = {}
        for q, (lo, hi) in enumerate(((0, 4), (2, 6), (1, 5), (3, 7))):
            col[lo] = _shuffle(builder, u[q], u[4 + q], [0, 1, 2, 3, 8, 9, 10, 11])
            col[hi] = _shuffle(builder, u[q], u[4 + q], [4, 5, 6, 7, 12, 13, 14, 15])
        for j in range(8):
            builder.store(col[j], at(w0, builder.add(oi, _ir.Constant(i64, j)), wstride, oj),
                          align=8)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _prefetch_write(typingctx, A, i, j):  # pragma: no cover - compiled
    """A hint to the processor that ``A[i, j]`` (2-D C-contiguous float64) will be written soon:
    LLVM's ``prefetch`` for writing, into every cache level. It changes no value and never
    faults (an address outside ``A`` is harmless); it only starts the memory transfer early."""
    if A != _nbt.Array(_nbt.float64, 2, "C") or not all(isinstance(a, _nbt.Integer)
                                                        for a in (i, j)):
        return None
    sig = _nbt.void(A, _nbt.intp, _nbt.intp)

    def codegen(context, builder, signature, args):
        a = context.make_array(signature.args[0])(context, builder, args[0])
        i64 = _ir.IntType(64)
        i32 = _ir.IntType(32)
        i8p = _ir.IntType(8).as_pointer()
        off = builder.add(builder.mul(args[1], builder.extract_value(a.strides, 0)),
                          builder.mul(args[2], _ir.Constant(i64, 8)))
        ptr = builder.inttoptr(builder.add(builder.ptrtoint(a.data, i64), off), i8p)
        fn = builder.module.declare_intrinsic(
            "llvm.prefetch", [i8p], _ir.FunctionType(_ir.VoidType(), [i8p, i32, i32, i32]))
        # (address, 1: for writing, 3: keep in every level, 1: data)
        builder.call(fn, [ptr, _ir.Constant(i32, 1), _ir.Constant(i32, 3), _ir.Constant(i32, 1)])
        return context.get_dummy_value()

    return sig, codegen


@njit(**OPTS)
def write_lanes(S, out, b0, L, size):  # pragma: no cover - compiled
    """``out[b0 + l, x] = S[x, l]`` for every lane ``l < L`` (a multiple of 8) and ``x < size``:
    a block of lanes-innermost rows written query after query, 8 x 8 blocks transposed in
    registers (:func:`_transpose8`; element by element, the strided reads cost twice as much:
    measured in the obstacle-line kernel, see its ``_plan_lanes``). Each block also asks for
    the same place in the next L rows (:func:`_prefetch_write`): a caller writing block after
    block, with work in between, then finds them in cache instead of waiting for memory
    (kernel time over before, alternating A/B runs: (3,4,2) 0.90-0.97 in four runs of five,
    1.12 in one; (4,4,2) 0.96-0.97; (2,4,2) 0.93-0.99)."""
    q = size - size % 8
    ahead = b0 + 2 * L <= out.shape[0]
    for l0 in range(0, L, 8):
        for x0 in range(0, q, 8):
            _transpose8(S, x0, l0, out, b0 + l0, x0)
            if ahead:
                for j in range(8):
                    _prefetch_write(out, b0 + L + l0 + j, x0)
        for lane in range(l0, l0 + 8):
            for x in range(q, size):
                out[b0 + lane, x] = S[x, lane]


@njit(**OPTS)
def read_lanes(A, b0, L, n, Y, y0):  # pragma: no cover - compiled
    """``Y[y0 + x, l] = A[b0 + l, x]`` for every lane ``l < L`` (a multiple of 8) and
    ``x < n``: rows of queries (``A`` 2-D, C-contiguous) read into lanes-innermost rows,
    :func:`write_lanes` the other way (8 x 8 blocks transposed in registers, the last
    ``n mod 8`` columns element by element)."""
    q = n - n % 8
    for l0 in range(0, L, 8):
        for x0 in range(0, q, 8):
            _transpose8(A, b0 + l0, x0, Y, y0 + x0, l0)
        for lane in range(l0, l0 + 8):
            for x in range(q, n):
                Y[y0 + x, lane] = A[b0 + lane, x]
