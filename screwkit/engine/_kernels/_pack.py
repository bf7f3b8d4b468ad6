"""The tuples of arrays the kernels take, packed into three arrays each (private).

A kernel called from Python pays for every argument it unboxes; a model tuple of 21 arrays
and the inputs and outputs of a pose would cost tens of microseconds a call.  Each tuple is
therefore handed over as one float64 array, one int64 array and a descriptor ``d (k, 5)``:
``d[j] = (int, offset, n0, n1, n2)`` (booleans travel as integers), and unpacked here into
views of the same types as always (C-contiguous arrays of fixed dimensions), borrowed
(:func:`._jit.borrowed`: the arrays Python passed own the data for the whole call).
"""

from ._jit import borrowed, inner


@inner
def f1(F, d, k):
    o = d[k, 1]
    return borrowed(F[o:o + d[k, 2]])


@inner
def f2(F, d, k):
    o = d[k, 1]
    return borrowed(F[o:o + d[k, 2] * d[k, 3]].reshape((d[k, 2], d[k, 3])))


@inner
def f3(F, d, k):
    o = d[k, 1]
    return borrowed(F[o:o + d[k, 2] * d[k, 3] * d[k, 4]].reshape((d[k, 2], d[k, 3],
                                                                   d[k, 4])))


@inner
def model(F, I, d):
    """The model tuple ``M`` (:mod:`._layout`)."""
    return (f3(F, d, 0), f3(F, d, 1), f2(F, d, 2), f2(F, d, 3), f2(F, d, 4), f2(F, d, 5),
            f3(F, d, 6), f3(F, d, 7), f2(F, d, 8), f2(I, d, 9), f2(I, d, 10), f1(F, d, 11),
            f1(I, d, 12), f2(F, d, 13), f2(F, d, 14), f3(I, d, 15), f3(I, d, 16),
            f3(I, d, 17), f2(I, d, 18), f3(I, d, 19), f2(I, d, 20))


@inner
def params(F, I, d):
    """The pose parametrisation ``Z`` (:mod:`._driver`)."""
    return (f1(I, d, 0), f1(F, d, 1), f1(I, d, 2), f1(F, d, 3), f1(I, d, 4), f1(I, d, 5),
            f1(F, d, 6), f2(F, d, 7), f1(F, d, 8), f1(F, d, 9), f1(I, d, 10))


@inner
def inputs(F, I, d):
    """The inputs ``I`` of the analysis kernel (:mod:`._driver`)."""
    return (f2(F, d, 0), f2(F, d, 1), f1(F, d, 2), f1(F, d, 3), f1(F, d, 4), f2(F, d, 5),
            f1(I, d, 6), f1(I, d, 7), f2(F, d, 8))


@inner
def out_row(I, p):
    """The row of the outputs that pose ``p`` of the inputs writes: ``I[7][p]``, the rows
    given (a path's level writes its samples' rows of the path's outputs), else ``p``."""
    rows = I[7]
    return rows[p] if rows.shape[0] else p


@inner
def outputs(F, I, d):
    """The outputs ``O`` of the analysis kernel (:mod:`._driver`, ``OUT_*``)."""
    return (f2(F, d, 0), f1(F, d, 1), f1(I, d, 2), f1(I, d, 3), f1(I, d, 4), f3(F, d, 5),
            f2(F, d, 6), f1(I, d, 7), f2(I, d, 8), f2(F, d, 9), f1(F, d, 10), f2(F, d, 11),
            f1(I, d, 12), f1(F, d, 13), f1(I, d, 14), f1(F, d, 15), f2(F, d, 16),
            f1(F, d, 17), f1(F, d, 18), f1(F, d, 19), f3(F, d, 20), f3(F, d, 21),
            f2(F, d, 22), f1(F, d, 23))
