"""``screwkit size PM``: the largest force of every actuator and leg over a map and workloads."""

from __future__ import annotations

import argparse
import sys

from ...errors import InputError
from .._progress import progress_bar
from ._common import dump_json, fmt_num, fmt_vec
from .._types import path
from .map import add_map_arguments, grid_of, map_keywords

HELP = """Size a PM's actuators and legs: over every cell of a grid (or random samples; the
arguments of 'screwkit map') and every workload of --workloads FILE.csv (columns Fx,Fy,Fz,
Tx,Ty,Tz in the model's force and torque units at o, optionally name; default: --force and
--torque, else the model's declared workload), the largest |value| of each actuator's force
or torque, of each constraint force or couple, and of each linear leg's T_r, with the signed
value, the pose and the workload where it occurs, the cell's conditioning class and trust
level; and the range of each extension r_i and actuated joint value q_ai (the strokes). Only cells that are ok, within the model's limits and of
--max-level or better count.
--json prints the table under the key 'extremes'."""

EPILOG = """examples:
  screwkit size 3RRPRR --grid alpha=-10:10:41 --grid beta=-10:10:41 --grid Zo=70:90:21
  screwkit size 2SPS+2SPR --grid alpha=-5:5:21 --grid gamma=-5:5:21 --fix beta=0 \\
      --fix Zo=80 --workloads loads.csv --json"""


def register(sub):
    p = sub.add_parser("size", help="actuator and leg sizing: largest forces over a map and "
                       "workloads", description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_map_arguments(p)
    p.add_argument("--max-level", choices=("ok", "ill-conditioned", "near-singular"),
                   default="near-singular",
                   help="count only cells of this trust level or better (default "
                        "near-singular: every cell that is not singular, near-singular ones "
                        "and those whose efforts exceed 5x the load included)")
    p.add_argument("--workloads", metavar="CSV", type=path,
                   help="workloads to size for (Fx,Fy,Fz,Tx,Ty,Tz[,name]); default: --force, "
                        "--torque")
    p.set_defaults(func=run)


def run(args) -> int:
    from ...api import size
    from ...maps import read_workloads
    from .analyze import resolve_model

    if args.workloads and (args.force is not None or args.torque is not None):
        raise InputError("--workloads FILE lists the loads: give it or --force/--torque, "
                         "not both")
    model = resolve_model(args)
    units = None if args.units == "model" else args.units
    if units is not None:
        from ...engine._report import output_scales
        output_scales(model, units)              # fail before a long run, not after it
    grid = grid_of(args)
    with progress_bar(args, "size", "cell") as progress:
        kw = map_keywords(args, model, progress,
                          load="required" if not args.workloads else False)
        F, T = kw.pop("force"), kw.pop("torque")
        if args.workloads:
            loads = [(f"{n} ({args.workloads})", f, t)
                     for n, f, t in read_workloads(args.workloads)]
        elif F is None:
            w = model.workload
            loads = [(w.origin, w.force, w.torque)]
        else:
            loads = [("command line", F, T)]
        res = size(model, grid, workloads=loads, max_level=args.max_level, **kw)
    from ...maps import sizing_in_units
    res = sizing_in_units(res, units)
    _warn_singular_surface(res)
    if args.json:
        print(dump_json(res.to_dict()))
        return 0
    u = res.units
    print(f"sizing of {res.pm} over {res.usable_cells} usable cells of {res.cells} (ok, within "
          f"the limits, level {res.max_level} or better) and {len(res.workloads)} workload(s); "
          f"lengths {u['length']}, forces {u['force']}, torques {u['torque']}, angles "
          f"{u['angle']}")
    for w in res.workloads[:5]:
        print(f"  workload {w['name']}: F = {fmt_vec(w['force'])} {u['force']}, T = "
              f"{fmt_vec(w['torque'])} {u['torque']} at o")
    if len(res.workloads) > 5:
        print(f"  ... {len(res.workloads) - 5} more workloads (--json lists them)")
    if not res.usable_cells:
        print("  no usable cell: nothing to size", file=sys.stderr)
        return 0
    print(f"  {'row':<6} {'max |value|':>13} {'unit':<6} {'signed':>12}  workload / pose / "
          "conditioning (trust level)")
    undetermined = False
    for r in res.rows:
        if r["max_abs"] is None:
            continue
        if r.get("round_off"):
            print(f"  {r['name']:<6} {0:>12}  {r['unit']:<6} {0:>12}  at every usable cell "
                  "(zero to round-off)")
            continue
        pose = ", ".join(f"{k}={fmt_num(v)}" for k, v in r["pose"].items())
        star = "*" if r.get("determined") is False else " "
        undetermined |= star == "*"
        print(f"  {r['name']:<6} {fmt_num(r['max_abs']):>12}{star} {r['unit']:<6} "
              f"{fmt_num(r['value']):>12}  {r['workload']} / {pose} / {r['conditioning']} "
              f"(trust {r['level']})")
    if undetermined:
        print("  * not fixed by statics alone: the PM is statically indeterminate and this is "
              "the least-norm value (screwkit.size(..., stiffness=...) weights it)")
    print("  ranges (strokes):")
    for r in res.ranges:
        if r["min"] is None:
            continue
        print(f"  {r['name']:<6} {fmt_num(r['min']):>12} .. {fmt_num(r['max']):<12} {r['unit']}")
    return 0


def _warn_singular_surface(res) -> None:
    """Say so where the task's cells lie on both sides of a singular surface (det J of both
    signs) or on it: the efforts between cells grow without bound there, and the maxima are
    those of the cells only."""
    import numpy as np
    ds = res.dataset
    if ds is None or "det_sign" not in ds:
        return
    det = np.asarray(ds["det_sign"].values).ravel()
    sing = int(np.sum(np.asarray(ds["singular"].values))) if "singular" in ds else 0
    home = int(ds.attrs.get("home_det_sign", 0))
    other = int(np.sum((det != 0) & (det != home))) if home else 0
    if other or sing:
        print(f"screwkit size: warning: the task's cells include {other} beyond a singular "
              f"surface from home (det J of the other sign) and {sing} singular: between "
              "them the efforts grow without bound, and the maxima are the cells' only (see "
              "screwkit map's singular locus)", file=sys.stderr)
