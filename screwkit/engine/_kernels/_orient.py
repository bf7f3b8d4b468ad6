"""The assembly-mode sign of ``det J``: each leg's constraint rows oriented as at a reference
pose (private).

The sign of a constraint row is a convention of the leg's geometry (a reference direction
evaluated at the pose, ``docs/conventions.md``), and a reference direction can pass through
zero inside the workspace (the RRPRR's ``OA x leg`` where the leg lies along ``OA``): the row
then turns over, and ``det J`` changes sign, with no singularity.  Compared with the same
leg's rows at the model's reference pose instead, a sign change of the product is a
singularity of ``J`` or a turn of the rows by a right angle, which is reported as undefined.
"""

import math

import numpy as np

from ._jit import entry, inner

#: ``|det (C_p C_ref^T)|`` of a leg's unit, length-normalised constraint rows against its
#: reference rows below which their orientation is not defined (the rows turned about a right
#: angle from the reference pose's).
ORIENT_MIN = 1e-3


@entry
def oriented_signs(J, ref, groups, centre, L, det, out):
    """``out[p] = det[p]`` times the orientation of each leg's constraint rows of ``J[p]``
    (``N, mr, 6``) against the same rows of ``ref (mr, 6)``: the sign of ``det (C_p
    C_ref^T)`` over the unit rows ``[f; (m - c x f) / L]`` (``c = centre``), each leg's rows
    ``groups[g, 0]:groups[g, 1]`` (at most three); 0 where one is not defined (below
    :data:`ORIENT_MIN`) or ``det[p]`` is 0."""
    N, mr = J.shape[0], J.shape[1]
    a, b = np.empty((mr, 6)), np.empty((mr, 6))
    G = np.zeros((3, 3))
    _unit_rows(ref, centre, L, b)
    for p in range(N):
        s = det[p]
        if s != 0.0:
            _unit_rows(J[p], centre, L, a)
            for g in range(groups.shape[0]):
                r0, k = groups[g, 0], groups[g, 1] - groups[g, 0]
                for i in range(k):
                    for j in range(k):
                        x = 0.0
                        for q in range(6):
                            x += a[r0 + i, q] * b[r0 + j, q]
                        G[i, j] = x
                d = G[0, 0]
                if k == 2:
                    d = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
                elif k == 3:
                    d = (G[0, 0] * (G[1, 1] * G[2, 2] - G[1, 2] * G[2, 1])
                         - G[0, 1] * (G[1, 0] * G[2, 2] - G[1, 2] * G[2, 0])
                         + G[0, 2] * (G[1, 0] * G[2, 1] - G[1, 1] * G[2, 0]))
                if not abs(d) >= ORIENT_MIN:
                    s = 0.0
                    break
                if d < 0.0:
                    s = -s
        out[p] = s


@inner
def _unit_rows(W, c, L, out):
    """The rows ``W (mr, 6)`` about ``c``, moments over ``L``, at unit norm, into ``out``."""
    for r in range(W.shape[0]):
        f0, f1, f2 = W[r, 0], W[r, 1], W[r, 2]
        out[r, 0], out[r, 1], out[r, 2] = f0, f1, f2
        out[r, 3] = (W[r, 3] - (c[1] * f2 - c[2] * f1)) / L
        out[r, 4] = (W[r, 4] - (c[2] * f0 - c[0] * f2)) / L
        out[r, 5] = (W[r, 5] - (c[0] * f1 - c[1] * f0)) / L
        n = 0.0
        for q in range(6):
            n += out[r, q] * out[r, q]
        n = max(math.sqrt(n), 1e-300)
        for q in range(6):
            out[r, q] /= n
