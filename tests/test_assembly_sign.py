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
