"""``screwkit export PM --urdf OUT.urdf``: the PM's tree as URDF, loop closures beside it."""

from __future__ import annotations

from .._types import output, path
from ._common import dump_json

HELP = """Export a PM for other tools, in the units each format defines. --urdf writes the
spanning tree of the closed-loop model (every leg a branch from the base, leg 1 carrying the
platform, simple visual geometry, the home pose) in URDF's metres and kilograms, with the
link inertias of the model's 'dynamics:' block or --mass FILE (none without either: the
links are massless, and the output says so), and, beside it, OUT.closures.json: the loop
closures (metres), which a few lines of Pinocchio turn into RigidConstraintModel objects
(docs/pinocchio.md). The model must declare its units (they are converted)."""


def register(sub):
    p = sub.add_parser("export", help="export a PM as URDF (tree + loop closures)",
                       description=HELP)
    p.add_argument("pm", nargs="?", help="catalog PM name (see 'screwkit catalog')")
    p.add_argument("--model", type=path, metavar="FILE", help="a YAML model file")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a dimension, e.g. --set L=150 (repeatable)")
    p.add_argument("--urdf", type=output, required=True, metavar="OUT.urdf",
                   help="the URDF file to write (OUT.closures.json is written beside it)")
    p.add_argument("--mass", metavar="FILE", type=path,
                   help="a YAML file with a 'dynamics:' mapping: the link masses and inertias "
                        "(default: the model's own dynamics: block)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...interop import closures, write_urdf
    from ...interop._si import si_bodies
    from .analyze import resolve_model

    pm = resolve_model(args)
    params = None
    if args.mass:
        from ...pm import dynamics_for
        params = dynamics_for(pm, args.mass)
    urdf, side = write_urdf(pm, args.urdf, params)
    loops = closures(pm)
    bodies, note = si_bodies(pm, params)
    if args.json:
        print(dump_json({"urdf": urdf, "closures": side, "pm": pm.name,
                         "joints": sum(len(lg.joints) for lg in pm.home_legs),
                         "constraints": len(loops["constraints"]),
                         "actuated_joints": loops["actuated_joints"],
                         "length_unit": "m", "mass_unit": "kg",
                         "massive_links": [b.name for b in bodies], "inertias": note}))
        return 0
    n = sum(len(lg.joints) for lg in pm.home_legs)
    print(f"wrote {urdf} ({pm.name}: {len(pm.home_legs)} legs, {n} joints, lengths in m, "
          f"masses in kg) and {side} ({len(loops['constraints'])} loop closures, "
          f"{loops['contact_type']})")
    print(f"  inertias: {note}" + (f" ({len(bodies)} massive links)" if bodies else ""))
    return 0
