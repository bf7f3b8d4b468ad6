"""Mobility of assembled PMs: DOF, motion type, redundancy, common constraints, Grubler."""

import numpy as np
import pytest

import screwkit
from screwkit.legs import Joint, Leg, parse_leg
from screwkit.pm import default_catalog, linkage_graph, load_pm, mobility, mobility_of_legs
from screwkit.screws import reciprocal_system

PMS = sorted(default_catalog().pms)


def test_the_paper_lists_are_all_there():
    paper = ["3SPR", "3RPS", "3RRPRR", "3UPU", "2UPU+SPR", "3UPRR", "3RPRU", "3RSR", "3RPUR",
             "2UPS+2SPR", "2UPS+2UPU", "4UPU", "3SPU+UPR", "3SPU+SP", "3SPU+PRRR", "3SPU+RPRR",
             "4SPS+SPR", "4SPS+UPU", "4SPS+URPR", "2SPS+2SPR"]
    assert set(paper) <= set(PMS)
    for n in paper:
        want = 3 if n in paper[:9] else 4 if n in paper[9:16] or n == "2SPS+2SPR" else 5
        assert load_pm(n).stated_dof == want, n


@pytest.mark.parametrize("name", PMS)
def test_dof_is_the_stated_one_at_default_and_random_poses(name):
    pm = load_pm(name)
    rng = np.random.default_rng(11)
    sols = [screwkit.solve(pm, {p: pm.default_pose[p] for p in pm.independent})]
    for _ in range(3):
        ind = {p: pm.default_pose[p] + (rng.uniform(-0.1, 0.1) if p in ("alpha", "beta", "gamma")
                                        else rng.uniform(-5, 5)) for p in pm.independent}
        sols.append(screwkit.solve(pm, ind, guess=sols[0]))
    for s in sols:
        m = mobility(s)
        assert m.dof == pm.stated_dof, (name, s.params)
        assert m.twists.shape == (m.dof, 6)
        # every platform twist is reciprocal to every leg's constraint wrenches
        for lg in s.legs:
            W = reciprocal_system(lg.twists, lg.points).wrenches
            n = pm.normalisation
            assert np.allclose(n.wrenches(W) @ n.twists(m.twists).T, 0, atol=1e-8)
        if pm.motion and not s.notes:   # (3RPUR's legs lose their structure off its home)
            assert m.motion_type == pm.motion
        assert m.dof == m.gruebler + m.redundant - m.idle     # modified Kutzbach criterion


def test_grubler_counts_by_hand():
    # 3RRPRR: 3 legs x 5 R/P joints; links = base + platform + 3 x 4 = 14; joints = 15
    s = screwkit.solve(load_pm("3RRPRR"), {"alpha": 0.05, "beta": -0.03, "Zo": 80})
    m = mobility(s)
    assert (m.n_links, m.n_joints, m.loops) == (14, 15, 2)
    assert m.gruebler == 6 * (14 - 15 - 1) + 15 == 3
    assert (m.dof, m.motion_type, m.n_constraints, m.redundant, m.idle) == (3, "1T2R", 3, 0, 0)
    # 2SPS+2SPR: SPS = 3 + 1 + 3 = 7 joints, SPR = 3 + 1 + 1 = 5; links 2 + 2 x 6 + 2 x 4 = 22
    s = screwkit.solve(load_pm("2SPS+2SPR"), {"alpha": 0.07, "beta": 0.05, "gamma": 0.03, "Zo": 80})
    m = mobility(s)
    assert (m.n_links, m.n_joints, m.loops) == (22, 24, 3)
    assert m.gruebler == 6 * (22 - 24 - 1) + 24 == 6
    assert m.idle == 2                   # each SPS spins about its own line
    assert (m.dof, m.motion_type, m.constraint_rank) == (4, "1T3R", 2)
    # with compound joints: 10 links, 12 joints, sum f = 2 x 7 + 2 x 5 -> the same count
    assert 6 * (10 - 12 - 1) + 24 == m.gruebler
    g = linkage_graph(s.legs)
    assert g.degree("base") == 4 and g.degree("platform") == 4


def test_known_motion_types_and_redundancy():
    # translational 3UPU: three couples -> pure translations
    assert mobility(screwkit.solve(load_pm("3UPU"), {"Xo": 3, "Yo": 2, "Zo": 58})).motion_type == "3T"
    # Schoenflies 4UPU: four couples all normal to the base normal span a plane: 2 redundant
    m = mobility(screwkit.solve(load_pm("4UPU"), {"Xo": 3, "Yo": 2, "Zo": 78, "gamma": 0.1}))
    assert (m.n_constraints, m.constraint_rank, m.redundant, m.motion_type) == (4, 2, 2, "3T1R")
    assert np.allclose(m.wrenches[:, :3], 0, atol=1e-9)          # couples only ...
    assert np.allclose(m.wrenches[:, 5], 0, atol=1e-9)           # ... normal to Z
    w = m.twists[:, 3:]
    assert np.allclose(np.cross(w, [0, 0, 1]), 0, atol=1e-9)     # the one rotation is about Z


def _planar_rrr(points):
    ls = parse_leg("RRR")
    return Leg(ls, tuple(Joint(s, [0, 0, 1], p) for s, p in zip(ls.equivalent, points)),
               points[0], points[-1])


def test_common_constraints_of_a_planar_3rrr():
    # three planar RRR legs with vertical axes: each exerts the same 3-system (force along Z,
    # couples about X and Y), so 3 are common, 9 - 3 = 6 redundant, and the platform moves in
    # the plane (2T1R)
    legs = []
    for k in range(3):
        c, s = np.cos(2 * np.pi * k / 3), np.sin(2 * np.pi * k / 3)
        legs.append(_planar_rrr([[100 * c, 100 * s, 0], [60 * c - 30 * s, 60 * s + 30 * c, 0],
                                 [30 * c, 30 * s, 0]]))
    m = mobility_of_legs(legs)
    assert (m.dof, m.motion_type, m.common, m.n_constraints, m.redundant) == (3, "2T1R", 3, 9, 6)
    assert m.gruebler == 6 * (2 + 6 - 9 - 1) + 9 == -3


def test_mobility_invariance_under_frame_and_units():
    pm = load_pm("3SPU+RPRR")
    ind = {"Xo": 4, "Zo": 82, "alpha": 0.06, "beta": -0.04}
    m1 = mobility(screwkit.solve(pm, ind))
    R = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]])
    m2 = mobility(screwkit.solve(pm.moved(R, [1e3, -2e3, 5e2]), ind))
    big = load_pm("3SPU+RPRR", {"L": 1e5, "l": 5e4})
    m3 = mobility(screwkit.solve(big, {**ind, "Xo": 4e3, "Zo": 8.2e4}))
    for m in (m2, m3):
        assert (m.dof, m.motion_type, m.constraint_rank, m.common) == \
            (m1.dof, m1.motion_type, m1.constraint_rank, m1.common)
