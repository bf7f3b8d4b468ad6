"""A pose of the analysis kernel after its closures, compiled (private): its rows, then its
block's conditioning and statics (:mod:`._driver`'s loops call these, a pose or a block of
poses at a time; the arguments are the driver's).

A pose whose frames are its lane of the block's (no step alone, no rescue, no whole turn)
reads what the block formed for its lanes at once: the rows of its template legs, their
frames' twists, its centroid, spread and platform origin (the rows workspace ``RL``); only
a leg without a template, or whose template does not hold there, forms its rows from the
frames copied into the one-pose workspace (:func:`reads_frames`).
"""

from ._jit import inlined, one_lane

from ._block import lane_frames_into
from ._members import DONE, NOT_DONE, SC_STATUS
from ._indices import pose_lines
from ._kin import forward
from ._layout import (D, F_LINES, F_ORIENT, F_ROWS, F_STATICS, F_TWISTS, LEG, L_ACT, L_AROW, L_SIZE,
                      OUT_AMP, OUT_CCOND, OUT_CENTRE, OUT_COND, OUT_CRANK, OUT_DET, OUT_EQ,
                      OUT_J, OUT_LENGTH, OUT_LINES, OUT_PLATFORM, OUT_RANK, OUT_RES,
                      OUT_ROWS_OK, OUT_SCALE, OUT_STRUCT, OUT_SV, OUT_TWISTS, OUT_VALUES, OUT_X,
                      PLAT, RL_SC, RL_SP, RL_TW, ROWS, TPL)
from ._orient import leg_orientation, orients
from ._newton import W_FA, W_FE, W_FL, W_FP, W_P6, W_S, W_XN
from ._pack import out_row
from ._rows import RW_TW, leg_frames, leg_rows, template_rows
from ._statics import (CW_COND, CW_D, CW_JN, CW_O, CW_RANK, CW_SV, SW_D, SW_JN, SW_LU, SW_PIV,
                       SW_SP, conditioning_lanes, normalise_rows, spread_lanes)
from ._statics_block import statics_block


@inlined
def pose_rows(M, Z, I, O, flags, p, W, RW, SW, b, res, CW, l, lines_here, RL, lane):
    """:func:`finish_rows` of pose ``p`` after its closures (``b < 0``: its frames formed
    here at its unknowns, given or returned by a rescue's Newton runs)."""
    if b < 0:
        b = 0
        res = forward(M, Z[0], Z[1], I[0][p], O[OUT_X][out_row(I, p)], W[W_FA], W[W_FL],
                      W[W_FE], W[W_FP], 0, W[W_S], W[W_P6])
    finish_rows(M, Z, I, O, flags, p, W, RW, SW, b, res, CW, l, lines_here, RL, lane)


@inlined
def finish_rows(M, Z, I, O, flags, p, W, RW, SW, b, res, CW, l, lines_here, RL, lane):
    """Pose ``p`` after its closures (its frames in buffer ``b`` of ``W``, its residual
    ``res``): the lines (``lines_here``: else its block's, :func:`._block.block_lines`) and
    rows, as ``flags`` says; its normalised rows, their norms and its platform's origin
    into lane ``l`` of the conditioning workspace ``CW`` (for :func:`finish_block`).  Its
    legs' frames are lane ``lane`` of the block's ``RL`` where ``lane >= 0``, else formed here."""
    unk, xs = Z[0], Z[1]
    p6fix = I[0][p]
    q = out_row(I, p)               # (pose p of the inputs writes row q of the outputs)
    X = O[OUT_X][q]
    FA, FP = W[W_FA], W[W_FP]
    O[OUT_RES][q] = res
    if flags[F_LINES] and lines_here:
        bl = pose_lines(M, unk, xs, p6fix, X, FA, W[W_FL], W[W_FE], FP, b, W[W_S], W[W_P6],
                        W[W_XN], O[OUT_LINES][q])
        po, fl = O[OUT_PLATFORM][q], FP[bl]
        for k in range(po.shape[0]):  # (a loop: an array assignment needs reference counts)
            po[k] = fl[k]
    if not flags[F_ROWS]:
        return
    n = M[D].shape[0]
    fp = FP[b]
    J, scale = O[OUT_J][q], O[OUT_SCALE][q]
    mr = J.shape[0]
    ok = True
    tw_out = O[OUT_TWISTS]
    leg = M[LEG]
    # the legs' orientation of det J's sign (_orient), asked for, where the statics forms
    # that sign
    statics = flags[F_STATICS] and O[OUT_DET].shape[0] > 0
    orient = statics and flags[F_ORIENT] and mr == 6
    sign = 1.0
    for i in range(n):
        a = leg[i, L_AROW]
        if lane >= 0 and RL[RL_SC][i, SC_STATUS, lane] != NOT_DONE:
            # its template's rows, formed for the block's lanes at once and put in its rows
            # of the outputs already (_block.block_rows_into)
            ok = RL[RL_SC][i, SC_STATUS, lane] == DONE and ok
            O[OUT_STRUCT][q, i] = True
            if flags[F_TWISTS] and a >= 0:
                for k in range(6):
                    tw_out[q, a, k] = RL[RL_TW][i, leg[i, L_ACT], k, lane]
            if orient and orients(leg[i], M[TPL][i]):
                tw = RW[RW_TW]          # (the one-pose twists: free for this leg's lane's)
                for j in range(leg[i, L_SIZE]):
                    for k in range(6):
                        tw[j, k] = RL[RL_TW][i, j, k, lane]
                sign *= leg_orientation(leg[i], M[TPL][i], M[PLAT], tw, J, SW[SW_LU],
                                        SW[SW_PIV])
            continue
        if lane >= 0:
            lane_frames_into(M, i, RL, lane, RW, FA[b, i])
        else:
            leg_frames(M, i, RW, FA[b, i], fp)
        lok, st, done = template_rows(M, i, RW, FA[b, i], fp, J, scale)
        if not done:                  # the general rules (the call kept out of the legs')
            lok, st = leg_rows(M, i, RW, FA[b, i], fp, J, scale)
        ok = ok and lok
        O[OUT_STRUCT][q, i] = st
        if orient and orients(leg[i], M[TPL][i]):
            sign *= leg_orientation(leg[i], M[TPL][i], M[PLAT], RW[RW_TW], J, SW[SW_LU],
                                    SW[SW_PIV])
        if flags[F_TWISTS] and a >= 0:
            tw = RW[RW_TW][leg[i, L_ACT]]
            for k in range(6):
                tw_out[q, a, k] = tw[k]
    O[OUT_ROWS_OK][q] = ok
    if statics:                         # (the statics multiplies it by det J's own sign)
        O[OUT_DET][q] = sign
    # the centroid, spread and origin: the block's lane's, else formed here
    S, sl = RL[RL_SP], lane
    if lane < 0:
        S, sl = one_lane(SW[SW_SP]), 0
        spread_lanes(M, FA[b], fp, S, 1, 1)
    centre = O[OUT_CENTRE][q]
    for k in range(3):
        centre[k] = S[k, sl]
    L = S[3, sl]
    O[OUT_LENGTH][q] = L
    cj, cd, co = CW[CW_JN], CW[CW_D], CW[CW_O]
    if lane < 0 or reads_frames(M, flags, RL, lane):
        # (else its rows were normalised on the block's lanes: _driver.block_poses)
        normalise_rows(J, mr, centre, L, SW)
        Jn, d = SW[SW_JN], SW[SW_D]
        for r in range(mr):
            for k in range(6):
                cj[r, k, l] = Jn[r, k]
            cd[r, l] = d[r]
    for k in range(3):
        co[k, l] = S[5 + k, sl]


@inlined
def finish_block(M, I, O, flags, p0, nb, SW, CW):
    """The poses ``p0..p0+nb-1`` after :func:`finish_rows` (lanes ``0..nb-1`` of ``CW``): their
    conditioning (the lanes at once, :func:`conditioning_lanes`), then each one's statics,
    as ``flags`` says."""
    if not flags[F_ROWS]:
        return
    leg = M[LEG]
    n = M[D].shape[0]
    mr = M[ROWS].shape[0]
    n_act = 0
    for i in range(n):
        if leg[i, L_AROW] >= 0:
            n_act += 1
    conditioning_lanes(CW, mr, n_act, nb)
    sv, RK, CD = CW[CW_SV], CW[CW_RANK], CW[CW_COND]
    SV = O[OUT_SV]
    for k in range(SV.shape[1]):      # (each value along the lanes: the lanes' rows read once)
        for l in range(nb):
            SV[out_row(I, p0 + l), k] = sv[k, l]
    for l in range(nb):
        q = out_row(I, p0 + l)
        O[OUT_RANK][q], O[OUT_COND][q] = RK[0, l], CD[0, l]
        O[OUT_CRANK][q], O[OUT_CCOND][q] = RK[1, l], CD[1, l]
    if flags[F_STATICS]:
        statics_block(I, p0, nb, mr, SW, CW, O[OUT_J], O[OUT_CENTRE], O[OUT_LENGTH], O[OUT_SV],
                      O[OUT_VALUES], O[OUT_EQ], O[OUT_AMP], O[OUT_DET])


@inlined
def reads_frames(M, flags, RL, l):
    """Whether lane ``l``'s rows read its frames in the one-pose workspace: a leg whose rows
    the block did not form (:func:`._block.template_rows_block`).  The others read the
    block's lanes (their rows, centroid, spread and origin: ``RL``)."""
    if flags[F_ROWS]:
        for i in range(M[D].shape[0]):
            if RL[RL_SC][i, SC_STATUS, l] == NOT_DONE:
                return True
    return False
