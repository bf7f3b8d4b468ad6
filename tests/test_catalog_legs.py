"""Every leg type of the catalog (the paper's Fig. 2, reconstructed).

The expected counts in ``legs_catalog.yaml`` were derived by hand from the
observation rules; here they are checked against

* an independent rank count (6 minus the rank of the joint twists, built in
  this file from each joint's axis and point, not by screwkit),
* the engine's decomposition and observation-rule notes (``agrees``),
* a scale-free reciprocal product computed in this file,
* invariance of the constraint system under a change of base frame and of
  length units, and the counts under a tilted platform.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from screwkit.errors import GeometryError
from screwkit.legs import Placement, default_placement, parse_pm
from screwkit.pm import default_catalog

CAT = default_catalog()
NAMES = sorted(CAT.legs)

#: The PMs of the paper's section 2.3.
PMS_3DOF = ["3SPR", "3RPS", "3RRPRR", "3UPU", "2UPU+SPR", "3UPRR", "3RPRU", "3RSR", "3RPUR"]
PMS_4DOF = ["2UPS+2SPR", "2UPS+2UPU", "4UPU", "3SPU+UPR", "3SPU+SP", "3SPU+PRRR", "3SPU+RPRR"]
PMS_5DOF = ["4SPS+SPR", "4SPS+UPU", "4SPS+URPR"]
SECTION_2_3 = PMS_3DOF + PMS_4DOF + PMS_5DOF

#: Leg types whose structure keeps the platform parallel to the base (a Schoenflies
#: leg): no tilted placement satisfies their structure checks.
PLATFORM_PARALLEL = {"PRRR", "UPU/schoenflies"}

REL_TOL = 1e-9


# ---------------------------------------------------------------- helpers

def my_twist(joint) -> np.ndarray:
    """Unit twist [v; w] of a joint about the origin, from its axis and point."""
    d, p = np.asarray(joint.direction), np.asarray(joint.point)
    if joint.kind == "P":
        return np.r_[d, 0.0, 0.0, 0.0]
    v = np.cross(p, d) + (joint.pitch * d if joint.kind == "H" else 0.0)
    return np.r_[v, d]


def my_twists(leg) -> np.ndarray:
    return np.array([my_twist(j) for j in leg.joints])


def frame(leg):
    """Centre and length of a scale-free normalisation chosen here (not screwkit's)."""
    pts = np.vstack([leg.A, leg.a] + [j.point for j in leg.joints])
    return pts.mean(axis=0), leg.length


def normalise_wrench(W, c, L):
    f, m = W[:3], W[3:]
    return np.r_[f, (m - np.cross(c, f)) / L]


def normalise_twist(V, c, L):
    v, w = V[:3], V[3:]
    return np.r_[(v + np.cross(w, c)) / L, w]


def rel_reciprocal(W, V, c, L) -> float:
    """|W.V| / (|W_n| |V_n|) with both screws normalised about c by L (scale-free)."""
    Wn, Vn = normalise_wrench(W, c, L), normalise_twist(V, c, L)
    return abs(float(np.dot(W, V))) / L / (np.linalg.norm(Wn) * np.linalg.norm(Vn))


def rank(M, tol=1e-8) -> int:
    M = np.atleast_2d(M)
    if M.size == 0:
        return 0
    s = np.linalg.svd(M, compute_uv=False)
    return int(np.sum(s > tol * max(1.0, s[0])))


def constraint_dimension(leg) -> int:
    """6 - rank of the joint twists, normalised about the leg's centroid."""
    c, L = frame(leg)
    return 6 - rank(np.array([normalise_twist(V, c, L) for V in my_twists(leg)]))


def member_wrench(c) -> np.ndarray:
    """The wrench of a decomposed member rebuilt from its description (line or direction)."""
    d = np.asarray(c.direction)
    if c.kind == "couple":
        return np.r_[0.0, 0.0, 0.0, d]
    if c.kind == "force":
        return np.r_[d, np.cross(c.point, d)]
    return np.asarray(c.wrench.vector)


def transform_wrench(W, R, p):
    f, m = W[:3], W[3:]
    return np.r_[R @ f, R @ m + np.cross(p, R @ f)]


def same_span(A, B, c, L) -> bool:
    An = np.array([normalise_wrench(w, c, L) for w in A]).reshape(-1, 6)
    Bn = np.array([normalise_wrench(w, c, L) for w in B]).reshape(-1, 6)
    ra, rb = rank(An), rank(Bn)
    return ra == rb == rank(np.vstack([An, Bn]))


PL = default_placement()
ROT = Rotation.from_euler("ZYX", [0.7, -0.4, 1.1]).as_matrix()
SHIFT = np.array([3.0, -250.0, 40.0])


def tilted(axis, angle=0.3) -> Placement:
    """The default placement with the platform turned about an axis through a."""
    Rt = Rotation.from_rotvec(angle * np.asarray(axis, float)).as_matrix()
    return Placement(PL.A, PL.a, PL.O, PL.a + Rt @ (PL.o - PL.a), PL.base_rotation,
                     Rt @ PL.platform_rotation, PL.C)


TILTS = {"about the platform tangent": tilted([0.0, 1.0, 0.0]),
         "about the platform radius": tilted([1.0, 0.0, 0.0]),
         "about the leg": tilted((PL.a - PL.A) / PL.length)}


@pytest.fixture(scope="module")
def analyses():
    return {n: CAT.legs[n].build().analyze() for n in NAMES}


# ---------------------------------------------------------------- coverage

def test_catalog_has_at_least_21_leg_types():
    assert len(CAT.legs) >= 21


@pytest.mark.parametrize("pm", SECTION_2_3)
def test_every_leg_of_the_section_2_3_pms_is_in_the_catalog(pm):
    for leg in parse_pm(pm).legs:
        specs = [s for s in CAT.legs.values() if s.string.text == leg.text]
        assert specs, f"{pm}: no catalog entry for {leg.text}"
        assert any(pm in s.used_by for s in specs), f"{pm}: no {leg.text} entry lists it in used_by"


@pytest.mark.parametrize("name", NAMES)
def test_used_by_names_pms_that_contain_the_leg(name):
    spec = CAT.legs[name]
    for pm in spec.used_by:
        assert spec.string.text in {leg.text for leg in parse_pm(pm).legs}, (name, pm)


def test_both_actuation_types_and_both_upu_variants():
    kinds = {s.string.actuation_type for s in CAT.legs.values()}
    assert {"linear", "rotational"} <= kinds
    assert {"UPU/force", "UPU/couple"} <= set(CAT.legs)
    assert CAT.legs["RSR"].string.marked == "_RSR"


# ---------------------------------------------------------------- each leg

@pytest.mark.parametrize("name", NAMES)
def test_builds_and_my_twists_match(name, analyses):
    leg = analyses[name].leg
    assert len(leg.joints) == len(leg.string.equivalent)
    np.testing.assert_allclose(leg.twists, my_twists(leg), atol=1e-12 * leg.length)


@pytest.mark.parametrize("name", NAMES)
def test_counts_match_hand_derivation_and_independent_rank(name, analyses):
    res, e = analyses[name], CAT.legs[name].expect
    want = e.get("forces", 0) + e.get("couples", 0) + e.get("screws", 0)
    assert constraint_dimension(res.leg) == want
    assert (res.n_forces, res.n_couples, res.n_screws) == \
        (e.get("forces", 0), e.get("couples", 0), e.get("screws", 0))
    assert res.dependent_joints == () or len(res.leg.joints) > 6


@pytest.mark.parametrize("name", NAMES)
def test_rules_and_solver_agree(name, analyses):
    res = analyses[name]
    assert res.agrees()
    for c in res.constraints:
        assert all(n.holds for n in c.rules), (name, [str(n) for n in c.rules])


@pytest.mark.parametrize("name", NAMES)
def test_expectation_holds(name, analyses):
    spec = CAT.legs[name]
    assert spec.check_expectation(analyses[name]) == []
    assert spec.expect.get("words"), f"{name}: expected wrenches not described in words"


@pytest.mark.parametrize("name", NAMES)
def test_constraints_are_reciprocal_to_every_joint(name, analyses):
    res = analyses[name]
    leg = res.leg
    c0, L = frame(leg)
    T = my_twists(leg)
    for c in res.constraints:
        W = member_wrench(c)
        # the description (line or direction) is the wrench reported
        w_rep = np.asarray(c.wrench.vector)
        assert rank(np.array([normalise_wrench(W, c0, L), normalise_wrench(w_rep, c0, L)])) == 1
        worst = max(rel_reciprocal(W, V, c0, L) for V in T)
        assert worst < REL_TOL, (name, c.describe(), worst)
    # and the members span the whole reciprocal system (its dimension is counted above)
    rows = np.array([normalise_wrench(member_wrench(c), c0, L) for c in res.constraints])
    assert rank(rows) == constraint_dimension(leg)


@pytest.mark.parametrize("name", NAMES)
def test_actuation_wrench(name, analyses):
    res = analyses[name]
    leg = res.leg
    act = res.actuation
    assert act is not None, f"{name}: the actuated joint depends on the passive ones"
    ia = leg.actuated_index
    assert act.joint == leg.joints[ia].name
    c0, L = frame(leg)
    T = my_twists(leg)
    W = np.asarray(act.wrench)
    assert abs(float(W @ T[ia]) - 1.0) < 1e-9
    for i, V in enumerate(T):
        if i != ia:
            assert rel_reciprocal(W, V, c0, L) < REL_TOL, (name, leg.joints[i].name)
    # the actuator does work: the wrench is not in the constraint system
    rows = [normalise_wrench(member_wrench(c), c0, L) for c in res.constraints]
    rows.append(normalise_wrench(W, c0, L))
    assert rank(np.array(rows)) == len(res.constraints) + 1


# ---------------------------------------------------------------- other placements

@pytest.mark.parametrize("name", NAMES)
def test_moved_base_frame(name, analyses):
    spec, res0 = CAT.legs[name], analyses[name]
    res = spec.build(PL.transformed(ROT, SHIFT)).analyze()
    assert (res.n_forces, res.n_couples, res.n_screws) == \
        (res0.n_forces, res0.n_couples, res0.n_screws)
    assert res.agrees()
    # the system is the default one carried by the rigid motion
    W0 = [transform_wrench(member_wrench(c), ROT, SHIFT) for c in res0.constraints]
    W1 = [member_wrench(c) for c in res.constraints]
    c, L = frame(res.leg)
    assert same_span(W0, W1, c, L) if W0 else not W1


@pytest.mark.parametrize("name", NAMES)
def test_lengths_times_1000(name, analyses):
    spec, res0 = CAT.legs[name], analyses[name]
    res = spec.build(PL.scaled(1000.0)).analyze()
    assert (res.n_forces, res.n_couples, res.n_screws) == \
        (res0.n_forces, res0.n_couples, res0.n_screws)
    assert res.agrees()
    assert constraint_dimension(res.leg) == constraint_dimension(res0.leg)
    # a force line scales with the geometry: [f; m] -> [f; 1000 m]
    W0 = [np.r_[member_wrench(c)[:3], 1000.0 * member_wrench(c)[3:]] for c in res0.constraints]
    W1 = [member_wrench(c) for c in res.constraints]
    c, L = frame(res.leg)
    assert same_span(W0, W1, c, L) if W0 else not W1


@pytest.mark.parametrize("name", NAMES)
def test_tilted_platform(name, analyses):
    spec, res0 = CAT.legs[name], analyses[name]
    built = {}
    for label, pl in TILTS.items():
        try:
            built[label] = spec.build(pl)
        except GeometryError as exc:
            assert "structure check" in str(exc), (name, label, str(exc))
    if name in PLATFORM_PARALLEL:
        assert not built, f"{name} keeps the platform parallel to the base, yet builds tilted"
        return
    if not built:
        pytest.skip(f"{name}: no tilted placement satisfies its structure checks")
    for label, leg in built.items():
        res = leg.analyze()
        assert (res.n_forces, res.n_couples, res.n_screws) == \
            (res0.n_forces, res0.n_couples, res0.n_screws), (name, label)
        assert res.agrees(), (name, label)
        assert constraint_dimension(leg) == constraint_dimension(res0.leg)


def test_docs_table_is_current():
    """docs/catalog.md's leg table is regenerated from the catalog (docs/gen_catalog_md.py)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "docs" / "gen_catalog_md.py"
    spec = importlib.util.spec_from_file_location("gen_catalog_md", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    text = mod.DOC.read_text(encoding="utf-8")
    assert mod.render(text, CAT) == text, "run: python docs/gen_catalog_md.py"
    for name in CAT.legs:
        assert f"`{name}`" in text
