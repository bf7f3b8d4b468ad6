"""``path=True`` on scattered poses: detected, solved as scattered poses, and said so."""

import numpy as np

import screwkit
from random_poses import random_pose


def test_scattered_poses_given_as_a_path_are_solved_each_from_home():
    pm = screwkit.load_pm("3RRPRR")
    pose = random_pose(pm, 400, seed=11)
    as_path = screwkit.analyze(pm, pose, path=True)
    scattered = screwkit.analyze(pm, pose)
    assert any("far apart" in n for n in as_path.solution.common_notes)
    assert not any("far apart" in n for n in scattered.solution.common_notes)
    assert as_path.ok.all() and scattered.ok.all()
    np.testing.assert_allclose(as_path.statics.active, scattered.statics.active, rtol=1e-10)


def test_a_smooth_path_is_not_taken_for_scattered_poses():
    pm = screwkit.load_pm("3RRPRR")
    s = np.linspace(0, 1, 32)             # one full period in 32 samples: coarse but smooth
    pose = {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
            "beta": np.radians(2 + 6 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
    res = screwkit.analyze(pm, pose, path=True)
    assert not any("far apart" in n for n in res.solution.common_notes)
    assert res.diagnostics["anchors"] > 0                 # solved by the path solver


def test_a_fine_raster_and_a_noisy_constant_are_paths():
    pm = screwkit.load_pm("3RRPRR")
    t = np.linspace(0, 1, 200)
    noisy = {"alpha": np.radians(10 * np.sin(2 * np.pi * t)),
             "beta": np.radians(5 * np.cos(2 * np.pi * t)),
             "Zo": 80 + 1e-12 * (-1.0) ** np.arange(200)}        # constant up to rounding
    a, b = np.meshgrid(np.linspace(-0.05, 0.05, 3), np.linspace(-1, 1, 40))
    a[1::2] = a[1::2, ::-1]                                        # a serpentine raster
    raster = {"alpha": np.radians(a.ravel()), "beta": np.radians(b.ravel()),
              "Zo": np.full(120, 80.0)}
    for pose in (noisy, raster):
        res = screwkit.analyze(pm, pose, path=True)
        assert not any("far apart" in n for n in res.solution.common_notes)
        assert res.diagnostics["anchors"] > 0 and res.ok.all()


def test_an_empty_path_is_refused_as_empty_arrays_are():
    import pytest
    from screwkit.errors import InputError
    pm = screwkit.load_pm("3RRPRR")
    with pytest.raises(InputError, match="no path samples"):
        screwkit.solve_path(pm, [])
    with pytest.raises(InputError, match="no poses"):
        screwkit.analyze(pm, {k: np.array([]) for k in ("alpha", "beta", "Zo")}, path=True)
