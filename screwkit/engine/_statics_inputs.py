"""The inputs of the statics checked (private): workload vectors, the legs' end points."""

from __future__ import annotations

import numpy as np

__all__ = ["_finite3", "_leg_points"]


def _errors():
    from ..errors import InputError
    return InputError


def _finite3(x, name) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise _errors()(f"{name} must be numbers (3 components), got {x!r:.60}") from None
    if a.ndim == 0 or a.shape[-1] != 3 or a.size == 0:
        raise _errors()(f"{name} must have 3 components in its last axis, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise _errors()(f"{name} must be finite (no NaN or inf), got {a.tolist()}")
    return a


def _leg_points(jacobian, base_points, platform_points, N):
    """``A (n, 3)`` and ``a (N, n, 3)`` checked against the legs of ``jacobian`` (their
    count, finite): the compiled leg wrenches index them by leg."""
    InputError = _errors()
    n = 1 + max(int(r.leg) for r in jacobian.info)
    if platform_points is None:
        raise InputError("base_points without platform_points: give both (T_r needs A_i and "
                         "a_i)")
    A = _finite3(base_points, "base_points")
    try:                  # (NaN allowed: an unreachable pose of a batch has no a_i)
        a = np.asarray(platform_points, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"platform_points must be numbers, got {platform_points!r:.60}") from None
    if A.shape != (n, 3):
        raise InputError(f"base_points must be ({n}, 3), one A_i a leg, got {A.shape}")
    if a.shape == (n, 3):
        a = a[None]
    if a.shape not in ((1, n, 3), (N, n, 3)):
        raise InputError(f"platform_points must be ({n}, 3) or ({N}, {n}, 3), got {a.shape}")
    return A, np.broadcast_to(a, (N, n, 3))
