"""The paper's first worked example: statics of the 3RRPRR (Hu, Lu, Zhang, Yu, sections 3 and 5.1).

Equilateral base of side L = 120 cm, platform of side l = 60 cm, three RRPRR legs with a
linear actuator, under the paper's workload F = [-20, -30, -60] kN, T = [-30, -30, 100] kN.cm
at the platform centre o, at the pose alpha = 5, beta = -3 deg, Zo = 80 cm (intrinsic XYX
Euler angles). Prints the pose, the leg extensions, the active forces F_ai, the constraint
forces F_ci as vectors on their lines, the torques T_ri and checks of the balance.

Run: python examples/paper_3rrprr.py
"""

import numpy as np

import screwkit

pm = screwkit.load_pm("3RRPRR")                       # catalog model: cm, kN
u = pm.units
res = screwkit.analyze(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True,
                       force=[-20, -30, -60], torque=[-30, -30, 100])
sol, st, jac = res.solution, res.statics, res.jacobian

print(f"{pm.name}: {res.mobility.dof} DOF ({res.mobility.motion_type}), units {u.length}, {u.force}")
pose = sol.params_degrees()
print("pose: " + "  ".join(f"{k}={v:.4f}" for k, v in pose.items())
      + f"   (deg, {u.length}; gamma = alpha and Xo, Yo follow from the legs)")
print("extensions r_i (" + u.length + "): " + "  ".join(f"{r:.4f}" for r in sol.extensions))
print(f"normalised condition number of J: {jac.condition_number:.4f} ({res.level})")
print()
print(f"active forces F_ai ({u.force}; > 0 pushes the platform away from A_i):")
for i, f in enumerate(st.active):
    print(f"  F_a{i + 1} = {f:9.4f}")
print(f"constraint forces F_ci as vectors ({u.force}) on their lines (R1^R5: where R1 meets R5):")
for k, row in enumerate(jac.rows):
    if row.kind == "actuation":
        continue
    v, q = np.round(st.vectors[k], 4) + 0.0, np.round(row.point, 3) + 0.0
    print(f"  {row.label} = ({v[0]:8.4f}, {v[1]:8.4f}, {v[2]:8.4f})  on the line through "
          f"({q[0]:.3f}, {q[1]:.3f}, {q[2]:.3f}) {u.length}, the point {row.point_name}")
print(f"torques T_ri about the leg axes ({u.force}.{u.length}): "
      + "  ".join(f"T_r{i + 1}={t:.3f}" for i, t in enumerate(st.T_r)))

# checks: the leg wrenches balance the workload, and each leg is in equilibrium with its
# own actuator (its wrench does no work on its passive joints)
print()
print(f"platform equilibrium residual: {st.equilibrium_residual:.1e}")
worst = 0.0
for i, leg in enumerate(sol.legs):
    work = leg.twists @ st.leg_wrenches[i]      # W . V_j: kN.cm on an R joint, kN on the P
    passive = np.delete(work, leg.actuated_index)
    worst = max(worst, float(np.abs(passive).max()))
    assert np.isclose(work[leg.actuated_index], st.active[i], rtol=1e-9)   # = F_ai on the P
print(f"largest reciprocal product of a leg wrench with a passive joint: {worst:.1e} "
      f"(0: each leg balances its own actuator)")
assert st.equilibrium_residual < 1e-9 and worst < 1e-9 * np.abs(st.leg_wrenches).max()
