"""The keyword options of :func:`screwkit.engine.analyze`, checked, and the stiffness of a
subset of a batch's poses (private; used by :mod:`screwkit.engine._analysis`)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["check_options", "stiffness_of_poses"]


def check_options(threshold, chunk, workers, degrees, path, progress, anchor_every,
                  raise_on_singular=True, twists=False, lines=False):
    """Check the keyword options of :func:`analyze` (InputError naming the one that is bad)."""
    if type(threshold) is float and 1.0 < threshold < math.inf and type(chunk) is int and \
            1 <= chunk <= 1 << 24 and workers is None and anchor_every is None and \
            type(degrees) is bool and type(path) is bool and progress is None and \
            type(raise_on_singular) is bool and type(twists) is bool and type(lines) is bool:
        return                                      # the defaults (the common case)
    from ..errors import InputError

    def whole(x, name, low, high=1 << 24):
        if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)) or \
                not low <= x <= high:
            raise InputError(f"{name} must be an integer from {low} to {high}, got {x!r:.40}")
    t = threshold
    if isinstance(t, (bool, np.bool_)) or not isinstance(t, (int, float, np.number)) or \
            not (np.isfinite(t) and t > 1):
        raise InputError(f"threshold must be a finite number > 1 (a condition number), "
                         f"got {t!r:.40}")
    whole(chunk, "chunk", 1)
    if workers is not None:
        whole(workers, "workers", 1, 64)
    if anchor_every is not None:
        whole(anchor_every, "anchor_every", 1)
    from ..legs._guards import flag
    for value, name in ((degrees, "degrees"), (path, "path"),
                        (raise_on_singular, "raise_on_singular"), (twists, "twists"),
                        (lines, "lines")):
        flag(value, name)
    if progress is not None and not callable(progress):
        raise InputError(f"progress must be a function progress(done, total), got "
                         f"{type(progress).__name__}")


def stiffness_of_poses(stiffness, i, N):
    """The stiffness of the poses ``i`` (an int or an index array) of a batch of ``N``: a
    per-pose array ``(N, m)`` is indexed with them; a mapping, a name or one row ``(m,)``
    holds for every pose."""
    if stiffness is None or isinstance(stiffness, (str, dict)):
        return stiffness
    k = np.asarray(stiffness)
    if k.ndim == 2 and k.shape[0] == N:
        return k[i:i + 1] if isinstance(i, int) else k[i]
    return stiffness
