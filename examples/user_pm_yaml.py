"""A new PM defined in YAML: a 3-PRS with vertical linear actuators, its own leg type included.

The leg type PRS/mine: P vertical at the base (actuated), R tangent to the base circle above
it, S at the platform. By the observation rules its one constraint force passes through the
S centre (rule 2), is perpendicular to P1 (rule 1, so horizontal) and meets or is parallel
to R2 (rule 2): the horizontal line through the S centre parallel to R2. Three such forces
leave the platform 3 DOF: a translation along Z and two rotations (1T2R).

The script writes the model to my_3prs.yaml in the working folder, loads it, and prints
the legs' constraint forces, the mobility and the statics at a pose. The same file works
at the command line: screwkit analyze 3PRS --model my_3prs.yaml --pose alpha=4 ...

Run: python examples/user_pm_yaml.py
"""

from pathlib import Path

import screwkit

MODEL = """\
units: {length: mm, force: N}
legs:
  - name: PRS/mine
    string: _PRS
    summary: vertical linear actuator at the base, R tangent to the base circle, S at the platform
    joints:
      - {axis: base.Z}
      - {axis: base.tangent, at: {offset: A, along: base.Z, fraction: 0.4}}
      - {at: a}
    expect:
      forces: 1
      couples: 0
      force_lines: [{through: a, parallel: R2}]
pms:
  3PRS:
    summary: 3-PRS with vertical actuators (a user model)
    dimensions: {R: 200, r: 80}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [PRS/mine, PRS/mine, PRS/mine]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: 250}
    pose: {alpha: 4, beta: -3, Zo: 250}
    dof: 3
    motion: 1T2R
"""

path = Path("my_3prs.yaml")
path.write_text(MODEL, encoding="utf-8")
# every problem of the file at once (the JSON Schema, the leg's rules, the PM), each with
# its line: the same as `screwkit model check my_3prs.yaml`
from screwkit.pm import check_model_file  # noqa: E402

problems = check_model_file(path, load=screwkit.load_pm)
print(f"{path}: " + ("valid" if not problems else "; ".join(map(str, problems))))
pm = screwkit.load_pm(f"{path}#3PRS")
u = pm.units
print(f"{pm.name}: independent {', '.join(pm.independent)}; units {u.length}, {u.force}")

res = screwkit.analyze(pm, {"alpha": 4, "beta": -3, "Zo": 250}, degrees=True,
                       force=[0, 0, -500], torque=[0, 0, 0])     # 500 N down at o
m = res.mobility
print(f"mobility: {m.dof} DOF ({m.motion_type}); {m.n_constraints} constraint forces, "
      f"{m.redundant} redundant")
for i, leg in enumerate(res.solution.legs):
    c = leg.analyze().constraints[0]
    print(f"  leg {i + 1}: {c.describe()}")
print("actuator strokes from home (" + u.length + "): "
      + "  ".join(f"{q:.3f}" for q in res.solution.actuator_values))
print(f"active forces F_ai ({u.force}): " + "  ".join(f"{f:.2f}" for f in res.statics.active))
print(f"constraint forces F_ci ({u.force}): "
      + "  ".join(f"{f:.2f}" for f in res.statics.constraint))
print(f"platform equilibrium residual {res.statics.equilibrium_residual:.1e}; "
      f"condition number {res.jacobian.condition_number:.2f}")
# by hand: each F_ai is the vertical component of its leg's actuation force (the P joint is
# vertical) and every constraint force is horizontal (rule 1), so the vertical balance of the
# platform gives F_a1 + F_a2 + F_a3 = 500 N exactly
print(f"F_a1 + F_a2 + F_a3 = {res.statics.active.sum():.6f} {u.force} (the 500 N load)")
assert m.dof == 3 and m.motion_type == "1T2R"
assert abs(res.statics.active.sum() - 500.0) < 1e-9 * 500.0
