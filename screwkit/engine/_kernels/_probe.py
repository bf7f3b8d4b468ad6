"""The home decisions of a leg's row template, by the kernels' own functions (private).

Each function takes a one-leg model at its reference geometry (``M``, with the candidate
reference directions in ``DIRS`` and the named points in ``PTS``) and the platform frame
``fp`` there, and evaluates the leg at home (joint values 0) exactly as the row kernels do
at any pose:

* :func:`home_groups`: whether each group's rows leave a null space of its dimension, and
  the first candidate directions (in order) that give it a clear basis (each with a
  remainder of at least ``REF_MIN``);
* :func:`home_generic`: the generic rule's reference wrenches: couples, then forces
  through ``A``, along the first candidates that keep a clear projection on the constraint
  system, and what each of its rows is at home (a force, a couple or a screw: the rows'
  labels);
* :func:`home_least_norm`: the least-norm actuation member at home.
"""

import math

import numpy as np

from ._geometry import eval_directions, eval_points, leg_setup
from ._jit import entry, inner, one_lane
from ._kin import chain
from ._layout import D, DIRS, GREF, KIND, LEG, L_SIZE, PTS, REF_MIN, TPL, T_K
from ._members import (SC_NULL, SC_P0, SC_P1, SC_P2, SC_REM, home_null_space,
                       home_remainder)
from ._rows import (RW_CTX, RW_DV, RW_NR, RW_PV, RW_REM, RW_SC, RW_TW, RW_VEC,
                    generic_members, least_norm_member, make_rows_work)


@inner
def _home(M, fp):
    """The leg at home: its frames and the rows workspace with its context, twists, named
    points and directions."""
    m = M[D].shape[1]
    RW = make_rows_work(m, M[PTS].shape[1], M[DIRS].shape[1])
    fa = np.zeros((m, 6))
    X = np.zeros((m, 1))           # joint values 0 (owned here: see one_lane)
    fal = one_lane(fa)             # a block of one lane
    chain(M, 0, X, 0, fal, np.zeros((12, 1)), 1, 1, False, fal, np.zeros((3, 3)),
          np.zeros((2, 1)))
    leg_setup(M, 0, fa, fp, RW[RW_CTX], RW[RW_TW])
    eval_points(M, 0, fa, RW[RW_CTX], RW[RW_PV])
    eval_directions(M, 0, fa, fp, RW[RW_CTX], RW[RW_DV])
    return fa, RW


@entry
def home_groups(M, fp, gkind, gpoint, gdim, cand, ok, chosen):
    """Per group: ``ok[g]`` its null space has dimension ``gdim[g]`` at home;
    ``chosen[g, :dim]`` the first candidates (rows of ``DIRS``) of a clear basis (-1: none).
    The rows' own functions (``_members``) on a block of one."""
    fa, RW = _home(M, fp)
    rows, vec, dv, SC = RW[RW_NR], RW[RW_VEC], RW[RW_DV], RW[RW_SC]
    basis = np.zeros((3, 3, 1))    # (with its lane axis: owned here, see one_lane)
    kind, size = M[KIND][0], M[LEG][0, L_SIZE]
    for g in range(gkind.shape[0]):
        dim = gdim[g]
        home_null_space(kind, size, gkind[g] == 0, one_lane(RW[RW_PV]), gpoint[g],
                        one_lane(fa), one_lane(RW[RW_TW]), one_lane(RW[RW_CTX]),
                        one_lane(rows), dim, one_lane(vec), SC)
        ok[g] = SC[SC_NULL, 0] != 0.0
        k = 0
        for c in cand:
            if k == dim:
                break
            d = dv[c]
            nd = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            if not (math.isfinite(nd) and nd > 0.5):
                continue
            home_remainder(dim, one_lane(vec), basis, k, one_lane(dv), c, SC)
            p0, p1, p2, rem = SC[SC_P0, 0], SC[SC_P1, 0], SC[SC_P2, 0], abs(SC[SC_REM, 0])
            if rem >= REF_MIN:
                chosen[g, k] = c
                if dim > 1:
                    basis[k, 0, 0], basis[k, 1, 0], basis[k, 2, 0] = p0 / rem, p1 / rem, \
                        p2 / rem
                k += 1


@entry
def home_generic(M, fp, k, cand, out):
    """The generic rule's ``k`` reference wrenches: ``out[r, :2] = (0 force through A / 1
    couple, row of DIRS)``, couples first (a couple of the constraint system is then a row
    of its own at every pose, as the analysis lists it, not mixed by the Gram-Schmidt into
    the force rows before it), each the first candidate whose projection on the
    constraint system keeps a remainder of at least ``REF_MIN`` (-1: none found); and
    ``out[r, 2]`` what the generic rule's row ``r`` is at home (:func:`_member_kind`: 0 a
    force, 1 a couple, 2 a finite-pitch screw), by which the row is labelled."""
    fa, RW = _home(M, fp)
    tpl, gref = M[TPL][0], M[GREF][0]
    tpl[T_K] = k
    cons = np.zeros((6, 6))
    n = 0
    for kind in (1, 0):
        for c in cand:
            if n == k:
                break
            gref[n, 0], gref[n, 1] = kind, c
            worst = _generic_remainder(M, RW, n + 1, cons)
            if worst >= REF_MIN:
                out[n, 0], out[n, 1] = kind, c
                n += 1
    if n == k:                      # (cons: the rows of the k references, the last pass)
        L = RW[RW_CTX][3, 0]
        for r in range(k):
            out[r, 2] = _member_kind(cons[r], L)


@inner
def _member_kind(w, L):
    """0 a force, 1 a couple, 2 a finite-pitch screw: the physical unit wrench ``w [f; m]``
    (of the generic rule) with its force part at most 1e-9 of its length-normalised norm a
    couple; else with its pitch ``f.m / |f|^2`` within ``GEOMETRY_RTOL`` of the length ``L``
    a force (on a line), else a screw."""
    ff = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    mm = (w[3] * w[3] + w[4] * w[4] + w[5] * w[5]) / (L * L)
    if ff <= 1e-18 * (ff + mm):
        return 1
    h = (w[0] * w[3] + w[1] * w[4] + w[2] * w[5]) / ff
    return 0 if abs(h) <= 1e-7 * L else 2


@inner
def _generic_remainder(M, RW, count, cons):
    """The remainder of the last of the first ``count`` reference wrenches (``GREF``)
    projected on the constraint system at home, after the others."""
    tpl = M[TPL][0]
    k = tpl[T_K]
    tpl[T_K] = count
    generic_members(M, 0, RW, cons)
    tpl[T_K] = k
    return RW[RW_REM][count - 1]


@entry
def home_least_norm(M, fp, member):
    """The least-norm actuation member of the leg at home (``member (6,)``); returns
    whether it is defined."""
    _, RW = _home(M, fp)
    return least_norm_member(M, 0, RW, member)
