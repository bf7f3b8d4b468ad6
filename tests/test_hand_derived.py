"""Constraint and actuation wrenches of the paper's legs, derived by hand.

Default placement (screwkit.legs.default_placement, scale 100):
A = (100, 0, 0) on the base X axis, a = (50, 0, 80), O = origin, o = (0, 0, 80),
base and platform frames = identity.  Leg direction d = (a - A)/|a - A| =
(-50, 0, 80)/sqrt(8900).  The expected lines below come from this geometry and
the catalog's placement rules (legs_catalog.yaml), worked out in the comments;
the solver's output is only compared with them.
"""

import numpy as np
import pytest

import screwkit
from screwkit.legs import Joint, Leg, Placement, generic_leg, parse_leg
from screwkit.screws import (couple_wrench, force_wrench, prismatic_twist, revolute_twist,
                             same_span, span_contains)

X, Y, Z = np.eye(3)
A0 = np.array([100.0, 0.0, 0.0])
a0 = np.array([50.0, 0.0, 80.0])
D0 = (a0 - A0) / np.linalg.norm(a0 - A0)
# a second placement, in the base's YZ plane: A = (0, 120, 0), a = (0, 40, 90)
PL2 = Placement(A=[0, 120, 0], a=[0, 40, 90])


def spans(res, rows):
    return same_span(np.array(rows, float), res.system.wrenches, res.system.normalisation)


def on_line(c, point, direction, L=100.0):
    """The force member ``c`` lies on the line (point, direction)."""
    assert c.kind == "force"
    assert np.linalg.norm(np.cross(c.direction, direction)) < 1e-9
    assert c.line.distance_to_point(point) < 1e-9 * L


def test_default_placement_is_what_the_derivations_assume():
    leg = screwkit.leg("RRPRR")
    np.testing.assert_allclose(leg.A, A0)
    np.testing.assert_allclose(leg.a, a0)


# ---------------------------------------------------------------- RRPRR

def test_rrprr_one_force_through_foot_of_platform_normal():
    # R1 along A->O: the X axis (y = z = 0).  R5 along the platform normal Z through
    # a = (50, 0, 80): the line x = 50, y = 0.  They meet at Q = (50, 0, 0), the foot
    # of the platform normal through a on the line A-O.  R2 = R1 x leg ~ (-1,0,0) x
    # (-50,0,80) = (0, 80, 0): along Y; R4 parallel to R2.  A force along Y through Q
    # meets R1 and R5 (rule 2), is parallel to R2 and R4 (rule 2) and perpendicular to
    # the leg, i.e. to P3 (rule 1).  5 independent joints -> exactly one wrench.
    res = screwkit.leg("RRPRR").analyze()
    assert res.connectivity == 5 and res.dependent_joints == ()
    assert (res.n_forces, res.n_couples, res.n_screws) == (1, 0, 0)
    Q = np.array([50.0, 0.0, 0.0])
    on_line(res.constraints[0], Q, Y)
    assert spans(res, [force_wrench(Y, Q).vector])
    rules = {n.joint: (n.rule, n.holds) for n in res.constraints[0].rules}
    assert rules == {"R1": (2, True), "R2": (2, True), "P3": (1, True), "R4": (2, True),
                     "R5": (2, True)}
    assert "meets R1" in res.constraints[0].rules[0].text and "parallel to R2" in \
        res.constraints[0].rules[1].text


def test_rrprr_at_another_placement():
    # A = (0,120,0), a = (0,40,90): R1 along A->O = -Y (the Y axis), R5 along Z through a
    # (x = 0, y = 40): Q = (0, 40, 0).  R2 = (-Y) x (0,-80,90) = (-90, 0, 0): along X.
    res = screwkit.leg("RRPRR", PL2).analyze()
    assert res.n_forces == 1 and res.n_couples == 0
    on_line(res.constraints[0], [0, 40, 0], X)


# ---------------------------------------------------------------- SPR, SP, SPS

def test_spr_force_through_s_centre_parallel_to_r():
    # R3 = platform tangent at a: z x (a - o) = z x (50, 0, 0) = (0, 50, 0): along Y.
    # A force through the S centre A (rule 2 for the three S axes) parallel to R3
    # (rule 2), perpendicular to the leg (rule 1).
    res = screwkit.leg("SPR").analyze()
    assert res.connectivity == 5 and (res.n_forces, res.n_couples) == (1, 0)
    on_line(res.constraints[0], A0, Y)
    assert res.constraints[0].point_name == "S1"
    assert spans(res, [force_wrench(Y, A0).vector])
    # the parallel line through a is NOT reciprocal to the S joint (see NOTES.md on eq. 19)
    assert not span_contains(res.system.wrenches, force_wrench(Y, a0).vector, res.system.normalisation)
    # second placement: R3 = z x (0, 40, 0) = (-40, 0, 0): along X through A = (0, 120, 0)
    res2 = screwkit.leg("SPR", PL2).analyze()
    on_line(res2.constraints[0], [0, 120, 0], X)


def test_sp_two_forces_through_s_centre_perpendicular_to_p():
    # S at A: forces must pass through A (rule 2); P along the leg: forces perpendicular
    # to d (rule 1).  Two such directions: Y, and Y x (-50, 0, 80) = (80, 0, 50).
    res = screwkit.leg("SP").analyze()
    assert res.connectivity == 4 and (res.n_forces, res.n_couples) == (2, 0)
    assert spans(res, [force_wrench(Y, A0).vector, force_wrench([80, 0, 50], A0).vector])
    for c in res.constraints:
        assert abs(c.direction @ D0) < 1e-9 and c.line.distance_to_point(A0) < 1e-7


def test_sps_no_constraint_and_one_dependent_joint():
    # 7 joint axes but at most 6 freedoms: the rotation about the leg line (the "idle"
    # rotation) is in the span of S1 and of S3.  Greedy order: S1a S1b S1c give all
    # rotations about A, P2 adds d, and S3a, S3b (about X, Y at a) add translations
    # (a - A) x X = (0, 80, 0) and (a - A) x Y = (-80, 0, -50), independent of d: rank 6
    # after S3b, so S3c is the dependent joint.
    res = screwkit.leg("SPS").analyze()
    assert res.connectivity == 6 and res.system.dimension == 0 and res.constraints == ()
    assert res.dependent_joints == ("S3c",)
    idle = revolute_twist(D0, A0).vector
    leg = res.leg
    s1 = np.array([j.twist.vector for j in leg.joints if j.name.startswith("S1")])
    s3 = np.array([j.twist.vector for j in leg.joints if j.name.startswith("S3")])
    norm = res.system.normalisation
    assert span_contains(s1, idle, norm, kind="twist") and span_contains(s3, idle, norm, kind="twist")


# ---------------------------------------------------------------- UPU

def test_upu_force_variant():
    # C = half-way from O to o = (0, 0, 40).  U1a along A->C = (-100, 0, 40), U3b along
    # a->C = (-50, 0, -40): both pass through C.  U1b = U1a x leg ~ (-100,0,40) x
    # (-50,0,80) = (0, 6000, 0): along Y; U3a parallel to U1b.  Force along Y through C.
    res = screwkit.leg("UPU/force").analyze()
    assert res.connectivity == 5 and (res.n_forces, res.n_couples) == (1, 0)
    C = np.array([0.0, 0.0, 40.0])
    on_line(res.constraints[0], C, Y)
    assert spans(res, [force_wrench(Y, C).vector])
    assert {n.joint: n.rule for n in res.constraints[0].rules} == \
        {"U1a": 2, "U1b": 2, "P2": 1, "U3a": 2, "U3b": 2}


def test_upu_couple_variant():
    # U1a = base tangent z x (A - O) = Y, U3b = platform tangent = Y; U1b = Y x leg ~
    # (0,1,0) x (-50,0,80) = (80, 0, 50), U3a parallel to it.  A couple perpendicular to
    # both Y and (80, 0, 50) (rule 3): Y x (80,0,50) = (50, 0, -80), i.e. along the leg.
    res = screwkit.leg("UPU/couple").analyze()
    assert res.connectivity == 5 and (res.n_forces, res.n_couples) == (0, 1)
    c = res.constraints[0]
    assert abs(abs(c.direction @ D0) - 1) < 1e-12
    assert spans(res, [couple_wrench(D0).vector])
    assert all(n.rule == 3 for n in c.rules if not n.joint.startswith("P"))


# ---------------------------------------------------------------- PRRR

def test_prrr_two_couples_perpendicular_to_parallel_axes():
    # P along Z, R2 R3 R4 along Z: rule 3 gives couples about X and Y; no force can be
    # perpendicular to Z (rule 1) and parallel to (or meet) three non-coplanar parallel
    # axes at the same time.  4 joints, rank 4 -> 2 wrenches, both couples.
    res = screwkit.leg("PRRR").analyze()
    assert res.connectivity == 4 and (res.n_forces, res.n_couples) == (0, 2)
    assert spans(res, [couple_wrench(X).vector, couple_wrench(Y).vector])
    for c in res.constraints:
        assert abs(c.direction @ Z) < 1e-12


# ---------------------------------------------------------------- dependent joints

def test_generic_pppp_is_rank_three():
    # four translations in R^3: any three generic directions span R^3, so the fourth is
    # dependent; the system is every couple; the actuated P1 is spanned by the passive
    # P2..P4, so no wrench can actuate it.
    res = generic_leg("PPPP").analyze()
    assert res.connectivity == 3 and res.dependent_joints == ("P4",)
    assert (res.n_forces, res.n_couples) == (0, 3)
    assert spans(res, [couple_wrench(v).vector for v in (X, Y, Z)])
    assert res.actuation is None


def test_explicit_dependent_prismatic_joints():
    # directions X, Y, X - Y, Z: the third is X - Y, spanned by the first two.
    ls = parse_leg("PPPP")
    dirs = [X, Y, X - Y, Z]
    leg = Leg(ls, tuple(Joint(s, d, (0, 0, 10.0 * i)) for i, (s, d) in enumerate(zip(ls.equivalent, dirs))),
              np.zeros(3), np.array([0, 0, 30.0]))
    res = leg.analyze()
    assert res.connectivity == 3 and res.dependent_joints == ("P3",)
    assert res.n_couples == 3 and res.actuation is None


# ---------------------------------------------------------------- actuation wrenches

@pytest.mark.parametrize("name", ["SPS", "SPR", "RRPRR", "SP", "UPU/force", "UPU/couple"])
def test_actuation_is_unit_force_along_the_leg(name):
    # A linear actuator between A and a transmits a force along A->a: the line A-a meets
    # (or is parallel to) every passive R axis at A or a, so it does no work on them; its
    # product with the P twist [d; 0] is d.d = 1.
    leg = screwkit.leg(name)
    act = leg.analyze().actuation
    assert act is not None and act.joint == leg.actuated_joint.name
    assert act.member.kind == "force"
    np.testing.assert_allclose(act.wrench, force_wrench(D0, A0).vector, atol=1e-9 * 100)
    assert act.wrench @ prismatic_twist(D0).vector == pytest.approx(1.0)
    passive = np.array([j.twist.vector for j in leg.joints if not j.actuated])
    np.testing.assert_allclose(passive @ act.wrench, 0.0, atol=1e-9 * 100)
    assert all(n.holds for n in act.member.rules)


def test_prrr_actuation_along_the_vertical_slide():
    # P1 along Z, R axes along Z: a force along Z is parallel to every R (rule 2) and
    # does work 1 on the P; no couple can (a couple does no work on a P).
    act = screwkit.leg("PRRR").analyze().actuation
    assert act.member.kind == "force" and abs(act.member.direction @ Z) == pytest.approx(1)
    assert act.wrench @ prismatic_twist(Z).vector == pytest.approx(1.0)
    assert {n.rule for n in act.member.rules} == {2}


def test_actuation_moves_with_the_leg():
    # under x -> R x + p the actuation force of SPR stays the line A'-a'
    from scipy.spatial.transform import Rotation
    R = Rotation.from_euler("XYX", [0.3, -0.7, 1.1]).as_matrix()
    p = np.array([10.0, -20.0, 5.0])
    leg = screwkit.leg("SPR").moved(R, p)
    act = leg.analyze().actuation
    np.testing.assert_allclose(act.wrench, force_wrench(R @ D0, R @ A0 + p).vector, atol=1e-8 * 100)
