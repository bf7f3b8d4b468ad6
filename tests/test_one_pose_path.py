"""One pose through ``screwkit.analyze`` (the path kept cheap in Python) and an optimiser's
candidate (the base model's engine arrays reused): the same numbers as the general path,
results that do not share buffers, nothing derived again per candidate."""

import numpy as np
import pytest

import screwkit

F = (-20.0, -30.0, -60.0)
T = (-30.0, -30.0, 100.0)


def test_plain_numbers_equal_a_batch_of_one_bit_for_bit():
    pm = screwkit.load_pm("6SPS")
    pose = {k: v + 0.01 for k, v in pm.default_pose.items()}
    one = screwkit.analyze(pm, pose, force=F, torque=T)
    ints = screwkit.analyze(pm, {k: np.float64(v) for k, v in pose.items()}, force=list(F),
                            torque=np.array(T))
    batch = screwkit.analyze(pm, {k: np.array([v]) for k, v in pose.items()}, force=F,
                             torque=T)[0]
    for r in (ints, batch):
        np.testing.assert_array_equal(r.jacobian.J, one.jacobian.J)
        np.testing.assert_array_equal(r.statics.values, one.statics.values)
        np.testing.assert_array_equal(r.solution.closures.X, one.solution.closures.X)
    # degrees: the same conversion as numpy's on arrays
    deg = screwkit.analyze("3RRPRR", {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
    arr = screwkit.analyze("3RRPRR", {"alpha": [5.0], "beta": [-3.0], "Zo": [80.0]},
                           degrees=True)[0]
    np.testing.assert_array_equal(deg.statics.values, arr.statics.values)


def test_successive_poses_share_no_buffer():
    pm = screwkit.load_pm("3RRPRR")
    a = screwkit.analyze(pm, {"alpha": 0.08, "beta": -0.05, "Zo": 80.0})
    keep = (a.jacobian.J.copy(), a.statics.values.copy(), a.solution.closures.X.copy(),
            a.jacobian.condition_number)
    b = screwkit.analyze(pm, {"alpha": -0.1, "beta": 0.07, "Zo": 90.0}, guess=a)
    assert not np.array_equal(b.jacobian.J, keep[0])
    np.testing.assert_array_equal(a.jacobian.J, keep[0])
    np.testing.assert_array_equal(a.statics.values, keep[1])
    np.testing.assert_array_equal(a.solution.closures.X, keep[2])
    assert a.jacobian.condition_number == keep[3]
    A = a.solution.base_points
    np.testing.assert_array_equal(A, pm.world_base_points)
    with pytest.raises(ValueError):
        A[0, 0] = 1.0                     # the model's copy, read-only


@pytest.mark.parametrize("pose", [{"alpha": 3601.0}, {"alpha": float("nan")},
                                  {"alpha": True}, {"Zo": 2e14}, {"Xo": 1.0}])
def test_refused_numbers_are_refused_as_before(pose):
    with pytest.raises(screwkit.InputError):
        screwkit.analyze("3RRPRR", pose, degrees=True)


def test_a_candidate_reuses_the_base_models_row_templates(monkeypatch):
    from screwkit.design import evaluate, problem
    from screwkit.design._evaluate import objectives_of
    from screwkit.engine import _templates
    base = screwkit.load_pm("3RRPRR")
    grid = {"alpha": (-5, 5, 2), "beta": (-5, 5, 2)}
    prob = problem(base, {"l": (40, 90)}, grid, {"Zo": 80}, degrees=True,
                   loads=[("paper", np.array(F), np.array(T))])
    _templates.templates_of(base)
    made = []
    init = _templates.RowTemplate.__init__

    def counted(self, *a, **k):
        made.append(1)
        init(self, *a, **k)
    monkeypatch.setattr(_templates.RowTemplate, "__init__", counted)
    got = evaluate(base, {"l": 70.0}, prob.task)
    assert made == []                     # no leg analysed again for the candidate
    # the same numbers as a model of its own (its own templates), as screwkit size builds it
    own = objectives_of(base.with_dimensions({"l": 70.0}), prob.task)
    assert len(made) == 3
    np.testing.assert_equal(got["objectives"], own["objectives"])      # (NaN equals NaN)
    assert got["feasible"] == own["feasible"]
