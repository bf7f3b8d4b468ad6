"""The motion type: the PM's finite type never flips with the pose; the instantaneous twist
space is classified by its screws (translations, rotations about lines through a point,
principal pitches).

Independent references: the catalog's stated motion types; the spherical 3UPU's rotation
centre, where the U axes meet (the rules' centre C), recomputed from the placed legs; the
translational 3UPU's three translations; the Schoenflies 4UPU's vertical rotation axis.
"""

import numpy as np
import pytest

import screwkit
from screwkit.pm import describe_twist_space, load_pm


@pytest.mark.parametrize("name", ["3RSR", "2UPU+SPR", "3RPUR", "3RRPRR", "3SPR"])
def test_the_finite_type_does_not_flip_with_a_tilt(name):
    pm = load_pm(name)
    home = {p: pm.home_pose[p] for p in pm.independent}
    tilted = {p: v + (0.06 if p in ("alpha", "beta", "gamma") else 0.0) for p, v in home.items()}
    for pose in (home, tilted):
        m = screwkit.analyze(pm, pose, raise_on_singular=False).mobility
        assert m.motion_type == pm.motion
        assert m.instantaneous


def test_spherical_rotations_about_the_centre():
    pm = load_pm("3UPU/spherical")
    res = screwkit.analyze(pm, {"alpha": 0.05, "beta": -0.04, "gamma": 0.03})
    leg = res.solution.legs[0]
    ua, ub = leg.joint("U1a"), leg.joint("U3b")
    # where U1a and U3b meet (closest points of the two axes)
    d1, d2, w = ua.direction, ub.direction, ua.point - ub.point
    b = d1 @ d2
    s = (b * (d2 @ w) - (d1 @ w)) / (1 - b * b)
    C = ua.point + s * d1
    m = res.mobility
    assert m.instantaneous.startswith("3 rotations about lines through")
    P = np.array([float(x) for x in m.instantaneous.split("through (")[1].rstrip(")").split(",")])
    np.testing.assert_allclose(P, C, atol=1e-3)


def test_translations_and_schoenflies():
    assert describe_twist_space(np.c_[np.eye(3), np.zeros((3, 3))], 1.0) == "3 translations"
    T = np.vstack([np.c_[np.eye(3), np.zeros((3, 3))], [[0, 0, 0, 0, 0, 1]]])
    assert describe_twist_space(T, 1.0) == "3 translations + 1 rotation about any line along " \
                                           "(0, 0, 1)"
    # one screw of pitch 2 along z through the origin: [h w; w]
    assert "principal pitches 2" in describe_twist_space([[0, 0, 2, 0, 0, 1]], 1.0)
    # rotations about x and y through (0, 0, 5): v = P x w
    P = np.array([0.0, 0.0, 5.0])
    T = [np.r_[np.cross(P, w), w] for w in np.eye(3)[:2]]
    assert describe_twist_space(T, 1.0) == "2 rotations about lines through (0, 0, 5)"
