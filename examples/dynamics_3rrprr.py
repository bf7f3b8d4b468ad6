"""Inverse dynamics of the 3RRPRR along a 1-second motion: how much do the inertia and the
weight of the platform and legs add to the static actuator forces?

Masses (ours, for illustration: the paper gives none): a 25 kg platform, each leg a 3 kg
cylinder and a 1.5 kg piston, gravity along -Z. The motion: alpha = 8 sin(2 pi t),
beta = 6 sin(2 pi t + 1) deg, Zo = 70 + 20 t cm, t in seconds, under the paper's workload.
Prints the peak static and dynamic active forces and checks the energy balance
P_actuators + P_external = d(kinetic + potential energy)/dt, which the Newton-Euler
equations must satisfy without friction.

Run: python examples/dynamics_3rrprr.py
"""

import numpy as np

import screwkit
from screwkit.dynamics import motion_from_expressions

pm = screwkit.load_pm("3RRPRR")
u = pm.units
masses = {"units": {"mass": "kg", "length": "cm", "force": "N"},
          "platform": {"mass": 25, "inertia": [0.5, 0.5, 0.9]},        # kg.m^2 about the com
          "legs": {"cylinder": {"mass": 3, "length": 40, "radius": 3},
                   "piston": {"mass": 1.5, "length": 40, "radius": 2}}}
motion = motion_from_expressions(["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
                                 pm.independent, samples=201, t_range=(0, 1))
dyn = screwkit.dynamics(pm, motion, params=masses, force=[-20, -30, -60], torque=[-30, -30, 100])
print(f"{pm.name} along {len(dyn.t)} samples over {dyn.t[-1] - dyn.t[0]:.1f} s: {dyn.counts()}")
print(f"actuator   static peak |F_ai| ({u.force})   dynamic peak |F_ai| ({u.force})   difference")
for i in range(dyn.dynamic_active.shape[1]):
    s, d = np.abs(dyn.static_active[:, i]).max(), np.abs(dyn.dynamic_active[:, i]).max()
    print(f"  F_a{i + 1}     {s:14.3f}               {d:14.3f}            {d - s:+8.3f}")

energy = dyn.kinetic_energy + dyn.potential_energy               # kN.cm
power = dyn.actuator_power + dyn.external_power                   # kN.cm/s
balance = power - np.gradient(energy, dyn.t)
rel = np.abs(balance[2:-2]).max() / np.abs(dyn.actuator_power).max()
work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(dyn.t)))
print(f"energy balance: largest |P - dE/dt| = {rel:.1e} of the actuators' peak power "
      f"({np.abs(dyn.actuator_power).max():.0f} {u.force}.{u.length}/s; dE/dt by finite differences)")
print(f"work of the actuators and the load {work:.4f} {u.force}.{u.length}, "
      f"change of energy {energy[-1] - energy[0]:.4f} {u.force}.{u.length}")
assert rel < 1e-4 and abs(work - (energy[-1] - energy[0])) < 1e-3 * abs(work)
