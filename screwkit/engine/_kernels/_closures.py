"""The inverse displacement of one pose, compiled: starts, continuation, polish, the
representation singularity (private).

Starts.  Without a warm start a pose begins at the home predictor: a quartic polynomial in
the independent parameters (cubic for six of them) fitted once per model to exact solutions
around home (its coefficients ``C``, fitted by :mod:`screwkit.engine._solve`); far outside
the fit (more than four half-widths), at home.

Continuation.  A pose whose Newton iteration does not converge is solved again from home by
moving its independent parameters in 4, 16, then 64 steps, each started from the last; a
level whose steps lose the track (residual above 1e-4) gives way to the next.  A pose left
just short of convergence is polished by a fresh Newton run.

Representation singularity.  Where ``beta`` is given at ``sin(beta) = 0`` (proper orders) or
``cos(beta) = 0`` (Tait-Bryan) and ``alpha`` or ``gamma`` is dependent, that angle is
undetermined: it is taken as its limit from both sides (the solutions at ``beta +- 1e-4``,
interpolated) or, with a warm start, from the warm start's side (Richardson), and the pose
is solved with it given (the unknowns ``unk2``).
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, inlined, lanes

from ._kin import forward
from ._layout import ACCEPTED, CONVERGED, KIND, K_R, LEG, L_SIZE, ORDER, STOP
from ._newton import (W_FA, W_FE, W_FL, W_FP, W_P6, W_P6S, W_S, W_XB, W_XC, W_XR,
                      gauss_newton, home_vector, newton_iterate, tolerance)
from ._trig import trig_exceeds

#: A whole turn (radians).
TURN = 2.0 * math.pi
SING_STEP = 1e-4
SING_TOL = 1e-7
NEAR_TOL = 1e-5
CONTINUATION = (4, 16, 64)


@borrowing
def predict(C, fix, home, span, degree, P6, Xhome, out, z, nb, ls):
    """The home predictor's starts ``out (nx, ls)`` of the lanes ``0..nb-1`` at their given
    parameters ``P6 (6, ls)`` (``C (features, nx)``, the monomials of degree up to ``degree``
    (3 or 4) in :func:`screwkit.engine._solve._monomials`'s order; no rows: start at home, as
    does a lane more than four half-widths out; ``z (12, ls)`` scratch).  The lanes at once,
    each as alone (the monomials' terms added in the same order); one pose is a block of
    one.  The monomials are formed four at a time into ``z[8:12]`` and their terms added
    four at a time (:func:`_add_terms`: each start read and written once per four terms, not
    once per term; the same sums)."""
    nf = fix.shape[0]
    nx = out.shape[0]
    po, pz, pp = lanes(out), lanes(z), lanes(P6)
    FR, BUF = 7 * ls, 8 * ls          # z's rows: the lane far out, the monomials' buffer
    for l in range(nb):
        pz[FR + l] = 1.0 if C.shape[0] == 0 else 0.0
    for k in range(nf):
        row, h, s = fix[k] * ls, home[k], span[k]
        for l in range(nb):
            t = (pp[row + l] - h) / s
            pz[k * ls + l] = t
            pz[FR + l] = pz[FR + l] if abs(t) <= 4.0 else 1.0
    if C.shape[0] == 0:
        for x in range(nx):
            for l in range(nb):
                po[x * ls + l] = Xhome[x]
        return
    for x in range(nx):
        c = C[0, x]
        for l in range(nb):
            po[x * ls + l] = c
    f = 1                             # the next monomial's row of C
    q = 0                             # monomials in the buffer
    for a in range(nf):
        for l in range(nb):
            pz[BUF + q * ls + l] = pz[a * ls + l]
        f, q = _buffered(C, f, q, pz, po, BUF, nx, nb, ls)
    for a in range(nf):
        for b in range(a, nf):
            for l in range(nb):
                pz[BUF + q * ls + l] = pz[a * ls + l] * pz[b * ls + l]
            f, q = _buffered(C, f, q, pz, po, BUF, nx, nb, ls)
    if degree >= 3:
        for a in range(nf):
            for b in range(a, nf):
                for e in range(b, nf):
                    for l in range(nb):
                        pz[BUF + q * ls + l] = pz[a * ls + l] * pz[b * ls + l] * pz[e * ls + l]
                    f, q = _buffered(C, f, q, pz, po, BUF, nx, nb, ls)
    if degree >= 4:
        for a in range(nf):
            for b in range(a, nf):
                for e in range(b, nf):
                    for g in range(e, nf):
                        for l in range(nb):
                            pz[BUF + q * ls + l] = pz[a * ls + l] * pz[b * ls + l] * \
                                pz[e * ls + l] * pz[g * ls + l]
                        f, q = _buffered(C, f, q, pz, po, BUF, nx, nb, ls)
    _add_terms(C, f - q, q, pz, po, BUF, nx, nb, ls)
    for x in range(nx):
        h = Xhome[x]
        for l in range(nb):
            po[x * ls + l] = h if pz[FR + l] != 0.0 else po[x * ls + l]


@inlined
def _buffered(C, f, q, pz, po, BUF, nx, nb, ls):
    """A monomial put in the buffer's slot ``q``: its terms (and the three before it) added
    when the buffer is full.  Returns the next ``(f, q)``."""
    if q == 3:
        _add_terms(C, f - 3, 4, pz, po, BUF, nx, nb, ls)
        return f + 1, 0
    return f + 1, q + 1


@inlined
def _add_terms(C, f0, count, pz, po, BUF, nx, nb, ls):
    """Add the terms of the ``count`` (0 to 4) buffered monomials, rows ``f0..`` of ``C``,
    to the starts, one after the other (the order of a term at a time)."""
    if count == 4:
        for x in range(nx):
            c0, c1, c2, c3 = C[f0, x], C[f0 + 1, x], C[f0 + 2, x], C[f0 + 3, x]
            for l in range(nb):
                v = po[x * ls + l]
                v += pz[BUF + l] * c0
                v += pz[BUF + ls + l] * c1
                v += pz[BUF + 2 * ls + l] * c2
                v += pz[BUF + 3 * ls + l] * c3
                po[x * ls + l] = v
        return
    for j in range(count):
        for x in range(nx):
            c = C[f0 + j, x]
            for l in range(nb):
                po[x * ls + l] += pz[BUF + j * ls + l] * c


@borrowing
def newton_continued(M, unk, xs, p6fix, X, p6home, fix, continuation, W):
    """Newton from ``X`` (in place); where it fails, continuation from home; then the
    polish.  Returns ``(residual, iterations, how, fresh)``: how 0 Newton from the start, 1
    continuation, 2 not solved; ``fresh``: the frames of buffer 0/1 belong to the final
    ``X`` (else -1: recompute them)."""
    res, its, _, cur = gauss_newton(M, unk, xs, p6fix, X,
                                    tolerance(M[ORDER], unk, xs, p6fix, X), 30, W)
    if res <= CONVERGED:
        return res, its, 0, cur
    return rescue(M, unk, xs, p6fix, X, p6home, fix, continuation, W, res, its, cur)


@borrowing
def rescue(M, unk, xs, p6fix, X, p6home, fix, continuation, W, res, its, cur):
    """After a Newton run from ``X`` that left the residual ``res`` above convergence: the
    continuation from home, then the polish (:func:`newton_continued`'s second half, apart
    so that a pose solved by its first Newton run, the common case, calls no more)."""
    order = M[ORDER]
    nx = X.shape[0]
    how = 0
    XC, p6s = W[W_XC], W[W_P6S][0]
    if not res <= CONVERGED and continuation:
        for steps in CONTINUATION:
            home_vector(unk, xs, p6home, XC)
            alive = True
            r, it, c = np.inf, 0, -1
            for s in range(1, steps + 1):
                for k in range(6):
                    p6s[k] = p6fix[k]
                for k in range(fix.shape[0]):
                    p = fix[k]
                    p6s[p] = p6home[p] + (p6fix[p] - p6home[p]) * s / steps
                r, it, _, c = gauss_newton(M, unk, xs, p6s, XC, 1e-12 if s == steps else 1e-8,
                                           30, W)
                cur = -1           # the run overwrote both buffers: X's frames formed again
                if s < steps and not r <= 1e-4:
                    alive = False
                    break
            if not alive:
                continue           # the track was lost on the way: try finer steps
            if r < res:
                for k in range(nx):
                    X[k] = XC[k]
                res = r
                its += it
                how = 1
            if res <= CONVERGED:
                break
    if res > CONVERGED and res <= ACCEPTED:
        XB = W[W_XB]
        for k in range(nx):
            XB[k] = X[k]
        r, it, _, c = gauss_newton(M, unk, xs, p6fix, XB, tolerance(order, unk, xs, p6fix, XB),
                                   30, W)
        cur = -1
        if r < res:
            for k in range(nx):
                X[k] = XB[k]
            res = r
            its += it
    if not res <= ACCEPTED:
        how = 2
    return res, its, how, cur


@borrowing_inlined
def pose_checks(order, unk, xs, p6fix, X0):
    """A pose's stopping residual from its start ``X0`` (:func:`._newton.tolerance`) and
    whether it is near the representation singularity, to be solved alone, and singular
    (:func:`near_singular` at :data:`NEAR_TOL` and :data:`SING_TOL`): ``(tol, near,
    sing)``.  For a ``beta`` given more than 1e-2 from the singularity (nearly every pose)
    one test settles all three (each function's own first test, at tolerances of 1e-2 and
    below): one scan of the unknowns and one distance a pose, not three."""
    pair, given = False, True
    for k in range(unk.shape[0]):
        pair = pair | (unk[k] == 3) | (unk[k] == 5)
        given = given & (unk[k] != 4)
    if not pair or (given and trig_exceeds(p6fix[4], order[4] == 1, 1e-2)):
        return STOP, False, False
    return (tolerance(order, unk, xs, p6fix, X0), near_singular(order, unk, p6fix, NEAR_TOL),
            near_singular(order, unk, p6fix, SING_TOL))


@borrowing
def near_singular(order, unk, p6fix, tol):
    """``beta`` given within ``tol`` (on its sine or cosine) of the representation
    singularity while alpha or gamma is dependent."""
    pair = False
    for k in range(unk.shape[0]):
        if unk[k] == 3 or unk[k] == 5:
            pair = True
        if unk[k] == 4:
            return False
    if not pair:
        return False
    b = p6fix[4]
    if trig_exceeds(b, order[4] == 1, tol):
        return False
    s = abs(math.sin(b)) if order[4] == 1 else abs(math.cos(b))
    return s <= tol


@inlined
def resolve_singular(M, unk, xs, unk2, xs2, p6fix, X, side, p6home, fix, fix2, W):
    """A pose at a representation singularity: the dependent angle(s) of the pair as the
    limit, then the pose solved with them given (``X`` in place: the full unknowns).
    Returns ``(residual, iterations, how)`` (residual inf when a side is unreachable)."""
    order = M[ORDER]
    nu, nu2 = unk.shape[0], unk2.shape[0]
    nx = X.shape[0]
    nj = nx - nu
    beta = p6fix[4]
    off = 0.0 if order[4] == 1 else 0.5 * math.pi
    b0 = round((beta - off) / math.pi) * math.pi + off
    u = beta - b0
    sd = 0.0 if side == 0.0 else (1.0 if side > 0 else -1.0)
    sb = abs(math.sin(beta)) if order[4] == 1 else abs(math.cos(beta))
    both = sd == 0.0 or not sb <= SING_TOL
    XR = W[W_XR]
    p6n = W[W_P6S][1]
    side_ok = True
    for q in range(4):
        db = SING_STEP * (1.0 if q % 2 == 0 else -1.0) * (1.0 if q < 2 else 2.0)
        for k in range(6):
            p6n[k] = p6fix[k]
        p6n[4] = b0 + db
        Xq = XR[2 + q]
        for k in range(nx):
            Xq[k] = X[k]
        r, _, _, _ = newton_continued(M, unk, xs, p6n, Xq, p6home, fix, True, W)
        if not r <= ACCEPTED:
            side_ok = False
    # the limits, and the pose solved with them given
    p6g = W[W_P6S][2]
    for k in range(6):
        p6g[k] = p6fix[k]
    for k in range(nu):
        p = unk[k]
        if p != 3 and p != 5:
            continue
        vp, vm, v2p, v2m = XR[2, k], XR[3, k], XR[4, k], XR[5, k]
        if both:
            lim = 0.5 * (vp + vm) + (vp - vm) * (u / (2 * SING_STEP))
        elif sd > 0:
            lim = 2 * vp - v2p
        else:
            lim = 2 * vm - v2m
        p6g[p] = lim * xs[k]
    X2 = XR[0]
    j = 0
    for k in range(nu):
        if unk[k] != 3 and unk[k] != 5:
            X2[j] = X[k]
            j += 1
    for k in range(nj):
        X2[nu2 + k] = X[nu + k]
    X2v = X2[:nu2 + nj]
    r, its, how, _ = newton_continued(M, unk2, xs2, p6g, X2v, p6home, fix2, True, W)
    j = 0
    for k in range(nu):
        if unk[k] == 3 or unk[k] == 5:
            X[k] = p6g[unk[k]] / xs[k]
        else:
            X[k] = X2[j]
            j += 1
    for k in range(nj):
        X[nu + k] = X2[nu2 + k]
    if not side_ok:
        return np.inf, its, 2
    return r, its, how


@borrowing
def solve_pose(M, unk, xs, unk2, xs2, p6fix, X, side, p6home, fix, fix2, continuation, W):
    """One pose's closures from the start ``X`` (in place; a kernel of its own, which the
    first compile builds in its second process: ``_warm``).  Returns ``(residual,
    iterations, how, singular_beta, buffer)``: the frames of the final ``X`` are in that
    buffer of the workspace."""
    order = M[ORDER]
    tol, near, sing = pose_checks(order, unk, xs, p6fix, X)
    if near:
        res, its, how = resolve_singular(M, unk, xs, unk2, xs2, p6fix, X, side, p6home, fix,
                                         fix2, W)
        cur = -1
    else:
        # newton_continued written out and the Newton run inlined: a pose solved by its
        # first Newton run (the common case) passes the model and the workspace down no call
        res, its, _, cur = newton_iterate(M, unk, xs, p6fix, X, tol, 30, W)
        how = 0
        if not res <= CONVERGED:
            res, its, how, cur = rescue(M, unk, xs, p6fix, X, p6home, fix, continuation, W,
                                        res, its, cur)
    FA, FL, FE, FP = W[W_FA], W[W_FL], W[W_FE], W[W_FP]
    if cur < 0:
        cur = 0
        f = forward(M, unk, xs, p6fix, X, FA, FL, FE, FP, 0, W[W_S], W[W_P6])
    else:
        f = res
    if near and not math.isfinite(res):
        f = np.inf                # an unreachable side makes the limit meaningless
    return f, its, how, sing, cur


@borrowing_inlined
def whole_turns(M, unk, X, X0, warm):
    """Take the whole turns out of a solved pose's angles (in place): each dependent Euler
    angle and revolute joint value of ``X`` more than half a turn from its reference is
    moved by whole turns to within half a turn of it.  The reference is the warm start
    ``X0`` where ``warm`` (a path stays continuous), else 0: the angles of a pose solved
    from home or the predictor lie in ``[-pi, pi]``.  Newton steps know no turns, so a pose
    far from its start could come back a turn or a hundred away from the canonical value
    (the same configuration; a joint limit then judged on the wrong number).  Helical
    joints keep their turns (they translate).  Returns True where ``X`` changed (its frames
    are then formed again).  Inlined by LLVM into its callers: called, it took every array
    of the model tuple as arguments on the stack (some 220 words), every pose (a profile of
    a path: 4 % of the samples in those pushes, twice the function's own)."""
    # as a rule no unknown is half a turn from its reference (a path's sample from its
    # start, a pose from home): one pass over all of them settles it, branch-free (the
    # test below reads the joints' kinds, an unknown at a time; NaN: not far, as there)
    far = False
    if warm:
        for k in range(X.shape[0]):
            far = far | (abs(X[k] - X0[k]) > math.pi)
    else:
        for k in range(X.shape[0]):
            far = far | (abs(X[k]) > math.pi)
    if not far:
        return False
    changed = False
    nu = unk.shape[0]
    for k in range(nu):
        if unk[k] >= 3:                     # alpha, beta, gamma (radians: xs 1)
            changed = _turns(X, X0, k, warm) or changed
    kind, leg = M[KIND], M[LEG]
    m = kind.shape[1]
    for i in range(kind.shape[0]):
        for j in range(leg[i, L_SIZE]):
            if kind[i, j] == K_R:           # (the unknown is the angle: q_scale 1)
                changed = _turns(X, X0, nu + i * m + j, warm) or changed
    return changed


@borrowing_inlined
def _turns(X, X0, k, warm):
    ref = X0[k] if warm else 0.0
    d = X[k] - ref
    if not abs(d) > math.pi:                # (NaN: left alone)
        return False
    X[k] = X[k] - TURN * round(d / TURN)
    return True
