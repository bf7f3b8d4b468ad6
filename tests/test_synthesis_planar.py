"""Planar motion (2T1R): the type synthesis finds the planar 3-RRR and 3-PRR, and the
3-RRR it writes analyses like the textbook planar 3-RRR.

The check is independent of the engine: the elbows are placed by intersecting two circles
in the plane (link lengths from the home placement), each distal link is a two-force member
along elbow -> a_i, the platform's planar equilibrium (Fx, Fy, Mz) gives the three link
forces, and each base actuator's torque is the moment of its link force about its axis."""

import numpy as np
import pytest

import screwkit
from screwkit.design import synthesize_motion


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    res = synthesize_motion("2T1R", asymmetric=False, limit=4, generate=False)
    path = tmp_path_factory.mktemp("planar") / "3rrr.yaml"
    best = res.listed[0]
    path.write_text(best.model_yaml())
    return res, screwkit.load_pm(str(path))


def test_the_planar_3rrr_and_3prr_are_found_first(planar):
    res, _ = planar
    assert res.variants()[:2] == ["3RRR/planar", "3PRR/planar"]
    assert res.names()[:2] == ["3-RRR", "3-PRR"]
    assert all(p.verdict.success for p in res.listed)
    assert {p.motion for p in res.listed} == {"2T1R"}


def _elbow(A, a, e0, l1, l2):
    """The intersection of the circles |e - A| = l1 and |e - a| = l2 (in the plane) nearer
    the home elbow e0."""
    d = a - A
    dist = np.hypot(*d)
    x = (l1 ** 2 - l2 ** 2 + dist ** 2) / (2 * dist)
    y = np.sqrt(l1 ** 2 - x ** 2)
    ex, ey = d / dist, np.array([-d[1], d[0]]) / dist
    cands = [A + x * ex + s * y * ey for s in (1.0, -1.0)]
    return min(cands, key=lambda e: np.hypot(*(e - e0)))


def test_the_3rrr_statics_equal_a_planar_hand_derivation(planar):
    _, model = planar
    home = screwkit.analyze(model, {"Xo": 0.0, "Yo": 0.0, "gamma": 0.0})
    elbows0 = np.array([lg.joints[1].point[:2] for lg in home.jacobian.legs])
    A = np.asarray(model.base_points)[:, :2]
    ap = np.asarray(model.platform_points)[:, :2]
    l1 = np.hypot(*(elbows0 - A).T)
    l2 = np.hypot(*(elbows0 - ap).T)                  # home: o at the base centre, gamma 0
    F, Tz = np.array([10.0, -5.0]), 30.0
    for x, y, g in [(4.0, -3.0, 0.2), (-6.0, 2.5, -0.15), (1.0, 7.0, 0.05)]:
        res = screwkit.analyze(model, {"Xo": x, "Yo": y, "gamma": g}, force=(*F, 0.0),
                               torque=(0.0, 0.0, Tz))
        # the planar invariant: no tilt, the platform stays at its height
        assert np.allclose(res.solution.rotation[:, 2], [0, 0, 1], atol=1e-12)
        c, s = np.cos(g), np.sin(g)
        o = np.array([x, y])
        a = o + ap @ np.array([[c, s], [-s, c]])       # R(gamma) a_i
        e = np.array([_elbow(A[i], a[i], elbows0[i], l1[i], l2[i]) for i in range(3)])
        u = (a - e) / np.hypot(*(a - e).T)[:, None]
        cross = lambda p, q: p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]  # noqa: E731
        # sum_i f_i [u_i; (a_i - o) x u_i] = -[F; Tz]  (moments about o)
        M = np.vstack([u.T, cross(a - o, u)])
        f = np.linalg.solve(M, -np.r_[F, Tz])
        torque = f * cross(a - A, u)                   # about each base axis
        np.testing.assert_allclose(res.statics.active, torque, rtol=1e-9)
        # the engine's elbows are the hand-placed ones
        got = np.array([lg.joints[1].point[:2] for lg in res.jacobian.legs])
        np.testing.assert_allclose(got, e, atol=1e-9)
