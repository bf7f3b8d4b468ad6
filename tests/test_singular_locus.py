"""The singular locus of the 2SPS+2SPR at beta = 0, from a map, against an independent
root-finding of det J written here from J's definition.

The independent J (paper section 4 with the corrections of NOTES.md): square base
A_i = (L/2)(+-1, +-1, 0), rectangular platform a_i = R m_i + o with m_i = (+-l1/2, +-l2/2, 0),
R = R_X(alpha) R_Y(beta) R_X(gamma); X_o and Y_o from the SPR structure (the leg A_2 a_2
normal to a_1 - a_3, the leg A_3 a_3 normal to a_2 - a_4: linear in o).  Rows about o: each
leg's actuation force along (a_i - A_i) with arm a_i - o, the SPR legs' constraint forces
along c_2 = (a_1 - a_3)/|.| and c_3 = (a_2 - a_4)/|.| through A_2 and A_3.  det J = 0 is
solved by brentq on alpha + gamma (at beta = 0 the rotation is R_X(alpha + gamma)); the map
(grid over alpha, gamma and Zo in 50, 60, 75, 90, 100 cm) must find every such root, each
crossing refined by bisection to 1e-6 of a cell, as an actuation singularity.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import screwkit

L, L1, L2 = 100.0, 60.0, 50.0
A = L / 2 * np.array([[1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]], float)
M = 0.5 * np.array([[L1, -L2, 0], [L1, L2, 0], [-L1, L2, 0], [-L1, -L2, 0]])
ZO = (50.0, 60.0, 75.0, 90.0, 100.0)


def _rx(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def det_j(alpha, beta, gamma, zo):
    R = _rx(alpha) @ _ry(beta) @ _rx(gamma)
    u2, u3 = R @ (M[0] - M[2]), R @ (M[1] - M[3])
    # (R m_j + o - A_j) . u_j = 0 for j = 2, 3, with o = (x, y, zo)
    Mx = np.array([u2[:2], u3[:2]])
    rhs = -np.array([(R @ M[1] + [0, 0, zo] - A[1]) @ u2, (R @ M[2] + [0, 0, zo] - A[2]) @ u3])
    o = np.r_[np.linalg.solve(Mx, rhs), zo]
    a = M @ R.T + o
    rows = []
    for i in range(4):
        d = (a[i] - A[i]) / np.linalg.norm(a[i] - A[i])
        rows.append(np.r_[d, np.cross(a[i] - o, d)])
    for j, (p, q) in ((1, (0, 2)), (2, (1, 3))):
        c = (a[p] - a[q]) / np.linalg.norm(a[p] - a[q])
        rows.append(np.r_[c, np.cross(A[j] - o, c)])
    J = np.array(rows)
    J[:, 3:] /= L                                  # moments in units of L (scale only)
    return np.linalg.det(J)


def independent_roots(zo, lo, hi):
    """Roots s = alpha + gamma of det J(s, 0, 0, zo) in [lo, hi] (radians)."""
    s = np.linspace(lo, hi, 4001)
    f = np.array([det_j(x, 0.0, 0.0, zo) for x in s])
    k = np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))
    return np.array([brentq(lambda x: det_j(x, 0.0, 0.0, zo), s[i], s[i + 1], xtol=1e-15)
                     for i in k])


@pytest.fixture(scope="module")
def locus():
    grid = {"alpha": (-20.0, 40.0, 61), "gamma": (-5.0, 5.0, 6), "Zo": list(ZO)}
    ds = screwkit.map("2SPS+2SPR", grid, fix={"beta": 0.0}, degrees=True)
    return ds, screwkit.maps.locus_list(ds)


def test_the_independent_det_is_the_engines_up_to_sign():
    """Sanity of the reference: |det| of the hand-built J tracks the engine's conditioning
    (it vanishes where the engine says singular), and its sign is fixed up to row signs."""
    res = screwkit.analyze("2SPS+2SPR", {"alpha": 4, "beta": 3, "gamma": 2, "Zo": 80},
                           degrees=True)
    assert abs(det_j(*np.radians([4, 3, 2]), 80.0)) > 1e-3
    assert res.jacobian.condition_number < 1e3


@pytest.mark.parametrize("zo", ZO)
def test_map_locus_equals_independent_roots(locus, zo):
    ds, loc = locus
    here = [x for x in loc if x["pose"]["Zo"] == zo and x["along"] in ("alpha", "gamma")]
    roots = np.degrees(independent_roots(zo, np.radians(-25.0), np.radians(45.0)))
    assert roots.size >= 1
    cell = 1.0                                             # grid spacing of alpha (deg)
    # every crossing of the map lies on a root of the independent det J ...
    for x in here:
        s = x["pose"]["alpha"] + x["pose"]["gamma"]
        assert np.min(np.abs(roots - s)) <= 2e-6 * cell, (zo, s, roots)
        assert x["kind"] == "actuation" and x["width"] <= 1e-6
        assert x["condition_number"] > 1e6
    # ... and every root inside the grid shows up at every gamma of the grid
    for s in roots:
        for g in ds["gamma"].values:
            a = s - g
            if -20.0 + 1e-6 < a < 40.0 - 1e-6:
                assert any(abs(x["pose"]["alpha"] - a) <= 2e-6 * cell and
                           x["pose"]["gamma"] == g and x["along"] == "alpha" for x in here), \
                    (zo, s, g)


def test_the_locus_moves_with_zo(locus):
    """The root alpha + gamma = s*(Zo) depends on the height: the five curves differ."""
    _, loc = locus
    s = {zo: sorted({round(x["pose"]["alpha"] + x["pose"]["gamma"], 5) for x in loc
                     if x["pose"]["Zo"] == zo and x["along"] == "alpha"}) for zo in ZO}
    firsts = [v[0] for v in s.values() if v]
    assert len(firsts) == len(ZO) and len(set(firsts)) == len(ZO)


def test_crossings_between_heights_are_bisected_in_zo(locus):
    """Sign changes between two heights are refined along Zo; there det J vanishes too."""
    _, loc = locus
    along_z = [x for x in loc if x["along"] == "Zo"]
    for x in along_z[:20]:
        p = x["pose"]
        f = det_j(np.radians(p["alpha"]), 0.0, np.radians(p["gamma"]), p["Zo"])
        h = 1e-3
        df = abs(det_j(np.radians(p["alpha"]), 0.0, np.radians(p["gamma"]), p["Zo"] + h) -
                 det_j(np.radians(p["alpha"]), 0.0, np.radians(p["gamma"]), p["Zo"] - h)) / (2 * h)
        # the crossing is within 1e-6 of a Zo cell (>= 10 cm) of the root
        assert abs(f) / max(df, 1e-300) <= 1e-5 * 10.0
