"""``screwkit stiffness PM``: the Cartesian stiffness, compliance and deflection at a pose."""

from __future__ import annotations

import numpy as np

from ._common import dump_json, fmt_num, fmt_vec
from .analyze import (add_load_arguments, add_pm_arguments, parse_assignments, parse_triple,
                      resolve_model)

HELP = """The Cartesian stiffness of a PM at a pose, from its unified Jacobian J = [J_a; J_c] and
a stiffness for each row (actuator axial stiffness, stiffness of each constraint force and
couple): K = J_o^T diag(k) J_o about the platform centre o, in the order [v; w] -> [f; m]; the
deflection [dp_o; dtheta] of the platform under the workload (F, T) at o (rows without a
stiffness are rigid); the principal translational and rotational stiffnesses. The
stiffnesses are the model's 'dynamics: stiffness:' block, --mass FILE, or given here (model
units: force/length, torque/rad). Angles in degrees at the command line."""

EPILOG = """examples:
  screwkit stiffness 3RRPRR --pose alpha=5 --pose beta=-3 --k-actuator 2000 --k-force 5000
  screwkit stiffness --model stewart.yaml --force 0,0,-1 --json"""


def register(sub):
    import argparse

    p = sub.add_parser("stiffness", help="Cartesian stiffness and deflection at a pose",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_pm_arguments(p)
    add_load_arguments(p)
    p.add_argument("--mass", metavar="FILE",
                   help="a YAML file with a 'dynamics:' mapping whose 'stiffness:' gives the legs'")
    p.add_argument("--k-actuator", type=float, metavar="K",
                   help="stiffness of every actuator (force/length; torque/rad if rotary)")
    p.add_argument("--k-force", type=float, metavar="K",
                   help="stiffness of every constraint force row (force/length)")
    p.add_argument("--k-couple", type=float, metavar="K",
                   help="stiffness of every constraint couple row (torque/rad)")
    p.add_argument("--row", metavar="LABEL=K", action="append", default=[],
                   help="stiffness of one row of J by label (F_a1, T_c2, ...; repeatable)")
    p.add_argument("--geometric", action="store_true",
                   help="add the load-dependent (geometric) term of the workload as a preload: "
                        "the tangent stiffness")
    p.add_argument("--json", action="store_true",
                   help="print JSON (keys stiffness, compliance, deflection, principal, units)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...dynamics import stiffness

    model = resolve_model(args)
    res = stiffness(model, parse_assignments(args.pose, "--pose") or None, degrees=True,
                    params=args.mass, actuator=args.k_actuator, force_stiffness=args.k_force,
                    couple_stiffness=args.k_couple,
                    rows=parse_assignments(args.row, "--row") or None,
                    force=parse_triple(args.force, "--force"),
                    torque=parse_triple(args.torque, "--torque"), geometric=args.geometric)
    d = res.to_dict()
    if args.json:
        print(dump_json(d))
        return 0
    u = d["units"]
    print(f"PM {d['pm']}: pose " + "  ".join(f"{k}={fmt_num(v)}" for k, v in d["pose"].items())
          + f" (deg, {u['length']}); o = {fmt_vec(d['o'])} {u['length']}")
    print("row stiffnesses: " + ", ".join(
        f"{r['label']} " + ("rigid" if r["rigid"] else f"{fmt_num(r['stiffness'])} {r['unit']}")
        for r in d["rows"]))
    for n in d["notes"]:
        print(f"  note: {n}")
    s = u["stiffness"]
    what = "tangent stiffness K + K_g" if "geometric" in d else "stiffness K"
    print(f"{what} about o, [v; w] -> [f; m], rank {d['rank']} (blocks f/v {s['f_per_v']}, "
          f"f/w {s['f_per_w']}, m/v {s['m_per_v']}, m/w {s['m_per_w']}):")
    for row in np.asarray(d["stiffness"]):
        print("  " + " ".join(f"{x:13.6g}" for x in row))
    F, T = d["workload"]["force"], d["workload"]["torque"]
    df = d["deflection"]
    print(f"deflection under F = {fmt_vec(F)} {u['force']}, T = {fmt_vec(T)} {u['torque']} at o:")
    if not d["restrained"]:
        print("  the legs do not hold the platform against this workload (no deflection)")
    print(f"  translation of o {fmt_vec(df['translation'])} {u['deflection']['translation']}; "
          f"rotation {fmt_vec(df['rotation'])} rad")
    for which, key, un in (("translational", "directions", u["principal"]["translational"]),
                           ("rotational", "axes", u["principal"]["rotational"])):
        p = d["principal"][which]
        parts = [f"{fmt_num(k) if np.isfinite(k) else 'rigid'} along {fmt_vec(v, 4)}"
                 for k, v in zip(p["stiffness"], np.asarray(p[key]))]
        print(f"principal {which} stiffness [{un}]: " + "; ".join(parts))
    return 0
