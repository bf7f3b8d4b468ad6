"""``screwkit trajectory PM``: statics along a path (CSV/JSON table, Fig. 5-style plot)."""

from __future__ import annotations

import sys

from ...errors import InputError
from .._types import figure, integer, label, output, scheduler
from .._progress import add_quiet_argument, progress_bar
from ._common import (add_unit_label_arguments, check_unit_labels, dask_mapper,
                      dump_json, emit_table)
from .analyze import (add_load_arguments, add_pm_arguments, load_source, require_load,
                      resolve_model, workload_note)

HELP = """Solve a PM along a path of its independent pose parameters: at every sample the full
pose (unified inverse displacement, warm-started), the leg extensions r_i, the active forces F_ai,
the constraint forces/couples and the constraint torques T_ri for a workload (F, T) at o, each
leg's constraint resultant (res<i>_f*: its total constraint force; res<i>_m*: its moment about
A_i), and the normalised condition number of the unified Jacobian. The path is a CSV file (--path: a
header row with t and the independent parameters, angles in degrees) or one expression in t
per independent parameter (--expr 'alpha=10*sin(2*pi*t)' --expr ... --samples N). Output: CSV
(default) or JSON on stdout or in --out FILE; --plot FILE draws the panels of the paper's
Fig. 5. Each sample's 'status' is ok (regular) or its conditioning class (near-singular,
singular, unreachable; the same classes as analyze); singular and unreachable samples have
NaN values; the run continues. The workload is --force/--torque (--force alone: zero
torque) or the model's declared one. Angles in degrees, lengths and
forces in the model's units or in SI (--units SI); the CSV header names each column's unit
(F_a1 [kN])."""

EPILOG = """examples:
  screwkit trajectory 3RRPRR --expr "alpha=8*sin(2*pi*t)" --expr "beta=6*sin(4*pi*t)" \\
      --expr "Zo=80+10*t" --samples 201 --out path.csv --plot fig5.png
  screwkit trajectory 2SPS+2SPR --path poses.csv --format json"""


def register(sub):
    from ...paths import add_path_arguments
    import argparse

    p = sub.add_parser("trajectory", help="statics along a path (table, Fig. 5 plot)",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_pm_arguments(p, pose=False)
    add_path_arguments(p)
    add_load_arguments(p)
    p.add_argument("--format", choices=("csv", "json"),
                   help="output format (default: from the --out suffix, else csv)")
    p.add_argument("--json", action="store_true", help="the same as --format json")
    p.add_argument("--out", metavar="FILE", type=output, help="write the table to FILE instead of stdout")
    p.add_argument("--units", choices=["model", "SI"], default="model",
                   help="units of the table (CSV header 'name [unit]', JSON units) and of "
                        "the plot: the model's (default) or SI (m, N, N.m, kg; needs pint)")
    p.add_argument("--plot", metavar="PNG", type=figure, help="also draw the panels of the paper's Fig. 5")
    p.add_argument("--title", type=label(), help="title of the plot")
    add_unit_label_arguments(p, "on the plot")
    p.add_argument("--workers", type=integer(1, 64), metavar="N",
                   help="form the rows and statics of the path's chunks on a local Dask cluster "
                        "of N worker processes (127.0.0.1; needs screwkit[dask]); the closures "
                        "are solved here; the table equals the serial one")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", type=scheduler,
                   help="the same on a running Dask scheduler")
    add_quiet_argument(p)
    p.add_argument("--no-progress", action="store_true", help=argparse.SUPPRESS)   # old --quiet
    from ._dynamics_args import add_dynamics_arguments
    add_dynamics_arguments(p)
    p.set_defaults(func=run)


def _format(args) -> str:
    """The table's format: ``--format``, else the ``--out`` suffix (.csv or .json), else
    csv; another suffix without ``--format`` is an error (a .parquet is not written as CSV
    silently)."""
    if args.format:
        return args.format
    if args.out:
        suffix = args.out.lower().rsplit(".", 1)[-1] if "." in args.out else ""
        if suffix in ("json", "csv"):
            return suffix
        raise InputError(f"--out {args.out!r}: the table is written as .csv or .json (give "
                         "--format csv or json for another file name)")
    return "csv"


def run(args) -> int:
    from ...paths import path_from_args
    from ...paths import run_trajectory
    if args.json:                       # (--json: as every other command spells it)
        args.format = "json"

    model = resolve_model(args)
    fmt = _format(args)
    if not getattr(args, "dynamics", False):
        given = [o for o, v in (("--mass", args.mass), ("--gravity", args.gravity),
                                ("--smoothing", args.smoothing)) if v is not None]
        if given:
            raise InputError(f"{', '.join(given)} {'is' if len(given) == 1 else 'are'} for "
                             "the dynamic columns: add --dynamics")
    if args.smoothing is not None and not getattr(args, "path", None):
        raise InputError("--smoothing smooths the spline through a CSV --path: expressions "
                         "(--expr) have exact derivatives")
    force, torque = require_load(args, model)
    if args.plot:
        from ...viz import require_matplotlib
        require_matplotlib()                     # fail before a long run, not after it
    mapper = dask_mapper(args)
    if mapper is not None and getattr(args, "dynamics", False):
        raise InputError("--workers and --scheduler do not apply to --dynamics")
    table_units = None if args.units == "model" else args.units
    if table_units is not None:
        if args.length_unit or args.force_unit:
            raise InputError("--length-unit/--force-unit name the model's units on the plot: "
                             "not with --units SI")
        from ...engine._report import output_scales
        output_scales(model, table_units)         # fail before a long run, not after it
    check_unit_labels(model, args.length_unit, args.force_unit)
    labels = [o for o, v in (("--title", args.title), ("--length-unit", args.length_unit),
                             ("--force-unit", args.force_unit)) if v]
    if labels and not args.plot:
        raise InputError(f"{', '.join(labels)} label{'s' if len(labels) == 1 else ''} the plot: "
                         "add --plot FILE.png")
    if getattr(args, "dynamics", False):
        from ._dynamics_args import run_dynamics
        with progress_bar(args, "dynamics", "step") as progress:
            return run_dynamics(args, model, fmt, progress, force, torque)
    path = path_from_args(args, model.independent,
                          model.units.length if model.units.declared else None)
    with progress_bar(args, "trajectory", "step") as progress:
        res = run_trajectory(model, path, force, torque, progress=progress, mapper=mapper)
    if fmt == "json":
        d = res.to_dict(table_units)
        d["workload"]["source"] = load_source(res)
        text = dump_json(d) + "\n"
    else:
        text = res.to_csv(units=table_units)
    emit_table(args.out, text)
    if sys.stderr.isatty() and not getattr(args, "quiet", False):   # (JSON: workload.source)
        print(workload_note("trajectory", model, res.force, res.torque, res), file=sys.stderr)
    if args.plot:
        units = {}
        if table_units is not None:
            res = res.in_units(table_units)
        elif args.length_unit or args.force_unit:
            mu = model.units
            lu, fu = args.length_unit or mu.length, args.force_unit or mu.force
            units = {"length": lu, "force": fu, "torque": f"{fu}·{lu}"}
        res.plot(args.plot, title=args.title, units=units or None)
        print(f"wrote {args.plot}", file=sys.stderr)
    c = res.counts()
    if c["near-singular"]:
        print(f"screwkit trajectory: {c['near-singular']} near-singular of {len(res)} samples "
              "(status column; efforts there are large and sensitive)", file=sys.stderr)
    an = res.analysis
    if an is not None:
        import numpy as np
        # the efforts' trust level and the assembly mode, as analyze warns of them (message
        # column): a path can cross a singular surface between two regular samples
        trust = int(np.sum((np.asarray(an.level) == "near-singular")
                           & (np.asarray(an.conditioning) == "regular")))
        beyond = int(np.sum(np.asarray(an.quality.beyond_singular_surface)))
        if trust:
            print(f"screwkit trajectory: {trust} of {len(res)} samples at trust level "
                  "near-singular though regular (efforts over 5 times the load; message "
                  "column)", file=sys.stderr)
        if beyond:
            print(f"screwkit trajectory: {beyond} of {len(res)} samples beyond a singular "
                  "surface from home (det J's sign opposite to home's: the path crosses "
                  "an actuation singularity; message column)",
                  file=sys.stderr)
        from ...engine._limits import within_limits
        outside = int(np.sum(~within_limits(an) & np.asarray(an.solution.reachable_mask)))
        if outside:
            print(f"screwkit trajectory: {outside} of {len(res)} samples outside the model's "
                  "declared limits (message column)", file=sys.stderr)
    if c["singular"] or c["unreachable"]:
        print(f"screwkit trajectory: {c['singular']} singular and {c['unreachable']} unreachable "
              f"of {len(res)} samples (status column; their statics are NaN)", file=sys.stderr)
    return 0
