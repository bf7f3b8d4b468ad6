"""Conditioning levels, force amplification and the assembly-mode warning.

Independent references: the ratio of the largest active or constraint force to the load's
force, computed here from the statics values; the sign of det J read off the matrix; the
singular surface of the 2SPS+2SPR located by bisection on det J (NOTES.md: near
alpha + gamma = 17 deg at beta = 0).
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine import PAPER_FORCE

SCAN = np.radians(np.linspace(0.0, 25.0, 501))


@pytest.fixture(scope="module")
def scan():
    pm = screwkit.load_pm("2SPS+2SPR")
    pose = {"alpha": SCAN / 2, "beta": 0 * SCAN, "gamma": SCAN / 2, "Zo": 75 + 0 * SCAN}
    return pm, screwkit.analyze(pm, pose, path=True)


def test_near_singular_before_any_force_passes_ten_times_the_load(scan):
    pm, res = scan
    forces = [k for k, r in enumerate(res.jacobian.info) if r.member != "couple"]
    ratio = np.nanmax(np.abs(res.statics.values[:, forces]), axis=1) / np.linalg.norm(PAPER_FORCE)
    first_big = np.argmax(ratio > 10)
    assert ratio[first_big] > 10 and first_big > 0
    level = res.level
    near = np.flatnonzero(np.isin(level, ["near-singular", "singular"]))
    assert near.size and near[0] < first_big
    # every pose with a force above 10x the load is at least near-singular
    assert np.all(np.isin(level[ratio > 10], ["near-singular", "singular"]))
    assert level[0] == "ok"


def test_the_assembly_mode_warning_beyond_the_singular_surface(scan):
    pm, res = scan
    det = np.sign(np.linalg.det(res.jacobian.matrix))
    home = np.sign(np.linalg.det(screwkit.analyze(pm, {p: pm.home_pose[p] for p in
                                                       pm.independent}).jacobian.J))
    q = res.quality
    assert q.home_det_sign == home
    np.testing.assert_array_equal(q.det_sign, det)
    crossing = np.flatnonzero(det != det[0])
    assert crossing.size and np.degrees(SCAN[crossing[0]]) == pytest.approx(17.2, abs=0.6)
    np.testing.assert_array_equal(q.beyond_singular_surface, (det != home) & ~res.singular)
    one = res[int(crossing[0]) + 20]
    assert any("beyond a singular surface" in w for w in one.warnings)
    assert not res[0].warnings


def test_conditioning_block_in_json(capsys):
    from screwkit.cli import main
    import json

    assert main(["analyze", "2SPS+2SPR", "--pose", "alpha=9", "--pose", "gamma=9", "--pose",
                 "beta=0", "--pose", "Zo=75", "--json"]) == 0
    out = capsys.readouterr()
    q = json.loads(out.out)["conditioning"]
    assert q["level"] == "near-singular" and q["beyond_singular_surface"]
    assert "warning: det J has the opposite sign" in out.err


def test_json_on_error_is_a_json_object(capsys):
    from screwkit.cli import main
    import json

    assert main(["analyze", "3RSR", "--pose", "Zo=400", "--json"]) == 2
    out = capsys.readouterr()
    err = json.loads(out.out)["error"]
    assert err["type"] == "UnreachablePoseError" and err["residual"] > 1e-6


def test_the_quality_and_the_indices_share_one_trust(monkeypatch):
    # the force amplification and levels (the trust rule) formed once for both
    from screwkit.engine import _quality
    calls = []
    real = _quality.trust

    def counted(jac, *args, **kwargs):
        calls.append(len(jac))
        return real(jac, *args, **kwargs)
    monkeypatch.setattr(_quality, "trust", counted)
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": np.linspace(-0.2, 0.2, 50), "beta": 0.1, "Zo": np.linspace(60.0, 100, 50)}
    res = screwkit.analyze(pm, pose)
    amp_q = np.asarray(res.quality.amplification)
    amp_i = np.asarray(res.indices.amplification)
    assert calls == [50]
    # the trust rule itself on the same analysis, independently of the cache
    st = res.statics
    fresh = real(res.jacobian, st.F_r, st._W, res.solution._platform[1],
                 np.asarray(res.solution.reachable_mask, bool), np.nan_to_num(st.amp, nan=0.0))
    assert np.array_equal(amp_q, fresh[0], equal_nan=True)
    assert np.array_equal(amp_i, fresh[0], equal_nan=True)
    assert np.array_equal(np.asarray(res.quality.level), fresh[1])
