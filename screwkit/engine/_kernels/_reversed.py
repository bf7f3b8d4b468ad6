"""Linear actuators turned inside out, compiled (private): the test of
:mod:`screwkit.engine._reversal`.

A leg is reversed where ``sign X[row] <= limit`` (its actuator's unknown ``X[row]``, the sign
of its home length and the limit: the model's ``REV`` table, :mod:`._layout`): one
comparison a leg and pose.  :func:`reversed_mask` is the test; the analysis kernel takes it
for every pose it solves, into ``OUT_REVERSED`` (the pose's unknowns at hand, in the cache:
a pass of its own over 100,000 poses' unknowns read 14 MB again), and
:func:`reversed_rows` for unknowns given from Python.
"""

from ._jit import entry, inlined, inner
from ._layout import OUT_REVERSED, OUT_X, REV, RV_LEG, RV_LIMIT, RV_ROW, RV_SIGN
from ._pack import out_row


@inner
def reversed_mask(REV, x):
    """The legs of ``REV (k, 4)`` the unknowns ``x (n_unknowns,)`` of one pose reverse: bit
    ``i`` set for leg ``i`` (a PM has at most six legs).  NaN reverses none."""
    mask = 0
    for c in range(REV.shape[0]):
        v = x[int(REV[c, RV_ROW])]
        limit = REV[c, RV_LIMIT]
        r = v <= limit if REV[c, RV_SIGN] > 0 else v >= -limit
        if r:
            mask |= 1 << int(REV[c, RV_LEG])
    return mask


@inlined
def reversed_block(M, I, O, p0, nb):
    """The legs each of the poses ``p0..p0+nb-1`` reverses (their solved unknowns, in their
    rows of the outputs, :func:`._pack.out_row`) into their rows of ``O[OUT_REVERSED]``."""
    for l in range(nb):
        q = out_row(I, p0 + l)
        O[OUT_REVERSED][q] = reversed_mask(M[REV], O[OUT_X][q])


@entry
def reversed_rows(XT, REV, out):
    """:func:`reversed_mask` of each of the poses ``XT (N, n_unknowns)`` (the engine's rows)
    into ``out (N,)``."""
    for p in range(XT.shape[0]):
        out[p] = reversed_mask(REV, XT[p])
