"""The assembly-mode sign of ``det J`` does not turn over with a constraint row's convention.

The 3RRPRR's constraint force of leg 2 is signed along ``OA x leg`` (the paper's ``c_i =
R_1i x delta_i``); at alpha = -20.75 deg, beta = 10 deg, Zo = 22.67 cm the leg lies along
``OA`` and that reference passes through zero: the row turns over, and the plain sign of
``det J`` with it, where ``J`` is regular (condition number about 25). An actuation
singularity lies next to it, at alpha = -19.12 deg, so that between the map's nodes at -22
and -18 deg the two sign changes cancelled: the singular locus, the cells beyond it and
``size``'s warning missed it. Independent references here: the condition number of ``J``
(which no sign convention changes) along the line and along straight paths from home, its
peak found by a bounded scalar search, and the plain ``numpy.linalg.det`` of ``J``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import screwkit
from screwkit.cli import main

BETA, ZO = np.radians(10.0), 22.6666667


@pytest.fixture(scope="module")
def pm():
    return screwkit.load_pm("3RRPRR")


def _line(pm, alpha_deg):
    a = np.radians(np.atleast_1d(np.asarray(alpha_deg, float)))
    return screwkit.analyze(pm, {"alpha": a, "beta": np.full_like(a, BETA),
                                 "Zo": np.full_like(a, ZO)})


def _path_from_home(pm, alpha_deg, n=801):
    t = np.linspace(0.0, 1.0, n)
    h = pm.home_pose
    return screwkit.analyze(pm, {"alpha": np.radians(alpha_deg) * t, "beta": BETA * t,
                                 "Zo": h["Zo"] + t * (ZO - h["Zo"])})


def test_the_sign_changes_at_the_singularity_only(pm):
    peak = minimize_scalar(lambda a: -_line(pm, a).jacobian.condition_number[0],
                           bounds=(-20.0, -18.5), method="bounded", options={"xatol": 1e-7})
    assert -_line(pm, peak.x).jacobian.condition_number[0] < -1e5       # a singularity
    alphas = np.linspace(-26.0, -10.0, 161)
    res = _line(pm, alphas)
    cond = res.jacobian.condition_number
    raw = np.sign(np.linalg.det(res.jacobian.J))
    flips = np.flatnonzero(np.diff(raw) != 0)
    # the plain sign changes twice: at the singularity and where the row turns over
    assert len(flips) == 2
    turn = [i for i in flips if max(cond[i], cond[i + 1]) < 100]
    assert len(turn) == 1 and -21.0 < alphas[turn[0]] < -20.5
    sign = np.asarray(res.quality.det_sign)
    assert set(np.unique(sign)) == {-1, 1}
    change = np.flatnonzero(np.diff(sign) != 0)
    assert len(change) == 1 and alphas[change[0]] < peak.x < alphas[change[0] + 1]
    # home's side: a straight path from home to alpha = -10 meets no singularity
    near = _path_from_home(pm, -10.0)
    assert near.jacobian.condition_number.max() < 10
    home = res.quality.home_det_sign
    assert np.all(sign[alphas > peak.x] == home) and np.all(sign[alphas < peak.x] == -home)
    beyond = np.asarray(res.quality.beyond_singular_surface)
    assert np.array_equal(beyond, alphas < peak.x)


def test_the_map_finds_the_singularity_between_its_nodes(pm, capsys):
    peak = minimize_scalar(lambda a: -_line(pm, a).jacobian.condition_number[0],
                           bounds=(-20.0, -18.5), method="bounded", options={"xatol": 1e-7})
    assert main(["map", "3RRPRR", "--grid", "alpha=-26:-10:5", "--fix", f"Zo={ZO}",
                 "--fix", "beta=10", "-q", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    points = d["singular_locus"]
    assert len(points) == 1 and points[0]["kind"] == "actuation"
    assert points[0]["pose"]["alpha"] == pytest.approx(peak.x, abs=1e-4)
    assert d["counts"]["other_assembly_mode"] == 2
    assert main(["size", "3RRPRR", "--grid", "alpha=-26:-10:5", "--fix", f"Zo={ZO}",
                 "--fix", "beta=10", "-q"]) == 0
    assert "beyond a singular surface" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["3RPS", "2SPS+2SPR", "3UPU"])
def test_the_analysis_run_and_a_later_pass_give_one_sign(name):
    """``analyze(lines=True)`` (a map's analysis) forms the legs' orientation in its own run
    (on a block's lanes for a batch, alone for one pose); otherwise ``quality`` forms it
    from the solved unknowns. The same signs, and those of ``numpy.linalg.det`` of the
    legs' joint twists over their rows (an S as the rotations about X, Y, Z through its
    centre) and of ``J`` itself (``test_forward._assembly_sign_by_hand``)."""
    from test_forward import _assembly_sign_by_hand
    pm = screwkit.load_pm(name)
    rng = np.random.default_rng(7)
    N = 300
    d = pm.default_pose
    pose = {p: d[p] + (rng.uniform(-0.15, 0.15, N) if p in ("alpha", "beta", "gamma") else
                       rng.uniform(-0.05, 0.05, N) * pm.normalisation.length)
            for p in pm.independent}
    run, later = screwkit.analyze(pm, pose, lines=True), screwkit.analyze(pm, pose)
    assert run.diagnostics.get("det_oriented") and not later.diagnostics.get("det_oriented")
    ok = run.ok & ~run.singular
    assert ok.sum() > N // 2
    np.testing.assert_array_equal(run.quality.det_sign[ok], later.quality.det_sign[ok])
    ref = {p: pm.home_pose[p] for p in pm.independent} \
        if run.quality.reference == "home" else {p: d[p] for p in pm.independent}
    np.testing.assert_array_equal(run.quality.det_sign[ok],
                                  _assembly_sign_by_hand(pm, run, ref)[ok])
    for i in np.flatnonzero(ok)[:3]:
        for lines in (True, False):
            one = screwkit.analyze(pm, {p: float(v[i]) for p, v in pose.items()}, lines=lines)
            assert one.quality.det_sign == run.quality.det_sign[i]


def _with_passive_ss():
    """A 5-SPS with a passive SS link as the sixth leg (the 6-SPS of the catalog otherwise):
    the SS has six joints but five freedoms (its spin about its own line) and one
    constraint, the force along the link: a leg with an idle motion, oriented against its
    row at the reference pose."""
    R, r, h = 300.0, 100.0, 200.0
    ab = np.radians([-2.5, 2.5, 117.5, 122.5, 237.5, 242.5])
    ap = np.radians([-50.0, 50.0, 70.0, 170.0, 190.0, 290.0])
    b = screwkit.PMBuilder("five_SPS_SS", units={"length": "cm", "force": "N"})
    ss = {"name": "SS", "string": "SS", "joints": [{"at": "A"}, {"at": "a"}]}
    for k in range(6):
        b.add_leg(ss if k == 5 else "SPS", base=[R * np.cos(ab[k]), R * np.sin(ab[k]), 0.0],
                  platform=[r * np.cos(ap[k]), r * np.sin(ap[k]), 0.0], passive=k == 5)
    b.set_pose(["alpha", "beta", "gamma", "Xo", "Yo"],
               home={"alpha": 0, "beta": 0, "gamma": 0, "Xo": 0, "Yo": 0}, guess={"Zo": h})
    return screwkit.load_pm(b)


def test_a_leg_with_an_idle_motion_is_oriented_against_its_reference_row():
    """By hand with numpy: ``sign det J`` times the sign of the SS row's cosine with its row
    at home (both about the model's centroid, moments over its length), relative to home."""
    pm = _with_passive_ss()
    assert [len(lg.joints) for lg in pm.home_legs] == [7] * 5 + [6]
    rng = np.random.default_rng(3)
    N = 200
    pose = {p: rng.uniform(-0.2, 0.2, N) if p in ("alpha", "beta", "gamma") else
            rng.uniform(-30.0, 30.0, N) for p in pm.independent}
    for lines in (False, True):           # (True: a map's analysis)
        res = screwkit.analyze(pm, pose, force=[0.0, 0.0, -10.0], lines=lines)
        home = screwkit.analyze(pm, {p: 0.0 for p in pm.independent}, force=[0, 0, -10.0])
        c, L = pm.normalisation.centre, pm.normalisation.length

        def unit(w):
            w = np.array(w, float)
            w[..., 3:] = (w[..., 3:] - np.cross(c, w[..., :3])) / L
            return w / np.linalg.norm(w, axis=-1, keepdims=True)

        row = [k for k, ri in enumerate(res.jacobian.info) if ri.leg == 5]
        assert len(row) == 1 and res.quality.reference == "home"
        J = res.jacobian.matrix
        cos = unit(J[:, row[0]]) @ unit(home.jacobian.matrix[0, row[0]])
        by_hand = np.sign(np.linalg.det(J)) * np.sign(cos) * np.sign(
            np.linalg.det(home.jacobian.matrix[0])) * res.quality.home_det_sign
        ok = res.ok & ~res.singular & (np.abs(cos) > 1e-3)
        assert ok.sum() > N // 2
        np.testing.assert_array_equal(res.quality.det_sign[ok], by_hand[ok])
        assert home.quality.det_sign == home.quality.home_det_sign == \
            np.sign(np.linalg.det(home.jacobian.matrix[0]))
    # the SS row signed the other way (its convention): det J turns over, the sign does not
    from types import SimpleNamespace
    from screwkit.engine import _quality
    flipped = np.array(J)
    flipped[:, row[0]] *= -1.0
    fake = SimpleNamespace(model=pm, solution=res.solution,
                           jacobian=SimpleNamespace(matrix=flipped),
                           diagnostics={"det_sign": np.sign(np.linalg.det(flipped))})
    ref, at_ref = _quality._REF_ROWS[pm]
    got = _quality._oriented(fake, ref) * at_ref
    np.testing.assert_array_equal(got[ok], res.quality.det_sign[ok])
