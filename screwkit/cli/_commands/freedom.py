"""``screwkit freedom``: the freedoms allowed by constraint lines, or by one leg."""

from __future__ import annotations

from ...errors import InputError
from ...legs._guards import parse_number
from ...pm._units import LENGTH_UNITS
from ...screws import MAX_WRENCHES
from .._types import path
from ._common import dump_json, fmt_num, fmt_vec

HELP = """The freedoms of a body held by constraint wrenches (the twists reciprocal to them,
classified as translations, rotations about lines and helical motions with their pitch):
give the constraint lines with --force POINT:DIRECTION and --couple DIRECTION (repeatable),
or a leg (catalog name or leg string) whose constraint system holds the body.  Points and
pitches are in --length-unit (default cm, the catalog's); twists [v; w] and wrenches
[f; m] about the origin."""


def register(sub):
    p = sub.add_parser("freedom", help="the freedoms allowed by constraint wrenches or a leg",
                       description=HELP)
    p.add_argument("--force", action="append", default=[], metavar="X,Y,Z:DX,DY,DZ",
                   help="a constraint force through point X,Y,Z along DX,DY,DZ (repeatable)")
    p.add_argument("--couple", action="append", default=[], metavar="DX,DY,DZ",
                   help="a constraint couple about DX,DY,DZ (repeatable)")
    p.add_argument("--leg", metavar="STRING",
                   help="a leg (catalog name such as RRPRR or UPU/couple, or a leg string "
                        "with a generic geometry): its constraint wrenches")
    p.add_argument("--model", type=path,
                   help="a YAML file with extra leg types for --leg (the catalog's schema)")
    p.add_argument("--length-unit", choices=LENGTH_UNITS, default="cm",
                   help="unit of the points and pitches (a label: no conversion; default cm)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)


def _vector(text: str, what: str):
    parts = text.split(",")
    if len(parts) != 3:
        raise InputError(f"{what} {text!r}: expected three comma-separated numbers")
    return [parse_number(x, what, bound=1e12) for x in parts]


def _wrenches(args):
    from ...screws import couple_wrench, force_wrench

    n = len(args.force) + len(args.couple)
    if n > MAX_WRENCHES:
        raise InputError(f"{n} constraint wrenches: at most {MAX_WRENCHES}")
    rows, points = [], []
    for k, text in enumerate(args.force):
        if text.count(":") != 1:
            raise InputError(f"--force {text!r}: expected POINT:DIRECTION, e.g. 0,0,0:0,0,1")
        p_txt, d_txt = text.split(":")
        p = _vector(p_txt, f"--force[{k}] point")
        rows.append(force_wrench(_vector(d_txt, f"--force[{k}] direction"), p).vector)
        points.append(p)
    for k, text in enumerate(args.couple):
        rows.append(couple_wrench(_vector(text, f"--couple[{k}] direction")).vector)
    return rows, points


def run(args) -> int:
    import numpy as np

    import screwkit

    lu = args.length_unit
    if args.leg is not None and not args.leg.strip():
        raise InputError("--leg: an empty leg string (give one such as SPR or RR_PRR)")
    if args.leg and (args.force or args.couple):
        raise InputError("give either --leg or constraint lines (--force/--couple), not both")
    if args.model and not args.leg:
        raise InputError("--model adds leg types for --leg: give --leg too")
    if args.leg:
        from ...pm import Catalog, default_catalog, load_catalog

        cat = default_catalog()
        if args.model:
            extra = load_catalog(args.model)
            cat = Catalog({**cat.legs, **extra.legs}, cat.table1, cat.pms, cat.source)
        analysis = screwkit.leg(args.leg, catalog=cat).analyze()
        W = analysis.system.wrenches
        points = analysis.leg.points
        source = {"leg": analysis.leg.name, "string": analysis.leg.string.marked}
    else:
        W, points = _wrenches(args)
        source = {"forces": list(args.force), "couples": list(args.couple)}
        points = points or None
    res = screwkit.freedoms(np.asarray(W, float).reshape(-1, 6), points=points)
    if args.json:
        print(dump_json({**source, "units": {"length": lu, "pitch": f"{lu}/rad"},
                         "dof": res.dof, "label": res.label,
                         "constraint_rank": res.constraint_rank,
                         "freedoms": [f.as_dict() for f in res.freedoms],
                         "twists": res.twists, "wrenches": res.wrenches,
                         "residual": res.residual, "condition_number": res.condition_number,
                         "rank_margin": res.margin}))
        return 0
    what = f"leg {source['leg']} ({source['string']})" if args.leg else \
        f"{len(args.force)} force(s) and {len(args.couple)} couple(s)"
    print(f"{what}: constraint rank {res.constraint_rank}, {res.dof} freedom(s): {res.label}")
    for f in res.freedoms:
        print(f"  {f.describe(lu)}; twist [v; w] {fmt_vec(f.twist)} "
              + ("(a unit translation)" if f.kind == "translation" else f"(v in {lu}/rad)"))
    print(f"  residual {fmt_num(res.residual, 3)} (normalised), condition number "
          f"{fmt_num(res.condition_number, 4)}, rank margin {fmt_num(res.margin, 4)}; "
          f"lengths in {lu}")
    return 0
