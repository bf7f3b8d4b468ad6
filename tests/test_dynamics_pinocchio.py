"""screwkit's inverse dynamics against Pinocchio's closed-loop model (RNEA, CRBA and the
loop-closure constraint Jacobian, solved for the accelerations, the actuator forces and the
constraint forces, driven by the path's independent pose parameters only) along 200-sample
paths with massive legs, friction and an external workload."""

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
    # Pinocchio solves the motion itself from the path's independent parameters
    assert chk.errors["twist"] < 1e-8 and chk.errors["acceleration"] < 1e-8, chk.errors
    assert chk.errors["actuator_rates"] < 1e-8, chk.errors
    # the energies of the energy-balance test, from Pinocchio (CRBA and its potential)
    assert chk.errors["energy"] < 1e-8, chk.errors
    assert chk.passed()
    # the legs' inertia matters: the forces are not those of a massless-leg model
    light = check_dynamics(pm, motion, params={"platform": MASS["platform"]}, samples=[0, 99],
                           force=[1, -2, 3], torque=[10, 20, -5])
    assert np.abs(light.active - chk.active[[0, 99]]).max() > 1e-3 * np.abs(chk.active).max()


def test_pinocchio_agrees_through_a_representation_singularity():
    """The 3RRPRR's beta crosses 0 (its dependent gamma: screwkit takes the limit along beta
    there).  Driven by screwkit's actuator motion, Pinocchio's closed loop gives the same
    forces, twist and acceleration at every sample, the limit ones included; driven by the
    path it agrees away from beta = 0 (at beta = 0 its Euler rows are singular)."""
    pm = screwkit.load_pm("3RRPRR")
    motion = motion_from_expressions(["alpha=8*sin(2*pi*t)+1", "beta=3*sin(2*pi*t)",
                                      "Zo=80+10*sin(2*pi*t)"], pm.independent, samples=41)
    res = screwkit.dynamics(pm, motion, params=MASS, force=[1, -2, 3], torque=[10, 20, -5])
    assert res.ok.all() and res.data["limit"].sum() >= 3
    chk = check_dynamics(pm, result=res, drive="actuators")
    assert chk.passed(1e-8), chk.errors
    away = np.flatnonzero(np.abs(res.params_values["beta"]) > 0.01)
    chk = check_dynamics(pm, result=res, samples=away)
    assert chk.passed(1e-8) and chk.euler_condition.max() < 1e3, chk.errors
