"""Euler angles of the platform: the 12 orders of :mod:`scipy.spatial.transform`.

An order is a three-letter string in the scipy convention: upper case
(``"XYX"``, ``"XYZ"``) is *intrinsic* (rotations about the moving axes, the
paper's convention: ``R = R_X(alpha) R_Y(beta) R_X(gamma)``), lower case
(``"xyx"``) is *extrinsic* (about the fixed axes, ``R = R_x(gamma) R_y(beta)
R_x(alpha)``).  Proper Euler orders repeat the first axis (``XYX``, ``ZYZ``...),
Tait-Bryan orders use three distinct axes (``XYZ``, ``ZYX``...).

The paper's eq. (10c) lists the direction cosines of intrinsic ``XYX`` (writing
``lambda`` for ``gamma``): ``R = [[x_l, y_l, z_l], [x_m, y_m, z_m], [x_n, y_n,
z_n]]`` with ``x_l = c_beta``, ``x_m = s_alpha s_beta``, ``x_n = -c_alpha s_beta``...

Representation singularity: the first and third rotation axes coincide when
``sin(beta) = 0`` (proper Euler) or ``cos(beta) = 0`` (Tait-Bryan); there only a
combination of ``alpha`` and ``gamma`` is defined (``alpha + gamma`` or
``alpha - gamma``).

Examples
--------
>>> import numpy as np
>>> R = rotation_matrix("XYX", 0.3, 0.2, 0.1)
>>> bool(np.isclose(R[0, 0], np.cos(0.2)))
True
>>> is_singular("XYX", 0.0), is_singular("XYZ", 0.0)
(True, False)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._tolerance import GEOMETRY_RTOL

__all__ = ["ORDERS", "EulerAngles", "check_order", "rotation_matrix", "euler_matrices",
           "euler_angles", "is_singular", "angular_jacobian", "axis_rotation", "cos_sin"]

_AX = {"x": 0, "y": 1, "z": 2}
#: The 12 intrinsic orders (their lower-case forms are the extrinsic ones).
ORDERS = ("XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ",
          "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX")


def check_order(order) -> str:
    """Validate an Euler order (``"XYX"`` intrinsic, ``"xyx"`` extrinsic)."""
    if not isinstance(order, str) or len(order) != 3 or not (order.isupper() or order.islower()):
        raise InputError(f"Euler order must be 3 letters, all upper case (intrinsic) or all "
                         f"lower case (extrinsic), got {order!r}")
    if order.upper() not in ORDERS:
        raise InputError(f"unknown Euler order {order!r}: one of {', '.join(ORDERS)} "
                         "(or lower case for extrinsic)")
    return order


def _angles(alpha, beta, gamma, degrees):
    a = np.array([alpha, beta, gamma], dtype=float)
    if not np.all(np.isfinite(a)):
        raise InputError(f"Euler angles must be finite, got {a.tolist()}")
    return np.radians(a) if degrees else a


def cos_sin(angle):
    """``(cos(angle), sin(angle))`` of an array, from the tangent of the half angle.

    numpy vectorises ``tan`` (SIMD) but, on many machines, not ``cos`` and ``sin`` of
    float64: for pose-sized arrays this is about 4x faster (110 against 490 us for 24,576
    angles here), within 2.3e-16 of them (``t = tan(angle / 2)``, ``cos = (1 - t^2) /
    (1 + t^2)``, ``sin = 2 t / (1 + t^2)``; at ``angle = pi`` the float ``t`` is 1.6e16, not
    infinite, and the formulas still hold).
    """
    t = np.tan(0.5 * np.asarray(angle, float))
    t2 = t * t
    inv = 1.0 / (1.0 + t2)
    return (1.0 - t2) * inv, 2.0 * t * inv


def axis_rotation(axis: int, angle):
    """Rotation matrices about base axis ``axis`` (0, 1, 2) by ``angle`` (radians).

    ``angle`` a number: ``(3, 3)``; an array of shape ``S``: ``(3, 3) + S`` (the components
    first, as the engine's batched algebra keeps them).
    """
    angle = np.asarray(angle, float)
    c, s = cos_sin(angle)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    R = np.zeros((3, 3) + angle.shape)
    R[axis, axis] = 1.0
    R[j, j] = R[k, k] = c
    R[k, j], R[j, k] = s, -s
    return R


def _mm(R, S):
    return np.einsum("ik...,kj...->ij...", R, S)


def euler_matrices(order: str, alpha, beta, gamma):
    """Rotation matrices and angular Jacobians of Euler angles, batched.

    The definitions are scipy's ``Rotation.from_euler(order, ...)``: an upper-case
    order is intrinsic (``R = R1(alpha) R2(beta) R3(gamma)`` about the moving axes), a
    lower-case one extrinsic (``R = R3(gamma) R2(beta) R1(alpha)``); the tests pin the two
    to each other.  scipy itself is not imported (its import costs ~0.3 s).

    Parameters
    ----------
    order : str
    alpha, beta, gamma : array_like (broadcast to a shape ``S``), radians

    Returns
    -------
    R : ndarray (3, 3) + S
        World <- platform rotations.
    E : ndarray (3, 3) + S
        Columns ``d omega / d(alpha, beta, gamma)`` (world frame).
    """
    ax = [_AX[ch] for ch in order.lower()]
    a, b, g = np.broadcast_arrays(*(np.asarray(x, float) for x in (alpha, beta, gamma)))
    eye = np.broadcast_to(np.eye(3).reshape((3, 3) + (1,) * a.ndim), (3, 3) + a.shape)
    if order.isupper():
        R1 = axis_rotation(ax[0], a)
        R12 = _mm(R1, axis_rotation(ax[1], b))
        R = _mm(R12, axis_rotation(ax[2], g))
        E = np.stack([eye[:, ax[0]], R1[:, ax[1]], R12[:, ax[2]]], axis=1)
    else:
        R3 = axis_rotation(ax[2], g)
        R32 = _mm(R3, axis_rotation(ax[1], b))
        R = _mm(R32, axis_rotation(ax[0], a))
        E = np.stack([R32[:, ax[0]], R3[:, ax[1]], eye[:, ax[2]]], axis=1)
    return R, E


def rotation_matrix(order: str, alpha: float, beta: float, gamma: float,
                    degrees: bool = False) -> np.ndarray:
    """World <- platform rotation matrix, shape (3, 3), from three Euler angles."""
    check_order(order)
    a, b, g = _angles(alpha, beta, gamma, degrees)
    return euler_matrices(order, a, b, g)[0]


def is_singular(order: str, beta: float, degrees: bool = False, tol: float = GEOMETRY_RTOL) -> bool:
    """True at the representation singularity: proper orders at ``beta = 0, pi``,
    Tait-Bryan orders at ``beta = +-pi/2`` (within ``tol`` on the sine/cosine)."""
    check_order(order)
    b = np.radians(beta) if degrees else float(beta)
    proper = order[0].lower() == order[2].lower()
    return bool(abs(np.sin(b) if proper else np.cos(b)) <= tol)


def angular_jacobian(order: str, alpha: float, beta: float, gamma: float) -> np.ndarray:
    """Columns ``d omega / d(alpha, beta, gamma)``, shape (3, 3), world frame (radians).

    ``omega = E @ [alpha_dot, beta_dot, gamma_dot]`` is the platform's angular
    velocity.  Its determinant vanishes at the representation singularity.
    """
    check_order(order)
    return euler_matrices(order, alpha, beta, gamma)[1]


@dataclass(frozen=True)
class EulerAngles:
    """Result of :func:`euler_angles`.

    Attributes
    ----------
    angles : ndarray (3,)
        ``(alpha, beta, gamma)`` in the requested unit.
    singular : bool
        At the representation singularity; then ``combination`` is the only
        determined quantity and ``gamma`` was taken from the reference (or 0).
    combination : str
        ``""``, ``"alpha+gamma"`` or ``"alpha-gamma"``.
    """

    angles: np.ndarray
    singular: bool = False
    combination: str = ""


def _angle_about(M, axis):
    j, k = (axis + 1) % 3, (axis + 2) % 3
    return float(np.arctan2(M[k, j] - M[j, k], M[j, j] + M[k, k]))


def euler_angles(R, order: str, degrees: bool = False, reference=None,
                 tol: float = GEOMETRY_RTOL) -> EulerAngles:
    """Euler angles of a rotation matrix (the inverse of :func:`rotation_matrix`).

    Parameters
    ----------
    R : array_like (3, 3)
    order : str
    degrees : bool
        Unit of the result and of ``reference``.
    reference : array_like (3,), optional
        Angles to stay close to: each angle is moved by multiples of 2 pi
        towards it, and at the singularity ``gamma`` is taken from it
        (continuity) and ``alpha`` follows.
    """
    check_order(order)
    R = np.asarray(R, dtype=float)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)):
        raise InputError("R must be a finite 3x3 matrix")
    ax = [_AX[c] for c in order.lower()]
    from scipy.spatial.transform import Rotation   # only here: its import is slow

    rot = Rotation.from_matrix(R)
    # beta from scipy's robust extraction without the gimbal-lock warning path
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ang = rot.as_euler(order)
    ref = None if reference is None else np.asarray(reference, float) * (np.pi / 180 if degrees else 1)
    singular = is_singular(order, ang[1], tol=tol)
    comb = ""
    if singular:
        g = float(ref[2]) if ref is not None else 0.0
        b = ang[1]
        if order.isupper():   # R = R1(a) R2(b) R3(g)  ->  R1(a) = R (R2 R3)^T
            M = R @ (axis_rotation(ax[1], b) @ axis_rotation(ax[2], g)).T
        else:                 # R = R3(g) R2(b) R1(a)  ->  R1(a) = (R3 R2)^T R
            M = (axis_rotation(ax[2], g) @ axis_rotation(ax[1], b)).T @ R
        ang = np.array([_angle_about(M, ax[0]), b, g])
        E = angular_jacobian(order, ang[0], b, g)
        comb = "alpha+gamma" if float(E[:, 0] @ E[:, 2]) > 0 else "alpha-gamma"
    if ref is not None:
        ang = ang + 2 * np.pi * np.round((ref - ang) / (2 * np.pi))
    return EulerAngles(np.degrees(ang) if degrees else ang, singular, comb)
