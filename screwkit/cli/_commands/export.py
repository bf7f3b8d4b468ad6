"""``screwkit export PM --urdf OUT.urdf``: the PM's tree as URDF, loop closures beside it."""

from __future__ import annotations

from .._types import output, path
from ._common import dump_json

HELP = """Export a PM for other tools. --urdf writes the spanning tree of the closed-loop
model (every leg a branch from the base, leg 1 carrying the platform, simple visual
geometry, the home pose, lengths in the model's unit) and, beside it, OUT.closures.json:
the loop closures, which a few lines of Pinocchio turn into RigidConstraintModel objects
(docs/pinocchio.md)."""


def register(sub):
    p = sub.add_parser("export", help="export a PM as URDF (tree + loop closures)",
                       description=HELP)
    p.add_argument("pm", nargs="?", help="catalog PM name (see 'screwkit catalog')")
    p.add_argument("--model", type=path, metavar="FILE", help="a YAML model file")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a dimension, e.g. --set L=150 (repeatable)")
    p.add_argument("--urdf", type=output, required=True, metavar="OUT.urdf",
                   help="the URDF file to write (OUT.closures.json is written beside it)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...interop import closures, write_urdf
    from .analyze import resolve_model

    pm = resolve_model(args)
    urdf, side = write_urdf(pm, args.urdf)
    loops = closures(pm)
    if args.json:
        print(dump_json({"urdf": urdf, "closures": side, "pm": pm.name,
                         "joints": sum(len(lg.joints) for lg in pm.home_legs),
                         "constraints": len(loops["constraints"]),
                         "actuated_joints": loops["actuated_joints"],
                         "length_unit": pm.units.length}))
        return 0
    n = sum(len(lg.joints) for lg in pm.home_legs)
    n3 = sum(c.get("contact_type") == "CONTACT_3D" for c in loops["constraints"])
    print(f"wrote {urdf} ({pm.name}: {len(pm.home_legs)} legs, {n} joints, lengths in "
          f"{pm.units.length}) and {side} ({len(loops['constraints'])} loop closures, "
          f"{loops['contact_type']}" + (f"; {n3} of them parallelogram loops, CONTACT_3D"
                                        if n3 else "") + ")")
    return 0
