"""Linear actuators turned inside out, compiled (private): the batch test of
:class:`screwkit.engine._reversal.ActuatorLines`.

A leg is reversed where ``sign X[row] <= limit`` (its actuator's unknown ``X[row]``, the sign
of its home length and the limit of :class:`~screwkit.engine._reversal.ActuatorLines`): one
comparison a leg and pose, all of a pose's legs read in one pass over the engine's rows of
the unknowns (numpy compared a strided column at a time, a pass over the rows for each
leg, some 2 ms for 100,000 poses).
"""

from ._jit import entry


@entry
def reversed_rows(XT, rows, sign, limit, legs, some):
    """Poses ``XT (N, n_unknowns)`` (the engine's rows): which of the ``k`` legs at the
    unknowns ``rows (k,)`` (signs and limits ``sign, limit (k,)``) each reverses into
    ``legs (N, k)`` (bool; or ``(0, k)``: not written), and whether it reverses any into
    ``some (N,)`` (bool).  NaN reverses none."""
    k = rows.shape[0]
    write = legs.shape[0] > 0
    for p in range(XT.shape[0]):
        hit = False
        for c in range(k):
            v = XT[p, rows[c]]
            r = v <= limit[c] if sign[c] > 0 else v >= -limit[c]
            hit = hit | r
            if write:
                legs[p, c] = r
        some[p] = hit
