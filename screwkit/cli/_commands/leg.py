"""``screwkit leg STRING``: analyse one leg (catalog variant or bare string)."""

from __future__ import annotations

import sys

from ...legs._guards import MAX_SEED
from .._types import figure, integer, path
from ._common import dump_json, fmt_num, fmt_vec

HELP = """Analyse one leg: a catalog variant by name (UPU/couple, RRPRR) or a bare leg
string with a generic geometry (an '_' marks the actuated joint: RR_PRR)."""


def register(sub):
    p = sub.add_parser("leg", help="analyse one leg's constraint and actuation wrenches",
                       description=HELP)
    p.add_argument("string", help="catalog name or leg string, e.g. RRPRR, UPU/couple, S_PR")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument("--seed", type=integer(0, MAX_SEED), default=0,
                   help="seed of the generic geometry of a bare string (default 0)")
    p.add_argument("--model", type=path, help="a YAML file with extra leg types (same schema as the catalog)")
    p.add_argument("--draw", metavar="FILE", type=figure,
                   help="also save a 3D drawing of the leg and its wrenches (PNG; needs "
                        "matplotlib)")
    p.set_defaults(func=run)


def leg_report(res) -> dict:
    """JSON-ready description of a :class:`~screwkit.legs.LegAnalysis`."""
    leg = res.leg

    def member(c):
        d = {"kind": c.kind, "direction": c.direction, "pitch": c.pitch,
             "rules": [{"joint": n.joint, "rule": n.rule, "text": n.text, "holds": n.holds}
                       for n in c.rules],
             "reciprocity": c.reciprocity}
        if c.kind != "couple":
            d["point"] = c.point
            d["point_name"] = c.point_name
        d["wrench"] = c.wrench.vector
        return d

    act = res.actuation
    return {
        "leg": leg.name,
        "string": leg.string.marked,
        "joints": [{"name": j.name, "kind": j.kind, "origin": j.spec.origin,
                    "position": j.spec.position, "actuated": j.actuated,
                    "direction": j.direction, "point": j.point,
                    **({"pitch": j.pitch} if j.kind == "H" else {}),
                    **({"bar": j.bar, "hinge": j.hinge} if j.bar is not None else {})}
                   for j in leg.joints],
        "end_points": {"A": leg.A, "a": leg.a},
        # (a leg alone declares no length unit: its lengths are the leg's own; placed in a
        # PM, the PM's)
        "length_unit": None,
        "connectivity": res.connectivity,
        "dependent_joints": list(res.dependent_joints),
        "singular_values": res.system.singular_values,
        "constraints": [member(c) for c in res.constraints],
        "agrees_with_rules": res.agrees(),
        "actuation": None if act is None else {**member(act.member), "joint": act.joint,
                                               "scale": act.scale, "wrench": act.wrench},
    }


def run(args) -> int:
    import screwkit
    from ...pm import Catalog, default_catalog, load_catalog

    cat = default_catalog()
    if args.model:
        extra = load_catalog(args.model)
        cat = Catalog({**cat.legs, **extra.legs}, cat.table1, cat.pms, cat.source)
    res = screwkit.leg(args.string, seed=args.seed, catalog=cat).analyze()
    if args.seed and cat.find_leg(args.string) is not None:
        print(f"screwkit leg: note: {args.string} is the catalog variant "
              f"{cat.find_leg(args.string).name}: its geometry is the catalog's, --seed "
              "(generic geometry of a bare string) is not used", file=sys.stderr)
    figure = None
    if getattr(args, "draw", None):
        from ...viz import draw_leg
        draw_leg(res.leg, res, out=args.draw)
        figure = str(args.draw)
    if args.json:
        report = leg_report(res)
        if figure:
            report["figure"] = figure
        spec = cat.find_leg(args.string)
        probs = spec.check_expectation(res) if spec and spec.expect else []
        report["expectation"] = None if not (spec and spec.expect) else \
            {"holds": not probs, "problems": list(probs)}
        print(dump_json(report))
        return 1 if probs else 0
    leg = res.leg
    spec = cat.find_leg(args.string)
    origin = "catalog variant" if spec else "bare string, generic geometry (seed %d)" % args.seed
    print(f"leg {leg.name}  [{leg.string.marked}]  ({origin})")
    if spec and spec.summary:
        print(f"  {spec.summary}")
    print(f"  A = {fmt_vec(leg.A)}   a = {fmt_vec(leg.a)}   (lengths in the leg's own unit: "
          "a leg alone declares none; placed in a PM, the PM's)")
    print("equivalent chain:")
    for j in leg.joints:
        src = "" if j.spec.origin == j.kind else f"  (part of {j.spec.origin}{j.spec.position})"
        if j.spec.parallelogram:
            src = (f"  (parallelogram: translation normal to its bar {fmt_vec(j.bar)} and "
                   f"hinges {fmt_vec(j.hinge)})")
        elif j.kind == "H":
            src += f"  pitch {fmt_num(j.pitch)}/rad"
        act = "  <- actuated" if j.actuated else ""
        print(f"  {j.name:<5} {j.kind}  axis {fmt_vec(j.direction)}  point {fmt_vec(j.point)}{src}{act}")
    dep = f"; dependent joints: {', '.join(res.dependent_joints)}" if res.dependent_joints else ""
    print(f"connectivity: {res.connectivity} of {len(leg.joints)} joints{dep}")
    print(f"singular values (normalised): {' '.join(fmt_num(s, 4) for s in res.system.singular_values)}")
    print(f"constraint wrenches: {res.summary()}")
    for i, c in enumerate(res.constraints, 1):
        print(f"  {i}. {c.describe()}")
        for n in c.rules:
            print(f"       - {n}")
    probs = []
    if spec and spec.expect:           # (counts, lines, axes: words or not)
        words = spec.expect.get("words") or ", ".join(
            f"{spec.expect[k]} {k}" for k in ("forces", "couples", "screws") if k in spec.expect)
        print(f"catalog expects: {words}")
        probs = spec.check_expectation(res)
        print("  expectation holds" if not probs else "  EXPECTATION FAILS: " + "; ".join(probs))
    act = res.actuation
    if act is None:
        print("actuation wrench: none (the actuated joint depends on the passive joints)")
    else:
        print(f"actuation wrench of {act.joint}: {act.member.describe()}  "
              f"(unit reciprocal product; scale {fmt_num(act.scale)})")
        for n in act.member.rules:
            print(f"       - {n}")
    if figure:
        print(f"drawing saved to {figure}")
    if probs:                          # (as check and validate: a disagreement is status 1)
        print(f"screwkit leg: the leg type's expectation fails: {'; '.join(probs)}",
              file=sys.stderr)
        return 1
    return 0
