"""How long each wrench arrow is drawn: the one rule of ``screwkit draw`` and the 3D view.

At one pose, arrow lengths are proportional to ``|value|`` within each kind (actuation
forces, constraint forces, torques: :func:`scale_key`), relative to the largest value of the
kind, with a floor (:data:`FLOOR`) so that small values stay visible; a value the statics
does not give (NaN) or a kind whose values are all zero is drawn at the floor.  The
drawings (:func:`screwkit.viz.draw_pm`) and the page (:meth:`Scene.to_json`) both take
their lengths from :func:`arrow_fractions`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["FLOOR", "scale_key", "arrow_fractions"]

#: The shortest arrow, as a fraction of the longest of its kind (so that small values show).
FLOOR = 0.25


def scale_key(quantity: str, actuation: bool) -> str:
    """The arrows one row's length is proportional with (``force-a``, ``force-c``,
    ``torque-a``, ``torque-c``): its quantity (force or torque) and whether it is an
    actuation wrench."""
    return f"{quantity}-{'a' if actuation else 'c'}"


def arrow_fractions(values, keys):
    """Signed arrow lengths, as fractions of the longest arrow of a kind, at one pose.

    Parameters
    ----------
    values : array_like (m,)
        The rows' values (NaN where statics gives none).
    keys : sequence of str (m,)
        Each row's :func:`scale_key`.

    Returns
    -------
    fractions : ndarray (m,)
        ``sign(value) * max(|value| / largest of its kind, FLOOR)``; ``+FLOOR`` for a NaN
        value or a kind whose values are all zero or NaN.  The drawn vector is
        ``fraction * longest * direction``.
    floored : ndarray (m,) of bool
        True where the arrow is drawn at the floor although its value is smaller (or
        not given): the drawings say so.
    """
    v = np.asarray(values, float).reshape(-1)
    keys = list(keys)
    if len(keys) != v.size:
        raise ValueError(f"{len(keys)} keys for {v.size} values")
    top = {}
    for x, k in zip(v, keys):
        if np.isfinite(x):
            top[k] = max(top.get(k, 0.0), abs(float(x)))
    frac, floored = np.full(v.size, FLOOR), np.ones(v.size, bool)
    for n, (x, k) in enumerate(zip(v, keys)):
        t = top.get(k, 0.0)
        if np.isfinite(x) and t > 0:
            frac[n] = np.copysign(max(abs(x) / t, FLOOR), x) if x != 0 else FLOOR
            floored[n] = abs(x) < FLOOR * t
    return frac, floored
