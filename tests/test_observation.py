"""The three observation rules (section 2.2 of the paper) and the decomposition.

Hand-built legs with known geometry; the expected lines/couples are derived in
the comments from the rules, and cross-checked by reciprocity (virtual power).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import screwkit
from screwkit.legs import (JOINT_DOF, Joint, Leg, candidate_points, decompose, explain_couple,
                           explain_force, generic_leg, parse_leg)
from screwkit.screws import couple_wrench, force_wrench, reciprocal_system, same_span

SETTINGS = settings(max_examples=50, deadline=None)
X, Y, Z = np.eye(3)


def make_leg(string, axes, A=(0, 0, 0), a=(0, 0, 100)):
    """A Leg from (direction, point[, pitch]) per equivalent joint."""
    ls = parse_leg(string)
    joints = tuple(Joint(spec, *ax) for spec, ax in zip(ls.equivalent, axes))
    return Leg(ls, joints, np.array(A, float), np.array(a, float))


def span_ok(res, hand_rows):
    return same_span(np.array(hand_rows), res.system.wrenches, res.system.normalisation)


# ---------------------------------------------------------------- hand-built legs

def test_two_parallel_r_axes():
    # R axes along Z through (0,0,0) and (10,0,0).  Rule 3: couples perpendicular to Z
    # (about X and Y).  Rule 2: forces parallel to Z (any), or meeting both axes, e.g.
    # the X axis itself.  6 - 2 = 4 = 2 couples + 2 forces.
    leg = make_leg("RR", [(Z, (0, 0, 0)), (Z, (10, 0, 0))], A=(0, 0, 0), a=(10, 0, 0))
    res = leg.analyze()
    assert (res.connectivity, res.n_couples, res.n_forces, res.n_screws) == (2, 2, 2, 0)
    assert span_ok(res, [couple_wrench(X).vector, couple_wrench(Y).vector,
                         force_wrench(Z, (0, 0, 0)).vector, force_wrench(X, (0, 0, 0)).vector])
    for c in res.constraints:
        assert {n.rule for n in c.rules} == ({3} if c.kind == "couple" else {2})
    assert res.agrees()


def test_finite_pitch_wrench_of_a_helical_chain():
    # P_x, P_y, R_x and R_y through O, H along Z through O of pitch h:
    # f.x = f.y = 0, m.x = m.y = 0, and f_z h + m_z = 0  ->  W = [0,0,1; 0,0,-h], pitch -h.
    h = 3.0
    leg = make_leg("PPRRH", [(X, (0, 0, 0)), (Y, (0, 0, 0)), (X, (0, 0, 0)), (Y, (0, 0, 0)),
                             (Z, (0, 0, 0), h)], A=(0, 0, 0), a=(0, 0, 10))
    res = leg.analyze()
    assert res.connectivity == 5 and (res.n_forces, res.n_couples, res.n_screws) == (0, 0, 1)
    c = res.constraints[0]
    assert c.kind == "screw" and c.pitch == pytest.approx(-h)
    assert abs(c.direction @ Z) == pytest.approx(1.0)
    np.testing.assert_allclose(np.cross(c.direction, c.point), 0, atol=1e-9)   # axis through O
    assert span_ok(res, [[0, 0, 1, 0, 0, -h]])
    assert all(n.rule is None for n in c.rules)


def test_helical_joint_notes_have_no_rule_number():
    # R along Z through O, H along Z through O (pitch 2): rotation and a screw about the
    # same axis span rotation about Z and translation along Z.  A force along X through
    # O meets the R axis and is perpendicular to the translation: no rule covers the H,
    # the note says so and checks f.v + m.w = 0.
    leg = make_leg("RH", [(Z, (0, 0, 0)), (Z, (0, 0, 0), 2.0)])
    notes = explain_force(X, (0, 0, 0), leg)
    assert [(n.joint, n.rule, n.holds) for n in notes] == [("R1", 2, True), ("H2", None, True)]
    bad = explain_force(Z, (0, 0, 0), leg)            # along the screw axis: f.(h z) = 2
    assert [(n.joint, n.holds) for n in bad] == [("R1", True), ("H2", False)]


def test_explain_force_rule_by_rule():
    # S at A = O, P along Z, R along Y through a = (0, 0, 100)
    leg = make_leg("SPR", [(X, (0, 0, 0)), (Y, (0, 0, 0)), (Z, (0, 0, 0)), (Z, (0, 0, 50)),
                           (Y, (0, 0, 100))])
    good = explain_force(Y, (0, 0, 0), leg)           # through the S centre, parallel to R3
    assert [(n.joint, n.rule, n.holds) for n in good] == [("S1", 2, True), ("P2", 1, True),
                                                          ("R3", 2, True)]
    assert "centre of S1" in good[0].text and "parallel to R3" in good[2].text
    meets = explain_force(X, (0, 0, 0), leg)          # along X through O: meets R3? no
    assert [(n.joint, n.holds) for n in meets] == [("S1", True), ("P2", True), ("R3", False)]
    assert "neither meets nor is parallel" in meets[2].text and "[FAILS]" in str(meets[2])
    off = explain_force(Y, (5, 0, 0), leg)            # misses the S centre by 5
    assert off[0].joint == "S1" and not off[0].holds and "misses the centre" in off[0].text
    tilted = explain_force(Z, (0, 0, 0), leg)         # along P: rule 1 fails
    assert [(n.joint, n.rule, n.holds) for n in tilted][1] == ("P2", 1, False)
    through_a = explain_force(X, (0, 0, 100), leg)    # meets R3 at a
    assert through_a[2].holds and "meets R3 at a" in through_a[2].text


def test_explain_couple_rule_3():
    leg = make_leg("PRR", [(Z, (0, 0, 0)), (Z, (0, 0, 0)), (Z, (10, 0, 50))])
    notes = explain_couple(X, leg)
    assert [(n.joint, n.rule, n.holds) for n in notes] == [("P1", None, True), ("R2", 3, True),
                                                           ("R3", 3, True)]
    notes = explain_couple([1, 0, 1], leg)
    assert [n.holds for n in notes] == [True, False, False] and "(rule 3)" in str(notes[1])


def test_candidate_points_name_meeting_points():
    # R1 along X through O and R2 along Z through (7, 0, 50) meet at (7, 0, 0)
    leg = make_leg("RR", [(X, (0, 0, 0)), (Z, (7, 0, 50))], a=(7, 0, 50))
    pts = candidate_points(leg, 1e-9)
    np.testing.assert_allclose(pts["R1^R2"], [7, 0, 0], atol=1e-12)
    assert {"A", "a", "R1", "R2"} <= set(pts)


def test_decompose_prefers_couples_then_named_forces():
    # an S at O and a P along Z: S gives all rotations about O, P the translation along Z.
    # 6 - 4 = 2: forces through O perpendicular to Z (rules 1, 2); no couple (rule 3
    # would need a direction perpendicular to three independent axes).
    leg = make_leg("SP", [(X, (0, 0, 0)), (Y, (0, 0, 0)), (Z, (0, 0, 0)), (Z, (0, 0, 50))])
    sysm = reciprocal_system(leg.twists, leg.points)
    out = decompose(sysm.wrenches, leg, sysm.normalisation)
    assert [c.kind for c in out] == ["force", "force"]
    assert all(c.point_name == "S1" for c in out)
    for c in out:
        assert abs(c.direction @ Z) < 1e-9 and np.linalg.norm(c.point) < 1e-9
    assert decompose(np.zeros((0, 6)), leg, sysm.normalisation) == ()


# ---------------------------------------------------------------- catalog legs: rule numbers

@pytest.mark.parametrize("name, want", [
    ("RRPRR", {"R1": 2, "R2": 2, "P3": 1, "R4": 2, "R5": 2}),
    ("SPR", {"S1": 2, "P2": 1, "R3": 2}),
    ("SP", {"S1": 2, "P2": 1}),
    ("UPU/force", {"U1a": 2, "U1b": 2, "P2": 1, "U3a": 2, "U3b": 2}),
])
def test_force_notes_name_rules_1_and_2(name, want):
    res = screwkit.leg(name).analyze()
    for c in res.constraints:
        assert c.kind == "force"
        assert {n.joint: n.rule for n in c.rules} == want
        assert all(n.holds for n in c.rules)


@pytest.mark.parametrize("name", ["PRRR", "UPU/couple"])
def test_couple_notes_name_rule_3(name):
    res = screwkit.leg(name).analyze()
    for c in res.constraints:
        assert c.kind == "couple"
        for n in c.rules:
            assert n.rule == (None if n.joint.startswith("P") else 3) and n.holds


# ---------------------------------------------------------------- properties

@st.composite
def leg_strings(draw):
    budget = draw(st.integers(1, 6))
    s = ""
    while True:
        room = [c for c in "RPHUSC" if JOINT_DOF[c] <= budget - sum(JOINT_DOF[x] for x in s)]
        if not room or (s and draw(st.booleans()) and draw(st.booleans())):
            break
        s += draw(st.sampled_from(room))
    return s if any(c in "PCRUS" for c in s) else "_" + s


@SETTINGS
@given(leg_strings(), st.integers(0, 10_000))
def test_rules_and_solver_agree_on_generic_legs(s, seed):
    """Every decomposed member satisfies its rule notes geometrically, the members span
    the solver's system, and each member's kind matches its pitch."""
    res = generic_leg(s, seed=seed).analyze()
    assert res.agrees()
    assert res.n_forces + res.n_couples + res.n_screws == res.system.dimension
    for c in res.constraints:
        f, m = c.wrench.force, c.wrench.moment
        if c.kind == "couple":
            assert np.linalg.norm(f) == 0 and np.linalg.norm(m) == pytest.approx(1)
            assert all(n.rule in (3, None) for n in c.rules)
        elif c.kind == "force":
            assert np.linalg.norm(f) == pytest.approx(1) and abs(f @ m) < 1e-9 * res.leg.length
            assert c.line.distance_to_point(c.point) < 1e-9 * res.leg.length
            assert all(n.rule in (1, 2, None) for n in c.rules)
        else:
            assert c.pitch == pytest.approx(float(f @ m) / float(f @ f))
