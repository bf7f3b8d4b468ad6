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


def around_default(pm, n, seed, angle, frac):
    """``n`` poses (a dict of ``(n,)`` arrays) around every parameter of the default pose:
    angles within ``+-angle`` radians, lengths within ``+-frac`` times ``max(|value|, 1)``."""
    rng = np.random.default_rng(seed)
    pose = {}
    for p, v in dict(pm.default_pose).items():
        amp = angle if p in ("alpha", "beta", "gamma") else frac * max(abs(v), 1.0)
        pose[p] = v + rng.uniform(-amp, amp, n)
    return pose


def assert_same_bits(a, b, where, skip=()):
    """Every array of the dict ``a`` equals ``b``'s of the same name bit for bit."""
    for key in a:
        if key in skip:
            continue
        x, y = np.asarray(a[key]), np.asarray(b[key])
        assert x.shape == y.shape, (where, key)
        assert x.tobytes() == y.tobytes(), (where, key)
