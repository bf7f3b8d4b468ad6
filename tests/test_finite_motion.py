"""The motion type computed from the finite motion (``screwkit.engine.finite_motion``).

The label of every catalog PM is compared with the literature's (written here, not read
from the catalog), and the invariants and parasitic motions with what the engine's own
solutions show when read independently (rotations compared, dependent parameters varied).
A model whose declared motion or independent parameters disagree with the computed type
fails to load, with both named.

Literature (the project writes 2R1T as 1T2R):

* 3-RRPRR and 2-SPS+2-SPR: Hu, Lu, Zhang, Yu, "Unified analysis of statics of some
  limited-DOF parallel manipulators" (the paper this project follows), sections 3 and 4:
  two rotations and a translation (alpha, beta, Zo); three rotations and a translation.
* 3-RPS: K.-M. Lee, D. K. Shah, "Kinematic analysis of a three-degrees-of-freedom in-parallel
  actuated manipulator", IEEE J. Robotics and Automation 4(3), 1988: 2R1T with parasitic
  translations and rotation (J. A. Carretero, R. P. Podhorodeski et al., J. Mech. Des.
  122, 2000).
* 3-SPR, 3-UPRR, 3-RPRU, 3-RPUR, 3-RSR, 2-UPU+SPR: 2R1T PMs of Q. Li, J. M. Hervé,
  "1T2R parallel mechanisms without parasitic motion", IEEE Trans. Robotics 26(3), 2010,
  and X. Kong, C. Gosselin, "Type Synthesis of Parallel Mechanisms", Springer 2007, ch. 8
  (3-DOF 2R1T); the 3-RSR of Z. Huang, Y. Fang, Robotica 2005.
* translational 3-UPU: L.-W. Tsai, "Kinematics of a three-DOF platform with three extensible
  limbs", in Recent Advances in Robot Kinematics, 1996: 3T.
* spherical 3-UPU: R. Di Gregorio, "Kinematics of the 3-UPU wrist", Mech. Mach. Theory 38,
  2003: 3R about a fixed point.
* 4-UPU, 2-UPS+2-UPU, 3-SPU+PRRR: Schoenflies (3T1R), Kong and Gosselin 2007 ch. 9; the
  rotations about one fixed direction.
* the Exechon 2-UPR+SPR: Z. M. Bi, Y. Jin, "Kinematic modeling of Exechon parallel kinematic
  machine", Robotics and Computer-Integrated Manufacturing 27, 2011: 2R1T; the Tricept
  3-UPS+UP (B. Siciliano, Robotica 17, 1999): 2R1T; the 3-UPS with a passive spherical
  column: 3R about the column's S.
* 3-SPU+SP, 2-UPS+2-SPR: 1T3R (the SP leg's two forces through one point); 4-SPS+SPR,
  4-SPS+UPU, 4-SPS+URPR: 2T3R (one constraint force); 3-SPU+UPR, 3-SPU+RPRR: 2T2R (a
  force and a couple): the motion types of Kong and Gosselin's wrench-system
  classification, ch. 2 (a PM's motion is the reciprocal of its legs' constraints).
* the 6-SPS Stewart platform: D. Stewart, "A platform with six degrees of freedom", Proc.
  IMechE 180, 1965: 3T3R (no leg constrains the platform).
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine import finite_motion
from screwkit.errors import CatalogError
from screwkit.pm import load_pm, mobility, pm_names

LITERATURE = {
    "3RRPRR": "1T2R", "2SPS+2SPR": "1T3R", "3RPS": "1T2R", "3SPR": "1T2R", "3UPRR": "1T2R",
    "3RPRU": "1T2R", "3RPUR": "1T2R", "3RSR": "1T2R", "2UPU+SPR": "1T2R", "3UPU": "3T",
    "3UPU/spherical": "3R", "4UPU": "3T1R", "2UPS+2UPU": "3T1R", "3SPU+PRRR": "3T1R",
    "3SPU+SP": "1T3R", "2UPS+2SPR": "1T3R", "4SPS+SPR": "2T3R", "4SPS+UPU": "2T3R",
    "4SPS+URPR": "2T3R", "3SPU+UPR": "2T2R", "3SPU+RPRR": "2T2R",
    "2UPR+SPR": "1T2R", "3UPS+UP/passive": "1T2R", "3UPS+S/passive": "3R",
    "6SPS": "3T3R",
}


def test_every_catalog_pm_has_its_literature_motion_type():
    names = pm_names()
    assert set(names) <= set(LITERATURE), "a catalog PM without its literature motion type"
    for name in names:
        fm = finite_motion(load_pm(name))
        assert fm.label == LITERATURE[name], name


def _solve(model, k=6, seed=1):
    rng = np.random.default_rng(seed)
    L = float(model.normalisation.length)
    pose = {p: model.home_pose[p] + (np.radians(4.0) if p in ("alpha", "beta", "gamma")
                                     else 0.04 * L) * rng.uniform(-1, 1, k)
            for p in model.independent}
    return screwkit.solve(model, pose)


def test_invariants_against_the_solutions_read_independently():
    # 3T: the rotation never changes; 3R: o - C = R R0^T (o0 - C) with the catalog's centre
    tri = load_pm("3UPU")
    sol = _solve(tri)
    assert float(np.max(np.abs(sol.rotation - np.eye(3)))) <= 1e-9
    fm = finite_motion(tri)
    assert "fixed orientation" in fm.invariants and fm.parasitic == ()
    sph = load_pm("3UPU/spherical")
    fm = finite_motion(sph)
    C = np.asarray(sph.centre, float)
    np.testing.assert_allclose(fm.centre, C, atol=1e-6 * float(sph.normalisation.length))
    sol = _solve(sph)
    R0, o0 = sol.rotation[0], sol.position[0]
    for R, o in zip(sol.rotation, sol.position):
        assert np.linalg.norm((o - C) - R @ R0.T @ (o0 - C)) <= 1e-8 * 60
    # Schoenflies: every rotation about the base normal
    sch = load_pm("4UPU")
    sol = _solve(sch)
    assert float(np.max(np.abs(sol.rotation[:, :, 2] - [0, 0, 1]))) <= 1e-9
    fm = finite_motion(sch)
    np.testing.assert_allclose(np.abs(fm.axis), [0, 0, 1], atol=1e-9)


def test_the_3rps_parasitic_motions_are_its_varying_dependent_parameters():
    rps = load_pm("3RPS")
    fm = finite_motion(rps)
    sol = _solve(rps)
    varies = {p for p in rps.dependent
              if np.ptp(np.asarray(sol.params[p], float)) > 1e-6}
    assert varies == {"Xo", "Yo", "gamma"} == set(fm.parasitic)
    assert fm.text.startswith("1T2R: independent alpha, beta, Zo; parasitic motion")


def test_mobility_reports_the_computed_type_and_the_instantaneous_one_apart():
    rps = screwkit.load_pm("3RPS")
    a = screwkit.analyze(rps, {"alpha": 0.1, "beta": -0.05, "Zo": 62.0})
    m = a.mobility
    assert m.motion_type == "1T2R" and "parasitic motion" in m.finite
    assert m.instantaneous_type != m.motion_type        # tilted: screws of finite pitch
    assert mobility(a.solution).motion_type == "1T2R"   # the registered computed type


DECLARED = """
pms:
  wrong:
    string: 3RPS
    dimensions: {R: 60, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [RPS, RPS, RPS]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: R}
    pose: {alpha: 0, beta: 0, Zo: R}
    dof: 3
    motion: MOTION
"""


def test_a_declared_motion_that_is_not_the_computed_one_is_an_error(tmp_path, capsys):
    path = tmp_path / "wrong.yaml"
    path.write_text(DECLARED.replace("MOTION", "3T"))
    with pytest.raises(CatalogError, match="declares motion 3T.*computed from home is 1T2R"):
        screwkit.load_pm(str(path))
    path.write_text(DECLARED.replace("MOTION", "2R1T"))     # the literature's order reads
    assert screwkit.load_pm(str(path)).motion == "2R1T"
    from screwkit.cli import main
    assert main(["analyze", str(path), "--force=0,0,-1"]) == 0     # (a stated workload)
    out = capsys.readouterr().out
    assert "1T2R" in out and "parasitic motion Xo, Yo, gamma" in out


def test_freedoms_where_an_angular_part_is_just_above_the_rank_tolerance():
    """A 3RPUR pose whose twists' angular parts have a third singular value of 1.05e-8, just
    above the rank tolerance (1e-8): the principal screws' metric w w^T then has an
    eigenvalue of 1e-16, which rounding made negative (NaN, then numpy's eigh failed).  The
    freedoms are finite, as many as the DOF, and every one is reciprocal to the PM's
    constraint wrenches (f.v + m.w = 0, the solver's wrenches, not the classification's)."""
    import warnings

    from screwkit.engine import analyze_pm
    model = load_pm("3RPUR")
    pose = {"alpha": 0.009080764225058758, "beta": -0.016194688578630757,
            "Zo": 60.22932488249735}
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        m = analyze_pm(model, pose).mobility
        freedoms = m.freedoms
    w = np.linalg.svd(np.asarray(m.twists)[:, 3:], compute_uv=False)
    assert 1e-8 < w[-1] < 2e-8                           # the case this test is about
    assert m.dof == model.stated_dof == len(freedoms)
    W = np.asarray(m.wrenches)
    for f in freedoms:
        t = np.asarray(f.twist, float)
        assert np.isfinite(t).all()
        u = t / np.linalg.norm(t)
        recip = W[:, :3] @ u[:3] + W[:, 3:] @ u[3:]
        assert np.abs(recip).max() <= 1e-6 * np.abs(W).max()


@pytest.mark.parametrize("h", [20.0, -7.5])
def test_a_screw_motion_is_labelled_helical_as_the_instantaneous_type_labels_it(h):
    """Three UPS legs and a passive column P(x), P(y), H(z, pitch h): the platform's height
    follows its turn, Zo = h gamma (by hand: an H joint of pitch h about z), so its finite
    motion is two translations and a screw of pitch h about z, ``2T1H(p=h)``, the label the
    twist space at home has too (it was ``2T1R`` with ``Zo`` parasitic beside the
    instantaneous ``2T1H``); a declared ``2T1H`` loads."""
    col = screwkit.leg_from_joints([("P", [1, 0, 0], [0, 0, 0]), ("P", [0, 1, 0], [0, 0, 0]),
                                    ("H", [0, 0, 1], [0, 0, 500.0], h)], [0, 0, 0],
                                   [0, 0, 500.0])
    b = screwkit.PMBuilder("hel", units={"length": "mm", "force": "N"})
    for t in np.radians([0, 120, 240]):
        u = np.array([np.cos(t), np.sin(t), 0.0])
        b.add_leg("UPS", base=300 * u, platform=100 * u + [0, 0, 500])
    b.add_leg(col, passive=True)
    b.set_pose(["Xo", "Yo", "gamma"], home={"Xo": 0, "Yo": 0, "gamma": 0}, order="XYZ",
               motion="2T1H")
    pm = b.build()
    fm = finite_motion(pm)
    assert (fm.translations, fm.rotations) == (2, 1)
    assert fm.pitch == pytest.approx(h, rel=1e-9)
    assert fm.label == f"2T1H(p={h:.4g})"
    assert fm.parasitic == ("Zo",)
    mob = screwkit.analyze(pm, {"Xo": 5.0, "Yo": -3.0, "gamma": 0.2},
                           force=[0, 0, -100]).mobility
    assert mob.motion_type == fm.label
    home = {k: pm.home_pose[k] for k in pm.independent}
    assert mobility(screwkit.solve(pm, home)).instantaneous_type == fm.label
