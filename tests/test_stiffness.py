"""Cartesian stiffness (screwkit.dynamics.stiffness): symmetry, rank, the Stewart platform's
K = k J_a^T J_a, the deflection against the spring-leg equilibrium solved by the engine, the
compliance-weighted statics, the beam formulas, the CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.dynamics import row_stiffness, stiffness
from screwkit.engine import PARAMS, link_frames

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

STEWART = str(Path(__file__).parent / "data" / "stewart_6sps.yaml")


@pytest.fixture(scope="module")
def stewart():
    return screwkit.load_pm(STEWART)


def _rows_about_o(J, o):
    return np.concatenate([J[:, :3], J[:, 3:] - np.cross(o, J[:, :3])], axis=1)


def _stewart_Ja_by_hand():
    """The 6-SPS actuation rows about o from the YAML's geometry: unit leg lines d_i through
    a_i, as [d_i; (a_i - o) x d_i] (hexagons of radii 60 and 30 cm, pose in XYZ degrees)."""
    ang = np.radians
    A = np.array([[60 * np.cos(ang(t)), 60 * np.sin(ang(t)), 0]
                  for t in (-15, 15, 105, 135, 225, 255)])
    ap = np.array([[30 * np.cos(ang(t)), 30 * np.sin(ang(t)), 0]
                   for t in (-45, 45, 75, 165, 195, 285)])
    R = Rotation.from_euler("XYZ", [3, -2, 4], degrees=True).as_matrix()
    o = np.array([2.0, -1.0, 70.0])
    a = ap @ R.T + o
    d = (a - A) / np.linalg.norm(a - A, axis=1)[:, None]
    return np.concatenate([d, np.cross(a - o, d)], axis=1)


def test_stewart_K_is_k_Ja_T_Ja(stewart):
    st = stiffness(stewart, **PAPER_LOAD)
    k = stewart.dynamics.legs[0].stiffness.actuator
    assert k == pytest.approx(2.0e6 * 1e-3)               # N/cm -> kN/cm
    Jo = _stewart_Ja_by_hand()
    assert np.allclose(st.K[0], k * Jo.T @ Jo, rtol=0, atol=1e-12 * np.abs(st.K[0]).max())
    assert st.rank == 6
    assert np.allclose(st.compliance[0] @ st.K[0], np.eye(6), atol=1e-10)


@pytest.mark.parametrize("name, kwargs, rank", [
    ("3RRPRR", {"actuator": 2e3}, 3),
    ("3RRPRR", {"actuator": 2e3, "force_stiffness": 5e3}, 6),
    ("3UPU", {"actuator": 2e3, "couple_stiffness": 1e7}, 6),
    ("2SPS+2SPR", {"actuator": 2e3}, 4),
    ("4UPU", {"actuator": 2e3, "couple_stiffness": 1e7}, 6),
])
def test_K_is_symmetric_psd_with_the_rank_of_its_rows(name, kwargs, rank):
    st = stiffness(name, **kwargs)
    K = st.K[0]
    L = screwkit.load_pm(name).normalisation.length
    S = np.diag([L, L, L, 1, 1, 1])
    Kn = S @ K @ S
    assert np.allclose(K, K.T, rtol=0, atol=1e-14 * np.abs(K).max())
    ev = np.linalg.eigvalsh(Kn)
    assert ev.min() >= -1e-12 * ev.max()
    assert st.rank == rank == int(np.sum(ev > 1e-8 * ev.max()))
    assert st.restrained[0]
    C = st.compliance[0]
    assert np.allclose(C, C.T, atol=1e-14 * np.abs(C).max())


def test_rigid_rows_do_not_deflect():
    st = stiffness("3RRPRR", actuator=2e3, force=[1, 2, 3], torque=[5, -4, 2])
    J = st.analysis.jacobian.J
    Jo = _rows_about_o(J, st.analysis.solution.position)
    d = st.deflection[0]
    assert np.allclose(Jo[3:] @ d, 0, atol=1e-14 * np.abs(d).max())     # rigid constraints
    Fr = st.analysis.statics.values
    assert np.allclose(Jo[:3] @ d, -Fr[:3] / 2e3, rtol=1e-9)             # springs: dr = -F/k


@pytest.mark.parametrize("soft, stiff", [(2e3, 5e4), (1e-10, 1e10), (1e-20, 1e20)])
def test_the_deflection_keeps_its_soft_rows_whatever_the_spread(soft, stiff):
    # every row of a square J compliant: dX = J_o^-1 diag(1/k) J_o^-T W exactly, however far
    # apart the stiffnesses (a spread of 1e40 once gave no deflection at all)
    st = stiffness("3RRPRR", actuator=soft, force_stiffness=stiff,
                   **PAPER_LOAD)
    a = st.analysis
    Jo = _rows_about_o(a.jacobian.J, a.solution.position)
    k = np.r_[np.full(3, soft), np.full(3, stiff)]
    Ji = np.linalg.inv(Jo)
    W = np.r_[PAPER_LOAD["force"], PAPER_LOAD["torque"]]
    expected = Ji @ np.diag(1.0 / k) @ Ji.T @ W
    np.testing.assert_allclose(st.deflection[0], expected, rtol=1e-7,
                               atol=1e-12 * np.abs(expected).max())
    assert np.abs(st.deflection[0]).max() > 1e-3 / soft            # the soft rows give


def _spring_equilibrium(pm, F, T, k, start=None):
    """Forward kinematics (Newton through the engine) of the Stewart platform whose legs are
    springs: leg lengths r0 - F_a(X) / k (r0 at the default pose, unloaded) with F_a the
    statics at the deflected pose.  Returns the deflection from ``start`` (default: the
    default pose) and the deflected pose."""
    names = pm.independent
    x0 = dict(pm.default_pose)

    def an(x):
        return screwkit.analyze(pm, {n: np.array([x[n]]) for n in names}, force=F, torque=T)

    r0 = an(x0).solution.extensions[0]
    a0 = an(start if start is not None else x0)
    x = dict(x0)
    for _ in range(30):
        a = an(x)
        target = r0 - a.statics.active[0] / k
        D = a.jacobian.matrix[0, :6] @ link_frames(a.solution).columns[:, :, 0]
        step = np.linalg.solve(D, target - a.solution.extensions[0])
        for j, p in enumerate(PARAMS):
            x[p] += step[j]
        if np.abs(step).max() < 1e-13:
            break
    a = an(x)
    R0, R1 = a0.solution.rotation[0], a.solution.rotation[0]
    return np.concatenate([a.solution.position[0] - a0.solution.position[0],
                           Rotation.from_matrix(R1 @ R0.T).as_rotvec()]), x


def test_deflection_equals_the_spring_leg_equilibrium_to_second_order(stewart):
    k = stewart.dynamics.legs[0].stiffness.actuator
    W = np.array([0.5, -0.3, 1.0, 2.0, 1.0, -3.0])
    errs = []
    for s in (1.0, 0.5, 0.25):
        st = stiffness(stewart, force=s * W[:3], torque=s * W[3:])
        exact, _ = _spring_equilibrium(stewart, s * W[:3], s * W[3:], k)
        errs.append(np.abs(st.deflection[0] - exact).max() / np.abs(exact).max())
    assert errs[0] < 1e-4
    # the relative error is linear in the load: the absolute error is of second order
    assert errs[0] / errs[1] == pytest.approx(2.0, rel=0.05)
    assert errs[1] / errs[2] == pytest.approx(2.0, rel=0.05)


def test_geometric_term_gives_the_tangent_stiffness_under_a_preload(stewart):
    """Under the paper's workload as a preload, the deflection increment of a small extra load
    is K_t^-1 dW to second order in dW with the geometric term; without it the error is of
    first order (it stays as dW shrinks)."""
    k = stewart.dynamics.legs[0].stiffness.actuator
    W0 = np.array([20.0, -30.0, -60.0, -30.0, -30.0, 100.0])
    _, x1 = _spring_equilibrium(stewart, W0[:3], W0[3:], k)
    tangent = stiffness(stewart, x1, force=W0[:3], torque=W0[3:], geometric=True)
    elastic = stiffness(stewart, x1, force=W0[:3], torque=W0[3:])
    assert np.allclose(tangent.elastic, elastic.K) and tangent.geometric is not None
    assert np.allclose(tangent.K, tangent.elastic + tangent.geometric)
    err_t, err_e = [], []
    for s in (0.1, 0.05):
        dW = s * np.array([1.0, 2.0, -1.0, 10.0, -5.0, 3.0])
        W = W0 + dW
        exact, _ = _spring_equilibrium(stewart, W[:3], W[3:], k, start=x1)
        scale = np.abs(exact).max()
        err_t.append(np.abs(np.linalg.solve(tangent.K[0], dW) - exact).max() / scale)
        err_e.append(np.abs(np.linalg.solve(elastic.K[0], dW) - exact).max() / scale)
    assert err_t[0] < 1e-5 and err_t[0] / err_t[1] == pytest.approx(2.0, rel=0.05)
    assert err_e[1] > 100 * err_t[1] and err_e[0] / err_e[1] == pytest.approx(1.0, rel=0.05)
    assert "geometric" in tangent.to_dict() and "elastic" in tangent.to_dict()


def test_compliance_weighted_statics_is_the_spring_solution():
    """For the indeterminate 4UPU, the engine's stiffness-weighted statics equals the spring
    solution F_r = -k_r J_r dX of the deflection."""
    pm = screwkit.load_pm("4UPU")
    k_rows = {"F_a1": 2e3, "F_a2": 3e3, "F_a3": 2.5e3, "F_a4": 2e3,
              "T_c1": 1e7, "T_c2": 2e7, "T_c3": 1.5e7, "T_c4": 1e7}
    st = stiffness(pm, rows=k_rows, **PAPER_LOAD)
    labels = st.analysis.jacobian.labels
    an = screwkit.analyze(pm, stiffness=k_rows, **PAPER_LOAD)
    k = np.array([k_rows[lab] for lab in labels])
    Jo = _rows_about_o(st.analysis.jacobian.J, st.analysis.solution.position)
    springs = -k * (Jo @ st.deflection[0])
    assert np.allclose(springs, an.statics.values, rtol=1e-8,
                       atol=1e-10 * np.abs(an.statics.values).max())


def test_beam_formulas(stewart):
    """EA/l along the leg for the SPS actuation rows (hand formula)."""
    from screwkit.pm import dynamics_for
    E, A = 2.1e7, 12.0             # N/cm^2, cm^2 (the block's units: kg, cm, N)
    p = dynamics_for(stewart, {"stiffness": {"beam": {"E": E, "G": 8e6, "area": A, "I": 40,
                                                      "J": 80}}})
    an = screwkit.analyze(stewart, **PAPER_LOAD)
    k = row_stiffness(an, p)
    r = an.solution.extensions
    assert np.allclose(k[0], E * 1e-3 * A / r, rtol=1e-12)           # N -> kN
    rps = screwkit.load_pm("3RPS")
    p = dynamics_for(rps, {"stiffness": {"actuator": 2e6, "beam": {"E": E, "G": 8e6,
                                                                   "area": A, "I": 40,
                                                                   "J": 80}}})
    an = screwkit.analyze(rps, **PAPER_LOAD)
    k = row_stiffness(an, p)
    assert np.allclose(k[0, :3], 2e3)
    # the RPS constraint force is perpendicular to the leg: cantilever bending 3EI/l^3
    f = an.jacobian.J[3:, :3]
    d = an.solution.platform_points - an.solution.base_points
    assert np.allclose(np.einsum("ij,ij->i", f, d), 0, atol=1e-9)
    ell = an.solution.extensions
    assert np.allclose(k[0, 3:], 3 * E * 1e-3 * 40 / ell ** 3, rtol=1e-10)


def test_stiffness_cli(tmp_path, capsys):
    from screwkit.cli import main
    assert main(["stiffness", "--model", STEWART, "--force", "0,0,-1", "--torque", "0,0,0",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"stiffness", "deflection", "units"} <= set(d)
    assert np.array(d["stiffness"]).shape == (6, 6)
    assert d["units"]["stiffness"]["f_per_v"] == "kN/cm"
    assert d["units"]["deflection"] == {"translation": "cm", "rotation": "rad"}
    assert main(["stiffness", "3RRPRR", "--pose", "alpha=5", "--k-actuator", "2000"]) == 0
    out = capsys.readouterr().out
    assert "rank 3" in out and "rigid" in out and "kN/cm" in out
    assert main(["stiffness", "3RRPRR", "--k-actuator", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "positive" in err


def test_stiffness_fields_for_maps(stewart):
    """The per-pose scalars for maps against the hand-built K = k J_a^T J_a of the 6-SPS:
    principal stiffnesses are the inverted eigenvalues of the blocks of K^-1, the
    deflection is K^-1 W; a singular cell is NaN."""
    from screwkit.dynamics import stiffness_fields
    k = stewart.dynamics.legs[0].stiffness.actuator
    Ja = _stewart_Ja_by_hand()
    C = np.linalg.inv(k * Ja.T @ Ja)
    W = np.array([0.5, -0.3, 1.0, 2.0, 1.0, -3.0])
    # the second cell is singular: both hexagons in one plane
    pose = {n: np.array([v, v if n != "Zo" else 0.0]) for n, v in stewart.default_pose.items()}
    pose.update({n: np.array([pose[n][0], 0.0]) for n in ("alpha", "beta", "gamma")})
    an = screwkit.analyze(stewart, pose, force=W[:3], torque=W[3:], raise_on_singular=False)
    f = stiffness_fields(an)
    kt = 1 / np.linalg.eigvalsh(C[:3, :3])
    kr = 1 / np.linalg.eigvalsh(C[3:, 3:])
    assert f["k_translation_min"][0][0] == pytest.approx(kt.min(), rel=1e-10)
    assert f["k_translation_max"][0][0] == pytest.approx(kt.max(), rel=1e-10)
    assert f["k_rotation_min"][0][0] == pytest.approx(kr.min(), rel=1e-10)
    assert f["k_rotation_max"][0][0] == pytest.approx(kr.max(), rel=1e-10)
    d = C @ W
    assert f["deflection_translation"][0][0] == pytest.approx(np.linalg.norm(d[:3]), rel=1e-10)
    assert f["deflection_rotation"][0][0] == pytest.approx(np.linalg.norm(d[3:]), rel=1e-10)
    assert f["stiffness_rank"][0][0] == 6 and f["stiffness_rank"][0][1] == -1
    assert np.isnan(f["k_translation_min"][0][1])
    assert f["k_translation_min"][1] == "kN/cm" and f["k_rotation_min"][1] == "kN.cm/rad"
    assert f["deflection_translation"][1] == "cm"


def test_a_map_of_a_model_with_leg_stiffness_carries_the_stiffness_fields(stewart):
    """`screwkit.map` of the 6-SPS (its YAML declares the legs' stiffness): the cell at the
    default pose has the principal stiffnesses of the hand-built K = k J_a^T J_a, with units."""
    pytest.importorskip("xarray")
    k = stewart.dynamics.legs[0].stiffness.actuator
    Ja = _stewart_Ja_by_hand()
    C = np.linalg.inv(k * Ja.T @ Ja)
    d = stewart.default_pose
    grid = {"alpha": (d["alpha"], d["alpha"] + 0.02, 2)}
    ds = screwkit.map(stewart, grid, fix={n: v for n, v in d.items() if n != "alpha"}, **PAPER_LOAD)
    cell = ds.isel(alpha=0)
    assert float(cell["k_translation_min"]) == pytest.approx(
        1 / np.linalg.eigvalsh(C[:3, :3]).max(), rel=1e-10)
    assert float(cell["k_rotation_max"]) == pytest.approx(
        1 / np.linalg.eigvalsh(C[3:, 3:]).min(), rel=1e-10)
    assert ds["k_translation_min"].attrs["units"] == "kN/cm"
    assert int(cell["stiffness_rank"]) == 6
    assert "k_translation_min" not in screwkit.map("3RRPRR", {"alpha": (0.0, 0.1, 2)},
                                                   fix={"beta": 0.0, "Zo": 80.0}).data_vars


def test_a_buckling_tangent_stiffness_is_flagged_not_called_rigid(capsys):
    """3RRPRR under a growing preload with the geometric term: once the symmetric part of the
    tangent K + K_g (its printed matrix, numpy's eigenvalues) has a negative eigenvalue the
    result says it is not stable and warns, and no principal stiffness reads as rigid where
    K + K_g has full rank; under a small load it is stable and silent."""
    from screwkit.cli import main
    small = stiffness("3RRPRR", actuator=2000, force_stiffness=5000, geometric=True,
                      force=[0, 0, -1], torque=[0, 0, 0])
    assert small.stable and not small.warnings
    for load in (2e3, 1e4):
        r = stiffness("3RRPRR", actuator=20, force_stiffness=50, geometric=True,
                      force=[0, 0, -load], torque=[0, 0, 0])
        K = np.asarray(r.K)[0]
        ev = np.linalg.eigvalsh(0.5 * (K + K.T))
        assert ev[0] < 0 and not r.stable
        assert any("not positive definite" in w for w in r.warnings)
        kt, _ = r.principal("translational")
        kr, _ = r.principal("rotational")
        assert np.all(np.isfinite(kt)) and np.all(np.isfinite(kr))
    assert main(["stiffness", "3RRPRR", "--k-actuator", "20", "--k-force", "50", "--geometric",
                 "--force", "0,0,-1e4"]) == 0
    err = capsys.readouterr().err
    assert "not positive definite" in err and "not small beside the PM" in err


def test_the_rank_of_K_is_its_rows_whatever_the_spread_of_stiffnesses():
    """Six compliant rows of a regular 3RRPRR pose (numpy: J has rank 6) give K of rank 6,
    with stiffnesses 1e23 apart as with equal ones; the deflection of the soft rows is then
    large, and said to be beyond the linear model."""
    r = stiffness("3RRPRR", actuator=2000, force_stiffness=1e-20, force=[0, 0, -1],
                  torque=[0, 0, 0])
    J = np.asarray(r.analysis.jacobian.matrix)[0]
    assert np.linalg.matrix_rank(J) == 6 and r.rank == 6
    assert any("not small beside the PM" in w for w in r.warnings)
    assert stiffness("3RRPRR", actuator=2000, force_stiffness=2000, force=[0, 0, -1],
                     torque=[0, 0, 0]).rank == 6


def test_stiffness_rank_is_the_analysis_rank_next_to_a_singularity():
    """The 6-SPS along Zo across a singular pose (found here by bisection on the sign of
    det J): at every pose, compliant legs all, the stiffness's rank is 6 exactly where the
    analysis calls the pose regular and the legs restrain it (the rank, the singular flag and
    ``restrained`` are one decision; an SVD of its own normalisation, about ``o``, once gave
    rank 5 beside ``restrained`` and a condition number of 1e8 less a few per cent)."""
    from screwkit.dynamics import stiffness_fields, stiffness_of
    pm = screwkit.load_pm("6SPS")
    home = pm.default_pose

    def at(zo):
        zo = np.atleast_1d(np.asarray(zo, float))
        pose = {p: np.full(zo.size, home[p]) for p in pm.independent}
        pose["Zo"] = zo
        return screwkit.analyze(pm, pose, raise_on_singular=False, force=[0, 0, -100],
                                torque=[0, 0, 0])

    zs = home["Zo"] + np.linspace(-1.0, 1.0, 201) * float(pm.normalisation.length)
    a = at(zs)
    ok = np.asarray(a.solution.reachable_mask)
    det = np.sign(np.linalg.det(a.jacobian.matrix))
    k = np.flatnonzero(ok[:-1] & ok[1:] & (det[:-1] * det[1:] < 0))[0]
    lo, hi = zs[k], zs[k + 1]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        s = np.sign(np.linalg.det(at(mid).jacobian.matrix[0]))
        lo, hi = (mid, hi) if s == det[k] else (lo, mid)
    offsets = np.concatenate([-np.logspace(-12, -3, 120), np.logspace(-12, -3, 120)])
    a = at(lo + offsets * float(pm.normalisation.length))
    reach = np.asarray(a.solution.reachable_mask)
    st = stiffness_of(a, actuator=2000.0)
    regular = ~np.asarray(a.jacobian.singular_mask)
    assert regular[reach].any() and (~regular[reach]).any()         # both sides of the flag
    rank = np.asarray(st.rank)
    assert np.array_equal((rank == 6)[reach], regular[reach])
    assert np.array_equal(np.asarray(st.restrained)[reach], regular[reach])
    fields = stiffness_fields(a, actuator=2000.0)
    assert np.array_equal(fields["stiffness_rank"][0][reach & regular], rank[reach & regular])


def test_the_principal_stiffnesses_are_the_compliance_blocks_inverse_eigenvalues(capsys):
    """stiffness --json of a 6-SPS: each principal stiffness is 1 / an eigenvalue of the
    translational (rotational) block of K^-1, inverted here from the printed K (the
    stiffness under a force alone, not K's own block); the JSON says so, and gives the
    workload's units."""
    from screwkit.cli import main
    assert main(["stiffness", "6SPS", "--k-actuator", "1000", "--force=1,2,-10",
                 "--torque=5,-3,2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    C = np.linalg.inv(np.array(d["stiffness"]))
    for which, sl in (("translational", slice(0, 3)), ("rotational", slice(3, 6))):
        block = 0.5 * (C[sl, sl] + C[sl, sl].T)
        expect = np.sort(1.0 / np.linalg.eigvalsh(block))
        np.testing.assert_allclose(np.sort(d["principal"][which]["stiffness"]), expect,
                                   rtol=1e-9)
        K_block = np.sort(np.linalg.eigvalsh(np.array(d["stiffness"])[sl, sl]))
        assert not np.allclose(K_block, expect, rtol=1e-3)     # (the other definition)
    assert "compliance's translational" in d["principal"]["definition"]
    assert (d["workload"]["force_unit"], d["workload"]["torque_unit"]) == ("kN", "kN.cm")


def test_the_tangent_compliance_keeps_soft_rows_whatever_the_stiffness_spread():
    """With a geometric term the compliance was a pseudo-inverse of the reduced tangent
    stiffness cut at 1e-13: actuators 1e17 times stiffer than the constraint rows (5000)
    read as rigid everywhere (the deflection 4e-16 cm instead of 1.55e-3, rank 3).  By hand:
    at actuator stiffness 1e6 the tangent compliance is ``inv(J_o^T diag(k) J_o + K_g)``
    (well conditioned there, inverted in the test); from 1e12 to 1e17 the actuators are
    rigid beside the force rows, so the deflection stops changing (its limit), and the
    rank stays the rows' 6."""
    pm = screwkit.load_pm("3RRPRR")
    pose = dict(pm.default_pose)
    r = stiffness(pm, pose, actuator=1e6, force_stiffness=5000.0, geometric=True)
    from screwkit.dynamics._compliance import rows_about_o
    Jo = rows_about_o(r.analysis)[0]
    Kt = Jo.T @ np.diag(r.k[0]) @ Jo + np.asarray(r.geometric)[0]
    np.testing.assert_allclose(np.asarray(r.compliance)[0], np.linalg.inv(Kt),
                               rtol=1e-7, atol=1e-9 * np.abs(np.linalg.inv(Kt)).max())
    X = [np.asarray(stiffness(pm, pose, actuator=ka, force_stiffness=5000.0,
                              geometric=True).deflection).ravel() for ka in (1e12, 1e17)]
    assert np.abs(X[0]).max() > 1e-4
    np.testing.assert_allclose(X[1], X[0], rtol=1e-6, atol=1e-9 * np.abs(X[0]).max())
    assert stiffness(pm, pose, actuator=1e17, force_stiffness=5000.0, geometric=True).rank == 6


def test_the_geometric_term_at_a_singular_pose_is_a_clear_error(capsys):
    """At a singular pose there are no efforts to preload with: ``--geometric`` ended in an
    AttributeError (exit 3); it is a SingularityError naming the way out (exit 2), and the
    elastic stiffness is still given without it."""
    from screwkit.cli import main
    from screwkit.errors import SingularityError
    pm = screwkit.load_pm("3SPU+SP")
    pose = dict(pm.default_pose, alpha=0.0374898304306222)          # det J changes sign
    res = screwkit.analyze(pm, pose, force=[0, 0, -1], raise_on_singular=False)
    assert res.singular
    from screwkit.dynamics._stiffness import stiffness_of
    with pytest.raises(SingularityError, match="drop the geometric term"):
        stiffness_of(res, None, actuator=2000, force_stiffness=5000, geometric=True)
    elastic = stiffness_of(res, None, actuator=2000, force_stiffness=5000)
    assert elastic.unrestrained().shape[0] >= 1
    assert main(["stiffness", "3RPS", "--pose", "alpha=-43.12884710315615", "--pose", "beta=0",
                 "--pose", "Zo=60", "--k-actuator", "2000", "--force", "0,0,-1",
                 "--geometric"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "singular" in err[0]


def test_the_geometric_term_at_a_singular_pose_of_a_batch_is_undefined_not_elastic():
    """In a batch the singular pose has no efforts to preload with: its tangent stiffness,
    compliance, deflection and principal stiffnesses are NaN (it was the elastic stiffness,
    silently, and ``stable``), with a note naming the pose; the elastic part is
    ``J_o^T diag(k) J_o`` formed here; the other poses are their one-pose runs."""
    pm = screwkit.load_pm("3SPU+SP")
    pose = {k: np.full(3, v) for k, v in pm.default_pose.items()}
    pose["alpha"] = np.array([0.0, 0.0374898304306222, -0.05])      # det J changes sign at [1]
    kw = dict(actuator=2000.0, force_stiffness=5000.0, force=[0, 0, -1], torque=[0, 0, 0],
              geometric=True)
    r = stiffness(pm, pose, **kw)
    assert r.analysis.jacobian.singular_mask.tolist() == [False, True, False]
    assert np.isnan(r.K[1]).all() and np.isnan(r.compliance[1]).all()
    assert np.isnan(r.deflection[1]).all() and np.isnan(r.principal()[0][1]).all()
    assert not r.stable[1]
    Jo = _rows_about_o(r.analysis.jacobian.J[1], r.analysis.solution.position[1])
    assert np.allclose(r.elastic[1], Jo.T @ np.diag(r.k[1]) @ Jo, rtol=1e-10,
                       atol=1e-12 * np.abs(r.elastic[1]).max())
    assert any("undefined at 1 singular pose(s) (index 1" in n for n in r.notes)
    for i in (0, 2):
        one = stiffness(pm, {k: float(v[i]) for k, v in pose.items()}, **kw)
        assert np.allclose(r.K[i], one.K[0], rtol=1e-9, atol=1e-9 * np.abs(one.K[0]).max())
        assert np.allclose(r.deflection[i], one.deflection[0], rtol=1e-8,
                           atol=1e-10 * np.abs(one.deflection[0]).max())
        assert r.stable[i] == one.stable


@pytest.mark.parametrize("euler_deg,p", [((0, 0, 0), (0, 0, 100.0)),
                                         ((30, 20, -15), (12.0, -7.0, 25.0))])
def test_the_tangent_stiffness_does_not_move_with_the_base_frame(euler_deg, p):
    """A 3-DOF PM (3RPS) with its base frame moved: the tangent stiffness about o, its load
    term, compliance and deflection are the unmoved ones turned by the frame's rotation
    (``K' = B K B^T``, ``B = diag(R, R)``; a translation changes nothing). The load term was
    completed off the PM's motions in twists about O, so a base 100 cm higher changed it by
    up to 80 %."""
    from scipy.spatial.transform import Rotation
    pm = screwkit.load_pm("3RPS")
    R = Rotation.from_euler("zyx", euler_deg, degrees=True).as_matrix()
    moved = pm.moved(R, p)
    F, T = np.array([3.0, -2.0, -60.0]), np.array([10.0, -5.0, 8.0])
    pose = dict(pm.default_pose, alpha=0.07, beta=-0.04)
    kw = dict(actuator=2000.0, force_stiffness=5000.0, geometric=True)
    a = stiffness(pm, pose, force=F, torque=T, **kw)
    b = stiffness(moved, pose, force=R @ F, torque=R @ T, **kw)
    B = np.zeros((6, 6))
    B[:3, :3] = B[3:, 3:] = R
    G = B @ np.asarray(a.geometric)[0] @ B.T
    assert np.abs(G).max() > 1e-3 * np.abs(F).max()           # (a load term to speak of)
    assert np.allclose(b.geometric[0], G, rtol=1e-6, atol=1e-6 * np.abs(G).max())
    Kt = B @ a.K[0] @ B.T
    assert np.allclose(b.K[0], Kt, rtol=1e-9, atol=1e-9 * np.abs(Kt).max())
    C = B @ a.compliance[0] @ B.T
    assert np.allclose(b.compliance[0], C, rtol=1e-7, atol=1e-9 * np.abs(C).max())
    X = B @ a.deflection[0]
    assert np.allclose(b.deflection[0], X, rtol=1e-7, atol=1e-9 * np.abs(X).max())
