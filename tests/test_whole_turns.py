"""Solved angles carry no whole turns: a pose solved from home reports its revolute joint
values and dependent Euler angles in [-pi, pi]; a warm-started pose stays within half a turn
of its start.

Newton steps know no turns: before this, a 3RRPRR pose far from home (its closures started
at home, seven to sixteen steps) came back with joints a turn or up to a hundred turns away
(707 rad), and a joint limit was judged on that number.  The reference configuration here
comes from a second method, a path tracked continuously from the default pose.
"""

import math

import numpy as np
import pytest

import screwkit
from screwkit.engine._chains import chains_of

#: A 3RRPRR pose far below and tilted away from its default pose (Zo five half-widths of
#: the predictor's grid out: its closures start at home), where leg 3's second and fourth
#: joints used to come back a whole turn out (7.209 and -6.382 rad).
FAR = {"alpha": 0.46692594229320267, "beta": -0.47889977446639265, "Zo": 28.772296372663952}


def _revolute_values(model, res):
    """``(values (n, m, N), mask (n, m))``: the solved joint values and which are revolute."""
    ch = chains_of(model)
    X = np.asarray(res.solution.closures.X)
    nu, N = len(ch.unknown), X.shape[1]
    q = X[nu:].reshape(ch.n, ch.m, N) * ch.q_scale[:, :, None]
    revolute = (np.asarray(ch.rotation) != 0) & (ch.q_scale == 1.0)
    return q, revolute


def _angles(model, res):
    """The solved revolute joint values and dependent Euler angles, flattened."""
    q, rev = _revolute_values(model, res)
    vals = [q[rev]]
    for p in ("alpha", "beta", "gamma"):
        if p in model.dependent:
            vals.append(np.asarray(res.solution._params[p], float)[None, :])
    return np.concatenate([v.ravel() for v in vals])


def test_far_pose_matches_a_tracked_path_without_turns():
    pm = screwkit.load_pm("3RRPRR")
    one = screwkit.analyze(pm, {k: np.array([v]) for k, v in FAR.items()},
                           raise_on_singular=False)
    q, rev = _revolute_values(pm, one)
    assert np.all(np.abs(q[rev]) <= math.pi)
    # the second method: the default pose moved continuously to FAR (200 samples)
    t = np.linspace(0.0, 1.0, 200)
    d = pm.default_pose
    path = screwkit.analyze(pm, {k: d[k] + t * (v - d[k]) for k, v in FAR.items()}, path=True,
                            raise_on_singular=False)
    qp, _ = _revolute_values(pm, path)
    # the same configuration, and the same numbers (no turn between them)
    np.testing.assert_allclose(q[:, :, 0], qp[:, :, -1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(one.jacobian.J[0], path.jacobian.J[-1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(one.statics.F_r[0], path.statics.F_r[-1], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name, deg, spread", [("3RRPRR", 25.0, 0.8), ("3RPS", 40.0, 0.8),
                                               ("6SPS", 30.0, 0.5)])
def test_scattered_poses_report_angles_in_one_turn(name, deg, spread):
    pm = screwkit.load_pm(name)
    ch = chains_of(pm)
    rng = np.random.default_rng(1)
    n = 4000
    d = pm.default_pose
    L = float(pm.normalisation.length)
    pose = {p: d[p] + (np.radians(rng.uniform(-deg, deg, n)) if p in ("alpha", "beta", "gamma")
                       else rng.uniform(-spread, spread, n) * L) for p in ch.fixed}
    res = screwkit.analyze(pm, pose, raise_on_singular=False)
    a = _angles(pm, res)
    a = a[np.isfinite(a)]
    assert a.size and np.all(np.abs(a) <= math.pi)
    # a pose solved alone reports the same numbers as in the batch
    k = int(np.argmax(np.abs(_revolute_values(pm, res)[0]).max(axis=(0, 1))))
    alone = screwkit.analyze(pm, {p: v[k:k + 1] for p, v in pose.items()},
                             raise_on_singular=False)
    np.testing.assert_array_equal(alone.solution.closures.X[:, 0],
                                  res.solution.closures.X[:, k])


def test_warm_start_keeps_its_turn():
    """A warm start a turn away (gamma + 2 pi) is a start on the same configuration: the
    solution stays within half a turn of it (continuity, as along a path); without one the
    angle is the canonical one.  The platform's rotation is the same either way."""
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": np.array([0.1]), "beta": np.array([0.05]), "Zo": np.array([80.0])}
    plain = screwkit.analyze(pm, pose)
    g = float(plain.solution._params["gamma"][0])
    assert abs(g) <= math.pi
    warm = screwkit.analyze(pm, pose, guess={"gamma": g + 2 * math.pi})
    gw = float(warm.solution._params["gamma"][0])
    assert abs(gw - (g + 2 * math.pi)) < 1e-9
    np.testing.assert_allclose(warm.solution.rotation, plain.solution.rotation, atol=1e-12)
    np.testing.assert_allclose(warm.statics.F_r, plain.statics.F_r, rtol=1e-9, atol=1e-9)
