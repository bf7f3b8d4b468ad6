"""Paths and the check of a level's starts, shared by the path tests."""

import numpy as np

#: The paper's workload of the 3RRPRR (section 5.1), kN and kN.cm.
PAPER_PATH_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}


def smooth_path(n):
    """A smooth 3RRPRR path of ``n`` samples: one period of alpha and beta, Zo rising."""
    s = np.linspace(0, 1, n)
    return {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
            "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}


def check_starts(idx, k, mid, good, XT, Xs):
    """The starts ``Xs (G, nx)`` of the samples ``mid`` (each in the gap ``idx[k[g]]``..
    ``idx[k[g] + 1]``) against numpy: the cubic through the four solved samples around the
    gap (``np.polyfit`` of degree 3) where all four converged, else the linear interpolation
    of the gap's ends, or the one that converged.  Returns the kinds met."""
    nx = XT.shape[1]
    kinds = set()
    for g, (kg, q) in enumerate(zip(k, mid)):
        left, right = idx[kg], idx[kg + 1]
        nodes = idx[max(kg - 1, 0):kg + 3]
        if len(nodes) == 4 and kg >= 1 and good[nodes].all():
            want = [np.polyval(np.polyfit(nodes, XT[nodes, x], 3), q) for x in range(nx)]
            np.testing.assert_allclose(Xs[g], want, rtol=1e-9, atol=1e-9)
            kinds.add("cubic")
        elif good[left] and good[right]:
            w = (q - left) / (right - left)
            np.testing.assert_allclose(Xs[g], (1 - w) * XT[left] + w * XT[right], rtol=1e-14)
            kinds.add("linear")
        else:
            np.testing.assert_array_equal(Xs[g], XT[left] if good[left] else XT[right])
            kinds.add("one")
    return kinds
