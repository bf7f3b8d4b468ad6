"""Scale-aware numerical tolerances.

All rank decisions in screwkit are made on *length-normalised* screws: linear
parts of twists and moment parts of wrenches are divided by a characteristic
length of the geometry, and the frame is moved to the centroid of the geometry,
so that a decision does not change when every length is multiplied by 1000 or
when the base frame is moved.  The relative tolerances below are the only
literals that decide ranks; every function takes them as overridable arguments.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = [
    "RANK_RTOL",
    "GEOMETRY_RTOL",
    "characteristic_length",
]

#: Relative tolerance on singular values of length-normalised screw matrices:
#: a singular value below ``RANK_RTOL * max(1, s_max)`` counts as zero.
RANK_RTOL = 1e-8

#: Relative tolerance for geometric predicates on unit vectors and on distances
#: divided by the characteristic length (parallel, perpendicular, meets).
GEOMETRY_RTOL = 1e-7


def characteristic_length(points) -> float:
    """Characteristic length of a set of points.

    Parameters
    ----------
    points : array_like, shape (..., 3)

    Returns
    -------
    float
        The RMS distance of the points from their centroid; when all the points
        coincide, their largest coordinate magnitude; 1.0 when they all lie at the
        origin (a pure-direction geometry has no length of its own).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    if p.size == 0:
        return 1.0
    return _centroid_and_length(p)[1]


#: Up to this many points, :func:`_centroid_and_length` works on Python floats.
_SMALL_POINTS = 64


def _pairwise_sum(a: list) -> float:
    """``numpy.add.reduce`` of a short 1-D float array, in numpy's order (pairwise summation
    with eight accumulators from eight terms on, up to its block of 128)."""
    n = len(a)
    if n < 8:
        res = 0.0
        for x in a:
            res += x
        return res
    r = a[:8]
    i = 8
    while i + 8 <= n:
        for j in range(8):
            r[j] += a[i + j]
        i += 8
    res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
    for x in a[i:]:
        res += x
    return res


def _centroid_and_length(p: np.ndarray):
    """``(p.mean(axis=0), characteristic_length(p))`` for points ``p`` (n, 3), n >= 1.

    A few points are summed on Python floats in numpy's order (the same values bit for bit,
    without a dozen numpy calls)."""
    if len(p) > _SMALL_POINTS:
        c = p.mean(axis=0)
        return c, _spread_length(p, c)
    rows = p.tolist()
    n = len(rows)
    s0 = s1 = s2 = 0.0                  # numpy sums a column sequentially
    for x, y, z in rows:
        s0 += x
        s1 += y
        s2 += z
    c0, c1, c2 = s0 / n, s1 / n, s2 / n
    sq = [(x - c0) * (x - c0) + (y - c1) * (y - c1) + (z - c2) * (z - c2) for x, y, z in rows]
    spread = math.sqrt(_pairwise_sum(sq) / n)
    return np.array([c0, c1, c2]), _finish_length(spread, p)


def _spread_length(p: np.ndarray, centroid: np.ndarray) -> float:
    """:func:`characteristic_length` of the points ``p``, shape (n, 3), given their centroid."""
    if p.size == 0:
        return 1.0
    return _finish_length(float(np.sqrt(np.mean(np.sum((p - centroid) ** 2, axis=1)))), p)


def _finish_length(spread: float, p: np.ndarray) -> float:
    if not math.isfinite(spread):
        return 1.0
    # coincident points: no spread to measure, fall back to the distance from the origin
    # (so the result still scales with the units) or to 1 for points at the origin
    biggest = float(np.abs(p).max())
    if spread <= 1e-12 * biggest:
        spread = biggest
    return spread if spread > 0 else 1.0


def check_rtol(x, name: str = "rtol") -> float:
    """A relative tolerance: a finite number in (0, 1), else InputError."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number in (0, 1), got {str(x)[:40]}") from None
    if not 0.0 < v < 1.0:
        raise InputError(f"{name} must be a number in (0, 1), got {v!r}")
    return v
