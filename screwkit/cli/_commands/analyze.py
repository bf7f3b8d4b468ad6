"""``screwkit analyze PM``: pose, mobility, Jacobian and statics of a parallel manipulator."""

from __future__ import annotations

import os
import sys

from ...legs._guards import (MAX_LOAD, MAX_NAME, MAX_STIFFNESS, MIN_STIFFNESS, parse_number,
                             shorten)
from ...errors import InputError
from .._types import path
from ...legs import point_label
from ._common import dump_json, fmt_num, fmt_vec

HELP = """Analyse a PM at a pose: legs, mobility, the solved pose (unified inverse displacement),
leg extensions, the unified Jacobian J = [J_a; J_c] and its condition number, and the statics
F_r = -(J^-1)^T [F; T] for a workload (F, T) at the platform centre o. Angles in degrees,
lengths, forces and torques in the model's units (the catalog's: cm, kN, kN.cm) or, with
--units SI, in m, N and N.m; every printed line names its unit."""


def parse_assignments(items, what: str, *, bound: float | None = None) -> dict:
    """``["alpha=5", "Zo=80"]`` -> ``{"alpha": 5.0, "Zo": 80.0}`` (InputError on bad items).

    Values are ASCII decimal numbers (no ``nan``, ``inf``, ``1_000`` or non-ASCII digits),
    finite, at most ``bound`` in magnitude; a name given twice is refused."""
    out = {}
    for item in items or ():
        name, sep, val = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise InputError(f"{what} {shorten(item)} must look like NAME=VALUE")
        if len(name) > MAX_NAME or not name.isidentifier():
            raise InputError(f"{what} {shorten(name)}: not a name (a dimension, pose parameter "
                             "or row label such as L, alpha, F_a1)")
        if name in out:
            raise InputError(f"{what} {name} is given twice")
        if "," in val and "=" in val:       # alpha=5,beta=2: a list where one is taken
            raise InputError(f"{what} {shorten(item)}: one NAME=VALUE each; repeat {what} for "
                             "each value")
        out[name] = parse_number(val, f"{what} {name}", bound=bound)
    return out


def parse_triple(text: str, what: str, *, bound: float | None = MAX_LOAD):
    """``"-20,-30,-60"`` -> three numbers (ASCII decimal, finite, at most ``bound``)."""
    parts = text.split(",")
    if len(parts) != 3:
        raise InputError(f"{what} {shorten(text)} must be three numbers X,Y,Z")
    return [parse_number(p, f"{what} {'XYZ'[k]}", bound=bound) for k, p in enumerate(parts)]


def add_pm_arguments(p, pose=True):
    """Arguments shared by analyze, check, trajectory and draw."""
    p.add_argument("pm", nargs="?", help="catalog PM name (3RRPRR, 2SPS+2SPR, ...); "
                   "optional with --model")
    p.add_argument("--model", metavar="FILE", type=path,
                   help="a YAML model file (schema of the catalog's pms:)")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a dimension, e.g. --set L=150 (repeatable)")
    if pose:
        p.add_argument("--pose", metavar="NAME=VALUE", action="append", default=[],
                       help="independent pose parameter, degrees for angles, e.g. --pose alpha=5 "
                            "(repeatable; default: the model's regular default pose)")


def add_load_arguments(p):
    p.add_argument("--force", metavar="FX,FY,FZ",
                   help="force at o, in the model's force unit (default: the model's declared "
                        "workload; --force alone means zero torque)")
    p.add_argument("--torque", metavar="TX,TY,TZ",
                   help="torque at o, in the model's force.length unit (default: the model's "
                        "declared workload; --torque alone means zero force)")


#: How the workload options are named in messages of the command line.
LOAD_OPTIONS = ("--force FX,FY,FZ", "--torque TX,TY,TZ")


def parse_load(args):
    """``(force, torque)`` of ``--force``/``--torque`` (one without the other: the other is
    zero), or ``(None, None)`` when neither is given (the model's declared workload)."""
    if args.force is None and args.torque is None:
        return None, None
    F = parse_triple(args.force, "--force") if args.force is not None else [0.0, 0.0, 0.0]
    T = parse_triple(args.torque, "--torque") if args.torque is not None else [0.0, 0.0, 0.0]
    return F, T


def require_load(args, model):
    """:func:`parse_load`, with the one-line error naming the options when neither is given
    and the model declares no workload."""
    from ...engine._workloads import no_workload_message
    F, T = parse_load(args)
    if F is None and getattr(model, "workload", None) is None:
        raise InputError(no_workload_message(model, LOAD_OPTIONS))
    return F, T


def workload_note(command, model, force, torque, res, what="workload") -> str:
    """``screwkit CMD: workload F = (..) kN, T = (..) kN.cm at o (command line)``."""
    u = model.units
    return (f"screwkit {command}: {what} F = {fmt_vec(force)} {u.force}, T = "
            f"{fmt_vec(torque)} {u.torque} at o ({load_source(res)})")


def load_source(res) -> str:
    """Where the workload of a result comes from, as the command line says it."""
    src = getattr(res, "workload_source", "") or ""
    return "command line" if src == "given" else src


def resolve_model(args):
    """Load the PM named on the command line (catalog name or --model file) with --set overrides."""
    from ...api import load_pm

    overrides = parse_assignments(args.set, "--set")
    path = args.model
    if path and "#" in path and not os.path.isfile(path):
        from ...pm._checks import split_path        # FILE#NAME: one PM of a multi-PM file
        path = split_path(path)[0] or path.split("#", 1)[0]
    if args.model and not os.path.isfile(path):
        why = "not a regular file" if os.path.exists(path) else "no such file"
        raise InputError(f"--model {shorten(args.model)}: {why}")
    if args.model:
        if args.pm and path != args.model:
            raise InputError(f"--model {shorten(args.model)} already names its PM: not also "
                             f"{shorten(args.pm)}")
        target = args.model if not args.pm else f"{args.model}#{args.pm}"
        return load_pm(target, overrides)
    if not args.pm:
        raise InputError("name a PM (see 'screwkit catalog') or give --model FILE")
    return load_pm(args.pm, overrides)


def register(sub):
    p = sub.add_parser("analyze", help="pose, mobility, Jacobian and statics of a PM",
                       description=HELP)
    add_pm_arguments(p)
    add_load_arguments(p)
    p.add_argument("--stiffness", metavar="ROW=K", action="append", default=[],
                   help="stiffness of a row of J by label (F_a1, T_c2 ...; force/length for "
                        "forces, torque/rad for couples), or 'model' for the model's "
                        "dynamics: stiffness: block; an indeterminate PM then takes the "
                        "compliance-weighted solution, every row its self-stresses load "
                        "given one (repeatable)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument("--units", choices=["model", "SI"], default="model",
                   help="units of the report (text and JSON): the model's (default) or SI "
                        "(m, N, N.m; needs pint)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...engine import analyze_pm

    # the values first (a typo fails at once), then the model
    given = getattr(args, "stiffness", [])
    if "model" in given:
        if len(given) > 1:
            raise InputError("--stiffness model takes the model's stiffnesses: give no ROW=K "
                             "with it")
        stiffness = "model"
    else:
        stiffness = parse_assignments(given, "--stiffness", bound=MAX_STIFFNESS) or None
        for name, k in (stiffness or {}).items():
            if not k >= MIN_STIFFNESS:
                raise InputError(f"--stiffness {name}: {k:g} is not a positive stiffness from "
                                 f"{MIN_STIFFNESS:g} to {MAX_STIFFNESS:g}")
    pose = parse_assignments(args.pose, "--pose")
    force, torque = parse_load(args)
    model = resolve_model(args)
    res = analyze_pm(model, pose, degrees=True, force=force, torque=torque, stiffness=stiffness)
    units = None if args.units == "model" else args.units
    missing = None
    if not res.has_workload:                         # kinematics and J print; statics cannot
        from ...engine._workloads import no_workload_message
        missing = no_workload_message(model, LOAD_OPTIONS)
    else:                                            # (an error is the one line on stderr)
        for w in res.warnings:                       # one line each, on stderr
            print(f"screwkit analyze: warning: {w}", file=sys.stderr)
    if stiffness is not None and not res.jacobian.indeterminacy:
        print("screwkit analyze: note: statically determinate here (no self-stress: statics "
              "alone fixes every row): the row stiffnesses do not change the values",
              file=sys.stderr)
    if args.json:
        d = res.to_dict(units)
        d["workload"]["source"] = load_source(res) or None
        if missing:
            d["error"] = {"type": "InputError", "message": missing}
        print(dump_json(d))
    else:
        print_text(res, units)
    if missing:
        print(f"screwkit analyze: error: {missing}", file=sys.stderr)
        return 2
    return 0


def print_text(res, units=None) -> None:
    """The text report of one pose, in the model's units or (``units="SI"``) in SI: every
    length, force and torque printed times the factor of :func:`output_scales`."""
    from ...engine._quality import describe_class
    from ...engine._report import output_scales, row_quantity, row_units, unit_row

    model, sol, mob, jac, st = res.model, res.solution, res.mobility, res.jacobian, res.statics
    ub, k = output_scales(model, units)
    kl, kf, kt = k["length"], k["force"], k["torque"]
    u = model.units if units is None else type(model.units)(ub["length"], ub["force"])
    kq = {"force": kf, "torque": kt}
    print(f"PM {model.name}  ({len(sol.legs)} legs, Euler order {model.order}, "
          f"independent {', '.join(model.independent)})")
    if getattr(model, "summary", ""):
        print(f"  {model.summary}")
    print("legs:")
    for i, leg in enumerate(sol.legs, 1):
        tag = "passive" if i - 1 in model.passive else leg.string.marked
        print(f"  {i}. {leg.name:<12} [{tag}]  A{i} = {fmt_vec(leg.A * kl)}  "
              f"a{i} = {fmt_vec(leg.a * kl)} {u.length}")
    print(f"mobility: {mob.dof} DOF ({mob.motion_type}); constraint rank {mob.constraint_rank} of "
          f"{mob.n_constraints} constraint wrenches; redundant {mob.redundant}; common {mob.common}; "
          f"Grubler-Kutzbach count {mob.gruebler}")
    if mob.finite:
        print(f"  finite motion type {mob.finite}")
    from ...engine._report import twist_space
    label, text = twist_space(mob, kl, u.length)
    print(f"  twist space here ({label}): {text}")
    p = sol.params_degrees()
    print(f"units: lengths {u.length}, forces {u.force}, torques {u.torque}, angles deg"
          + ("" if model.units.declared else " (the model declares no units)")
          + (f" (converted from the model's {model.units.length}, {model.units.force})"
             if units is not None else ""))
    print(f"pose (deg, {u.length}): " + "  ".join(
        f"{n}={fmt_num(p[n] * (kl if n in ('Xo', 'Yo', 'Zo') else 1.0))}"
        for n in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")))
    print(f"  closure residual {sol.residual:.2e} (length-normalised)")
    for n in sol.notes:
        print(f"  note: {n}")
    print(f"extensions r_i ({u.length}): " +
          "  ".join(f"r{i}={fmt_num(r * kl)}" for i, r in enumerate(sol.extensions, 1)))
    q = res.quality.as_dict(0)
    print(f"unified Jacobian J = [J_a; J_c] (rows [f; m] about O per unit effort), normalised "
          f"condition number "
          f"{jac.condition_number:.6g}" + (f"  SINGULAR ({jac.singularity_kind})" if jac.singular else ""))
    amp = q["force_amplification"]
    print(f"  conditioning: {describe_class(q['class'], q['condition_number'])}; trust level "
          f"{q['level']}" + (f", efforts up to {amp:.3g} times the load" if amp is not None
                             else "")
          + (f"; det J sign {q['det_sign']:+d} ({q['det_reference']} {q['home_det_sign']:+d})"
             if jac.n_rows == 6 else f"; J is {jac.n_rows}x6: no det J sign")
          + (f"  BEYOND A SINGULAR SURFACE FROM {q['det_reference'].upper()}"
             if q["beyond_singular_surface"] else ""))
    _print_transmission(res, kl, u.length)
    for r, row in zip(jac.rows, jac.J):
        q = row_quantity(r)
        print(f"  {' '.join(f'{x:10.5g}' for x in unit_row(row, q, k))}   leg {r.leg + 1} "
              f"{r.kind} {row_units(q, u.length)}")
    if not res.has_workload:
        print("statics: not computed: no workload (the model declares none; give --force "
              "and/or --torque)")
        return
    F, T = res.force * kf, res.torque * kt
    print(f"statics for F = {fmt_vec(F)} {u.force} and T = {fmt_vec(T)} {u.torque} at o "
          f"(workload: {load_source(res)}):")
    if st is None:
        print("  not solved: singular pose")
        return
    det = st.determined
    if st.indeterminate:
        how = "compliance-weighted" if res.stiffness is not None else "least-norm"
        print(f"  statically indeterminate: {st.indeterminacy} redundant rows; the values marked "
              f"* are not determined by statics ({how} solution)")
    for k, (r, v, vec) in enumerate(zip(jac.rows, st.values, st.vectors)):
        label = {"actuation": "active", "force": "constraint force", "couple": "constraint couple",
                 "screw": "constraint wrench"}[r.kind]
        where = ""
        if r.point is not None and r.member == "screw":
            where = (f" on the screw axis through {fmt_vec(r.point * kl)} {u.length}, pitch "
                     f"{fmt_num(r.pitch * kl)} {u.length}")
        elif r.point is not None:
            where = (" on the line through "
                     + (point_label(r.point_name) or f"{fmt_vec(r.point * kl)} {u.length}"))
        mark = " " if det[k] else "*"
        unit = u.of(row_quantity(r))
        vunit = u.torque if r.member == "couple" else u.force
        vk = kt if r.member == "couple" else kf
        print(f"  leg {r.leg + 1} {label:<17} {fmt_num(v * kq[row_quantity(r)]):>12}{mark} "
              f"{unit:<6} vector {fmt_vec(vec * vk)} {vunit}{where}")
    undet = [not all(det[k] for k in jac.leg_rows(i)) for i in range(len(st.T_r))]
    linear = [lg.actuated_joint.kind == "P" for lg in sol.legs]
    if any(linear):
        print(f"  T_ri, the moment of each linear leg's constraint wrench about its axis "
              f"({u.torque}): " +
              "  ".join(f"T_r{i}={fmt_num(t * kt)}{'*' if bad else ''}"
                        for i, (t, bad, lin) in enumerate(zip(st.T_r, undet, linear), 1) if lin))
    from ...engine._report import constraint_resultants, resultants_determined

    res_f, res_m = constraint_resultants(st, [lg.A for lg in sol.legs])
    res_det = resultants_determined(st, [lg.A for lg in sol.legs])
    print(f"  each leg's constraint resultant (independent of the basis of its rows): force "
          f"({u.force}) and moment about A_i ({u.torque})")
    for i in range(len(sol.legs)):
        bf, bm = ("" if ok else "*" for ok in res_det[i])
        print(f"  leg {i + 1} force ({u.force}) {fmt_vec(res_f[i] * kf)}{bf}  moment about "
              f"A{i + 1} ({u.torque}) {fmt_vec(res_m[i] * kt)}{bm}")
    print(f"  platform equilibrium residual {st.equilibrium_residual:.2e}")


def _print_transmission(res, kl: float, length: str) -> None:
    """The transmission and constraint indices of the pose (docs/design.md)."""
    d = res.indices.as_dict(0)

    def g(x):
        return "n/a" if x is None else f"{x:.4g}"

    def arm(x):
        return "" if x is None else f" (arm {fmt_num(x * kl)} {length})"
    print(f"  transmission: LTI {g(d['lti'])} = min(ITI {g(d['iti'])}, OTI {g(d['oti'])}); "
          f"CTI {g(d['cti'])}; smallest singular value {g(d['sigma_min'])} (all in [0, 1], "
          "0 at a singularity; docs/design.md)")
    for e in d["legs"]:
        print(f"    leg {e['leg']}: ITI {g(e['iti'])}{arm(e['input_arm'])}, "
              f"OTI {g(e['oti'])}{arm(e['output_arm'])}")
    if d["constraints"]:
        print("    constraint rows: " + ", ".join(
            f"{e['label']} CTI {g(e['cti'])}{arm(e['arm'])}" for e in d["constraints"])
            + ("  (n/a: a redundant row)" if any(e["cti"] is None for e in d["constraints"])
               else ""))
