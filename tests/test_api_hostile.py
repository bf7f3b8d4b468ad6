"""Hostile input at the Python API: each mistake is a ScrewkitError naming what is wrong
(never numpy's ValueError, a TypeError naming an internal function, or an AttributeError),
and coordinates beyond the model files' bound (1e12) are refused where they would lose the
geometry's digits (a leg moved 1e15 away read as two forces instead of one).

The right answers beside the refusals are derived here from the geometry: a force along x
removes the translation along x whatever its magnitude (5 freedoms), an RRPRR leg has one
constraint force wherever it stands."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import screwkit
from screwkit.design import synthesize_motion
from screwkit.dynamics import stiffness
from screwkit.errors import InputError, MisuseError, ScrewkitError

GRID = {"alpha": (-5.0, 5.0, 3)}
FIX = {"beta": 0.0, "Zo": 80.0}


@pytest.fixture(scope="module")
def pm():
    return screwkit.load_pm("3RRPRR")


@pytest.mark.parametrize("call", [
    lambda pm: screwkit.analyze(pm, bogus=1),
    lambda pm: screwkit.map(pm, GRID, fix=FIX, bogus=1),
    lambda pm: screwkit.size(pm, GRID, fix=FIX, bogus=1),
    lambda pm: screwkit.optimize(pm, {"L": (60.0, 80.0)}, GRID, fix=FIX, bogus=1),
    lambda pm: stiffness(pm, actuator=2e3, bogus=1),
])
def test_an_unknown_keyword_is_a_misuse_error_naming_it(pm, call):
    with pytest.raises(MisuseError, match="no keyword 'bogus'"):
        call(pm)


@pytest.mark.parametrize("call, words", [
    (lambda pm: screwkit.forward(pm, [0.0, 0.0, 0.0], guess={"alpha": "x"}), "alpha"),
    (lambda pm: screwkit.solve_path(pm, [{"alpha": "x", "beta": 0.0, "Zo": 80.0}]),
     "path sample 0: alpha"),
    (lambda pm: screwkit.solve_path(pm, [{"alpha": np.nan, "beta": 0.0, "Zo": 80.0}]),
     "finite"),
    (lambda pm: pm.moved("x", [0, 0, 0]), "rotation"),
    (lambda pm: pm.moved(np.eye(3), [1e300, 0, 0]), "translation"),
    (lambda pm: screwkit.load_pm("3RPS", [1, 2]), "overrides"),
    (lambda pm: screwkit.freedoms("abc"), "wrenches"),
    (lambda pm: screwkit.freedoms([[1j, 0, 0, 0, 0, 0]]), "wrenches"),
    (lambda pm: screwkit.PMBuilder("b", units="mm"), "units"),
    (lambda pm: screwkit.PMBuilder("b").add_leg("RPS", base=["a", 0, 0], platform=[1, 0, 0]),
     "3 finite numbers"),
    (lambda pm: screwkit.PMBuilder("b").add_leg("RPS", base=[70j, 0, 0], platform=[1, 0, 0]),
     "3 finite numbers"),
    (lambda pm: screwkit.PMBuilder("b").set_pose(["alpha", "beta", "Zo"],
                                                  home={"alpha": "0", "beta": 0, "Zo": 60}),
     "home: alpha"),
    (lambda pm: screwkit.optimize(pm, {"L": (60.0, 80.0)}, GRID, fix=FIX,
                                  workloads=[("a", [1, 2, 3])]), "workloads"),
    (lambda pm: screwkit.optimize(pm, {"L": (60.0, 80.0)}, GRID, fix=FIX, workloads="abc"),
     "workloads"),
    (lambda pm: screwkit.optimize(pm, {"L": (60.0, 80.0)}, GRID, fix=FIX, constraints=5),
     "constraints"),
    (lambda pm: synthesize_motion("3T", mapper=5), "mapper"),
    (lambda pm: synthesize_motion("3T", catalog="x"), "catalog"),
    (lambda pm: screwkit.forward(pm, [True, False, False]), "numbers"),
    (lambda pm: screwkit.assembly_modes(pm, [0.0, 0.0, 0.0], degrees="x"), "degrees"),
    (lambda pm: screwkit.analyze(pm, raise_on_singular="no"), "raise_on_singular"),
    (lambda pm: screwkit.analyze(pm, twists="yes"), "twists"),
    (lambda pm: screwkit.map(pm, GRID, fix=FIX, locus="no"), "locus"),
    (lambda pm: screwkit.analyze(pm, {"alpha": np.ma.array([0.0, 0.1], mask=[0, 1]),
                                      "beta": np.zeros(2), "Zo": np.full(2, 80.0)}),
     "masked"),
    (lambda pm: screwkit.leg_from_joints([("R", [0, 0, 1], [1e200, 0, 0]),
                                          ("R", [0, 1, 0], [0, 0, 0])]), "point of R1"),
    (lambda pm: screwkit.leg("RRPRR").moved(np.eye(3), [1e15, 0, 0]), "translation"),
    (lambda pm: screwkit.leg("RRPRR").moved(np.eye(3), [0, 0, 0], scale=1e-300), "scale"),
    # (session 70's review: raw exceptions, silently wrong tolerances, screws mixed up)
    (lambda pm: screwkit.Twist("abc"), "twist must be 6 numbers"),
    (lambda pm: screwkit.Wrench([1, 2, 3, 4, 5, "x"]), "wrench must be 6 numbers"),
    (lambda pm: screwkit.Twist([[1.0] * 6] * 2), "one 6-vector"),
    (lambda pm: screwkit.Twist([10 ** 400] * 6), "6 numbers"),
    (lambda pm: screwkit.Wrench(np.ones(6) * 1j), "complex"),
    (lambda pm: screwkit.Twist(np.ones(6)).reciprocal(screwkit.Twist(np.ones(6))),
     "taken with a Wrench"),
    (lambda pm: screwkit.Wrench(np.ones(6)).reciprocal(np.ones(6)), "taken with a Twist"),
    (lambda pm: screwkit.Twist(np.ones(6)).transformed(np.ones((3, 3)), [0, 0, 0]),
     "proper rotation"),
    (lambda pm: screwkit.freedoms([[0, 0, 1, 0, 0, 0]], rtol=np.nan), "rtol"),
    (lambda pm: screwkit.freedoms([[0, 0, 1, 0, 0, 0]], rtol=-1), "rtol"),
    (lambda pm: screwkit.freedoms([[0, 0, 1, 0, 0, 0]], geometry_rtol=np.nan), "geometry_rtol"),
    (lambda pm: screwkit.freedoms([screwkit.Twist(np.ones(6))]), "is a Twist"),
    (lambda pm: screwkit.freedoms([[0, 0, 1, 0, 0, 0]], points=[[1, 2]]), "points"),
    (lambda pm: screwkit.freedoms([[0, 0, 1, 0, 0, 0]], points=[[np.nan, 0, 0]]), "points"),
    (lambda pm: screwkit.assembly_modes(pm, [0.0, 0.0, 0.0], seeds=10, progress=5),
     "progress"),
    (lambda pm: screwkit.PMBuilder("b").set_limits("x"), "set_limits"),
    (lambda pm: screwkit.PMBuilder("b").set_workload("x"), "set_workload"),
    (lambda pm: screwkit.PMBuilder("b").add_leg("RPS", frame="x"), "frame"),
    (lambda pm: screwkit.analyze(pm, {"alpha": [0.0, 0.1], "beta": [0.0, 0.0],
                                      "Zo": [80.0, 80.0]}).solution.legs_at("a"), "index"),
    (lambda pm: screwkit.analyze(pm, {"alpha": [0.0, 0.1], "beta": [0.0, 0.0],
                                      "Zo": [80.0, 80.0]})[5], "does not fit"),
])
def test_a_bad_argument_is_a_screwkit_error_naming_it(pm, call, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # (no overflow warnings on the way either)
        with pytest.raises(ScrewkitError, match=words):
            call(pm)


def test_the_view_refuses_a_title_beyond_a_label_and_a_page_path_that_is_not_one(pm):
    pytest.importorskip("plotly")
    with pytest.raises(InputError, match="title"):
        screwkit.view(pm, title="x" * 10_000)
    page = screwkit.view(pm, steps=2)
    with pytest.raises(InputError, match="path"):
        page.write_html(5)


@pytest.mark.parametrize("scale", [1e-300, 1e-100, 1.0, 1e100, 1e200])
def test_a_constraint_force_removes_its_translation_at_any_magnitude(scale):
    """A force along x through O: the twists reciprocal to it are the five with no
    velocity of O along x (translations along y and z, the three rotations about lines
    through O... ), whatever the magnitude of the wrench (squared, 1e200 overflowed)."""
    res = screwkit.freedoms([[scale, 0, 0, 0, 0, 0]])
    T = np.asarray(res.twists)
    assert T.shape == (5, 6)
    assert np.allclose(T[:, 0], 0.0, atol=1e-12)       # f . v = 0 with f along x: no v_x
    assert np.linalg.matrix_rank(T, tol=1e-9) == 5


@pytest.mark.parametrize("offset", [0.0, 1e6, 1e11])
def test_a_moved_leg_within_the_bound_keeps_its_one_constraint_force(offset):
    """An RRPRR leg (two pairs of parallel R axes about a P): one constraint force
    wherever its frame stands within the bound."""
    leg = screwkit.leg("RRPRR").moved(np.eye(3), [offset, 0.0, 0.0])
    assert leg.analyze().summary() == "1 force"


def test_mobility_of_something_that_is_not_a_solved_pose_is_an_input_error():
    from screwkit.pm import mobility
    with pytest.raises(InputError, match="mobility takes a solved pose.*not tuple"):
        mobility((1, 2))


def test_twists_given_as_wrenches_are_refused_by_the_reciprocal_system():
    from screwkit.errors import MisuseError
    from screwkit.screws import reciprocal_system
    with pytest.raises(MisuseError, match="is a Wrench"):
        reciprocal_system([screwkit.Wrench(np.ones(6))])


def test_a_builders_workload_is_the_models_declared_one():
    """``PMBuilder.set_workload`` was dropped by ``to_mapping``: the built model declared no
    workload. The built PM's analysis now uses it, as the same load given explicitly."""
    b = screwkit.PMBuilder("w3rps", units={"length": "cm", "force": "kN"})
    for t in np.radians([90.0, 210.0, 330.0]):
        b.add_leg("RPS", base=[60 * np.cos(t), 60 * np.sin(t), 0.0],
                  platform=[30 * np.cos(t), 30 * np.sin(t), 0.0])
    b.set_pose(["alpha", "beta", "Zo"], home={"alpha": 0, "beta": 0, "Zo": 60})
    b.set_workload({"force": [1.0, -2.0, -40.0], "torque": [3.0, 0.0, 5.0], "units": "model"})
    pm = b.build()
    assert pm.workload is not None
    pose = {"alpha": 0.05, "beta": -0.03, "Zo": 62.0}
    declared = screwkit.analyze(pm, pose)
    given = screwkit.analyze(pm, pose, force=[1.0, -2.0, -40.0], torque=[3.0, 0.0, 5.0])
    assert np.array_equal(declared.statics.values, given.statics.values)
    assert "declared" in declared.workload_source


def test_what_results_and_models_hold_is_read_only(pm):
    """Written in place, a result's J, condition numbers or efforts, a row's direction, a
    leg's constraint or a model's points changed what later calls computed and said
    (``res.under`` gave NaN; a batch was reclassified 'singular'; a model analysed with
    other points than its definition), silently. They are read-only views now, and a
    later analysis of the same result is what it was."""
    one = screwkit.analyze(pm, {"alpha": 0.05, "beta": -0.03, "Zo": 80.0})
    many = screwkit.analyze(pm, {"alpha": [0.0, 0.1, 0.2], "beta": [0.0] * 3, "Zo": [80.0] * 3})
    leg = screwkit.leg("RRPRR").analyze()
    arrays = {
        "J": one.jacobian.J, "matrix": one.jacobian.matrix,
        # (one pose's, read-only from the kernel's records: _outputs.OnePose.views)
        "one condition_number": one.jacobian.conditioning.condition_number,
        "one singular_values": one.jacobian.singular_values, "one values": one.statics.values,
        "one rank": one.jacobian.conditioning.rank, "one scale": one.jacobian.scale,
        "condition_number": many.jacobian.condition_number,
        "singular_values": many.jacobian.singular_values, "values": many.statics.values,
        "active": many.statics.active, "constraint": many.statics.constraint,
        "row direction": one.jacobian.rows[3].direction,
        "row point": one.jacobian.rows[3].point,
        "leg constraint direction": leg.constraints[0].direction,
        "leg constraint point": leg.constraints[0].point,
        "leg system singular values": leg.system.singular_values,
        "base_points": pm.base_points, "platform_points": pm.platform_points,
        "centre": pm.centre, "frame rotation": pm.frame[0],
        "normalisation centre": pm.normalisation.centre}
    for name, a in arrays.items():
        assert isinstance(a, np.ndarray) and not a.flags.writeable, name
        with pytest.raises(ValueError):
            a[...] = 0.0
    before = one.under([0.0, 0.0, -10.0], [0.0, 0.0, 0.0]).statics.active
    assert np.all(np.isfinite(before))
    assert many.ok.tolist() == [True, True, True]
