"""Statics of the 3RRPRR along a path, with the Fig. 5-style plot saved to a PNG.

The path (angles in degrees, Zo in cm, t from 0 to 1 over 201 samples):
alpha = 8 sin(2 pi t), beta = 6 sin(2 pi t + 1), Zo = 70 + 20 t, under the paper's workload.
Prints the peaks an actuator designer sizes for (largest push and pull of each actuator,
the range of leg lengths, the largest constraint force and leg torque) and writes 3rrprr_path.csv and
3rrprr_fig5.png in the working folder (needs matplotlib: pip install "screwkit[plot]").

Run: python examples/trajectory_plot.py
"""

import numpy as np

import screwkit
from screwkit.paths import path_from_expressions, run_trajectory

pm = screwkit.load_pm("3RRPRR")
u = pm.units
path = path_from_expressions(["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
                             pm.independent, samples=201)          # expressions in degrees
res = run_trajectory(pm, path, force=[-20, -30, -60], torque=[-30, -30, 100])
print(f"{pm.name} along {len(res)} samples: {res.counts()}")

print(f"actuator   push max ({u.force})   pull max ({u.force})   leg length r_i ({u.length})")
for i in range(res.active.shape[1]):
    f, r = res.active[:, i], res.extensions[:, i]
    print(f"  F_a{i + 1}    {max(f.max(), 0.0):14.3f}   {max(-f.min(), 0.0):14.3f}   "
          f"{r.min():7.2f} .. {r.max():7.2f}")
print(f"largest |F_ci|: {np.abs(res.constraint).max():.3f} {u.force}; "
      f"largest |T_ri|: {np.abs(res.T_r).max():.2f} {u.force}.{u.length}")
print(f"condition number along the path: {res.condition_number.min():.3f} .. "
      f"{res.condition_number.max():.3f}")

res.to_csv("3rrprr_path.csv")
res.plot("3rrprr_fig5.png", title="3RRPRR along alpha = 8 sin 2pi t, beta = 6 sin(2pi t + 1), "
                                  "Zo = 70 + 20 t")
print("wrote 3rrprr_path.csv and 3rrprr_fig5.png")
