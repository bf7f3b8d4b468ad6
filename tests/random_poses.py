"""Random poses around a PM's default pose, shared by the engine tests."""

import numpy as np


def random_pose(pm, n, seed, span=8.0, frac=0.08):
    """``n`` poses (a dict of ``(n,)`` arrays, radians and model lengths): the independent
    angles within ``+-span`` degrees of the default pose, the lengths within ``+-frac``
    times its ``|Zo|``."""
    rng = np.random.default_rng(seed)
    c = pm.default_pose
    z = abs(c.get("Zo", 0.0)) or 1.0
    return {p: c[p] + (rng.uniform(-frac, frac, n) * z if p in ("Xo", "Yo", "Zo")
                       else np.radians(rng.uniform(-span, span, n))) for p in pm.independent}
