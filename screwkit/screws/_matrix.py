"""Screws given as a matrix of rows (private): checked, twists and wrenches kept apart."""

from __future__ import annotations

import numpy as np

from ..errors import InputError, MisuseError


def _check_matrix(T, name: str) -> np.ndarray:
    if isinstance(T, (list, tuple)):
        from ._screw import Twist, Wrench
        wrong = {"twists": Wrench, "wrenches": Twist}.get(name)
        for i, x in enumerate(T):
            if wrong is not None and isinstance(x, wrong):
                raise MisuseError(f"{name}[{i}] is a {wrong.__name__}: these are {name} "
                                  f"({'[v; w]' if name == 'twists' else '[f; m]'})")
        T = [getattr(x, "vector", x) for x in T]
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be an (m, 6) array of real numbers, got "
                         f"{str(T)[:60]}") from None
    if T.ndim == 1 and T.size == 0:
        T = T.reshape(0, 6)
    if T.ndim != 2 or T.shape[1] != 6:
        raise InputError(f"{name} must have shape (m, 6), got {T.shape}")
    if not np.isfinite(T).all():
        raise InputError(f"{name} contains NaN or infinite entries")
    return T
