"""Type synthesis of PMs for a motion pattern (``screwkit synthesize``, screwkit.design).

The listed PMs are checked against facts derived by hand, independently of the search:
the constraint systems of the legs (a translational UPU exerts one couple normal to its
U axes; a PRRR leg with P parallel to its R axes two couples normal to them; an RPS a
force through its S centre parallel to its base R; a spherical UPU a force through the
centre C), and the finite motion of the written model analysed afresh with
``screwkit.load_pm`` + ``screwkit.analyze`` (no rotation for 3T, a fixed centre for 3R,
the platform normal kept for 3T1R).  Symmetric searches only (fast); the asymmetric
ones are in the benchmark and the docs.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.design import CHECK_POSES, synthesize_motion
from screwkit.errors import InputError
from screwkit.synthesis import extra_legs, leg_pool, motion_pattern
from screwkit.pm import default_catalog

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


@pytest.fixture(scope="module")
def found():
    # the catalog's leg types only (the generated ones: tests/test_synthesis_generated.py)
    return {m: synthesize_motion(m, asymmetric=False, generate=False)
            for m in ("3T", "1T2R", "3R", "3T1R")}


def _by_name(res, name):
    hit = [p for p in res.listed if p.variant == name]
    assert hit, f"{name} not in {res.variants()}"
    return hit[0]


def _written_model(p, tmp_path):
    path = tmp_path / (p.variant.replace("/", "-") + ".yaml")
    path.write_text(p.model_yaml(), encoding="utf-8")
    return screwkit.load_pm(str(path)), path


def _couples_only(rows, tol=1e-9):
    """Every row a pure couple: force parts zero (rows normalised)."""
    r = rows / np.linalg.norm(rows, axis=1, keepdims=True)
    return float(np.max(np.abs(r[:, :3]))) <= tol


# ------------------------------------------------------------------ hand-known leg systems

def test_translational_upu_exerts_one_couple_normal_to_its_u_axes():
    leg = default_catalog().legs["UPU/couple"].build()
    an = leg.analyze()
    assert (an.n_forces, an.n_couples) == (0, 1)
    W = np.asarray(an.system.wrenches, float).reshape(-1, 6)
    axes = [j.direction for j in leg.joints]          # U1a U1b P2 U3a U3b
    m = W[0, 3:] / np.linalg.norm(W[0, 3:])
    assert np.linalg.norm(W[0, :3]) <= 1e-12 * np.linalg.norm(W[0])
    n = np.cross(axes[0], axes[1])                    # by hand: normal to U1a and U1b
    assert abs(abs(m @ n / np.linalg.norm(n)) - 1) <= 1e-9
    for k in (0, 1, 3, 4):                            # and to U3a, U3b (parallel to them)
        assert abs(m @ axes[k]) <= 1e-9


def test_prrr_leg_with_p_parallel_to_its_r_axes_exerts_two_couples_normal_to_them():
    leg = extra_legs()["PRRR/translational"].build()
    an = leg.analyze()
    assert (an.n_forces, an.n_couples) == (0, 2)
    d = leg.joints[0].direction
    W = np.asarray(an.system.wrenches, float).reshape(-1, 6)
    assert _couples_only(W)
    assert np.max(np.abs(W[:, 3:] @ d)) <= 1e-9 * np.max(np.abs(W))


def test_leg_pool_counts_fit_the_complementary_systems():
    # 3T: only legs exerting couples (or nothing); 3R: only forces
    for k in leg_pool(motion_pattern("3T")):
        assert k.forces == 0 and k.screws == 0
    for k in leg_pool(motion_pattern("3R")):
        assert k.couples == 0 and k.screws == 0
    names3t = {k.name for k in leg_pool(motion_pattern("3T"))}
    assert {"UPU/couple", "PRRR/translational", "SPS"} <= names3t
    assert "UPU/force" not in names3t and "RPS" not in names3t


# ------------------------------------------------------------------ what must be listed

def test_3t_lists_3upu_couple_and_3prrr(found, tmp_path):
    res = found["3T"]
    upu = _by_name(res, "3UPU/couple")
    prrr = _by_name(res, "3PRRR/translational")
    assert prrr.rank < upu.rank                       # 12 joints before 15
    for p in (upu, prrr):
        assert len(p.verdict.checks) >= 1 + 5 and all(c.dof == 3 for c in p.verdict.checks)
        model, _ = _written_model(p, tmp_path)
        pose = {"Xo": [0.0, 4.0, -3.0], "Yo": [0.0, -2.0, 3.0], "Zo": [60.0, 63.0, 57.0]}
        a = screwkit.analyze(model, pose, **PAPER_LOAD)
        assert bool(np.all(a.ok))
        # by hand: a translational PM does not rotate, and its constraint rows are couples
        assert float(np.max(np.abs(a.solution.rotation - np.eye(3)))) <= 1e-9
        Jc = np.asarray(a.jacobian.J_c, float)
        for i in range(3):
            assert _couples_only(Jc[i])
            assert np.linalg.matrix_rank(Jc[i][:, 3:], 1e-9) == 3


def test_1t2r_lists_3rps_and_3spr(found, tmp_path):
    res = found["1T2R"]
    for name in ("3RPS", "3SPR"):
        p = _by_name(res, name)
        assert all((c.translations, c.rotations) == (1, 2) for c in p.verdict.checks)
    model, _ = _written_model(_by_name(res, "3RPS"), tmp_path)
    a = screwkit.analyze(model, {"alpha": 0.05, "beta": -0.03, "Zo": 62.0}, **PAPER_LOAD)
    # by hand: each RPS exerts a force through its S centre (the platform vertex a_i)
    # parallel to its base R axis (horizontal, tangent to the base circle)
    rows = np.asarray(a.jacobian.J_c, float)
    for i, lg in enumerate(a.solution.legs):
        f, m = rows[i, :3], rows[i, 3:]
        s_centre = lg.points[-1]
        assert np.linalg.norm(m - np.cross(s_centre, f)) <= 1e-9 * np.linalg.norm(rows[i]) * 60
        assert abs(f @ lg.joints[0].direction) >= (1 - 1e-9) * np.linalg.norm(f)


def test_3r_lists_a_spherical_pm_with_a_fixed_centre(found, tmp_path):
    res = found["3R"]
    p = _by_name(res, "3UPU/force")
    model, _ = _written_model(p, tmp_path)
    C = np.asarray(model.centre, float)
    ang = {"alpha": np.radians([0.0, 6.0, -4.0]), "beta": np.radians([0.0, -3.0, 5.0]),
           "gamma": np.radians([0.0, 4.0, 2.0])}
    a = screwkit.analyze(model, ang, **PAPER_LOAD)
    R, o = a.solution.rotation, a.solution.position
    for i in range(3):       # by hand: o - C = R (R_0^T (o_0 - C))
        assert np.linalg.norm(o[i] - C - R[i] @ R[0].T @ (o[0] - C)) <= 1e-8 * 60
        Jc = np.asarray(a.jacobian.J_c, float)[i]
        for f, m in zip(Jc[:, :3], Jc[:, 3:]):        # every constraint force through C
            assert np.linalg.norm(m - np.cross(C, f)) <= 1e-9 * 60 * np.linalg.norm(f)


def test_3t1r_lists_a_4upu_schoenflies_type(found, tmp_path):
    res = found["3T1R"]
    p = _by_name(res, "4UPU/schoenflies")
    assert len(p.legs) == 4 and p.verdict.checks[-1].dof == 4
    model, _ = _written_model(p, tmp_path)
    a = screwkit.analyze(model, {"Xo": [0.0, 5.0], "Yo": [0.0, -3.0], "Zo": [80.0, 84.0],
                                 "gamma": np.radians([0.0, 10.0])}, **PAPER_LOAD)
    z = a.solution.rotation[:, :, 2]
    assert float(np.max(np.abs(z - [0, 0, 1]))) <= 1e-9      # the normal stays vertical
    Jc = np.asarray(a.jacobian.J_c, float)[1]
    assert _couples_only(Jc) and float(np.max(np.abs(Jc[:, 5]))) <= 1e-9 * np.abs(Jc).max()


def test_every_listed_pm_verified_at_enough_poses(found):
    for res in found.values():
        assert res.listed
        for p in res.listed:
            assert len(p.verdict.checks) == 1 + CHECK_POSES >= 6
            assert p.verdict.success and p.condition_home < 1e8
            assert all(c.dof == res.motion.dof for c in p.verdict.checks)


def test_wrong_pms_are_not_listed(found):
    # by hand: the translational 3-UPU cannot rotate, so it is no 1T2R PM; the 3-RPS
    # cannot translate sideways, so it is no 3T PM; both are formed as candidates
    from screwkit.synthesis import compositions_for
    for motion, wrong in (("1T2R", "3UPU/couple"), ("3T", "3RPS"), ("3R", "3UPU/couple")):
        m = motion_pattern(motion)
        formed = {c.name for c in compositions_for(m, leg_pool(m, generate=False),
                                                   asymmetric=False)}
        assert wrong not in found[motion].variants()
        if wrong in formed:
            assert found[motion].tried >= 1
    for res in found.values():
        assert (res.screened_out + len(res.rejected) + res.verified + res.not_verified
                + res.pruned) == res.tried


# ------------------------------------------------------------------ model files, CLI

def test_written_model_analyses_from_the_cli(found, tmp_path, capsys):
    _, path = _written_model(_by_name(found["3T"], "3UPU/couple"), tmp_path)
    assert main(["analyze", str(path), "--json", *PAPER_ARGS]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["pm"] == "3UPU/couple"


def test_cli_synthesize_json(capsys, tmp_path):
    rc = main(["synthesize", "3T", "--symmetric", "--no-generate", "--limit", "2", "--json",
               "--write", str(tmp_path / "models")])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["motion"] == "3T" and len(out["listed"]) == 2
    assert out["listed"][0]["rank"] == 1 and len(out["written"]) == 2
    assert screwkit.load_pm(out["written"][0]).stated_dof == 3


def test_cli_bad_motion_is_one_line(capsys):
    assert main(["synthesize", "4X"]) == 2
    err = capsys.readouterr().err
    assert "unknown motion pattern" in err and len(err.strip().splitlines()) == 1
    assert main(["synthesize", "3T", "--legs", "9"]) == 2


def test_motion_pattern_aliases():
    assert motion_pattern("2R1T").name == "1T2R"
    assert motion_pattern("schoenflies").independent == ("Xo", "Yo", "Zo", "gamma")
    with pytest.raises(InputError):
        motion_pattern("")
    with pytest.raises(InputError):
        synthesize_motion("3T", legs=2)


def test_the_delta_with_base_tangent_axes_is_listed(tmp_path):
    """The classic Delta leg (R-R-Pa-R, every axis along the base tangent) was rejected: its
    generic elbow, moved along the tangent (its own axes), stayed on the line A -> a seen
    along them, so the leg was 0.7 cm from stretching at home and the verification's path
    left the workspace. Its elbows move across the axes now; the verified PM keeps its
    platform's orientation at poses 5 cm around home (every rotation vector 0, checked
    here on the engine's solutions) with its three legs' arms bent (the elbow off the line
    A -> a by more than a tenth of the leg)."""
    res = synthesize_motion("3T", asymmetric=False, passive=False)
    delta = [p for p in res.listed if p.variant == "3RRPaR/t.t.t.t"]
    assert delta, [p.variant for p in res.listed]
    pm, _ = _written_model(delta[0], tmp_path)
    rng = np.random.default_rng(4)
    L = float(pm.normalisation.length)
    for _ in range(5):
        pose = {k: v + rng.uniform(-0.1, 0.1) * L for k, v in pm.home_pose.items()
                if k in pm.independent}
        sol = screwkit.analyze(pm, pose, force=[0, 0, -1]).solution
        assert np.allclose(np.asarray(sol.rotation).reshape(3, 3), np.eye(3), atol=1e-9)
        for leg in sol.legs:
            A, a = np.asarray(leg.A, float), np.asarray(leg.a, float)
            E = np.asarray(leg.joints[1].point, float)
            off = np.linalg.norm(np.cross(E - A, a - A)) / np.linalg.norm(a - A)
            assert off > 0.1 * np.linalg.norm(a - A)
