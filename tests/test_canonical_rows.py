"""Canonical constraint members: declared bases and signs, invariance of every row, continuity.

Independent references: the paper's c_i = R1i x delta_i (eqs. 14b, 14e) built by hand in
test_paper_examples; the catalog's stated directions (base axes, the leg's plane with the
base normal) recomputed here from the placed legs; the same PM in a moved base frame and in
units 1000 times smaller, whose rows must map one to one onto the original's.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE
from screwkit.pm import load_pm, pm_names
from test_paper_examples import REGULAR_3RRPRR, paper_3rrprr

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


@pytest.mark.parametrize("a, b, Zo", REGULAR_3RRPRR)
def test_3rrprr_constraint_values_have_the_papers_sign(a, b, Zo):
    res = screwkit.analyze("3RRPRR", {"alpha": a, "beta": b, "Zo": Zo}, degrees=True)
    Fr, _, _, _ = paper_3rrprr(np.radians(a), np.radians(b), Zo)
    np.testing.assert_allclose(res.statics.constraint, Fr[3:], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(res.statics.active, Fr[:3], rtol=1e-9, atol=1e-9)


def test_sp_forces_follow_the_leg_and_the_base_normal():
    res = screwkit.analyze("3SPU+SP", {"alpha": 4, "beta": -3, "gamma": 2}, degrees=True, **PAPER_LOAD)
    jac, sol = res.jacobian, res.solution
    i = 3                                          # the SP leg
    leg = sol.legs[i]
    d = (leg.a - leg.A) / np.linalg.norm(leg.a - leg.A)
    Z = np.array([0.0, 0.0, 1.0])
    k1, k2 = [k for k, r in enumerate(jac.rows) if r.leg == i and r.kind == "force"]
    f1, f2 = jac.rows[k1].direction, jac.rows[k2].direction
    e1 = Z - (Z @ d) * d
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, Z) / np.linalg.norm(np.cross(d, Z))
    np.testing.assert_allclose(f1, e1, atol=1e-12)
    np.testing.assert_allclose(f2, e2, atol=1e-12)
    for k in (k1, k2):
        assert jac.rows[k].point_name == "S1"
        np.testing.assert_allclose(jac.rows[k].point, leg.A, atol=1e-12)


def test_prrr_couples_along_the_base_axes():
    res = screwkit.analyze("3SPU+PRRR", {"Xo": 3, "Yo": -2, "Zo": 60, "gamma": 0.1}, **PAPER_LOAD) \
        if "gamma" in load_pm("3SPU+PRRR").independent else screwkit.analyze("3SPU+PRRR", **PAPER_LOAD)
    jac = res.jacobian
    couples = [r.direction for r in jac.rows if r.kind == "couple"]
    np.testing.assert_allclose(couples, [[1, 0, 0], [0, 1, 0]], atol=1e-12)


def _poses(pm, n, seed):
    rng = np.random.default_rng(seed)
    c = pm.default_pose
    z = abs(c.get("Zo", 0.0)) or 1.0
    return {p: c[p] + (rng.uniform(-0.06, 0.06, n) * z if p in ("Xo", "Yo", "Zo")
                       else np.radians(rng.uniform(-6, 6, n))) for p in pm.independent}


@pytest.mark.parametrize("name", pm_names())
def test_every_row_is_unchanged_by_a_frame_move_and_by_units(name):
    pm = load_pm(name)
    pose = _poses(pm, 20, 11)
    ref = screwkit.analyze(pm, pose, **PAPER_LOAD)
    R = Rotation.from_euler("zyx", [0.7, -0.4, 1.1]).as_matrix()
    p = np.array([300.0, -120.0, 45.0])
    moved = screwkit.analyze(pm.moved(R, p), pose, force=R @ np.array(PAPER_FORCE),
                             torque=R @ np.array(PAPER_TORQUE))
    k = 1000.0
    small = load_pm(name, {d: v / k for d, v in pm.dimensions.items()})
    scaled = screwkit.analyze(small, {q: (v / k if q in ("Xo", "Yo", "Zo") else v)
                                      for q, v in pose.items()},
                              force=np.array(PAPER_FORCE), torque=np.array(PAPER_TORQUE) / k)
    ok = ref.ok
    assert ok.sum() >= 15 and np.array_equal(moved.ok, ok) and np.array_equal(scaled.ok, ok)
    torque_rows = np.array([r.member == "couple" or (r.kind == "actuation" and
                                                      (r.joint or "P")[0] in "RH")
                            for r in ref.jacobian.info])
    v0 = ref.statics.values[ok]
    fs = np.abs(v0).max(axis=1, keepdims=True)
    cond = ref.jacobian.condition_number[ok][:, None]
    tol = 1e-9 * np.maximum(1.0, cond / 100) * fs
    assert np.all(np.abs(moved.statics.values[ok] - v0) <= tol), name
    back = scaled.statics.values[ok] * np.where(torque_rows, k, 1.0)
    assert np.all(np.abs(back - v0) <= tol * np.where(torque_rows, 1.0, 1.0)), name
    np.testing.assert_allclose(moved.statics.T_r[ok], ref.statics.T_r[ok], rtol=0,
                               atol=1e-9 * np.abs(ref.statics.leg_wrenches).max())


@pytest.mark.parametrize("name", ["3SPU+SP", "3SPU+PRRR"])
def test_rows_are_continuous_along_a_path(name):
    pm = load_pm(name)
    s = np.linspace(0, 1, 1000)
    c = pm.default_pose
    pose = {}
    for k, p in enumerate(pm.independent):
        amp = 0.015 * (abs(c.get("Zo", 1.0)) or 1.0) if p in ("Xo", "Yo", "Zo") else np.radians(1.5)
        pose[p] = c[p] + amp * np.sin(2 * np.pi * s + k)
    res = screwkit.analyze(pm, pose, path=True, **PAPER_LOAD)
    assert res.ok.all()
    v = res.statics.values
    step = np.abs(np.diff(v, axis=0))
    scale = np.abs(v).max(axis=0)
    # the largest step is a small fraction of each row's range: no jump, no swap, no flip
    assert np.all(step.max(axis=0) <= 0.02 * np.maximum(scale, 1e-300)), step.max(axis=0) / scale
    d = res.jacobian.directions
    assert np.min(np.sum(d[1:] * d[:-1], axis=-1)) > 0.99
