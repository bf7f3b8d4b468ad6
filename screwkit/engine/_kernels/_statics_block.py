"""The statics of a block of poses on its lanes, compiled (private).

After a block's conditioning (:func:`._statics.conditioning_lanes`, the lanes' normalised rows
in the conditioning workspace ``CW``), :func:`statics_block` solves every lane's statics as
the pose alone would (:func:`._statics.statics_prepare`, :func:`._statics.statics_apply`),
the common modes across the lanes at once: the LU of ``Jn^T`` of a square well-conditioned
``Jn`` and the normal equations of more rows (:func:`._small.lu_block`, each lane its own
pivots by selects: the same comparisons, the same bits); a lane that needs the
pseudo-inverse alone.
"""

import math

from ._jit import borrowing, borrowing_inlined
from ._layout import REFINE
from ._pack import out_row
from ._small import lu_apply_block, lu_block, lu_sign
from ._statics import (CW_COMP, CW_D, CW_G, CW_JN, CW_JW, CW_LU, CW_O, CW_PIV, CW_SV, CW_W,
                       CW_Y, CW_Z, SW_AP, SW_COMP, SW_D, SW_JN, SW_W, SW_WN, amplification,
                       equilibrium, normalise_wrench, statics_apply, statics_prepare,
                       workload_about_origin)


@borrowing_inlined
def _compliance(I, p, mr, torque, L, comp, l):
    """Pose ``p``'s compliances into lane ``l`` of ``comp (mr, ls)``.  Inlined: called, it
    took the inputs tuple's arrays on the stack (some 90 words), every lane."""
    c = I[5]
    for r in range(mr):
        if c.shape[0] == 0:
            comp[r, l] = 1.0 / (L * L) if torque[r] else 1.0
        else:
            comp[r, l] = c[p if c.shape[0] > 1 else 0, r]


@borrowing
def statics_block(I, p0, nb, mr, SW, CW, Jo, centres, lengths, svo, values_o, eq, amp, det):
    """The statics of the poses ``p0..p0+nb-1`` (lanes ``0..nb-1`` of ``CW``, their
    conditioning done), each lane's operations those of the pose alone
    (:func:`._statics.statics_prepare`, :func:`._statics.statics_apply`), in the same order:
    a square well-conditioned ``Jn`` (``MODE_SQUARE``) and the normal equations of more
    rows (``MODE_NORMAL``) on the lanes at once (:func:`._small.lu_block`,
    :func:`._small.lu_apply_block`); a lane that needs the pseudo-inverse (rare: an
    ill-conditioned pose) alone, through the one-pose functions.  Compiled once (the lane
    stride ``BLOCK``), for both loops.  The poses' outputs (each pose's row,
    :func:`._pack.out_row`): their rows ``Jo (., mr, 6)``, centroids, lengths, singular
    values (read), efforts, equilibrium residuals, force amplifications and signs of ``det
    J`` (written)."""
    torque = I[6]
    Jn, d, co, sv = CW[CW_JN], CW[CW_D], CW[CW_O], CW[CW_SV]
    LU, piv, Jw, g, z, y, Wl, comp = CW[CW_LU], CW[CW_PIV], CW[CW_JW], CW[CW_G], CW[CW_Z], \
        CW[CW_Y], CW[CW_W], CW[CW_COMP]
    Wp, Wn, o = SW[SW_W], SW[SW_WN], SW[SW_AP]   # (spread's scratch: free once rows formed)
    # the order 6 as a run-time value (the LU's): LLVM would otherwise unroll the loops of
    # known trip count 6 around the lane loops, every copy vectorised with its own checks
    # and remainder (twice the machine code, which each caller compiles again: a first
    # run's time); the lane loops inside are the work
    six = LU.shape[0]
    for l in range(nb):
        p = p0 + l
        L = lengths[out_row(I, p)]
        _compliance(I, p, mr, torque, L, comp, l)
        for q in range(3):
            o[q] = co[q, l]
        workload_about_origin(I[3], I[4], o, Wp)
        normalise_wrench(Wp, centres[out_row(I, p)], L, Wn)
        for q in range(6):
            Wl[q, l] = Wp[q]
            z[q, l] = -Wn[q]
    if mr == 6:                       # LU of Jn^T (every lane: the sign of det J)
        for r in range(six):
            for q in range(six):
                for l in range(nb):
                    LU[q, r, l] = Jn[r, q, l]
    elif mr > 6:                      # the normal equations of the weighted rows
        for r in range(mr):
            for l in range(nb):
                g[r, l] = d[r, l] / math.sqrt(comp[r, l])
            for q in range(six):
                for l in range(nb):
                    Jw[r, q, l] = Jn[r, q, l] * g[r, l]
        for a in range(six):
            for b in range(six):
                for l in range(nb):
                    LU[a, b, l] = 0.0
                for r in range(mr):
                    for l in range(nb):
                        LU[a, b, l] += Jw[r, a, l] * Jw[r, b, l]
    if mr >= 6:
        lu_block(LU, six, piv, nb)
        lu_apply_block(LU, six, piv, z, nb)
    if mr > 6:
        for r in range(mr):
            for l in range(nb):
                y[r, l] = 0.0
            for q in range(six):
                for l in range(nb):
                    y[r, l] += Jw[r, q, l] * z[q, l]
    Jp, dp, cp = SW[SW_JN], SW[SW_D], SW[SW_COMP]
    for l in range(nb):
        row = out_row(I, p0 + l)
        J, centre, L = Jo[row], centres[row], lengths[row]
        values = values_o[row]
        for r in range(mr):
            dp[r] = d[r, l]
        for q in range(6):
            Wp[q] = Wl[q, l]
        well = mr >= 6 and sv[5, l] * REFINE > sv[0, l]
        if well:
            sign = 0.0
            if mr == 6:
                sign = lu_sign(LU, 6, piv, l)
                for r in range(6):
                    values[r] = z[r, l] / d[r, l]
            else:
                for r in range(mr):
                    values[r] = y[r, l] * g[r, l] / d[r, l]
        else:                         # the pseudo-inverse: the pose alone
            for r in range(mr):
                for q in range(6):
                    Jp[r, q] = Jn[r, q, l]
                cp[r] = comp[r, l]
            mode, sign = statics_prepare(mr, svo[row], cp, SW)
            statics_apply(mode, mr, Wp, centre, L, SW, values)
        for q in range(3):
            o[q] = co[q, l]
        eq[row] = equilibrium(J, mr, values, Wp, centre, L, dp)
        amp[row] = amplification(values, mr, torque, Wp, o, L)
        # (times the legs' orientation that _finish.finish_rows put there: _orient)
        det[row] = sign * det[row]
