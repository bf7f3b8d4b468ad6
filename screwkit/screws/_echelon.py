"""The reduced row echelon form of a basis: one canonical basis of a subspace; the
canonical sign of a direction (private).

A subspace given by any basis (an SVD's null vectors, whose signs and mixing the last bits of
the matrix decide) has one basis in reduced row echelon form: each vector 1 on a coordinate
of its own (its pivot, the first coordinate, in order, that the vectors after the earlier
ones reach) and 0 on the other vectors' pivots.  Printed results take it so that they do not
depend on those bits, nor on anything the subspace itself does not depend on.
"""

from __future__ import annotations

import numpy as np

__all__ = ["reduced_echelon", "canonical_sign", "canonical_twist_sign"]


def reduced_echelon(B, rtol: float = 1e-9) -> tuple:
    """``(E, pivots)``: the reduced row echelon form of the rows of ``B``.

    Gauss-Jordan with partial pivoting, column by column.  A column whose entries left to
    pivot are all at most ``rtol`` times the largest entry of ``B`` has no pivot, and the
    entries of ``E`` at most that small are set to 0 (rounding of an exact zero: a
    coordinate the subspace does not reach).

    Parameters
    ----------
    B : array_like (k, m)
        Rows of full rank ``k``, entries of comparable size (an orthonormal basis, or one
        in normalised coordinates): the tolerance is relative to the largest.
    rtol : float

    Returns
    -------
    E : ndarray (k, m)
        The same span; ``E[i, pivots[i]] = 1`` and ``E[j, pivots[i]] = 0`` for ``j != i``.
    pivots : ndarray (k,) of int
        Increasing.  Fewer than ``k`` where ``B`` is not of full rank to ``rtol`` (the rows
        past them are then 0).

    Examples
    --------
    >>> import numpy as np
    >>> E, p = reduced_echelon([[0.0, 2.0, 2.0], [0.0, 1.0, -1.0]])
    >>> E.tolist(), p.tolist()
    ([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [1, 2])
    """
    E = np.array(B, float)
    k = E.shape[0]
    tol = rtol * np.abs(E).max(initial=0.0)
    piv = []
    for c in range(E.shape[1]):
        r = len(piv)
        if r == k:
            break
        best = r + int(np.argmax(np.abs(E[r:, c])))
        if abs(E[best, c]) <= tol:
            continue
        E[[r, best]] = E[[best, r]]
        E[r] /= E[r, c]
        others = np.arange(k) != r
        E[others] -= np.outer(E[others, c], E[r])
        E[others, c] = 0.0
        piv.append(c)
    E[len(piv):] = 0.0
    E[np.abs(E) <= tol] = 0.0
    return E + 0.0, np.array(piv, int)


def canonical_sign(x, rtol: float = 1e-8, axis: int = -1) -> np.ndarray:
    """``x`` or ``-x`` along ``axis``, each vector the one whose first entry above ``rtol``
    times its largest is positive (a direction free both ways, a null vector, has no sign
    of its own; an SVD's is set by the last bits of its matrix).  A zero vector is left.

    Examples
    --------
    >>> canonical_sign([1e-12, -0.6, 0.8]).tolist()
    [-1e-12, 0.6, -0.8]
    >>> canonical_sign([[0.0, -1.0], [2.0, 3.0]], axis=0).tolist()
    [[0.0, 1.0], [2.0, -3.0]]
    """
    x = np.moveaxis(np.asarray(x, float), axis, -1)
    big = np.abs(x) > rtol * np.max(np.abs(x), axis=-1, keepdims=True)
    first = np.take_along_axis(x, np.argmax(big, axis=-1)[..., None], axis=-1)
    return np.moveaxis(np.where(first < 0.0, -x, x) + 0.0, -1, axis)


def canonical_twist_sign(T, axis: int = -1) -> np.ndarray:
    """Twists ``[v; w]`` (6 entries along ``axis``) with the sign of :func:`canonical_sign`
    applied to their ``w`` (to their ``v`` for a translation, ``|w| <= 1e-9 |v|``): a
    motion free both ways (an unrestrained or uncontrolled twist) named one way.

    Examples
    --------
    >>> canonical_twist_sign([1.0, 0.0, 0.0, 0.0, -1.0, 0.0]).tolist()
    [-1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    """
    T = np.moveaxis(np.asarray(T, float), axis, -1)
    v, w = T[..., :3], T[..., 3:]
    rot = np.linalg.norm(w, axis=-1, keepdims=True) > \
        1e-9 * np.linalg.norm(v, axis=-1, keepdims=True)
    part = np.where(rot, w, v)
    flip = np.any(canonical_sign(part) != part, axis=-1, keepdims=True)
    return np.moveaxis(np.where(flip, -T, T) + 0.0, -1, axis)

