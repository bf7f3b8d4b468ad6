"""Workspace measures of a map (``screwkit.maps.workspace``) against closed forms.

* planar 3-RRR: a node is reachable iff every leg's platform joint lies in the annulus
  ``|l1 - l2| <= |C_i - A_i| <= l1 + l2`` about its base joint (the two link lengths read
  off the home legs); the good-transmission nodes are those whose closed-form LTI (the
  transmission angles of ``tests/test_transmission.py``) is at least 0.7;
* 2SPS+2SPR at beta = 0, Zo = 75 cm: the actuation singularity is the line
  alpha + gamma = 16.589 deg (``tests/test_singular_locus.py``), so the singularity-free
  region connected to home is the half-plane below it.
"""

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from test_transmission import PLANAR, _planar_closed_form


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    path = tmp_path_factory.mktemp("ws") / "3rrr.yaml"
    path.write_text(PLANAR)
    return screwkit.load_pm(str(path))


def test_planar_reachable_and_good_transmission(planar):
    ds = screwkit.map(planar, {"Xo": (-30, 30, 25), "Yo": (-30, 30, 25)}, fix={"gamma": 10},
                      degrees=True)
    ws = screwkit.maps.workspace(ds)
    legs = planar.home_legs
    A, B, C = (np.array([lg.joints[k].point[:2] for lg in legs]) for k in range(3))
    l1, l2 = np.linalg.norm(B - A, axis=1), np.linalg.norm(C - B, axis=1)
    g = np.radians(10.0)
    R = np.array([[np.cos(g), -np.sin(g)], [np.sin(g), np.cos(g)]])
    X, Y = np.meshgrid(ds["Xo"].values, ds["Yo"].values, indexing="ij")
    reach = np.ones(X.shape, bool)
    for i in range(3):
        d = np.linalg.norm(np.stack([X, Y], -1) + R @ planar.platform_points[i, :2] - A[i],
                           axis=-1)
        reach &= (d <= l1[i] + l2[i]) & (d >= abs(l1[i] - l2[i]))
    assert ws.units == "cm^2" and ws.box_volume == pytest.approx(3600.0)
    r = ws.regions["reachable"]
    assert r["cells"] == int(reach.sum()) and 0 < r["cells"] < reach.size
    assert r["fraction"] == pytest.approx(reach.mean())
    assert r["volume"] == pytest.approx(reach.mean() * 3600.0)
    # LTI >= 0.7 from the closed-form transmission angles, node by node
    res = screwkit.analyze(planar, {"Xo": X[reach], "Yo": Y[reach], "gamma": 10.0},
                           degrees=True)
    lti = np.array([min(a.min(), b.min()) for a, b in
                    (_planar_closed_form(res.solution.legs_at(n))[:2] for n in range(len(res)))])
    assert ws.regions["good_transmission"]["cells"] == int(np.sum(lti >= 0.7))
    assert 0 < int(np.sum(lti >= 0.7)) < reach.sum()
    half = screwkit.maps.workspace(ds, threshold=0.5).regions["good_transmission"]["cells"]
    assert half == int(np.sum(lti >= 0.5))


def test_singularity_free_region_is_the_half_plane_below_the_locus():
    ds = screwkit.map("2SPS+2SPR", {"alpha": (-10, 30, 21), "gamma": (-10, 30, 21)},
                      fix={"beta": 0, "Zo": 75}, degrees=True)
    ws = screwkit.maps.workspace(ds)
    a, g = np.meshgrid(ds["alpha"].values, ds["gamma"].values, indexing="ij")
    below = a + g < 16.589
    free = ws.regions["singularity_free"]
    assert free["cells"] == int(below.sum())
    assert free["fraction"] == pytest.approx(below.mean())
    assert ws.units == "deg^2" and ws.regions["reachable"]["fraction"] == 1.0
    assert "outside the box or off its slice" in ws.method     # home is at Zo = 80 cm
    # random samples: no neighbours, the home assembly mode instead; a Monte Carlo error
    sm = screwkit.map("2SPS+2SPR", {"alpha": (-10, 30), "gamma": (-10, 30)}, samples=400,
                      fix={"beta": 0, "Zo": 75}, degrees=True, seed=1)
    wss = screwkit.maps.workspace(sm)
    f = wss.regions["singularity_free"]
    assert wss.box == {"alpha": (-10.0, 30.0), "gamma": (-10.0, 30.0)}
    a, g = sm["alpha"].values, sm["gamma"].values
    assert f["cells"] == int(np.sum(a + g < 16.589))
    assert f["stderr"] == pytest.approx(np.sqrt(f["fraction"] * (1 - f["fraction"]) / 400)
                                        * 1600.0)


def test_cli_prints_the_workspace_and_refuses_a_bad_threshold(capsys):
    assert main(["map", "3RRPRR", "--grid", "alpha=-10:10:3", "--grid", "Zo=70:90:3",
                 "--lti-threshold", "0.9"]) == 0
    out = capsys.readouterr().out
    assert "workspace (task box alpha -10..10, Zo 70..90: 400 cm.deg)" in out
    assert "reachable with LTI >= 0.9" in out
    assert main(["map", "3RRPRR", "--grid", "alpha=-10:10:3", "--lti-threshold", "0"]) == 2
    err = capsys.readouterr().err
    assert err.strip() == "screwkit map: error: --lti-threshold must be in (0, 1], got 0"
    with pytest.raises(screwkit.InputError, match="threshold"):
        screwkit.maps.workspace(screwkit.map("3RRPRR", {"alpha": (0, 1, 2)}, degrees=True), 1.5)


@pytest.mark.parametrize("shape", [(7,), (9, 11), (6, 7, 8), (3, 4, 2, 5)])
def test_the_face_component_is_scipys_label_of_the_seed(shape):
    """The singularity-free region's flood fill against ``scipy.ndimage.label`` (face
    connectivity, the same grids): random masks in one to four dimensions, every seed of a
    few, one seed outside the mask (nothing)."""
    from scipy import ndimage

    from screwkit.engine._kernels import kernels
    rng = np.random.default_rng(len(shape))
    for density in (0.45, 0.6, 0.8):
        mask = rng.random(shape) < density
        lab, _ = ndimage.label(mask)
        for seed in rng.choice(mask.size, 6, replace=False):
            out = np.zeros(mask.size, bool)
            n = kernels().face_component(mask.reshape(-1), np.array(shape, np.int64),
                                         int(seed), out)
            k = lab.reshape(-1)[seed]
            want = (lab.reshape(-1) == k) if k else np.zeros(mask.size, bool)
            assert np.array_equal(out, want) and n == want.sum()
