"""Synthesis of leg arrangements from the observation rules, and the solver-side verifier.

Expected answers are derived by hand (comments give the derivation); synthesized
legs are checked by plain geometry (distances between lines, angles), independently
of the synthesizer's linear algebra.
"""

import numpy as np
import pytest

from screwkit.errors import InputError
from screwkit.legs import Joint, Leg, parse_leg
from screwkit.screws import Line, couple_wrench, force_wrench, transform_wrenches
from screwkit.synthesis import LAYOUTS, compositions, counting_rank, make_layout, synthesize, verify

L0 = 100.0  # the default placement's scale (leg length is about 94)


def _leg(string, joints, A=(100.0, 0, 0), a=(50.0, 0, 80.0)):
    """A hand-built leg: ``joints`` = [(direction, point)] in equivalent-chain order."""
    ls = parse_leg(string)
    js = tuple(Joint(s, d, p) for s, (d, p) in zip(ls.equivalent, joints))
    return Leg(ls, js, np.array(A, float), np.array(a, float))


# ----------------------------------------------------------------- hand-derived answers
def test_spr_force_only():
    # S: a couple would have to be perpendicular to three non-coplanar axes -> no couple.
    # Force: through the S centre, perpendicular to P, meeting R -> realizable.
    assert synthesize("SPR", (1, 0), seed=3).realizable
    s = synthesize("SPR", (0, 1), seed=3)
    assert not s.realizable and s.proof == "rule" and "S1" in s.reason


def test_spp_force_only():
    # SPP: the force passes through the S centre along P2 x P3 (perpendicular to both P);
    # S (3 rotations about the centre) + 2 translations = rank 5, independent.  No couple (S).
    s = synthesize("SPP", (1, 0), seed=5)
    assert s.realizable and not s.dependent
    assert not synthesize("SPP", (0, 1), seed=5).realizable


@pytest.mark.parametrize("string", ["PPPRR", "UPPP", "RRPPP", "CPC"])
def test_three_prismatic_parts_forbid_a_force(string):
    # Three P-type joints (P or the P of a C) perpendicular to one force lie in a plane:
    # dependent, so rank <= 4 < 5 -> no force; a couple only needs the R axes perpendicular
    # to t (at least two R-type axes here), P free -> realizable.
    s = synthesize(string, (1, 0), seed=1)
    assert not s.realizable and s.proof == "counting"
    assert synthesize(string, (0, 1), seed=1).realizable


def test_rrprr_both():
    # every R meets L, P perpendicular to L -> force; every R perpendicular to t -> couple
    assert synthesize("RRPRR", (1, 0), seed=2).realizable
    assert synthesize("RRPRR", (0, 1), seed=2).realizable


def test_ppppp_dependent_three_couples_only():
    # 5 P span at most 3 translations: rank 3, 3 constraints, 2 dependent joints always.
    # Any force must be perpendicular to P's spanning space -> impossible; 3 couples: yes,
    # with the passive P2..P5 in a plane so that the actuated P1 stays independent.
    assert counting_rank("PPPPP") == 3
    for comp in [(3, 0), (2, 1), (1, 2)]:
        assert not synthesize("PPPPP", comp, seed=0).realizable
    s = synthesize("PPPPP", (0, 3), seed=0)
    assert s.realizable and s.dependent
    passive = np.array([j.direction for j in s.leg.joints[1:]])
    assert np.linalg.matrix_rank(passive, tol=1e-9) == 2          # coplanar by construction
    assert abs(np.linalg.det(np.vstack([s.leg.joints[0].direction, passive[:2]]))) > 1e-6


def test_sp_two_forces_only():
    # S: no couple in the system at all; two forces through the centre perpendicular to P.
    assert synthesize("SP", (2, 0), seed=0).realizable
    assert not synthesize("SP", (1, 1), seed=0).realizable
    assert not synthesize("SP", (0, 2), seed=0).realizable


def test_rpu_no_pair_of_couples():
    # Two couples t1, t2: every R axis parallel to n = t1 x t2; the two crossed U axes
    # cannot both be -> 2C impossible.  2F: R and U through X, P along the normal of the
    # plane of the forces.  1F+1C: R and U axes perpendicular to t, meeting L.
    assert synthesize("RPU", (2, 0), seed=0).realizable
    assert synthesize("RPU", (1, 1), seed=0).realizable
    s = synthesize("RPU", (0, 2), seed=0)
    assert not s.realizable and "U3" in s.reason


def test_cc_force_and_coaxial_couple():
    # Two generic cylinders: constraint force and couple both along the common
    # perpendicular of the axes (coaxial layout).  Two forces or two couples would force
    # both C axes onto one direction (perpendicular to the forces and couples): dependent.
    s = synthesize("CC", (1, 1), seed=0)
    assert s.realizable and s.layout.name == "coaxial"
    assert not synthesize("CC", (2, 0), seed=0).realizable
    assert not synthesize("CC", (0, 2), seed=0).realizable


def test_planar_rrr_force_normal_to_two_couples():
    # three parallel R: force normal to the plane of motion and the two couples in it
    s = synthesize("RRR", (1, 2), seed=0)
    assert s.realizable and s.layout.name == "normal"
    assert not synthesize("RRR", (0, 3), seed=0).realizable   # R perpendicular to 3 couples


# ----------------------------------------------------------------- plain-geometry checks
def _check_force_rules(leg, point, direction, tol=1e-7):
    Lf = Line.through(point, direction)
    c = Lf.direction
    scale = leg.length
    for j in leg.joints:
        if j.kind == "P":
            assert abs(np.dot(j.direction, c)) < tol, j.name                  # rule 1
        else:
            par = np.linalg.norm(np.cross(j.direction, c)) < tol
            assert par or Lf.distance_to_line(j.line) < tol * scale, j.name    # rule 2


@pytest.mark.parametrize("string", ["RRPRR", "UPU", "SPR", "URC", "CCR", "PRRU", "US", "CS"])
def test_synthesized_force_legs_obey_rules_geometrically(string):
    for seed in range(3):
        s = synthesize(string, (1, 0), seed=seed)
        assert s.realizable
        (p, d), = s.layout.force_lines
        _check_force_rules(s.leg, p, d)
        for name, ctr in s.leg.centres().items():
            if name.startswith("S"):
                assert Line.through(p, d).distance_to_point(ctr) < 1e-7 * s.leg.length


@pytest.mark.parametrize("string", ["RRPRR", "UPU", "PPPU", "CPC", "RRRRR"])
def test_synthesized_couple_legs_obey_rule3(string):
    s = synthesize(string, (0, 1), seed=4)
    t, = s.layout.couples
    for j in s.leg.joints:
        if j.kind == "R":
            assert abs(np.dot(j.direction, t)) < 1e-9, j.name


def test_skew_layout_common_perpendicular():
    rng = np.random.default_rng(0)
    lay = make_layout((2, 0), "skew", rng, np.zeros(3), 100.0)
    N = next(lc for lc in lay.loci if lc.name == "N")
    (q1, c1), (q2, c2) = lay.force_lines
    for c, q in ((c1, q1), (c2, q2)):
        assert abs(np.dot(N.direction, c)) < 1e-12
        assert Line.through(N.point, N.direction).distance_to_line(Line.through(q, c)) < 1e-9


# ----------------------------------------------------------------- the verifier
def _hand_spr():
    # S at the origin (axes x, y, z), P along x, R along y through (50, 0, 100).
    # A force must pass through the origin (S), be perpendicular to x (P) and meet R:
    # lines through O in the plane x = 0 never reach x = 50, so it is parallel to R:
    # the force along y through O.
    return _leg("SPR", [([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 0]), ([0, 0, 1], [0, 0, 0]),
                        ([1, 0, 0], [25, 0, 50]), ([0, 1, 0], [50, 0, 100])],
                A=(0, 0, 0), a=(50, 0, 100))


def test_verify_hand_built_spr():
    leg = _hand_spr()
    W = force_wrench([0, 1, 0], [0, 0, 0]).vector
    v = verify(leg, [W])
    assert v.ok, v.problems
    assert v.residual < 1e-12
    # a couple is not in its system; neither is the force along z through O
    assert not verify(leg, [couple_wrench([0, 1, 0]).vector]).ok
    assert not verify(leg, [force_wrench([0, 0, 1], [0, 0, 0]).vector]).ok


def test_verify_accidental_dependence():
    # R along y through (0, 0, 100): its twist (-100, 0, 0; 0, 1, 0) = S_y + 100 * (-P_x):
    # dependent, and the system grows to 2 wrenches.
    leg = _leg("SPR", [([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 0]), ([0, 0, 1], [0, 0, 0]),
                       ([1, 0, 0], [0, 0, 50]), ([0, 1, 0], [0, 0, 100])],
               A=(0, 0, 0), a=(0, 0, 100))
    v = verify(leg, [force_wrench([0, 1, 0], [0, 0, 0]).vector])
    assert not v.ok
    assert v.dimension == 2 and v.dependent_joints == ("R3",)


def test_verify_hand_built_ppprr_couple():
    # P along x, y, z; R along x and y: rotations span x, y; the constraint: couple about z
    leg = _leg("PPPRR", [([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 0]), ([0, 0, 1], [0, 0, 0]),
                         ([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 100])])
    assert verify(leg, [couple_wrench([0, 0, 1]).vector]).ok
    assert not verify(leg, [couple_wrench([0, 1, 0]).vector]).ok


def test_verify_ppppp_actuation():
    # P1 (actuated) along z, P2..P5 in the xy-plane: 3 couples, P4 and P5 dependent,
    # P1 independent of the passive joints -> an actuation wrench (a force along z).
    good = _leg("PPPPP", [([0, 0, 1], [0, 0, 0]), ([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 0]),
                          ([1, 1, 0], [0, 0, 0]), ([1, -1, 0], [0, 0, 0])])
    couples = np.hstack([np.zeros((3, 3)), np.eye(3)])
    v = verify(good, couples, allow_dependent=True)
    assert v.ok and v.dependent_joints == ("P4", "P5") and v.actuation
    assert verify(good, couples, allow_dependent=True, actuation="rank").actuation
    assert not verify(good, couples).ok                      # dependence not allowed
    # P2..P4 span space: the actuated P1 is spanned by the passive joints
    bad = _leg("PPPPP", [([0, 0, 1], [0, 0, 0]), ([1, 0, 0], [0, 0, 0]), ([0, 1, 0], [0, 0, 0]),
                         ([0, 1, 1], [0, 0, 0]), ([1, -1, 0], [0, 0, 0])])
    for mode in ("wrench", "rank"):
        vb = verify(bad, couples, allow_dependent=True, actuation=mode)
        assert not vb.actuation and not vb.ok


def test_wrong_synthesis_is_caught():
    s = synthesize("RRPRR", (1, 0), seed=7)
    assert verify(s.leg, s.predicted_wrenches).ok
    (p, c), = s.layout.force_lines
    joints = list(s.leg.joints)
    j = joints[3]                                    # R4
    off = np.cross(j.direction, c)
    off /= np.linalg.norm(off)
    joints[3] = Joint(j.spec, j.direction, j.point + 0.2 * s.leg.length * off)
    assert Line.through(p, c).distance_to_line(joints[3].line) > 0.1 * s.leg.length
    wrong = Leg(s.leg.string, tuple(joints), s.leg.A, s.leg.a)
    v = verify(wrong, s.predicted_wrenches)
    assert not v.ok and v.contained == (False,)
    assert any("not in the constraint system" in m for m in v.problems)


def test_verify_invariant_under_frame_and_units():
    s = synthesize("UPU", (1, 0), seed=11)
    from scipy.spatial.transform import Rotation
    R = Rotation.from_euler("XYX", [0.3, -1.1, 2.0]).as_matrix()
    p = np.array([1e3, -2e3, 5e2])
    k = 1e-3
    moved = s.leg.moved(R, p, k)
    W = s.predicted_wrenches.copy()
    W[:, 3:] *= k                                    # moments scale with lengths
    Wm = transform_wrenches(R, p, W)
    assert verify(moved, Wm).ok


# ----------------------------------------------------------------- API details
def test_compositions_and_layouts():
    assert compositions(2) == ((2, 0), (1, 1), (0, 2))
    assert all(sum(c) <= 3 for c in LAYOUTS)


def test_counting_rank_compound_degeneracy():
    # counting ignores that two S share the rotation about the line of their centres
    assert counting_rank("SS") == 6
    assert counting_rank("RPPPP") == 4


def test_bad_requests():
    with pytest.raises(InputError):
        synthesize("RRPRR", (0, 0))
    with pytest.raises(InputError):
        synthesize("RRPRR", (1, 0), layouts=["nonsense"])
    with pytest.raises(InputError):
        synthesize("RR", (4, 0))


def test_reproducible_and_seed_independent_answer():
    a = synthesize("URPR", (1, 0), seed=42)
    b = synthesize("URPR", (1, 0), seed=42)
    assert np.allclose(a.leg.twists, b.leg.twists)
    c = synthesize("URPR", (1, 0), seed=43)
    assert c.realizable and not np.allclose(a.leg.twists, c.leg.twists)
