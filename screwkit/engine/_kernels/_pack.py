"""The tuples of arrays the kernels take, packed into three arrays each (private).

A kernel called from Python pays for every argument it unboxes; a model tuple of 22 arrays
and the inputs and outputs of a pose would cost tens of microseconds a call.  Each tuple is
therefore handed over as one float64 array, one int64 array and a descriptor ``d (k, 5)``:
``d[j] = (int, offset, n0, n1, n2)`` (booleans travel as integers), and unpacked here into
views of the same types as always (C-contiguous arrays of fixed dimensions), borrowed
(:func:`._jit.borrowed`: the arrays Python passed own the data for the whole call).
"""

from ._jit import borrowed, borrowing_inlined, inlined, inner, prefetch_write


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
            f3(I, d, 17), f2(I, d, 18), f3(I, d, 19), f2(I, d, 20), f2(F, d, 21))


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
            f2(F, d, 22), f1(F, d, 23), f1(I, d, 24))


@borrowing_inlined
def _row_ahead(A, q):
    """Ask for the cache lines of row ``q`` of the output ``A`` (none where ``A`` has no
    rows: an output not asked for)."""
    if q < A.shape[0]:
        n = 1                           # (a row's values: products, not a division a pose)
        for k in range(1, A.ndim):
            n *= A.shape[k]
        for e in range(0, n, 8):
            prefetch_write(A, q * n + e)
        prefetch_write(A, q * n + n - 1)


@inlined
def prefetch_outputs(I, O, p):
    """Ask for the lines of every output row pose ``p`` will write (:func:`out_row`): a
    launch of a path's level writes rows spread over the path's outputs, each row's lines
    missing the cache; asked for a block ahead, they are there when the pose writes them."""
    q = out_row(I, p)
    _row_ahead(O[0], q)
    _row_ahead(O[1], q)
    _row_ahead(O[2], q)
    _row_ahead(O[3], q)
    _row_ahead(O[4], q)
    _row_ahead(O[5], q)
    _row_ahead(O[6], q)
    _row_ahead(O[7], q)
    _row_ahead(O[8], q)
    _row_ahead(O[9], q)
    _row_ahead(O[10], q)
    _row_ahead(O[11], q)
    _row_ahead(O[12], q)
    _row_ahead(O[13], q)
    _row_ahead(O[14], q)
    _row_ahead(O[15], q)
    _row_ahead(O[16], q)
    _row_ahead(O[17], q)
    _row_ahead(O[18], q)
    _row_ahead(O[19], q)
    _row_ahead(O[20], q)
    _row_ahead(O[21], q)
    _row_ahead(O[22], q)
    _row_ahead(O[23], q)
    _row_ahead(O[24], q)
