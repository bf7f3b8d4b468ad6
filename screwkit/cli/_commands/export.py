"""``screwkit export PM --urdf OUT.urdf | --mjcf OUT.xml``: the PM for other tools."""

from __future__ import annotations

import sys

from ...errors import InputError
from .._types import output, path
from ._common import dump_json
from .analyze import parse_assignments

HELP = """Export a PM for other tools, in the units each format defines (SI: m, kg, s; the model's
declared units are converted, so a model without units cannot be exported). --urdf writes the
spanning tree of the closed-loop model (every leg a branch from the base, leg 1 carrying the
platform, simple visual geometry, the home pose) with the link inertias of the model's
'dynamics:' block or --mass FILE (none without either: the links are massless, and the
output says so), and, beside it, OUT.closures.json: the loop closures, which a few lines of
Pinocchio turn into RigidConstraintModel objects (docs/pinocchio.md). --mjcf writes the same
tree for MuJoCo: an S as a ball joint, a U as two hinges, the loops closed by weld equality
constraints, the masses and inertias of the model's dynamics: block (or --mass FILE;
--massless for none), one motor per actuator, qpos0 at home and keyframe 0 at --pose
(default: the model's default pose), solved by screwkit (docs/pinocchio.md)."""


def register(sub):
    p = sub.add_parser("export", help="export a PM as URDF (tree + loop closures) or MJCF",
                       description=HELP)
    p.add_argument("pm", nargs="?", help="catalog PM name (see 'screwkit catalog')")
    p.add_argument("--model", type=path, metavar="FILE", help="a YAML model file")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a dimension, e.g. --set L=150 (repeatable)")
    p.add_argument("--urdf", type=output, metavar="OUT.urdf",
                   help="the URDF file to write (OUT.closures.json is written beside it)")
    p.add_argument("--mjcf", type=output, metavar="OUT.xml", help="the MJCF file to write")
    p.add_argument("--pose", metavar="NAME=VALUE", action="append", default=[],
                   help="MJCF: the pose of keyframe 0, degrees for angles (repeatable; default: "
                        "the model's default pose)")
    p.add_argument("--mass", type=path, metavar="FILE",
                   help="a YAML file with a 'dynamics:' mapping: the links' masses and "
                        "inertias (default: the model's own block)")
    p.add_argument("--massless", action="store_true",
                   help="MJCF: no masses (every body at MuJoCo's bound mass, 1e-6 kg)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from ...interop import closures, write_mjcf, write_urdf
    from ...interop._si import si_bodies
    from .analyze import resolve_model

    if not (args.urdf or args.mjcf):
        raise InputError("name what to write: --urdf OUT.urdf and/or --mjcf OUT.xml")
    if not args.mjcf and (args.pose or args.massless):
        given = " and ".join(o for o, v in (("--pose", args.pose), ("--massless", args.massless))
                             if v)
        raise InputError(f"{given} given: --pose and --massless are options of --mjcf (its "
                         "keyframe and masses); the URDF has neither")
    if args.mass and args.massless:
        raise InputError("give either --mass FILE or --massless, not both")
    if args.urdf and args.mjcf:
        _distinct_outputs(args.urdf, args.mjcf)
    pose = parse_assignments(args.pose, "--pose")
    pm = resolve_model(args)
    params = None
    if args.mass:
        from ...pm import dynamics_for
        params = dynamics_for(pm, args.mass)
    out, lines = {"pm": pm.name}, []
    # the MJCF first (it is the one with more to check: masses, motors), so that a failure
    # writes nothing; a URDF failing after it takes the MJCF written away again
    if args.mjcf:
        info = write_mjcf(pm, args.mjcf, pose=pose or None, degrees=True,
                          params=params if params is not None else None,
                          massless=args.massless)
        out["mjcf"] = info
        out["warnings"] = _keyframe_warnings(pm, info["pose"])
        shown = ", ".join(f"{k}={info['pose'][k]:.6g}" for k in pm.independent)
        mjcf_line = (f"wrote {info['path']} ({pm.name}: {info['joints']} joints, "
                     f"{info['loops']} loop welds, {info['actuators']} motors; SI units; "
                     f"keyframe 0 at {shown}; masses: "
                     + ("none (--massless)" if args.massless else
                        f"{args.mass}" if args.mass else "the model's dynamics: block") + ")")
    try:
        if args.urdf:
            urdf, side = write_urdf(pm, args.urdf, params)
            loops = closures(pm)
            bodies, note = si_bodies(pm, params)
            n = sum(len(lg.joints) for lg in pm.home_legs)
            out.update({"urdf": urdf, "closures": side, "joints": n,
                        "constraints": len(loops["constraints"]),
                        "actuated_joints": loops["actuated_joints"], "length_unit": "m",
                        "mass_unit": "kg", "massive_links": [b.name for b in bodies],
                        "inertias": note})
            n3 = sum(c.get("contact_type") == "CONTACT_3D" for c in loops["constraints"])
            lines.append(f"wrote {urdf} ({pm.name}: {len(pm.home_legs)} legs, {n} joints, lengths "
                         f"in m, masses in kg) and {side} ({len(loops['constraints'])} loop "
                         f"closures, {loops['contact_type']}"
                         + (f"; {n3} of them parallelogram loops, CONTACT_3D" if n3 else "") + ")")
            lines.append(f"  inertias: {note}" + (f" ({len(bodies)} massive links)" if bodies
                                                  else ""))
    except Exception:
        if args.mjcf:
            Path(args.mjcf).unlink(missing_ok=True)
        raise
    if args.mjcf:
        lines.append(mjcf_line)
        for w in out["warnings"]:
            print(f"screwkit export: warning: keyframe 0: {w}", file=sys.stderr)
    if args.json:
        print(dump_json(out))
        return 0
    for line in lines:
        print(line)
    return 0


def _keyframe_warnings(pm, pose_deg) -> list:
    """What ``analyze`` warns of at the MJCF's keyframe 0 (a singular pose, a mirror or
    another assembly mode, a near-singular one, limits)."""
    from ...engine import analyze
    an = analyze(pm, {k: pose_deg[k] for k in pm.independent}, degrees=True,
                 raise_on_singular=False)
    out = list(an.warnings)
    if an.singular and not any(w.startswith("singular") for w in out):
        out.insert(0, f"singular pose (normalised condition number "
                      f"{float(an.jacobian.condition_number):.3g})")
    return out


def _distinct_outputs(urdf, mjcf) -> None:
    """The MJCF must not overwrite the URDF or its closures sidecar."""
    from pathlib import Path

    u = Path(urdf).resolve()
    side = u.with_name(u.stem + ".closures.json")
    if Path(mjcf).resolve() in (u, side):
        raise InputError(f"--mjcf {mjcf} would overwrite what --urdf writes ({urdf} and "
                         f"{side.name}): give another file name")
