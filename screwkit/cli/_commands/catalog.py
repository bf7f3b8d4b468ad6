"""``screwkit catalog``: list the catalog's leg types, Table I and PMs."""

from __future__ import annotations

from .._types import path
from ._common import dump_json


def register(sub):
    p = sub.add_parser("catalog", help="list the catalog's leg types, PMs and Table I; show a PM",
                       description="List the catalog (legs_catalog.yaml), or show one PM: its "
                                   "dimensions, independent parameters, defaults, units and "
                                   "limits.")
    p.add_argument("pm", nargs="?", type=path,
                   help="a PM name or a model file (PATH.yaml[#NAME]) to show")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument("--path", action="store_true", help="print the catalog file's path and exit")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...pm import catalog_path, default_catalog

    if args.path:
        if args.pm or args.json:
            from ...errors import InputError
            raise InputError("--path prints the catalog file's path: give no PM or --json "
                             "with it")
        print(catalog_path())
        return 0
    if args.pm:
        from ._catalog_pm import show_pm
        return show_pm(args.pm, args.json)
    cat = default_catalog()
    if args.json:
        print(dump_json({
            "source": cat.source,
            "legs": [{"name": s.name, "string": s.string.marked, "summary": s.summary,
                      "expect": s.expect, "used_by": list(s.used_by)} for s in cat.legs.values()],
            "pms": sorted(cat.pms),
            "table1": cat.table1_distinct(),
        }))
        return 0
    print(f"catalog: {cat.source}")
    print(f"leg types ({len(cat.legs)}):")
    w = max((len(n) for n in cat.legs), default=4)
    for s in cat.legs.values():
        e = s.expect
        counts = f"{e.get('forces', 0)}F {e.get('couples', 0)}T"
        print(f"  {s.name:<{w}}  {s.string.marked:<8} {counts:<7} {s.summary}")
    if cat.pms:
        print(f"PMs ({len(cat.pms)}): {', '.join(sorted(cat.pms))}")
    t = cat.table1_distinct()
    print(f"Table I: {len(cat.table1)} cells, {len(t)} distinct strings")
    return 0
