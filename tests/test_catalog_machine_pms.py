"""The catalog's Exechon-like 2UPR+SPR and spherical 3UPS+S/passive against hand derivations.

Exechon-like 2UPR+SPR (``legs_catalog.yaml``; R = 400, r = 150 mm): base and platform
points at -90, 180, 90 deg on circles of radii R and r: B1 = (0, -R, 0), B2 = (-R, 0, 0),
B3 = (0, R, 0); a1 = (0, -r, 0), a2 = (-r, 0, 0), a3 = (0, r, 0) in the platform frame.
Legs 1 and 3 are UPR: the U's first axes are along the base Y axis (A -> O), on one line;
the platform R axes are along the platform x axis (the tangent at a1 and a3), and a UPR
keeps its R parallel to the U's second axis, normal to the plane of the leg and that line.
Leg 2 is SPR with its R along the platform y axis (the tangent at a2), normal to the leg.
With R = Rx(alpha) Ry(beta) Rz(gamma) (intrinsic XYZ) and n = R x, m = R y:

* the plane of legs 1 and 3 contains the base Y axis: n . Y = 0, i.e.
  cos(alpha) sin(gamma) + sin(alpha) sin(beta) cos(gamma) = 0, so
  gamma = atan(-tan(alpha) sin(beta));
* it contains the platform centre o (n . P1 = n . o since n . R a1 = x . a1 = 0):
  n . o = 0;
* leg 2 is normal to its R axis: (P2 - B2) . m = (o - B2) . m = 0 (m . R a2 = 0);

two equations linear in Xo, Yo at given Zo.  The constraint wrenches: each UPR exerts a
force through its U centre along n and a couple along Y x n (normal to both U axes); the
SPR a force through B2 along m.  Five wrenches of rank 3 (two redundant).  The actuation
rows are unit forces along the legs (each leg's passive joints are anchored at its two
ends); the platform's freedoms are the twists reciprocal to the constraint wrenches, and
virtual work on them gives the actuator forces, which the two redundant constraints do not
change (only the constraint rows are statically indeterminate).

Spherical 3UPS+S/passive (R = 250, r = 120, H = 400 mm): the column's S is fixed at
c = (0, 0, H) and is the platform centre; the platform turns about it, R = Rx Ry Rz; its
freedoms are the rotations [c x e_k; e_k] about lines through c, the column exerts the
three forces [e_k; c x e_k], and the UPS actuation rows are unit forces along the legs.
"""

import re

import numpy as np
import pytest

import screwkit
from screwkit.pm import default_catalog

X, Y, Z = np.eye(3)


def _rot(alpha, beta, gamma):
    ca, sa, cb, sb, cg, sg = (np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta),
                              np.cos(gamma), np.sin(gamma))
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    Rz = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]])
    return Rx @ Ry @ Rz


def _unit_forces(B, P):
    u = (P - B) / np.linalg.norm(P - B, axis=1)[:, None]
    return np.hstack([u, np.cross(B, u)])


def _freedoms(wrenches, L):
    """The twists reciprocal to ``wrenches`` (rows [f; m] about O): with T = [v; w],
    f . v + m . w = 0; found as a null space on a length-normalised scale."""
    Wn = np.hstack([wrenches[:, :3] * L, wrenches[:, 3:]])       # [f L; m] . [v / L; w]
    _, s, Vt = np.linalg.svd(Wn)
    r = int(np.sum(s > 1e-10 * s[0]))
    T = Vt[r:]
    return np.hstack([T[:, :3] * L, T[:, 3:]]), r


def _virtual_work(Ja, freedoms, F, T, o):
    W = np.r_[F, np.asarray(T) + np.cross(o, F)]
    return np.linalg.solve(freedoms @ Ja.T, -(freedoms @ W))


def _exechon(alpha, beta, Zo, R=400.0, r=150.0):
    gamma = np.arctan(-np.tan(alpha) * np.sin(beta))
    Rp = _rot(alpha, beta, gamma)
    n, m = Rp @ X, Rp @ Y
    B = np.array([[0, -R, 0], [-R, 0, 0], [0, R, 0]], float)
    a = np.array([[0, -r, 0], [-r, 0, 0], [0, r, 0]], float)
    # n . o = 0 and (o - B2) . m = 0 with o = (Xo, Yo, Zo)
    M = np.array([[n[0], n[1]], [m[0], m[1]]])
    rhs = np.array([-n[2] * Zo, -m[2] * Zo + B[1] @ m])
    o = np.r_[np.linalg.solve(M, rhs), Zo]
    P = o + a @ Rp.T
    cons = np.array([np.r_[n, np.cross(B[0], n)], np.r_[0, 0, 0, np.cross(Y, n)],
                     np.r_[m, np.cross(B[1], m)],
                     np.r_[n, np.cross(B[2], n)], np.r_[0, 0, 0, np.cross(Y, n)]])
    return gamma, Rp, o, _unit_forces(B, P), cons


EXECHON_POSES = [(0.0, 0.0, 700.0), (5.0, -3.0, 700.0), (-10.0, 7.0, 650.0),
                 (12.0, 9.0, 760.0)]


@pytest.mark.parametrize("alpha,beta,Zo", EXECHON_POSES)
def test_exechon_against_the_hand_derivation(alpha, beta, Zo):
    F, T = np.array([40.0, -25.0, -800.0]), np.array([3000.0, 5000.0, -2000.0])
    res = screwkit.analyze("2UPR+SPR", {"alpha": alpha, "beta": beta, "Zo": Zo}, degrees=True,
                           force=F, torque=T)
    gamma, Rp, o, Ja, cons = _exechon(np.radians(alpha), np.radians(beta), Zo)
    sol = res.solution
    assert abs(sol.params["gamma"] - gamma) < 1e-10
    np.testing.assert_allclose(sol.rotation, Rp, atol=1e-10)
    np.testing.assert_allclose(sol.position, o, atol=1e-8)
    assert not sol.notes or all("default pose" not in n for n in sol.notes)
    # mobility: 5 constraint wrenches of rank 3 (2 redundant), 3 actuators
    L = 400.0
    freedoms, rank = _freedoms(cons, L)
    m = res.mobility
    assert rank == 3 and len(freedoms) == 3
    assert (m.dof, m.n_constraints, m.constraint_rank, m.redundant, m.actuators) == \
        (3, 5, 3, 2, 3)
    assert m.motion_type == "1T2R" and res.model.motion == "1T2R"
    scale = np.r_[np.full(3, 1 / L), np.ones(3)]
    s = np.linalg.svd(np.vstack([freedoms, m.twists]) * scale, compute_uv=False)
    assert s[3] < 1e-9 * s[0]
    # J: the actuation rows are the hand unit forces along the legs, the constraint rows
    # span the hand constraint system
    jac = res.jacobian
    np.testing.assert_allclose(jac.J_a, Ja, atol=1e-10)
    Wn = np.vstack([cons, jac.J_c]) * np.r_[np.full(3, L), np.ones(3)]
    s = np.linalg.svd(Wn, compute_uv=False)
    assert s[3] < 1e-9 * s[0]
    # statics: the actuator forces from virtual work, determined although the constraint
    # rows are not (two self-stresses among the UPR legs' rows)
    Fa = _virtual_work(Ja, freedoms, F, T, o)
    st = res.statics
    assert st.indeterminacy == 2
    assert np.all(st.determined[:3]) and not np.all(st.determined[3:])
    np.testing.assert_allclose(st.active, Fa, rtol=1e-9, atol=1e-9 * np.abs(Fa).max())
    W = np.r_[F, T + np.cross(o, F)]
    np.testing.assert_allclose(st.values @ jac.J, -W, atol=1e-8 * np.abs(W).max())


def _spherical(alpha, beta, gamma, R=250.0, r=120.0, H=400.0):
    Rp = _rot(alpha, beta, gamma)
    c = np.array([0.0, 0.0, H])
    t = np.radians([0.0, 120.0, 240.0])
    B = np.column_stack([R * np.cos(t), R * np.sin(t), np.zeros(3)])
    a = np.column_stack([r * np.cos(t + np.pi / 3), r * np.sin(t + np.pi / 3), np.zeros(3)])
    P = c + a @ Rp.T
    freedoms = np.array([np.r_[np.cross(c, e), e] for e in np.eye(3)])
    cons = np.array([np.r_[e, np.cross(c, e)] for e in np.eye(3)])
    return Rp, c, _unit_forces(B, P), freedoms, cons


@pytest.mark.parametrize("angles", [(0.0, 0.0, 0.0), (5.0, -3.0, 4.0), (-15.0, 10.0, -20.0)])
def test_spherical_3ups_s_against_the_hand_derivation(angles):
    F, T = np.array([100.0, 50.0, -600.0]), np.array([2000.0, -1000.0, 3000.0])
    pose = dict(zip(("alpha", "beta", "gamma"), angles))
    res = screwkit.analyze("3UPS+S/passive", pose, degrees=True, force=F, torque=T)
    Rp, c, Ja, freedoms, cons = _spherical(*np.radians(angles))
    np.testing.assert_allclose(res.solution.rotation, Rp, atol=1e-10)
    np.testing.assert_allclose(res.solution.position, c, atol=1e-8)
    m = res.mobility
    assert (m.dof, m.constraint_rank, m.actuators, m.passive) == (3, 3, 3, (3,))
    assert m.motion_type == "3R"
    jac = res.jacobian
    assert jac.labels == ("F_a1", "F_a2", "F_a3", "F_c4.1", "F_c4.2", "F_c4.3")
    np.testing.assert_allclose(jac.J_a, Ja, atol=1e-10)
    s = np.linalg.svd(np.vstack([cons, jac.J_c]) * np.r_[np.full(3, 400.0), np.ones(3)],
                      compute_uv=False)
    assert s[3] < 1e-9 * s[0]
    Fa = _virtual_work(Ja, freedoms, F, T, c)
    np.testing.assert_allclose(res.statics.active, Fa, rtol=1e-9, atol=1e-9 * np.abs(Fa).max())
    # the column carries the whole force, through the S centre: no moment about it
    col = res.statics.leg_wrenches[3]
    assert np.allclose(col[3:], np.cross(c, col[:3]), atol=1e-8 * np.abs(T).max())


def test_the_catalog_states_the_literature_motion_types():
    for name, motion, string in (("3UPS+UP/passive", "1T2R", "3UPS+UP/passive"),
                                 ("2UPR+SPR", "1T2R", "2UPR+SPR"),
                                 ("3UPS+S/passive", "3R", "3UPS+S/passive")):
        pm = screwkit.load_pm(name)
        assert (pm.motion, pm.string) == (motion, string)
        cited = default_catalog().pms[name]["source"]
        assert re.search(r"\b(19|20)\d\d\b", cited), cited          # a dated publication
