"""``screwkit stiffness PM``: the Cartesian stiffness, compliance and deflection at a pose."""

from __future__ import annotations

import numpy as np

import sys

from ...errors import InputError
from ...legs._guards import MAX_STIFFNESS, MIN_STIFFNESS
from ...legs._guards import argtype
from .._types import path
from ._common import dump_json, fmt_num, fmt_vec
from .analyze import (LOAD_OPTIONS, add_load_arguments, add_pm_arguments, load_source,
                      parse_assignments, parse_load, resolve_model)

HELP = """The Cartesian stiffness of a PM at a pose, from its unified Jacobian J = [J_a; J_c] and
a stiffness for each row (actuator axial stiffness, stiffness of each constraint force and
couple): K = J_o^T diag(k) J_o about the platform centre o, in the order [v; w] -> [f; m]; the
deflection [dp_o; dtheta] of the platform under the workload (F, T) at o (rows without a
stiffness are rigid); the principal translational and rotational stiffnesses. The
stiffnesses are the model's 'dynamics: stiffness:' block, --mass FILE, or given here (model
units: force/length, torque/rad; from 1e-20 to 1e20); rows without one are rigid (zero
compliance). The pose's conditioning class (regular, near-singular, singular) is the one
analyze gives; at a singular pose the unrestrained directions are named. The workload is
--force/--torque (--force alone: zero torque) or the model's declared one; without any, K
and the principal stiffnesses print and the deflection is an error. Angles in degrees at the
command line."""

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
    k = argtype(_stiffness_value, "stiffness")
    p.add_argument("--mass", metavar="FILE", type=path,
                   help="a YAML file with a 'dynamics:' mapping whose 'stiffness:' gives the legs' "
                        "rows their stiffnesses (actuator, force, couple, or a beam; "
                        "docs/dynamics.md)")
    p.add_argument("--k-actuator", type=k, metavar="K",
                   help="stiffness of every actuator (force/length; torque/rad if rotary)")
    p.add_argument("--k-force", type=k, metavar="K",
                   help="stiffness of every constraint force row (force/length)")
    p.add_argument("--k-couple", type=k, metavar="K",
                   help="stiffness of every constraint couple row (torque/rad)")
    p.add_argument("--row", metavar="LABEL=K", action="append", default=[],
                   help="stiffness of one row of J by label (F_a1, T_c2, ...; repeatable)")
    p.add_argument("--geometric", action="store_true",
                   help="add the load-dependent (geometric) term of the workload as a preload: "
                        "the tangent stiffness")
    p.add_argument("--units", choices=["model", "SI"], default="model",
                   help="units of the report (text and JSON): the model's (default) or SI (m, "
                        "N, N.m); the stiffnesses and the workload given stay in the model's")
    p.add_argument("--json", action="store_true",
                   help="print JSON (keys stiffness, compliance, deflection, principal, units)")
    p.set_defaults(func=run)


def _stiffness_value(text) -> float:
    from ...legs._guards import parse_number
    x = parse_number(text, "value")
    if not MIN_STIFFNESS <= x <= MAX_STIFFNESS:
        raise InputError(f"{text.strip()} is not a positive stiffness from {MIN_STIFFNESS:g} to "
                         f"{MAX_STIFFNESS:g} (leave a row without one for a rigid row)")
    return x


def _check_rows(model, args) -> None:
    """--k-force / --k-couple / --k-actuator for rows the PM does not have: an error."""
    from ...engine._templates import labels_of as _labels, templates_of
    kinds = {r.kind for r in _labels(templates_of(model))}
    for opt, v, kind, what in (("--k-actuator", args.k_actuator, "actuation", "actuation"),
                               ("--k-force", args.k_force, "force", "constraint force"),
                               ("--k-couple", args.k_couple, "couple", "constraint couple")):
        if v is not None and kind not in kinds:
            raise InputError(f"{opt}: {model.name} has no {what} rows (its rows: "
                             f"{', '.join(r.label for r in _labels(templates_of(model)))})")


def run(args) -> int:
    from ...dynamics import stiffness

    from ...engine._report import output_scales
    model = resolve_model(args)
    units = None if args.units == "model" else args.units
    output_scales(model, units)             # (a model without units: refused before solving)
    _check_rows(model, args)
    force, torque = parse_load(args)
    if args.geometric and force is None and model.workload is None:
        from ...engine._workloads import no_workload_message
        raise InputError("--geometric takes the workload as a preload: "
                         + no_workload_message(model, LOAD_OPTIONS))
    res = stiffness(model, parse_assignments(args.pose, "--pose") or None, degrees=True,
                    params=args.mass, actuator=args.k_actuator, force_stiffness=args.k_force,
                    couple_stiffness=args.k_couple,
                    rows=parse_assignments(args.row, "--row", bound=MAX_STIFFNESS) or None,
                    force=force, torque=torque, geometric=args.geometric,
                    raise_on_singular=False)
    d = res.to_dict(units)
    if d["workload"] is not None:
        d["workload"]["source"] = load_source(res)
    missing = None
    if res.deflection is None:
        from ...engine._workloads import no_workload_message
        missing = "the deflection needs a workload: " + no_workload_message(model, LOAD_OPTIONS)
    hint = ("give the rows stiffnesses with --k-actuator, --k-force, --k-couple, --row "
            "LABEL=K, --mass FILE or the model's 'dynamics: stiffness:' block")
    if args.json:
        if missing:
            d["error"] = {"type": "InputError", "message": missing}
        if d["rigid_everywhere"]:
            d["hint"] = hint
        print(dump_json(d))
    else:
        _print(d, hint)
    cls = d["conditioning"]["class"]
    warned = cls in ("near-singular", "singular") and not missing
    if warned:
        print(f"screwkit stiffness: warning: {cls} pose (normalised condition number "
              f"{d['conditioning']['condition_number']:.3g})" + (
                  ": unrestrained along " + "; ".join(x["description"] for x in
                                                      d["unrestrained"])
                  if d["unrestrained"] else ": the deflection is large and sensitive"),
              file=sys.stderr)
    # the pose's own warnings, as analyze prints them (the efforts' trust level, the
    # assembly mode, the side of the base), but the class said just above
    for w in res.analysis.warnings:
        if not (warned and w.startswith(f"{cls} pose:")):
            print(f"screwkit stiffness: warning: {w}", file=sys.stderr)
    for w in d["warnings"]:                   # the stiffness's own: stability, large deflection
        print(f"screwkit stiffness: warning: {w}", file=sys.stderr)
    if missing:
        print(f"screwkit stiffness: error: {missing}", file=sys.stderr)
        return 2
    return 0


def _print(d, hint) -> None:
    u = d["units"]
    print(f"PM {d['pm']}: pose " + "  ".join(f"{k}={fmt_num(v)}" for k, v in d["pose"].items())
          + f" (deg, {u['length']}); o = {fmt_vec(d['o'])} {u['length']}"
          + (" (converted from the model's {length}, {force})".format(**u["converted_from"])
             if "converted_from" in u else ""))
    c = d["conditioning"]
    print(f"conditioning: {c['class']} (normalised condition number "
          f"{c['condition_number']:.3g}, as analyze)")
    print("row stiffnesses: " + ", ".join(
        f"{r['label']} " + ("rigid" if r["rigid"] else f"{r['stiffness']:.6g} {r['unit']}")
        for r in d["rows"]))
    for n in d["notes"]:
        print(f"  note: {n}")
    if d["rigid_everywhere"]:
        print(f"  ({hint})")
    s = u["stiffness"]
    what = "tangent stiffness K + K_g" if "geometric" in d else "stiffness K"
    if d["stiffness"] is None:
        print(f"{what} about o: infinite in every direction (every row is rigid)")
    else:
        print(f"{what} about o of the compliant rows, [v; w] -> [f; m], rank {d['rank']} "
              f"(blocks f/v {s['f_per_v']}, f/w {s['f_per_w']}, m/v {s['m_per_v']}, m/w "
              f"{s['m_per_w']}):")
        for row in np.asarray(d["stiffness"]):
            print("  " + " ".join(f"{x:13.6g}" for x in row))
    for x in d["unrestrained"]:
        print(f"unrestrained (no row resists it): {x['description']}")
    if d["deflection"] is not None:
        F, T = d["workload"]["force"], d["workload"]["torque"]
        df = d["deflection"]
        print(f"deflection under F = {fmt_vec(F)} {u['force']}, T = {fmt_vec(T)} {u['torque']} "
              f"at o (workload: {d['workload']['source']}):")
        if d["load_on_unrestrained"]:
            print("  the workload works on an unrestrained direction: the legs cannot hold "
                  "it (no static equilibrium); below, the deflection of the held directions")
        print(f"  translation of o {fmt_vec(df['translation'])} "
              f"{u['deflection']['translation']}; rotation {fmt_vec(df['rotation'])} rad")
    for which, key, un in (("translational", "directions", u["principal"]["translational"]),
                           ("rotational", "axes", u["principal"]["rotational"])):
        p = d["principal"][which]
        parts = [f"{format(k, '.6g') if np.isfinite(k) else 'rigid'} along {fmt_vec(v, 4)}"
                 for k, v in zip(p["stiffness"], np.asarray(p[key]))]
        print(f"principal {which} stiffness [{un}]: " + "; ".join(parts))
    print(f"  (principal stiffnesses: {d['principal']['definition']})")
