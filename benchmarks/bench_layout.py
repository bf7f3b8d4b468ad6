"""A design study for the kernels' next layout: poses on the inner loop.

The engine's kernels run one pose at a time (``prange`` over poses, every per-pose function
on scalars), so the compiler vectorises nothing across poses, and every joint's rotation
calls the C library's ``sin`` and ``cos`` (this numba build has no vectorised maths
library).  This script times one part of the closure, the legs' product of exponentials
(``_kin.chain``: every joint's current axis and point, each leg's end displacement), three
ways on the same solved joint values of a catalog PM:

* ``engine``: the engine's own ``_kin.chain`` for one pose at a time (a block of one lane;
  no copy of it), then on blocks of ``B`` poses (the same function: it is written on a block
  with the pose axis innermost);
* ``poses inner, libm``: the same arithmetic on blocks of ``B`` poses, structure of arrays
  (one contiguous array per rotation entry), the loop over the block's poses innermost,
  where LLVM vectorises it (AVX2 / AVX-512 here); ``math.sin``, ``math.cos`` per pose;
* ``poses inner, polynomial sin/cos``: the same with a sine and cosine written as
  arithmetic (reduction by pi/2 in two parts, degree-17/18 Taylor polynomials on
  ``|r| <= pi/4``, the quadrant chosen by arithmetic), which vectorises too.  Its error
  against numpy's ``sin``/``cos`` on ``[-20, 20]`` rad is printed (one or two units in the
  last place; the two-part reduction is meant for joint angles, not ``|a| > 1e5``).

The block results are checked against the engine's (a checksum of the end displacements
and last joints' points; equal up to the summation order).  R and P joints only (the
Pa joints' circle is not written here).  Times are CPU time of this thread, best of 7.
Run: ``python benchmarks/bench_layout.py [PM]`` (default 3RRPRR).
"""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit

_TWO_OVER_PI = 0.6366197723675814
_HALF_PI_HI, _HALF_PI_LO = 1.5707963267341256, 6.077100506506192e-11


@njit(inline="always", error_model="numpy")
def _sincos(a):
    """``(sin a, cos a)`` by arithmetic only (vectorisable)."""
    qf = math.floor(a * _TWO_OVER_PI + 0.5)
    r = (a - qf * _HALF_PI_HI) - qf * _HALF_PI_LO
    r2 = r * r
    sr = r + r * r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (
        1.0 / 362880 + r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800 + r2 * (
            -1.0 / 1307674368000 + r2 * (1.0 / 355687428096000))))))))
    cr = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (
        -1.0 / 3628800 + r2 * (1.0 / 479001600 + r2 * (-1.0 / 87178291200 + r2 * (
            1.0 / 20922789888000))))))))
    q4 = qf - 4.0 * math.floor(qf * 0.25)               # the quadrant, 0..3
    odd = q4 - 2.0 * math.floor(q4 * 0.5)
    q5 = q4 + 1.0 - 4.0 * math.floor((q4 + 1.0) * 0.25)
    return ((1.0 - 2.0 * math.floor(q4 * 0.5)) * (sr + odd * (cr - sr)),
            (1.0 - 2.0 * math.floor(q5 * 0.5)) * (cr + odd * (sr - cr)))


@njit(error_model="numpy")
def _sincos_many(a, s, c):
    for k in range(a.shape[0]):
        s[k], c[k] = _sincos(a[k])


def _kernels():
    from screwkit.engine._kernels._jit import one_lane
    from screwkit.engine._kernels._kin import chain
    from screwkit.engine._kernels._layout import BLOCK
    from screwkit.engine._kernels._pack import model

    @njit(error_model="numpy")
    def engine(Mf, Mi, Md, Xs, nu):
        M = model(Mf, Mi, Md)
        n, m = M[0].shape[0], M[0].shape[1]
        fa, RT, E, CS = np.zeros((m, 6, 1)), np.zeros((12, 1)), np.zeros((3, 3)), np.zeros((2, 1))
        acc = 0.0
        for p in range(Xs.shape[0]):
            for i in range(n):
                chain(M, i, one_lane(Xs[p]), nu + i * m, fa, RT, 1, 1, False, fa, E, CS)
                acc += RT[9, 0] + RT[8, 0] + fa[M[10][i, 0] - 1, 3, 0]
        return acc

    @njit(error_model="numpy")
    def engine_blocks(Mf, Mi, Md, XT, nu):
        B = BLOCK                  # the lane stride is a constant (_kin.chain)
        M = model(Mf, Mi, Md)
        n, m, N = M[0].shape[0], M[0].shape[1], XT.shape[1]
        fa, RT, E, CS = np.zeros((m, 6, B)), np.zeros((12, B)), np.zeros((3, 3)), np.zeros((2, B))
        Xb = np.zeros((XT.shape[0], B))
        acc = 0.0
        for p0 in range(0, N, B):
            nb = min(B, N - p0)
            for k in range(XT.shape[0]):
                for l in range(nb):
                    Xb[k, l] = XT[k, p0 + l]
            for i in range(n):
                chain(M, i, Xb, nu + i * m, fa, RT, nb, BLOCK, False, fa, E, CS)
                last = M[10][i, 0] - 1
                for l in range(nb):
                    acc += RT[9, l] + RT[8, l] + fa[last, 3, l]
        return acc

    @njit(error_model="numpy")
    def blocks(Dm, Pm, rot, tra, qs, size, XT, nu, B, poly):
        n, m, N = Dm.shape[0], Dm.shape[1], XT.shape[1]
        S, FA, CS = np.empty((12, B)), np.empty((n, m, 6, B)), np.empty((2, B))
        acc = 0.0
        for b0 in range(0, N, B):
            nb = min(B, N - b0)
            for i in range(n):
                r00, r01, r02, r10, r11, r12 = S[0], S[1], S[2], S[3], S[4], S[5]
                r20, r21, r22, t0, t1, t2 = S[6], S[7], S[8], S[9], S[10], S[11]
                for k in range(nb):
                    r00[k], r01[k], r02[k], t0[k] = 1.0, 0.0, 0.0, 0.0
                    r10[k], r11[k], r12[k], t1[k] = 0.0, 1.0, 0.0, 0.0
                    r20[k], r21[k], r22[k], t2[k] = 0.0, 0.0, 1.0, 0.0
                for j in range(size[i]):
                    x, g, ro, tr = XT[nu + i * m + j, b0:b0 + nb], qs[i, j], rot[i, j], tra[i, j]
                    D0, D1, D2 = Dm[i, j, 0], Dm[i, j, 1], Dm[i, j, 2]
                    P0, P1, P2 = Pm[i, j, 0], Pm[i, j, 1], Pm[i, j, 2]
                    fa, sn, cs = FA[i, j], CS[0], CS[1]
                    if ro != 0.0:
                        if poly:
                            for k in range(nb):
                                sn[k], cs[k] = _sincos(ro * (x[k] * g))
                        else:
                            for k in range(nb):
                                a = ro * (x[k] * g)
                                sn[k], cs[k] = math.sin(a), math.cos(a)
                    for k in range(nb):
                        q = x[k] * g
                        a00, a01, a02 = r00[k], r01[k], r02[k]
                        a10, a11, a12 = r10[k], r11[k], r12[k]
                        a20, a21, a22 = r20[k], r21[k], r22[k]
                        d0 = a00 * D0 + a01 * D1 + a02 * D2
                        d1 = a10 * D0 + a11 * D1 + a12 * D2
                        d2 = a20 * D0 + a21 * D1 + a22 * D2
                        p0 = a00 * P0 + a01 * P1 + a02 * P2 + t0[k]
                        p1 = a10 * P0 + a11 * P1 + a12 * P2 + t1[k]
                        p2 = a20 * P0 + a21 * P1 + a22 * P2 + t2[k]
                        fa[0, k], fa[1, k], fa[2, k] = d0, d1, d2
                        fa[3, k], fa[4, k], fa[5, k] = p0, p1, p2
                        sh = tr * q
                        if ro != 0.0:
                            c, s = cs[k], sn[k]
                            v = 1.0 - c
                            e00, e11, e22 = D0 * D0 * v + c, D1 * D1 * v + c, D2 * D2 * v + c
                            sym, skew = D0 * D1 * v, D2 * s
                            e01, e10 = sym - skew, sym + skew
                            sym, skew = D1 * D2 * v, D0 * s
                            e12, e21 = sym - skew, sym + skew
                            sym, skew = D2 * D0 * v, D1 * s
                            e20, e02 = sym - skew, sym + skew
                            n00 = a00 * e00 + a01 * e10 + a02 * e20
                            n01 = a00 * e01 + a01 * e11 + a02 * e21
                            n02 = a00 * e02 + a01 * e12 + a02 * e22
                            n10 = a10 * e00 + a11 * e10 + a12 * e20
                            n11 = a10 * e01 + a11 * e11 + a12 * e21
                            n12 = a10 * e02 + a11 * e12 + a12 * e22
                            n20 = a20 * e00 + a21 * e10 + a22 * e20
                            n21 = a20 * e01 + a21 * e11 + a22 * e21
                            n22 = a20 * e02 + a21 * e12 + a22 * e22
                            r00[k], r01[k], r02[k] = n00, n01, n02
                            r10[k], r11[k], r12[k] = n10, n11, n12
                            r20[k], r21[k], r22[k] = n20, n21, n22
                            t0[k] = p0 - (n00 * P0 + n01 * P1 + n02 * P2) + sh * d0
                            t1[k] = p1 - (n10 * P0 + n11 * P1 + n12 * P2) + sh * d1
                            t2[k] = p2 - (n20 * P0 + n21 * P1 + n22 * P2) + sh * d2
                        else:
                            t0[k] += sh * d0
                            t1[k] += sh * d1
                            t2[k] += sh * d2
                last = FA[i, size[i] - 1]
                for k in range(nb):
                    acc += t0[k] + r22[k] + last[3, k]
        return acc

    return engine, engine_blocks, blocks


def measure(name: str = "3RRPRR", n: int = 20_000) -> None:
    from screwkit.engine._chains import chains_of
    from screwkit.engine._kernels._layout import BLEN, D, LEG, L_SIZE, P, QS, ROT, TRA
    from screwkit.engine._solve import predictor_of, solve_closures

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from bench_closure import _best, random_poses

    pm, pose = random_poses(name, n)
    ch = chains_of(pm)
    M = ch.flat.M
    if (M[BLEN] > 0).any():
        print(f"{name}: has a Pa joint, not written in this study")
        return
    Mp, _ = ch.flat.pack(predictor_of(ch))
    Xs = np.ascontiguousarray(solve_closures(pm, pose).X.T)
    XT = np.ascontiguousarray(Xs.T)
    arrays = [np.ascontiguousarray(M[k]) for k in (D, P, ROT, TRA, QS)]
    size = np.ascontiguousarray(M[LEG][:, L_SIZE])
    nu = ch.flat.nu
    engine, engine_blocks, blocks = _kernels()
    engine(*Mp.args, Xs[:4], nu)
    blocks(*arrays, size, XT[:, :4], nu, 64, False)
    blocks(*arrays, size, XT[:, :4], nu, 64, True)
    t_eng, ref = _best(lambda: engine(*Mp.args, Xs, nu))
    us = 1e6 / n
    joints = int(size.sum())
    print(f"{name}: the legs' product of exponentials ({joints} joints), {n} solved poses, "
          f"CPU time per pose on one thread")
    print(f"  engine (_kin.chain, one pose at a time)   {t_eng * us:6.3f} us")
    from screwkit.engine._kernels._layout import BLOCK
    engine_blocks(*Mp.args, XT[:, :4], nu)
    t, got = _best(lambda: engine_blocks(*Mp.args, XT, nu))
    print(f"  engine (_kin.chain), blocks of {BLOCK:3d}       {t * us:6.3f} us  "
          f"{t_eng / t:4.1f}x   checksum rel. diff {abs(got - ref) / abs(ref):.1e}")
    for B in (32, 64, 256):
        for poly, label in ((False, "libm"), (True, "polynomial sin/cos")):
            t, got = _best(lambda: blocks(*arrays, size, XT, nu, B, poly))
            print(f"  poses inner, B = {B:3d}, {label:18s}  {t * us:6.3f} us  "
                  f"{t_eng / t:4.1f}x   checksum rel. diff {abs(got - ref) / abs(ref):.1e}")
    a = np.random.default_rng(1).uniform(-20.0, 20.0, 1_000_000)
    s, c = np.empty_like(a), np.empty_like(a)
    _sincos_many(a, s, c)
    print(f"  polynomial sin/cos on [-20, 20] rad: max abs error "
          f"{max(np.abs(s - np.sin(a)).max(), np.abs(c - np.cos(a)).max()):.1e}")


if __name__ == "__main__":
    for pm_name in sys.argv[1:] or ["3RRPRR", "6SPS"]:
        measure(pm_name)
