"""``screwkit map PM``: a PM over a grid of poses (workspace, conditioning, forces, loci)."""

from __future__ import annotations

import argparse
import sys

from ...errors import InputError
from .._progress import add_quiet_argument, progress_bar
from ._common import dump_json, fmt_num
from .._types import figure, integer, output, scheduler
from .analyze import (add_load_arguments, add_pm_arguments, parse_assignments, parse_load,
                      require_load)

HELP = """Analyse a PM at every cell of a grid of 1 to 3 independent pose parameters
(--grid NAME=START:STOP:COUNT, angles in degrees; the other independent parameters from --fix
NAME=VALUE or the default pose), or at --samples N random poses in the box --grid NAME=LOW:HIGH.
Every cell: reachable, closure residual, condition number, sign of det J, singularity kind and
trust level, active and constraint forces, T_r, extensions, actuated joint values, and the
model's limits. Where det J changes sign between neighbouring cells the crossing is refined by
bisection (to 1e-6 of the cell size) and classified (actuation or constraint singularity).
Output: --out map.nc | map.zarr | map.csv (long format, one row per cell), --plot map.png
(heatmaps of --quantity), a summary on stdout (--json: with 'singular_locus' and
'extremes'). --workers N runs the cells on a local Dask cluster of N processes (loopback),
--scheduler tcp://HOST:PORT on a running one; the result equals the serial run bit for bit."""

EPILOG = """examples:
  screwkit map 3RRPRR --grid alpha=-15:15:61 --grid beta=-15:15:61 --fix Zo=80 \\
      --out map.nc --plot map.png --quantity forces --quantity conditioning
  screwkit map 2SPS+2SPR --grid alpha=-10:30:81 --grid gamma=-10:30:81 --fix beta=0 \\
      --fix Zo=75 --plot locus.png --json
  screwkit map 3RRPRR --samples 100000 --grid alpha=-10:10 --grid beta=-10:10 \\
      --grid Zo=60:100 --out samples.csv --workers 2"""


def add_map_arguments(p):
    """The cells, workload and cluster arguments shared by map and size."""
    from ...legs._guards import MAX_SEED
    from ...maps import MAX_CELLS
    add_pm_arguments(p, pose=False)
    p.add_argument("--grid", metavar="NAME=START:STOP:COUNT", action="append", default=[],
                   help="a grid parameter (degrees for angles; repeatable, 1 to 3; with "
                        "--samples: NAME=LOW:HIGH, the sampling box)")
    p.add_argument("--fix", metavar="NAME=VALUE", action="append", default=[],
                   help="fix another independent parameter (default: the model's default pose)")
    p.add_argument("--samples", type=integer(1, MAX_CELLS), metavar="N",
                   help="N random poses uniform in the --grid box instead of a grid "
                        f"(1 to {MAX_CELLS})")
    p.add_argument("--seed", type=integer(0, MAX_SEED), default=0,
                   help=f"seed of --samples (0 to {MAX_SEED}; default 0)")
    add_load_arguments(p)
    p.add_argument("--workers", type=integer(1, 64), metavar="N",
                   help="run the cells on a local Dask cluster of N worker processes "
                        "(127.0.0.1; needs screwkit[dask])")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", type=scheduler,
                   help="run the cells on a running Dask scheduler")
    p.add_argument("--threads", type=integer(1, 64), metavar="N",
                   help="threads of each block's analysis (as analyze's workers; default: 2 "
                        "for large blocks)")
    p.add_argument("--units", choices=["model", "SI"], default="model",
                   help="units of the outputs (files, plot, summary): the model's (default) or "
                        "SI (m, N, N.m; needs pint)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    add_quiet_argument(p)


def grid_of(args) -> dict:
    from ...maps import parse_range
    if not args.grid:
        raise InputError("give at least one --grid NAME=LOW:HIGH (the box of --samples)"
                         if args.samples is not None else
                         "give at least one --grid NAME=START:STOP:COUNT")
    out = {}
    for g in args.grid:
        name, rng = parse_range(g)
        if name in out:
            raise InputError(f"--grid {name} is given twice")
        if args.samples is None and len(rng) != 3:
            raise InputError(f"--grid {g!r}: a grid needs START:STOP:COUNT (LOW:HIGH is a "
                             "--samples box)")
        if args.samples is None and rng[2] == 1 and rng[0] != rng[1]:
            raise InputError(f"--grid {g!r}: one value cannot span {rng[0]:g} to {rng[1]:g}: "
                             f"give a COUNT of 2 or more, or --fix {name}=VALUE")
        if args.samples is not None and len(rng) != 2:
            raise InputError(f"--grid {g!r}: with --samples give the box NAME=LOW:HIGH")
        out[name] = rng
    return out


def map_keywords(args, model, progress=None, load=True) -> dict:
    """Keywords of :func:`screwkit.map` / :func:`screwkit.size` from the arguments."""
    if args.workers is not None and args.scheduler:
        raise InputError("give either --workers N or --scheduler ADDRESS")
    if args.seed and args.samples is None and args.command in ("map", "size"):
        raise InputError("--seed seeds the random poses of --samples: give --samples N")
    force, torque = (require_load(args, model) if load == "required" else parse_load(args)) \
        if load else (None, None)
    return dict(fix=parse_assignments(args.fix, "--fix"), samples=args.samples,
                seed=args.seed, degrees=True, force=force,
                torque=torque, workers=args.threads,
                cluster=args.workers, scheduler=args.scheduler,
                progress=progress)


def register(sub):
    p = sub.add_parser("map", help="a PM over a grid of poses: workspace, conditioning, "
                       "forces, singular loci", description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_map_arguments(p)
    p.add_argument("--out", metavar="FILE", type=output,
                   help="write the map: .nc (NetCDF), .zarr, .csv")
    p.add_argument("--plot", metavar="PNG", type=figure, help="draw heatmaps of --quantity")
    p.add_argument("--quantity", action="append", default=[],
                   help="what --plot draws: a variable (F_a1, T_r2, r1, condition_number, ...), "
                        "forces, constraints, conditioning or transmission (iti, oti, lti, "
                        "cti) (repeatable; default: forces and conditioning)")
    p.add_argument("--at", metavar="NAME=VALUE", action="append", default=[],
                   help="the slice of a 3-D map that --plot draws (default: the middle; in "
                        "the model's units, as --grid, whatever --units)")
    p.add_argument("--lti-threshold", type=float, default=0.7, metavar="X",
                   help="the LTI bound of the good-transmission workspace (default 0.7)")
    p.set_defaults(func=run)


def summary(ds, lti_threshold: float = 0.7) -> dict:
    """The JSON summary of a map (counts, loci, extremes)."""
    import numpy as np

    from ...maps import CONDITIONING_CODES, LEVEL_CODES, extremes, locus_list, workspace
    lev = ds["level"].values.reshape(-1)
    cls = ds["conditioning"].values.reshape(-1)
    counts = {"cells": int(lev.size), "reachable": int(np.sum(ds["reachable"].values)),
              "ok": int(np.sum(ds["ok"].values)),
              "conditioning": {name: int(np.sum(cls == k))
                               for k, name in enumerate(CONDITIONING_CODES)},
              "levels": {name: int(np.sum(lev == k)) for k, name in enumerate(LEVEL_CODES)},
              "singular_actuation": int(np.sum(ds["singular_kind"].values == 1)),
              "singular_constraint": int(np.sum(ds["singular_kind"].values == 2)),
              "other_assembly_mode": int(np.sum((ds["det_sign"].values != 0) &
                                                (ds["det_sign"].values != ds.attrs["home_det_sign"]))),
              }
    if "within_limits" in ds:
        counts["outside_limits"] = int(np.sum(ds["reachable"].values & ~ds["within_limits"].values))
    dims = ds["ok"].dims
    grid = {d: {"count": int(ds.sizes[d]), "start": float(ds[d].values[0]),
                "stop": float(ds[d].values[-1]), "unit": ds[d].attrs["units"]}
            for d in dims if d != "sample"}
    return {"pm": ds.attrs["pm"],
            "units": {"length": ds.attrs["units_length"], "force": ds.attrs["units_force"],
                      "torque": ds.attrs["units_torque"], "angle": ds.attrs["units_angle"]},
            "grid": grid, "fixed": {k: float(ds[k].values) for k in ds.coords if ds[k].ndim == 0},
            "workload": {"force": ds.attrs["force"], "torque": ds.attrs["torque"],
                         "applied_at": "o", "source": ds.attrs.get("workload_source", "")},
            "counts": counts, "locus": ds.attrs.get("locus"),
            "singular_locus": locus_list(ds),
            "other_sign_changes": locus_list(ds, singular_only=False),
            "extremes": extremes(ds),
            "workspace": workspace(ds, lti_threshold).to_dict()}


def check_outputs(args) -> None:
    """Refuse output arguments that would fail or be ignored, before the cells are computed."""
    from pathlib import Path

    from ...maps import FORMATS
    if args.out and Path(args.out).suffix.lower() not in FORMATS:
        raise InputError(f"--out {args.out!r}: the file must end in {', '.join(FORMATS)}")
    if not args.plot and (args.quantity or args.at):
        raise InputError("--quantity and --at choose what --plot draws: add --plot FILE.png")
    if args.plot and args.samples is not None:
        raise InputError("--plot: random samples have no grid to draw (use --grid "
                         "NAME=START:STOP:COUNT without --samples, or --out samples.csv)")


def run(args) -> int:
    from ...api import map as map_pm
    from ...maps import map_in_units, plot_map, write

    if args.plot:
        from ...viz import require_matplotlib
        require_matplotlib()                     # fail before a long run, not after it
    check_outputs(args)
    if not 0 < args.lti_threshold <= 1:
        raise InputError(f"--lti-threshold must be in (0, 1], got {args.lti_threshold:g}")
    from .analyze import resolve_model
    model = resolve_model(args)
    units = None if args.units == "model" else args.units
    length_factor = 1.0
    if units is not None:
        from ...engine._report import output_scales
        length_factor = output_scales(model, units)[1]["length"]   # (fails before a long run)
    grid = grid_of(args)
    with progress_bar(args, "map", "cell") as progress:
        ds = map_pm(model, grid, **map_keywords(args, model, progress))
    if ds.attrs.get("workload_source") == "given":
        ds.attrs["workload_source"] = "command line"
    forces = "F_a1" in ds or any("row" in v.attrs for v in ds.data_vars.values())
    quantities = args.quantity or (["forces", "conditioning"] if forces else ["conditioning"])
    if args.plot and not forces and any(q in ("forces", "constraints") or q.startswith(
            ("F_", "T_c", "T_a", "T_r")) for q in quantities):
        raise InputError(f"--quantity {', '.join(quantities)}: {model.name} declares no "
                         "workload: give --force FX,FY,FZ and/or --torque TX,TY,TZ for its forces")
    marks = _determined(model, ds) if forces else {}
    ds = map_in_units(ds, units)
    if args.plot:      # (first: a --quantity or --at it refuses leaves no --out file behind)
        # --at is read as --grid and --fix are, in the model's units, whatever --units shows
        at = {k: (v * length_factor if k in ("Xo", "Yo", "Zo") else v)
              for k, v in parse_assignments(args.at, "--at").items()}
        plot_map(ds, args.plot, quantities, at=at)
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.out:
        write(ds, args.out)
        print(f"wrote {args.out}", file=sys.stderr)
    s = summary(ds, args.lti_threshold)
    for r in s["extremes"]["rows"]:
        r["determined"] = marks.get(r["name"])
    if args.json:
        print(dump_json(s))
        return 0
    print_summary(s)
    return 0


def _determined(model, ds) -> dict:
    """Whether statics alone fixes each row's extreme (:func:`screwkit.maps.mark_determined`),
    by name, from the map in the model's units."""
    from ...maps import extremes, mark_determined
    rows = extremes(ds)["rows"]
    mark_determined(model, rows, ds)
    return {r["name"]: r["determined"] for r in rows}


def print_summary(s) -> None:
    u = s["units"]
    c = s["counts"]
    grid = ", ".join(f"{d} {g['start']:g}..{g['stop']:g} {g['unit']} ({g['count']})"
                     for d, g in s["grid"].items()) or "random samples"
    fixed = ", ".join(_with_unit(k, v, u) for k, v in s["fixed"].items())
    print(f"map of {s['pm']}: {grid}" + (f"; fixed {fixed}" if fixed else ""))
    print(f"  units: lengths {u['length']}, forces {u['force']}, torques {u['torque']}, "
          f"angles {u['angle']}")
    lv, cl = c["levels"], c["conditioning"]
    w = s["workload"]
    from ._common import fmt_vec
    if str(w["source"]).startswith("none"):
        print(f"  workload {w['source']}".replace("force=/torque=, at the command line ", ""))
    else:
        print(f"  workload F = {fmt_vec(w['force'])} {u['force']}, T = "
              f"{fmt_vec(w['torque'])} {u['torque']} at o ({w['source'] or 'given'})")
    print(f"  cells {c['cells']}: reachable {c['reachable']}, ok {c['ok']}; conditioning "
          f"regular {cl['regular']}, near-singular {cl['near-singular']}, singular "
          f"{cl['singular']}, unreachable {cl['unreachable']}")
    print(f"  trust levels of the efforts: ok {lv['ok']}, ill-conditioned "
          f"{lv['ill-conditioned']}, near-singular {lv['near-singular']}, singular "
          f"{lv['singular']}, unreachable {lv['unreachable']}")
    print(f"  det J of the other sign than home's: {c['other_assembly_mode']} cells"
          + (f"; outside the limits: {c['outside_limits']} cells" if "outside_limits" in c
             else ""))
    loc = s["singular_locus"]
    kinds = {k: sum(1 for x in loc if x["kind"] == k) for k in ("actuation", "constraint")}
    print(f"  singular locus: {len(loc)} crossings refined to 1e-6 of a cell "
          f"({kinds['actuation']} actuation, {kinds['constraint']} constraint); "
          f"{len(s['other_sign_changes'])} other det J sign changes"
          if s["locus"] == "refined" else f"  singular locus: {s['locus']}")
    for x in loc[:5]:
        print("    " + ", ".join(_with_unit(k, v, u, 9) for k, v in x["pose"].items())
              + f"  ({x['kind']}, condition {x['condition_number']:.3g})")
    if len(loc) > 5:
        print(f"    ... {len(loc) - 5} more (--json lists them)")
    ex = s["extremes"]
    if not ex["rows"]:
        print("  no forces: no workload")
    else:
        _print_extremes(ex, c, u)
    print_workspace(s["workspace"])


def _with_unit(k, v, u, digits: int = 6) -> str:
    """``Zo = 80 cm``: a pose value with its unit (the summary's units)."""
    return f"{k} = {fmt_num(v, digits)} {u['length'] if k in ('Xo', 'Yo', 'Zo') else u['angle']}"


def _print_extremes(ex, c, u) -> None:
    print(f"  largest |value| over the {ex['usable_cells']} usable cells (ok"
          + (", within the limits" if "outside_limits" in c else "") + "):")
    undetermined = False
    for r in ex["rows"]:
        if r["max_abs"] is None:
            continue
        if r.get("round_off"):
            print(f"    {r['name']:<6} {0:>12}  {r['unit']:<6} at every usable cell (zero to round-off)")
            continue
        star = "*" if r.get("determined") is False else " "
        undetermined |= star == "*"
        print(f"    {r['name']:<6} {fmt_num(r['value']):>12}{star} {r['unit']:<6} at "
              + ", ".join(_with_unit(k, v, u) for k, v in r["pose"].items())
              + f"  ({r['conditioning']}, trust {r['level']})")
    if undetermined:
        print("    * not fixed by statics alone: the PM is statically indeterminate there and "
              "this is the least-norm value (screwkit.map(..., stiffness=...) weights it)")


def print_workspace(w) -> None:
    """The workspace lines of a summary (docs/maps.md#workspace-measures)."""
    box = ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in w["box"].items())
    print(f"  workspace (task box {box}: {fmt_num(w['box_volume'])} {w['units']}):")
    for name, r in w["regions"].items():
        err = "" if r["stderr"] is None else f" +- {fmt_num(r['stderr'], 3)}"
        print(f"    {name.replace('_', '-'):<18} {fmt_num(r['volume'])}{err} {w['units']}  "
              f"{100 * r['fraction']:.1f}% of the box ({r['cells']} cells; {r['definition']})")
