"""Indexing a batch result: an int gives one pose, a slice, integers or a mask a sub-batch.

The sub-batch is checked against analyses run on those poses alone (a second computation,
not the batch's own arrays), and against the batch's rows."""

import numpy as np
import pytest

import screwkit
from random_poses import random_pose


@pytest.fixture(scope="module")
def batch():
    pm = screwkit.load_pm("3RRPRR")
    pose = random_pose(pm, 12, seed=7)
    return pm, pose, screwkit.analyze(pm, pose)


@pytest.mark.parametrize("key", [slice(2, 9, 3), [11, 0, 4, 4], np.array([5, -1]),
                                 np.arange(12) % 3 == 0])
def test_sub_batch_equals_those_poses_analysed_alone(batch, key):
    pm, pose, res = batch
    idx = np.arange(12)[key]
    sub = res[key]
    assert not sub.single and len(sub) == len(idx)
    alone = screwkit.analyze(pm, {p: v[idx] for p, v in pose.items()})
    for get in (lambda r: r.statics.active, lambda r: r.statics.constraint,
                lambda r: r.statics.T_r, lambda r: r.jacobian.matrix,
                lambda r: r.jacobian.condition_number, lambda r: r.jacobian.points):
        np.testing.assert_allclose(get(sub), get(alone), rtol=1e-10, atol=1e-9)
        np.testing.assert_array_equal(get(sub), np.asarray(get(res))[idx])
    assert sub.ok.tolist() == alone.ok.tolist()
    for p, v in alone.solution.params.items():
        np.testing.assert_allclose(sub.solution.params[p], v, rtol=1e-10, atol=1e-12)


def test_one_pose_of_a_sub_batch_is_that_pose(batch):
    pm, pose, res = batch
    sub = res[[9, 3]]
    one = sub[1]
    assert one.single
    assert str(one) == str(res[3])
    np.testing.assert_array_equal(one.statics.active, res.statics.active[3])
    assert len(one.jacobian.legs) == 3


def test_mask_of_ok_poses_and_bad_indices(batch):
    _, _, res = batch
    assert len(res[res.ok]) == int(np.sum(res.ok))
    with pytest.raises(IndexError, match="12 poses"):
        res[12]
    with pytest.raises(IndexError, match="12 poses"):
        res[np.ones(5, bool)]
    with pytest.raises(IndexError, match="one pose axis"):
        res[0, 1]
    with pytest.raises(TypeError, match="one-pose"):
        res[0][0]


def test_a_sub_batch_keeps_the_stiffness_of_its_own_poses():
    # a per-pose stiffness (N, m) follows the poses: a reversed sub-batch re-solved under
    # another workload equals a fresh analysis of the reversed poses and stiffnesses
    pm = screwkit.load_pm("4UPU")
    pose = random_pose(pm, 4, seed=3)
    rng = np.random.default_rng(0)
    k = np.concatenate([np.full((4, 4), 1e3), rng.uniform(1e5, 1e7, (4, 4))], axis=1)
    F, T = (1.0, 2.0, -3.0), (0.5, -40.0, 7.0)
    res = screwkit.analyze(pm, pose, stiffness=k)
    want = screwkit.analyze(pm, {p: v[::-1] for p, v in pose.items()}, stiffness=k[::-1],
                            force=F, torque=T)
    got = res[::-1].under(F, T)
    np.testing.assert_allclose(got.statics.values, want.statics.values, rtol=1e-10, atol=1e-9)
    one = res[2].under(F, T)
    np.testing.assert_allclose(one.statics.values, want.statics.values[1], rtol=1e-10,
                               atol=1e-9)
