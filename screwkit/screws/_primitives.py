"""Screw primitives: lines, twists and wrenches.

Conventions (see ``docs/conventions.md``)
-----------------------------------------
* A twist is ``V = [v; w]``: ``v`` is the velocity of the body point that
  coincides with the base origin ``O``, ``w`` the angular velocity.
* A wrench is ``W = [f; m]``: ``f`` the resultant force, ``m`` its moment about ``O``.
* The reciprocal product is ``W o V = f.v + m.w`` (virtual power), which in this
  ordering is the plain dot product of the two 6-vectors.

These are the paper's and Pinocchio's orders (linear part first).  The batched
helpers here work on arrays of shape ``(..., 6)``; the value types wrap one
line (:mod:`screwkit.screws._line`) or one screw (:mod:`screwkit.screws._screw`).

Examples
--------
>>> import numpy as np
>>> from screwkit.screws import revolute_twist, force_wrench
>>> V = revolute_twist([0, 0, 1], [1, 0, 0])      # R axis along Z through (1, 0, 0)
>>> W = force_wrench([0, 0, 1], [1, 0, 0])        # force on that same line
>>> float(W.reciprocal(V))
0.0
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import GeometryError, InputError
from ._vector import cross

__all__ = ["as_vector3", "as_rotation", "unit", "reciprocal_product", "transform_twists",
           "transform_wrenches", "screw_pitch", "screw_axis_point"]

_EPS = 1e-12


def as_vector3(x, name: str = "vector", bound: float | None = None) -> np.ndarray:
    """Return ``x`` as a finite float array of shape (3,), or raise :class:`InputError`;
    with ``bound``, each component at most ``bound`` in magnitude (a point or a
    translation: beyond, the geometry's digits are lost to its distance from ``O``)."""
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be 3 numbers, got {str(x)[:60]}") from None
    if a.shape != (3,):
        raise InputError(f"{name} must have 3 components, got shape {a.shape}")
    v = a.tolist()
    if not all(map(math.isfinite, v)):
        raise InputError(f"{name} must be finite, got {v}")
    if bound is not None and max(map(abs, v)) > bound:
        raise InputError(f"{name} must be within +-{bound:g}, got {v}")
    return a


def as_rotation(R, name: str = "rotation") -> np.ndarray:
    """Return ``R`` as a rotation matrix (3, 3): finite, orthonormal to 1e-9, determinant
    +1; else raise :class:`InputError`."""
    try:
        a = np.asarray(R, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a 3x3 rotation matrix, got {str(R)[:60]}") from None
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be a finite 3x3 rotation matrix, got shape {a.shape}")
    if not np.allclose(a.T @ a, np.eye(3), atol=1e-9) or np.linalg.det(a) < 0:
        raise InputError(f"{name} is not a proper rotation matrix (3, 3): orthonormal, "
                         "determinant +1")
    return a


def unit(x, name: str = "direction") -> np.ndarray:
    """Normalise a 3-vector; raise :class:`GeometryError` for a zero vector."""
    a = as_vector3(x, name)
    x0, x1, x2 = a.tolist()
    n = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if n <= _EPS * max(1.0, abs(x0), abs(x1), abs(x2)) or n == 0.0:
        raise GeometryError(f"{name} is the zero vector and has no direction")
    return a / n


def _as_screw6(x, name: str) -> np.ndarray:
    if np.iscomplexobj(x):
        raise InputError(f"{name} must be real numbers, got complex ones")
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be 6 numbers, got {str(x)[:60]}") from None
    if a.shape[-1:] != (6,):
        raise InputError(f"{name} must have 6 components in its last axis, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite")
    return a


# ---------------------------------------------------------------------------
# batched helpers on (..., 6) arrays
# ---------------------------------------------------------------------------

def reciprocal_product(wrenches, twists) -> np.ndarray:
    """Reciprocal product ``f.v + m.w`` of wrenches and twists, broadcast over ``...``.

    Parameters
    ----------
    wrenches, twists : array_like, shape (..., 6)

    Returns
    -------
    ndarray, shape (...)
    """
    return np.sum(np.asarray(wrenches, float) * np.asarray(twists, float), axis=-1)


def _rotation_and_translation(rotation, translation):
    try:
        R = np.asarray(rotation, dtype=float)
        p = np.asarray(translation, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError("rotation must be (..., 3, 3) and translation (..., 3) numbers") \
            from None
    if R.shape[-2:] != (3, 3) or p.shape[-1:] != (3,):
        raise InputError("rotation must be (..., 3, 3) and translation (..., 3)")
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(p))):
        raise InputError("rotation and translation must be finite")
    Rt = np.swapaxes(R, -1, -2)
    if not np.allclose(Rt @ R, np.eye(3), atol=1e-9) or np.any(np.linalg.det(R) < 0):
        raise InputError("rotation is not a proper rotation matrix (3, 3): orthonormal, "
                         "determinant +1")
    return R, p


def transform_twists(rotation, translation, twists) -> np.ndarray:
    """Express twists given in frame {b} in frame {a}, where ``x_a = R x_b + p``.

    The angular part rotates; the reference point moves from the origin of {b}
    to the origin of {a}: ``w' = R w``, ``v' = R v + p x (R w)``.

    Parameters
    ----------
    rotation : array_like, shape (..., 3, 3)
    translation : array_like, shape (..., 3)
    twists : array_like, shape (..., 6)
    """
    R, p = _rotation_and_translation(rotation, translation)
    V = np.asarray(twists, float)
    w = np.einsum("...ij,...j->...i", R, V[..., 3:])
    v = np.einsum("...ij,...j->...i", R, V[..., :3]) + cross(p, w)
    return np.concatenate([v, w], axis=-1)


def transform_wrenches(rotation, translation, wrenches) -> np.ndarray:
    """Express wrenches given in frame {b} in frame {a}, where ``x_a = R x_b + p``.

    ``f' = R f``, ``m' = R m + p x (R f)``.  Reciprocal products are invariant:
    ``transform_wrenches(R, p, W) . transform_twists(R, p, V) == W . V``.
    """
    R, p = _rotation_and_translation(rotation, translation)
    W = np.asarray(wrenches, float)
    f = np.einsum("...ij,...j->...i", R, W[..., :3])
    m = np.einsum("...ij,...j->...i", R, W[..., 3:]) + cross(p, f)
    return np.concatenate([f, m], axis=-1)


def screw_pitch(screws, kind: str = "twist") -> np.ndarray:
    """Pitch of twists (``v.w / w.w``) or wrenches (``f.m / f.f``); ``inf`` for pure
    translations or pure couples.

    Parameters
    ----------
    screws : array_like, shape (..., 6)
    kind : {"twist", "wrench"}
    """
    S = np.asarray(screws, float)
    lin, ang = S[..., :3], S[..., 3:]
    prim = ang if kind == "twist" else lin
    sec = lin if kind == "twist" else ang
    den = np.sum(prim * prim, axis=-1)
    num = np.sum(prim * sec, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def screw_axis_point(screws, kind: str = "twist") -> np.ndarray:
    """Point of the screw axis closest to the origin, shape (..., 3) (NaN for infinite pitch).

    For a twist the axis direction is ``w`` and the point is ``w x v / |w|^2``;
    for a wrench the direction is ``f`` and the point is ``f x m / |f|^2``.
    """
    S = np.asarray(screws, float)
    lin, ang = S[..., :3], S[..., 3:]
    d, sec = (ang, lin) if kind == "twist" else (lin, ang)
    if kind == "twist":
        # v = p x w + h w  ->  p = w x v / |w|^2
        num = cross(d, sec)
    else:
        # m = p x f + h f  ->  p = f x m / |f|^2
        num = cross(d, sec)
    den = np.sum(d * d, axis=-1)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.nan)
