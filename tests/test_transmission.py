"""Transmission and constraint indices (``PMAnalysis.indices``) against independent derivations.

* planar 3-RRR: the transmission angles in closed form (ITI = |sin| of the crank-coupler
  angle; OTI from the instantaneous centre of the other two couplers), from the solved
  joint positions only;
* 3-RPS: a hand computation from the definitions (Plücker coordinates of the legs' forces
  written here from A_i, a_i and the R axes, the output twists by SVD, the screw form
  ``|(h + lambda) cos(theta) - d sin(theta)| / sqrt((h + lambda)^2 + d_max^2)``);
* 0 at the singular locus that ``map`` refines, invariance under a base-frame move and a
  change of units, bounds, passive legs.
"""

import numpy as np
import pytest

import screwkit

PLANAR = """
legs:
- name: RRR/planar
  string: _RRR
  summary: three R axes along the base normal
  joints:
  - {axis: base.Z, at: A}
  - axis: base.Z
    at: {offset: {between: [A, a], t: 0.5}, along: base.tangent, fraction: 0.3}
  - {axis: base.Z, at: a}
pms:
  3RRR/planar:
    string: 3RRR
    dimensions: {R: 60, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [RRR/planar, RRR/planar, RRR/planar]
    euler: XYZ
    independent: [Xo, Yo, gamma]
    home: {Xo: 0, Yo: 0, gamma: 0}
    pose: {Xo: 0, Yo: 0, gamma: 0}
    dof: 3
    units: {length: cm, force: kN}
    guess: {Zo: R}
"""


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    path = tmp_path_factory.mktemp("planar") / "3rrr.yaml"
    path.write_text(PLANAR)
    return screwkit.load_pm(str(path))


def _cross2(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _planar_closed_form(legs):
    """ITI, OTI and the arms of a planar 3-RRR from its joint positions A, B, C (xy)."""
    pts = [[np.asarray(j.point[:2], float) for j in lg.joints] for lg in legs]
    e, iti, crank = [], [], []
    for A, B, C in pts:
        u, w = (B - A) / np.linalg.norm(B - A), (C - B) / np.linalg.norm(C - B)
        iti.append(abs(_cross2(u, w)))              # |sin| of the transmission angle
        crank.append(np.linalg.norm(B - A))
        e.append(w)
    oti, arm = [], []
    for i in range(3):
        j, k = (x for x in range(3) if x != i)
        # the other couplers' lines meet at the instantaneous centre of the platform
        Cj, Ck = pts[j][2], pts[k][2]
        t = _cross2(Ck - Cj, e[k]) / _cross2(e[j], e[k])
        P = Cj + t * e[j]
        d = pts[i][2] - P
        oti.append(abs(_cross2(e[i], d)) / np.linalg.norm(d))
        arm.append(np.linalg.norm(d))
    return np.array(iti), np.array(oti), np.array(crank), np.array(arm)


def test_planar_3rrr_transmission_angles_closed_form(planar):
    rng = np.random.default_rng(3)
    pose = {"Xo": rng.uniform(-8, 8, 12), "Yo": rng.uniform(-8, 8, 12),
            "gamma": rng.uniform(-15, 15, 12)}
    res = screwkit.analyze(planar, pose, degrees=True)
    ix = res.indices
    assert res.ok.all()
    for n in range(12):
        iti, oti, crank, arm = _planar_closed_form(res.solution.legs_at(n))
        np.testing.assert_allclose(ix.iti_legs[n], iti, rtol=0, atol=1e-9)
        np.testing.assert_allclose(ix.oti_legs[n], oti, rtol=0, atol=1e-9)
        np.testing.assert_allclose(ix.input_arm[n], crank, rtol=1e-9)
        np.testing.assert_allclose(ix.output_arm[n], arm, rtol=1e-9)
        assert ix.lti[n] == pytest.approx(min(iti.min(), oti.min()), abs=1e-9)
    # the shared planar constraints are redundant: no constraint index
    assert np.isnan(ix.cti_rows).all() and np.isnan(ix.cti).all()


def test_planar_input_singularity_near_the_boundary(planar):
    """Towards a stretched leg (the workspace boundary near Xo = 21.9 cm) the crank and
    coupler align: ITI -> 0 as |sin|, while the condition number of J stays below 10."""
    res = screwkit.analyze(planar, {"Xo": np.linspace(20, 22, 41), "Yo": 0.0, "gamma": 0.0},
                           degrees=True)
    ok = res.solution.reachable_mask
    iti = res.indices.iti_legs[ok]
    for n in np.flatnonzero(ok):
        np.testing.assert_allclose(res.indices.iti_legs[n],
                                   _planar_closed_form(res.solution.legs_at(n))[0], atol=1e-9)
    assert iti.min() < 0.1 < 0.5 < iti.max()
    assert res.jacobian.condition_number[ok].max() < 10


def _line(s, p, pitch=0.0):
    """Plücker coordinates [s; p x s + pitch s] of a unit screw."""
    s = np.asarray(s, float) / np.linalg.norm(s)
    return np.concatenate([s, np.cross(p, s) + pitch * s])


def _screw_index(W, p, V):
    """Wang et al.'s power coefficient from the screw parameters: the wrench ``W`` (pitch 0,
    through ``p``), the twist ``V = [v; w]``: ``|(h + l) cos(theta) - d sin(theta)| /
    sqrt((h + l)^2 + d_max^2)``, ``d_max`` the distance from ``p`` to the twist axis."""
    s1 = W[:3] / np.linalg.norm(W[:3])
    v, w = V[:3], V[3:]
    s2 = w / np.linalg.norm(w)
    h = float(w @ v) / float(w @ w)
    r2 = np.cross(w, v) / float(w @ w)                  # the twist axis' point nearest O
    n = np.cross(s1, s2)
    sin = np.linalg.norm(n)
    n /= sin
    d = float((r2 - p) @ n)                             # along the common normal
    cos = float(s1 @ s2)
    rho = np.linalg.norm(np.cross(p - r2, s2))          # p to the twist axis
    return abs(h * cos - d * sin) / np.hypot(h, rho), rho


def test_3rps_hand_computation():
    res = screwkit.analyze("3RPS", {"alpha": [5, -8, 2], "beta": [-3, 4, 9],
                                    "Zo": [60, 52, 70]}, degrees=True)
    ix = res.indices
    for n in range(3):
        legs = res.solution.legs_at(n)
        A = [lg.A for lg in legs]
        a = [lg.a for lg in legs]
        r = [lg.joints[0].direction for lg in legs]        # base R axes
        tws = [_line(a[i] - A[i], a[i]) for i in range(3)]  # along each leg, through S
        cws = [_line(r[i], a[i]) for i in range(3)]         # through S, parallel to R
        rows = tws + cws
        for i in range(3):
            # the prismatic actuator slides along the leg: its force does all the work
            assert ix.iti_legs[n, i] == pytest.approx(1.0, abs=1e-12)
        for k, W in enumerate(rows):
            M = np.array([np.concatenate([w[:3], w[3:]]) for j, w in enumerate(rows) if j != k])
            V = np.linalg.svd(M)[2][-1]                     # f.v + m.w = 0 for the others
            zeta, rho = _screw_index(W, a[k % 3], V)
            got = ix.oti_legs[n, k] if k < 3 else ix.cti_rows[n, k - 3]
            arm = ix.output_arm[n, k] if k < 3 else ix.constraint_arm[n, k - 3]
            assert got == pytest.approx(zeta, abs=1e-9)
            assert arm == pytest.approx(rho, rel=1e-9)
        assert ix.lti[n] == pytest.approx(min(1.0, ix.oti_legs[n].min()), abs=1e-15)
        assert 0 < ix.cti[n] <= 1


def test_zero_at_the_refined_singular_locus():
    """2SPS+2SPR: the actuation singularity that ``map`` refines (alpha + gamma = 16.589 deg
    at beta = 0, Zo = 75 cm): OTI and LTI vanish there, and exactly at every pose the
    engine flags singular."""
    ds = screwkit.map("2SPS+2SPR", {"alpha": (-10, 30, 41)},
                      fix={"beta": 0, "gamma": 0, "Zo": 75}, degrees=True)
    loc = screwkit.maps.locus_list(ds)
    assert len(loc) == 1 and loc[0]["kind"] == "actuation"
    a = loc[0]["pose"]["alpha"]
    res = screwkit.analyze("2SPS+2SPR", {"alpha": np.array([a, a - 1, a + 1]), "beta": 0.0,
                                         "gamma": 0.0, "Zo": 75.0}, degrees=True)
    ix = res.indices
    assert ix.oti[0] < 1e-6 and ix.lti[0] < 1e-6
    assert ix.oti[1] > 1e-3 and ix.oti[2] > 1e-3
    sing = res.singular
    assert sing[0]                       # refined to 1e-6 of a cell: flagged singular
    assert (ix.oti[sing] == 0).all() and (ix.lti[sing] == 0).all() and (ix.cti[sing] == 0).all()
    # the map carries them, and they dip to ~0 in the cells next to the crossing
    k = int(np.argmin(np.abs(ds["alpha"].values - a)))
    assert float(ds["lti"].values[k]) < 0.01 < float(ds["lti"].values[0])
    assert ds["lti"].attrs["units"] == "1"


def test_invariant_under_frame_move_and_units():
    pose = {"alpha": np.array([5.0, -7.0]), "beta": np.array([-3.0, 6.0]),
            "Zo": np.array([80.0, 72.0])}
    base = screwkit.analyze("3RRPRR", pose, degrees=True).indices
    from scipy.spatial.transform import Rotation
    pm = screwkit.load_pm("3RRPRR").moved(Rotation.from_euler("zyx", [30, -20, 10],
                                                                degrees=True).as_matrix(),
                                          [100.0, -50.0, 20.0])
    moved = screwkit.analyze(pm, pose, degrees=True).indices
    big = screwkit.load_pm("3RRPRR", {"L": 1200, "l": 600})
    scaled = screwkit.analyze(big, dict(pose, Zo=pose["Zo"] * 10), degrees=True).indices
    for name in ("iti_legs", "oti_legs", "cti_rows", "sigma_min", "condition_number"):
        np.testing.assert_allclose(getattr(moved, name), getattr(base, name), atol=1e-9)
        np.testing.assert_allclose(getattr(scaled, name), getattr(base, name), atol=1e-9)
    np.testing.assert_allclose(scaled.output_arm, 10 * base.output_arm, rtol=1e-9)
    np.testing.assert_allclose(moved.constraint_arm, base.constraint_arm, rtol=1e-9)


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR", "3UPU", "3RSR", "3SPU+SP", "4UPU"])
def test_bounds_and_one_pose_is_a_batch_of_one(name):
    pm = screwkit.load_pm(name)
    rng = np.random.default_rng(7)
    pose = {p: np.full(20, v) + rng.uniform(-0.08, 0.08, 20) * (
        pm.normalisation.length if p in ("Xo", "Yo", "Zo") else 1.0)
        for p, v in pm.default_pose.items()}
    res = screwkit.analyze(pm, pose, raise_on_singular=False)
    ix = res.indices
    for a in (ix.iti_legs, ix.oti_legs, ix.cti_rows, ix.iti, ix.oti, ix.lti, ix.cti):
        fin = a[np.isfinite(a)]
        assert ((fin >= 0) & (fin <= 1)).all()
    assert np.isfinite(ix.lti[res.ok]).all()
    one = screwkit.analyze(pm, {p: float(v[0]) for p, v in pose.items()},
                           raise_on_singular=False).indices
    np.testing.assert_allclose(one.lti, ix.lti[0], atol=1e-12)
    np.testing.assert_allclose(one.iti_legs, ix.iti_legs[0], atol=1e-12)


def test_passive_leg_has_no_input_index():
    """A passive leg contributes its constraint rows and no transmission wrench."""
    import dataclasses
    pm = dataclasses.replace(screwkit.load_pm("3RRPRR"), passive=(0,))
    ix = screwkit.analyze(pm, {"alpha": 0.05, "beta": -0.03, "Zo": 80.0},
                          raise_on_singular=False).indices
    assert ix.legs == (1, 2) and ix.iti_legs.shape == (2,)
    # two actuators for three freedoms: the output twists are not unique
    assert ix.oti == 0 and ix.cti == 0


def test_tricept_with_a_passive_column_hand_computation(tmp_path):
    """The Tricept-type 3UPS+UP/passive of tests/test_passive_legs.py: the column has no
    transmission wrench (no input index); the legs' OTI from the hand rows (the UPS forces
    along the legs through the S centres; the column's two forces through O normal to it and
    its couple), and the CTI of the couple (unique: the forces' span does not depend on a
    basis)."""
    from test_passive_legs import TRICEPT, _hand
    path = tmp_path / "tricept.yaml"
    path.write_text(TRICEPT)
    pm = screwkit.load_pm(str(path))
    alpha, beta, Zo = 5.0, -3.0, 650.0
    ix = screwkit.analyze(pm, {"alpha": alpha, "beta": beta, "Zo": Zo}, degrees=True).indices
    _, o, _, Ja, _, cons = _hand(np.radians(alpha), np.radians(beta), Zo)
    res = screwkit.analyze(pm, {"alpha": alpha, "beta": beta, "Zo": Zo}, degrees=True)
    a = [lg.a for lg in res.solution.legs[:3]]
    assert ix.legs == (0, 1, 2) and ix.iti_legs.shape == (3,)
    np.testing.assert_allclose(ix.iti_legs, 1.0, atol=1e-12)   # P along each UPS leg
    rows = list(Ja) + list(cons)
    for k in range(3):
        M = np.array([w for j, w in enumerate(rows) if j != k])
        V = np.linalg.svd(M)[2][-1]
        zeta, _ = _screw_index(Ja[k], a[k], V)
        assert ix.oti_legs[k] == pytest.approx(zeta, abs=1e-9)
    M = np.array(rows[:5])                        # all but the couple
    w = np.linalg.svd(M)[2][-1][3:]
    c = cons[2][3:]
    k = ix.constraint_labels.index("T_c4")
    assert ix.cti_rows[k] == pytest.approx(abs(c @ w) / np.linalg.norm(c) / np.linalg.norm(w),
                                           abs=1e-9)


def test_delta_with_parallelograms_closed_form(tmp_path):
    """The 3-RRPaR Delta of tests/test_parallelogram.py: each arm's force runs along its
    parallelogram's bars, so ITI_i = |b_i . e_i| (e_i the elbow's direction of motion, the
    arm the crank) and, the platform translating, OTI_i = |b_i . (b_j x b_k)| / |b_j x b_k|
    (the translation the other two legs' bars allow)."""
    from test_parallelogram import DELTA_YAML
    path = tmp_path / "delta.yaml"
    path.write_text(DELTA_YAML)
    pm = screwkit.load_pm(str(path))
    res = screwkit.analyze(pm, {k: np.array([v]) for k, v in pm.default_pose.items()})
    ix = res.indices
    for n in range(len(res)):
        legs = res.solution.legs_at(n)
        b, iti, arm = [], [], []
        for lg in legs:
            A, E, w = lg.joints[0].point, lg.joints[1].point, lg.joints[0].direction
            e = np.cross(w, E - A)
            bar = next(j.bar for j in lg.joints if j.bar is not None)
            b.append(bar / np.linalg.norm(bar))
            iti.append(abs(b[-1] @ e) / np.linalg.norm(e))
            arm.append(np.linalg.norm(e))
        oti = [abs(b[i] @ np.cross(b[j], b[k])) / np.linalg.norm(np.cross(b[j], b[k]))
               for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1))]
        np.testing.assert_allclose(ix.iti_legs[n], iti, atol=1e-9)
        np.testing.assert_allclose(ix.input_arm[n], arm, rtol=1e-9)
        np.testing.assert_allclose(ix.oti_legs[n], oti, atol=1e-9)
        assert np.isnan(ix.output_arm[n]).all()              # a translation: no axis
