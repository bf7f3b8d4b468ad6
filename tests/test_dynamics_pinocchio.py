"""screwkit's inverse dynamics against Pinocchio's closed-loop model (RNEA, CRBA and the
loop-closure constraint Jacobian, solved for the actuator forces and the constraint forces)
along 200-sample paths with massive legs, friction and an external workload."""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.dynamics import check_dynamics, motion_from_expressions

pytest.importorskip("pinocchio")

MASS = {"platform": {"mass": 40, "com": [1, 2, 3], "inertia": {"disc": {"radius": 30,
                                                                          "thickness": 3}}},
        "legs": {"cylinder": {"mass": 4, "length": 50, "radius": 4},
                 "piston": {"mass": 2, "length": 50, "radius": 2.5},
                 "friction": {"P": {"viscous": 30, "coulomb": 2}}}}

PATHS = {
    "3RRPRR": ["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)+8", "Zo=75+10*t"],
    "2SPS+2SPR": ["alpha=5*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "gamma=3*t", "Zo=70+10*t"],
    "3RPS": ["alpha=5*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "Zo=ZO+5*t"],
    "3UPU": ["Xo=5*sin(2*pi*t)", "Yo=4*sin(2*pi*t+1)", "Zo=ZO+5*t"],
}


@pytest.mark.parametrize("name", list(PATHS))
def test_pinocchio_agrees(name):
    pm = screwkit.load_pm(name)
    ex = [e.replace("ZO", repr(pm.default_pose.get("Zo", 0.0))) for e in PATHS[name]]
    motion = motion_from_expressions(ex, pm.independent, samples=200)
    chk = check_dynamics(pm, motion, params=MASS, force=[1, -2, 3], torque=[10, 20, -5])
    assert len(chk.samples) == 200
    assert chk.residual < 1e-10
    assert chk.errors["active"] < 1e-8, chk.errors
    assert chk.errors["leg_wrenches"] < 1e-8, chk.errors
    assert chk.errors["twist"] < 1e-8 and chk.errors["acceleration"] < 1e-8, chk.errors
    assert chk.passed()
    # the legs' inertia matters: the forces are not those of a massless-leg model
    light = check_dynamics(pm, motion, params={"platform": MASS["platform"]}, samples=[0, 99],
                           force=[1, -2, 3], torque=[10, 20, -5])
    assert np.abs(light.active - chk.active[[0, 99]]).max() > 1e-3 * np.abs(chk.active).max()
