r"""The degree-24 Taylor recurrence in vector instructions (a numba intrinsic).

:mod:`mbm.approximants.taylor`'s recurrence (its "Coefficients"), emitted as LLVM IR
at compile time: packed pairs of sin θ and cos θ coefficients, four lanes per
multiply, and the recurrence rearranged so that each order waits on the one before
through one multiply and one add.  The scalar written-out form was bound by its
instruction count (~2000 scalar multiplies, adds and spills per anchor at degree 24,
about a third of a window); this form needs about a third of them.

Rearranged recurrence
---------------------
With b_j = j a_j, s_m, c_m the coefficients of sin θ and cos θ, and n_m = −c_m, write
X_m = (s_m, n_m) and Y_m = (n_m, s_m) (lane 0, lane 1).  The module's convolution
k s_k = Σ_{m<k} b_{k−m} c_m, k c_k = −Σ_{m<k} b_{k−m} s_m reads, order k ≥ 3,

    X_k = ((W_k·(−1/k, 1/k) + Y_{k−2}·(−b₂/k, b₂/k)) + b_k·(c₀/k, s₀/k)) + Y_{k−1}·(−b₁/k, b₁/k),
    W_k = Σ_{m=1}^{k−3} b_{k−m} Y_m,

(X₁ = b₁(c₀, s₀); X₂ without W and the Y_{k−2} term): the three terms of the newest
inputs (b_k, Y_{k−1}, Y_{k−2}) are added last, each scaled by a factor formed off the
critical path, and W_k, whose inputs are three orders old, is summed meanwhile in four
lanes (the pairs m, m + 1 packed: (n_m, s_m, n_{m+1}, s_{m+1}) × (b_{k−m}, b_{k−m},
b_{k−m−1}, b_{k−m−1}), two accumulators, then lanes 0 + 2 and 1 + 3).  The θ
coefficients follow from

    b_{k+2} = (d_k/(k+1) + (−β/(k+1)) b_{k+1}) + (−ω²/(k+1)) s_k,   a_{k+2} = b_{k+2}/(k+2),

with d_k the drive's series (0 undriven; the driven form as taylor.py's).  The sums
are the module's in another order and another rounding (each operation is IEEE, no
reassociation is allowed to the compiler, so the bits are the same on every machine);
tests/approximants/test_taylor_simd.py bounds every coefficient against a 50-digit recurrence as
for the loop form.
"""

import collections
import math

from llvmlite import ir
from numba import types
from numba.core.extending import intrinsic

from ..compile.jit import kernel

__all__ = ["SIMD_ORDER", "LANES", "taylor24_series", "taylor24_driven_series", "taylor24_lanes", "horner24_lanes"]

# The degree emitted: the "auto" rule's (taylor.TAYLOR_DEFAULT_ORDER); each degree is
# one more emitted kernel to compile, so only the one the runs use.
SIMD_ORDER = 24

# Coefficients past a_N (taylor.N_EXTRA: the error estimate's two).
N_EXTRA = 2

# Scenes per call of the across-scene form (:func:`taylor24_lanes`): AVX-512's eight
# doubles (LLVM splits the vectors into halves on AVX2; the bits do not depend on it).
LANES = 8

# Where a₀ sits in the coefficient vector (taylor.HEADER): a_k is stored at the
# constant index HEADER + k, so the anchor makes no view of the vector.
HEADER = 5

#: The drive's series at a window's start (the driven form, :mod:`mbm.approximants.taylor`'s
#: docstring, "AC drive"): f = A, freq = Ω, u = sin ψ, w = cos ψ of the phase ψ there.
DriveSeries = collections.namedtuple("DriveSeries", ("f", "freq", "u", "w"))

_DBL = ir.DoubleType()
_I32 = ir.IntType(32)
_I64 = ir.IntType(64)
_V2 = ir.VectorType(_DBL, 2)
_V4 = ir.VectorType(_DBL, 4)


def _emit(builder, data, n_order, anchor, drive):
    """Emit the recurrence (module docstring) storing a₀ … a_{N+2} at data[HEADER + k].

    ``anchor`` is the IR values (β, γ, ω², sin θ₀, cos θ₀, θ₀, θ'₀) of the anchor, ``drive``
    None or the IR values (f, freq, u, w) of taylor.py's driven form.
    """
    beta, gamma, w2, s0, c0, theta0, v0 = anchor
    nt = n_order + N_EXTRA

    def cst(x):
        return ir.Constant(_DBL, float(x))

    def v2const(x, y):
        return ir.Constant(_V2, [cst(x), cst(y)])

    def pack2(x, y):
        v = builder.insert_element(ir.Constant(_V2, ir.Undefined), x, ir.Constant(_I32, 0))
        return builder.insert_element(v, y, ir.Constant(_I32, 1))

    def shuffle(a, b, mask):
        return builder.shuffle_vector(a, b, ir.Constant(ir.VectorType(_I32, len(mask)), list(mask)))

    def lane(v, i):
        return builder.extract_element(v, ir.Constant(_I32, i))

    def store(k, val):
        builder.store(val, builder.gep(data, [ir.Constant(_I64, HEADER + k)]), align=8)

    mul, add, sub = builder.fmul, builder.fadd, builder.fsub
    store(0, theta0)
    store(1, v0)
    b = {1: v0}
    if drive is None:
        g0 = gamma
    else:
        f, freq, u, w = drive
        g0 = add(gamma, mul(f, u))
    a2 = mul(cst(0.5), sub(sub(g0, mul(beta, v0)), mul(w2, s0)))
    store(2, a2)
    b[2] = mul(cst(2.0), a2)
    cs0 = pack2(c0, s0)
    nb1 = mul(v2const(-1.0, 1.0), pack2(v0, v0))
    nb2 = mul(v2const(-1.0, 1.0), pack2(b[2], b[2]))
    Y = {0: pack2(builder.fneg(c0), s0)}
    YY = {}  # YY[m] = (Y_m, Y_{m+1}) for odd m
    BB = {}  # BB[j] = (b_j, b_j, b_{j−1}, b_{j−1})

    def bb(j):
        if j not in BB:
            BB[j] = shuffle(pack2(b[j], b[j]), pack2(b[j - 1], b[j - 1]), (0, 1, 2, 3))
        return BB[j]

    for k in range(1, nt - 1):
        inv = 1.0 / k
        if k == 1:
            x = mul(pack2(b[1], b[1]), cs0)
        else:
            # The deep middle W_k (m = 1 … k − 3), four lanes.
            acc = [None, None]
            m, i = 1, 0
            while m + 1 <= k - 3:
                if m not in YY:
                    YY[m] = shuffle(Y[m], Y[m + 1], (0, 1, 2, 3))
                t = mul(bb(k - m), YY[m])
                acc[i] = t if acc[i] is None else add(acc[i], t)
                m += 2
                i ^= 1
            wk = None
            if acc[0] is not None:
                a4 = acc[0] if acc[1] is None else add(acc[0], acc[1])
                wk = add(shuffle(a4, a4, (0, 1)), shuffle(a4, a4, (2, 3)))
            if m <= k - 3:
                t = mul(pack2(b[k - m], b[k - m]), Y[m])
                wk = t if wk is None else add(wk, t)
            x = None
            if wk is not None:
                x = mul(wk, v2const(-inv, inv))
            if k >= 3:
                t = mul(Y[k - 2], mul(nb2, v2const(inv, inv)))
                x = t if x is None else add(x, t)
            t = mul(pack2(b[k], b[k]), mul(cs0, v2const(inv, inv)))
            x = t if x is None else add(x, t)
            x = add(x, mul(Y[k - 1], mul(nb1, v2const(inv, inv))))
        Y[k] = shuffle(x, x, (1, 0))
        sk = lane(x, 0)
        # b_{k+2} and a_{k+2}.
        inv1 = cst(1.0 / (k + 1.0))
        acc_b = mul(mul(builder.fneg(beta), inv1), b[k + 1])
        if drive is not None:
            f = mul(mul(f, freq), cst(inv))
            u, w = w, builder.fneg(u)
            acc_b = add(mul(mul(f, u), inv1), acc_b)
        bk2 = add(acc_b, mul(mul(builder.fneg(w2), inv1), sk))
        b[k + 2] = bk2
        store(k + 2, mul(bk2, cst(1.0 / (k + 2.0))))


class _LaneBuilder:
    """The subset of llvmlite's IRBuilder that :func:`_emit` calls, over ``LANES`` scenes.

    Each scalar of :func:`_emit` is one <LANES x double> value (lane i: scene i), each
    of its <2 x double> and <4 x double> vectors a list of 2 or 4 of them; every
    operation is the scalar one applied lane-wise, so each scene's coefficients are the
    same IEEE operations in the same order as :func:`_emit` on one scene: the same bits.
    A store of a_k goes to row i, column HEADER + k of the (LANES, stride) array at
    ``data``.
    """

    def __init__(self, builder, data, stride, soa):
        self.b = builder
        self.data = data
        self.stride = stride
        self.soa = soa
        self.vt = ir.VectorType(_DBL, LANES)

    def _val(self, x):
        # An operand: a lane vector or a list of them as is; a constant splat over lanes.
        if isinstance(x, ir.Constant):
            if isinstance(x.type, ir.VectorType):
                if x.constant is ir.Undefined:
                    return [None] * x.type.count
                return [self._val(c) for c in x.constant]
            return ir.Constant(self.vt, [ir.Constant(_DBL, x.constant)] * LANES)
        return x

    def _map(self, op, a, b):
        a, b = self._val(a), self._val(b)
        if isinstance(a, list):
            return [op(x, y) for x, y in zip(a, b)]
        return op(a, b)

    def fmul(self, a, b):
        return self._map(self.b.fmul, a, b)

    def fadd(self, a, b):
        return self._map(self.b.fadd, a, b)

    def fsub(self, a, b):
        return self._map(self.b.fsub, a, b)

    def fneg(self, a):
        a = self._val(a)
        if isinstance(a, list):
            return [self.b.fneg(x) for x in a]
        return self.b.fneg(a)

    def insert_element(self, vec, x, idx):
        v = list(self._val(vec))
        v[idx.constant] = self._val(x)
        return v

    def extract_element(self, vec, idx):
        return self._val(vec)[idx.constant]

    def shuffle_vector(self, a, b, mask):
        both = list(self._val(a)) + list(self._val(b))
        return [both[m.constant if isinstance(m, ir.Constant) else m] for m in mask.constant]

    def gep(self, data, idx):
        return idx[0].constant

    def store(self, val, col, align=8):
        # Row col − HEADER of the (N + 3, LANES) array at ``soa``: a_k of every lane.
        ptr = self.b.gep(self.soa, [ir.Constant(_I64, (col - HEADER) * LANES)])
        self.b.store(val, self.b.bitcast(ptr, self.vt.as_pointer()), align=8)
        for i in range(LANES):
            x = self.b.extract_element(val, ir.Constant(_I32, i))
            off = self.b.add(self.b.mul(ir.Constant(_I64, i), self.stride), ir.Constant(_I64, col))
            self.b.store(x, self.b.gep(self.data, [off]), align=align)


def _coef_data(context, builder, aryty, ary):
    return context.make_array(aryty)(context, builder, ary).data


def _tuples(*pairs):
    # Each (type, n) a tuple type of n entries: the intrinsics' arguments.
    return all(isinstance(ty, types.BaseTuple) and len(ty) == n for ty, n in pairs)


def _items(builder, tup, n):
    # The IR values of a tuple's n entries.
    return tuple(builder.extract_value(tup, i) for i in range(n))


@intrinsic
def _series(typingctx, model, anchor, coef):
    # model: (β, γ, ω²); anchor: (sin θ₀, cos θ₀, θ₀, θ'₀).
    if not _tuples((model, 3), (anchor, 4)):
        return None
    sig = types.none(model, anchor, coef)

    def codegen(context, builder, signature, args):
        data = _coef_data(context, builder, signature.args[-1], args[-1])
        _emit(builder, data, SIMD_ORDER, _items(builder, args[0], 3) + _items(builder, args[1], 4), None)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _driven_series(typingctx, model, drive, anchor, coef):
    # model and anchor as _series'; drive: the DriveSeries (f, freq, u, w).
    if not _tuples((model, 3), (drive, 4), (anchor, 4)):
        return None
    sig = types.none(model, drive, anchor, coef)

    def codegen(context, builder, signature, args):
        data = _coef_data(context, builder, signature.args[-1], args[-1])
        _emit(builder, data, SIMD_ORDER, _items(builder, args[0], 3) + _items(builder, args[2], 4),
              _items(builder, args[1], 4))
        return context.get_dummy_value()

    return sig, codegen


def _c2(arr):
    return (isinstance(arr, types.Array) and arr.layout == "C" and arr.ndim == 2
            and arr.dtype == types.float64)


@intrinsic
def _lane_series(typingctx, ins, coefs, soa):
    if not (_c2(ins) and _c2(coefs) and _c2(soa)):
        return None
    sig = types.none(ins, coefs, soa)

    def codegen(context, builder, signature, args):
        ins_ary = context.make_array(signature.args[0])(context, builder, args[0])
        out_ary = context.make_array(signature.args[1])(context, builder, args[1])
        soa_ary = context.make_array(signature.args[2])(context, builder, args[2])
        stride = builder.extract_value(out_ary.shape, 1)
        vt = ir.VectorType(_DBL, LANES)
        rows = []
        for q in range(7):
            ptr = builder.gep(ins_ary.data, [ir.Constant(_I64, q * LANES)])
            rows.append(builder.load(builder.bitcast(ptr, vt.as_pointer()), align=8))
        _emit(_LaneBuilder(builder, out_ary.data, stride, soa_ary.data), None, SIMD_ORDER, tuple(rows), None)
        return context.get_dummy_value()

    return sig, codegen


@kernel
def taylor24_lanes(ins, coefs, soa):
    """a₀ … a_26 of :func:`taylor24_series` for ``LANES`` scenes at once.

    ``ins`` is a C-contiguous (7, LANES) array: rows β, γ, ω², sin θ₀, cos θ₀, θ₀, θ̇₀ of
    each scene (lane); ``coefs`` a C-contiguous (LANES, W) array, W ≥ HEADER + 27, whose
    row i receives scene i's coefficients at columns HEADER … HEADER + 26 (the header is
    the caller's), and ``soa`` a C-contiguous (27, LANES) array whose row k receives
    a_k of every lane (for :func:`horner24_lanes`).  Each scene's coefficients are bit
    for bit :func:`taylor24_series`'s.
    """
    if ins.shape[0] != 7 or ins.shape[1] != LANES or coefs.shape[0] != LANES \
            or coefs.shape[1] < HEADER + SIMD_ORDER + N_EXTRA + 1 \
            or soa.shape[0] != SIMD_ORDER + N_EXTRA + 1 or soa.shape[1] != LANES:
        raise ValueError("taylor24_lanes: ins must be (7, LANES), coefs (LANES, >= HEADER + 27), "
                         "soa (27, LANES)")
    _lane_series(ins, coefs, soa)


@intrinsic
def _horner_lanes(typingctx, soa, s, out):
    if not (_c2(soa) and _c2(out) and isinstance(s, types.Array) and s.layout == "C" and s.ndim == 1
            and s.dtype == types.float64):
        return None
    sig = types.none(soa, s, out)

    def codegen(context, builder, signature, args):
        vt = ir.VectorType(_DBL, LANES)
        soa_d = context.make_array(signature.args[0])(context, builder, args[0]).data
        s_d = context.make_array(signature.args[1])(context, builder, args[1]).data
        out_d = context.make_array(signature.args[2])(context, builder, args[2]).data

        def vptr(data, i):
            return builder.bitcast(builder.gep(data, [ir.Constant(_I64, i * LANES)]), vt.as_pointer())

        def row(k):
            return builder.load(vptr(soa_d, k), align=8)

        def splat(x):
            return ir.Constant(vt, [ir.Constant(_DBL, float(x))] * LANES)

        mul, add = builder.fmul, builder.fadd
        n = SIMD_ORDER
        t = builder.load(vptr(s_d, 0), align=8)
        an = row(n)
        p = an
        q = mul(splat(n), an)
        for k in range(n - 1, 1, -1):
            ak = row(k)
            p = add(mul(p, t), ak)
            q = add(mul(q, t), mul(splat(k), ak))
        a1 = row(1)
        p = add(mul(p, t), a1)
        q = add(mul(q, t), a1)
        builder.store(add(row(0), mul(t, p)), vptr(out_d, 0), align=8)
        builder.store(q, vptr(out_d, 1), align=8)
        return context.get_dummy_value()

    return sig, codegen


@kernel
def horner24_lanes(soa, s, out):
    """θ, θ' of ``LANES`` degree-24 Taylor polynomials at their times ``s``.

    ``soa`` as :func:`taylor24_lanes` writes it, ``s`` (LANES,), ``out`` (2, LANES):
    row 0 θ, row 1 θ'.  Each lane is bit for bit
    :func:`mbm.approximants.taylor.taylor_eval_kernel` of its coefficients (the same
    Horner steps, lane-wise).
    """
    if soa.shape[0] != SIMD_ORDER + N_EXTRA + 1 or soa.shape[1] != LANES or s.size != LANES \
            or out.shape[0] != 2 or out.shape[1] != LANES:
        raise ValueError("horner24_lanes: soa must be (27, LANES), s (LANES,), out (2, LANES)")
    _horner_lanes(soa, s, out)


@kernel
def taylor24_series(beta, gamma, omega, theta0, v0, coef):
    """a₀ … a_26 of the recurrence at degree 24, written into ``coef[5:]``.

    ``coef`` must hold at least HEADER + 27 floats (the caller checks:
    :func:`mbm.approximants.taylor.taylor_coefficients_into`).
    """
    _series((beta, gamma, omega * omega), (math.sin(theta0), math.cos(theta0), theta0, v0), coef)


@kernel
def taylor24_driven_series(model, drive, theta0, v0, coef):
    """:func:`taylor24_series` of the driven recurrence: ``model`` (β, γ, ω), ``drive`` the
    :data:`DriveSeries` (f = A, Ω, u = sin ψ, w = cos ψ;
    :func:`mbm.approximants.taylor.taylor_driven_coefficients_into`)."""
    beta, gamma, omega = model
    _driven_series((beta, gamma, omega * omega), drive, (math.sin(theta0), math.cos(theta0), theta0, v0), coef)
