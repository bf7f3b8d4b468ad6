"""The Exechon-like 2-UPR+SPR found by the type synthesis of 1T2R PMs (issue 19, item 4).

Its two UPR legs must lie in one plane through the base normal (Bi and Jin 2011; Zoppi,
Zlatanov and Molfino 2010): the search places such pair compositions on a geometry whose
legs 1 and 2 stand at the ends of a base diameter.  Checked against facts derived by hand,
not against the search: a UPR leg whose U's first axis is radial and whose R is normal to
the leg's plane exerts a force through the U centre normal to that plane and a couple along
the base normal, so two of them on a diameter (the base Y axis) exert rank 2 together (a
force along X through O and a couple along Z) and an SPR at (-R, 0, 0) with its R along Y
adds a force along Y through its S centre: three wrenches, the complementary system of
1T2R.  Over a finite motion the plane of the two UPR legs turns about the base line through
their U centres, so that line and both platform R centres stay coplanar.
"""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.design import synthesize_motion
from screwkit.pm import Catalog, default_catalog
from screwkit.synthesis import LegKind, PAIR_GEOMETRIES, motion_pattern, pair_compositions


def _catalog(*names):
    cat = default_catalog()
    return Catalog({n: cat.legs[n] for n in names}, cat.table1, {}, "<test>")


@pytest.fixture(scope="module")
def exechon():
    res = synthesize_motion("1T2R", catalog=_catalog("UPR", "SPR"), generate=False,
                            passive=False)
    hit = [p for p in res.listed if p.name == "2-UPR+SPR"]
    assert hit, res.names()
    return hit[0]


def test_pair_compositions_need_a_redundant_pair_and_the_exact_rest():
    m = motion_pattern("1T2R")
    upr = LegKind("UPR", "UPR", "U_PR", 1, 1, 0, 4, 2)
    spr = LegKind("SPR", "SPR", "S_PR", 1, 0, 0, 5, 2)
    rps = LegKind("RPS", "RPS", "R_PS", 1, 0, 0, 5, 1)
    # by hand: two UPRs on a diameter exert rank 2 (not 4); one force completes 3
    out = pair_compositions(m, (upr, spr, rps), {"UPR": 2, "SPR": 2, "RPS": 2})
    assert {c.name for c in out} == {"2UPR+SPR@pair", "2UPR+RPS@pair"}
    assert all(c.pair and c.literature.startswith("2-UPR+") for c in out)
    # a pair of independent systems (rank 4) belongs on the standard triangle, not here
    assert not pair_compositions(m, (upr, spr), {"UPR": 4})
    assert not pair_compositions(motion_pattern("3T1R"), (upr, spr), {"UPR": 2})
    assert 3 in PAIR_GEOMETRIES


def test_the_exechon_is_listed_on_the_pair_geometry(exechon):
    assert exechon.variant == "2UPR+SPR@pair" and exechon.string == "2UPR+SPR"
    assert exechon.legs == ("UPR", "UPR", "SPR")
    assert "diameter" in exechon.geometry
    assert exechon.verdict.success and exechon.verdict.motion.startswith("1T2R")
    assert "parasitic" in exechon.verdict.motion       # 2R1T with parasitic motions


def test_the_written_exechon_exerts_the_hand_derived_system(exechon, tmp_path):
    path = tmp_path / "exechon.yaml"
    path.write_text(exechon.model_yaml())
    model = screwkit.load_pm(str(path))
    home = {k: model.home_pose[k] for k in model.independent}
    a = screwkit.analyze(model, home)
    R = 60.0                                            # the pair geometry's base radius
    hand = np.array([[1, 0, 0, 0, 0, 0],                # force along X through O
                     [0, 0, 0, 0, 0, 1],                # couple along Z
                     [0, 1, 0, 0, 0, -R]], float)       # force along Y through (-R, 0, 0)
    Jc = np.asarray(a.jacobian.J_c, float).reshape(-1, 6)
    assert np.linalg.matrix_rank(Jc, 1e-9 * np.abs(Jc).max()) == 3
    both = np.vstack([Jc / np.linalg.norm(Jc, axis=1, keepdims=True),
                      hand / np.linalg.norm(hand, axis=1, keepdims=True)])
    assert np.linalg.matrix_rank(both, 1e-9) == 3       # the same span


def test_the_upr_plane_turns_about_the_base_line_of_the_u_centres(exechon, tmp_path):
    path = tmp_path / "exechon.yaml"
    path.write_text(exechon.model_yaml())
    model = screwkit.load_pm(str(path))
    poses = {"alpha": np.radians([4.0, -6.0, 2.0]), "beta": np.radians([-3.0, 5.0, 7.0]),
             "Zo": np.array([55.0, 62.0, 66.0])}
    a = screwkit.analyze(model, poses, raise_on_singular=False)
    assert np.all(a.solution.success)
    for i in range(3):
        legs = a.solution.legs_at(i)
        A1, A2 = (np.asarray(lg.joints[0].point, float) for lg in legs[:2])
        a1, a2 = (np.asarray(lg.joints[-1].point, float) for lg in legs[:2])
        line = (A2 - A1) / np.linalg.norm(A2 - A1)
        normal = np.cross(line, a1 - A1)
        normal /= np.linalg.norm(normal)
        assert abs(normal @ (a2 - A1)) <= 1e-8 * R_SCALE     # a1, a2 and the base line coplanar
        assert abs(line @ [0.0, 1.0, 0.0]) == pytest.approx(1.0)


R_SCALE = 60.0
