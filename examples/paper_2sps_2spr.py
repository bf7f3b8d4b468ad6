"""The paper's second worked example: statics of the 2SPS+2SPR (Hu, Lu, Zhang, Yu, sections 4 and 5.1).

Square base of side L = 100 cm, rectangular platform 60 x 50 cm, SPS legs 1 and 4 and SPR
legs 2 and 3 (R axes along the platform diagonals), under the paper's workload
F = [-20, -30, -60] kN, T = [-30, -30, 100] kN.cm at o, at the pose alpha = 4, beta = 3,
gamma = 2 deg, Zo = 80 cm (intrinsic XYX). Prints the active forces F_ai, the two
constraint forces F_c2, F_c3 (through the S centres A_2, A_3) and how close the pose is to
the actuation singularity near home (alpha + gamma of about 17 deg at beta = 0, Zo = 80).

Run: python examples/paper_2sps_2spr.py
"""

import numpy as np

import screwkit

pm = screwkit.load_pm("2SPS+2SPR")
u = pm.units
res = screwkit.analyze(pm, {"alpha": 4, "beta": 3, "gamma": 2, "Zo": 80}, degrees=True,
                       force=[-20, -30, -60], torque=[-30, -30, 100])
sol, st, jac = res.solution, res.statics, res.jacobian

print(f"{pm.name}: {res.mobility.dof} DOF ({res.mobility.motion_type}); legs "
      + ", ".join(leg.name for leg in sol.legs))
print("pose: " + "  ".join(f"{k}={v:.4f}" for k, v in sol.params_degrees().items())
      + f"   (deg, {u.length})")
print("extensions r_i (" + u.length + "): " + "  ".join(f"{r:.4f}" for r in sol.extensions))
print()
print(f"active forces F_ai ({u.force}):  "
      + "  ".join(f"F_a{i + 1}={f:.3f}" for i, f in enumerate(st.active)))
for k, row in enumerate(jac.rows):
    if row.kind != "actuation":
        v, q = np.round(st.vectors[k], 4) + 0.0, np.round(row.point, 3) + 0.0
        print(f"constraint force {row.label} = ({v[0]:.4f}, {v[1]:.4f}, {v[2]:.4f}) {u.force} "
              f"through ({q[0]:.1f}, {q[1]:.1f}, {q[2]:.1f}), the centre of the S of leg "
              f"{row.leg + 1}")
print(f"T_ri ({u.force}.{u.length}): " + "  ".join(f"{np.round(t, 9) + 0.0:g}" for t in st.T_r)
      + "   (the constraint forces pass through A_i: no moment about the leg axes)")
amplification = np.abs(st.active).max() / np.linalg.norm([-20, -30, -60])
print(f"largest active force / |F| = {amplification:.2f}; normalised condition number "
      f"{jac.condition_number:.1f} ({res.level})")

# the actuation singularity near home: the condition number along alpha = gamma at beta = 0
print()
print("towards the actuation singularity (beta = 0, Zo = 80, alpha = gamma):")
a = np.radians([2.0, 4.0, 6.0, 8.0, 8.5])
scan = screwkit.analyze(pm, {"alpha": a, "beta": 0.0, "gamma": a, "Zo": 80.0})
for ai, c, f in zip(np.degrees(a), scan.jacobian.condition_number, scan.statics.active):
    print(f"  alpha = gamma = {ai:3.1f} deg: condition number {c:9.1f}, "
          f"largest |F_ai| {np.abs(f).max():8.1f} {u.force}")
assert st.equilibrium_residual < 1e-9 and np.all(np.abs(st.T_r) < 1e-9)
