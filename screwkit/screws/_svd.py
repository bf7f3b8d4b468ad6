"""Singular values of one- and two-row matrices in closed form, for rank decisions (private).

A rank decision counts the singular values above a tolerance.  The Table I validation makes
thousands of them on a single row or a pair of rows (the moment matrix of a one- or
two-wrench target, the first joints of a search), where ``numpy.linalg.svd``'s per-call
overhead is most of the cost.  For such matrices the singular values have closed forms
that are as accurate as LAPACK's (an absolute error of a few ulps of the largest one):

* one row ``r``: ``|r|``;
* two rows ``r1, r2``: ``s1 s2 = |r1 ^ r2| = |r1| |r2 - (c / a) r1|`` (the component of
  ``r2`` normal to ``r1``: an absolute error of a few ulps of ``|r2|``, no cancellation)
  and ``s1^2 = (a + b + sqrt((a - b)^2 + 4 c^2)) / 2`` with ``a = |r1|^2``,
  ``b = |r2|^2``, ``c = r1 . r2`` (a sum of squares under the root), so
  ``s2 = |r1 ^ r2| / s1``.

The thresholds of the rank decisions (``1e-9`` and more, relative) are far above these
errors; :func:`decided_count` defers to LAPACK the rare values close to a threshold, so
the decisions are always those of the SVD.

For larger matrices, and wherever the singular vectors are needed, :func:`svd_values` and
:func:`svd_full` call the SVD gufuncs of ``numpy.linalg`` directly: the same LAPACK routine
on the same data (the same results, bit for bit), without ``numpy.linalg.svd``'s argument
checks and result wrapping (about half its cost on a 3- or 6-column matrix).  Should the
routine fail to converge (NaN results), ``numpy.linalg.svd`` is called to raise its error.
"""

from __future__ import annotations

import math
import operator

import numpy as np

try:  # the gufuncs behind numpy.linalg.svd (singular values only; full U, s, Vt)
    from numpy.linalg import _umath_linalg
    _VALUES, _FULL = _umath_linalg.svd, _umath_linalg.svd_f
except (ImportError, AttributeError):      # another numpy layout: use the public function
    _VALUES = _FULL = None

__all__ = ["small_singular_values", "decided_count", "small_rank", "svd_values", "svd_full"]


def _direct(M) -> bool:
    return (_VALUES is not None and isinstance(M, np.ndarray) and M.dtype == np.float64
            and M.ndim >= 2 and M.shape[-1] > 0 and M.shape[-2] > 0)


def svd_values(M) -> np.ndarray:
    """``numpy.linalg.svd(M, compute_uv=False)`` (M a float64 matrix or a stack of them)."""
    if not _direct(M):
        return np.linalg.svd(M, compute_uv=False)
    with np.errstate(all="ignore"):
        s = _VALUES(M, signature="d->d")
    if math.isnan(s.sum()):
        return np.linalg.svd(M, compute_uv=False)       # raises LinAlgError
    return s


def svd_full(M):
    """``numpy.linalg.svd(M, full_matrices=True)`` as a tuple ``(U, s, Vt)``."""
    if not _direct(M):
        return tuple(np.linalg.svd(M, full_matrices=True))
    with np.errstate(all="ignore"):
        u, s, vt = _FULL(M, signature="d->ddd")
    if math.isnan(s.sum()):
        return tuple(np.linalg.svd(M, full_matrices=True))
    return u, s, vt


def decided_count(s, tol: float, margin: float = 1e-3) -> int | None:
    """How many of the closed-form singular values ``s`` exceed ``tol``; None when one of
    them lies within ``margin * tol`` of it, where a closed form and LAPACK could disagree
    (their errors are ~1e-15 of the largest value, the thresholds 1e-9 of it or more):
    the caller then asks LAPACK, so the decision is always the SVD's."""
    lo, hi = tol * (1.0 - margin), tol * (1.0 + margin)
    n = 0
    for x in s:
        if x > hi:
            n += 1
        elif x >= lo:
            return None
    return n


def small_rank(rows, rtol: float, floor: float = 1.0) -> int | None:
    """The number of singular values above ``rtol * max(floor, s_max)`` of a matrix of
    one or two rows (lists of floats), or None (more rows, or a value too close to the
    threshold): the caller then counts LAPACK's singular values."""
    s = small_singular_values(rows)
    return None if s is None else decided_count(s, rtol * max(floor, s[0]))


def small_singular_values(rows) -> list | None:
    """Singular values (descending) of a matrix of one or two rows (lists of floats).

    Returns None for more rows (or none), or where the closed form would overflow or
    underflow: the caller uses the SVD.
    """
    if len(rows) == 1:
        s = math.hypot(*rows[0])
        return [s] if math.isfinite(s) else None
    if len(rows) != 2:
        return None
    r1, r2 = rows
    n1, n2 = math.hypot(*r1), math.hypot(*r2)
    if not (n1 > 1e-150 and n2 > 1e-150 and n1 < 1e150 and n2 < 1e150):
        return None
    c = sum(map(operator.mul, r1, r2))
    t = c / (n1 * n1)
    # |r1 ^ r2| = |r1| |r2 - t r1|: the component of r2 normal to r1, without cancellation
    normal = math.hypot(*[y - t * x for x, y in zip(r1, r2)])
    a, b = n1 * n1, n2 * n2
    s1 = math.sqrt(0.5 * (a + b + math.hypot(a - b, 2.0 * c)))
    return [s1, n1 * normal / s1]
