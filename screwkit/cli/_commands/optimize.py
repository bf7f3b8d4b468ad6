"""``screwkit optimize PM``: the dimensions of a PM that are best over a task (dimensional
synthesis)."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ...errors import InputError
from .._progress import progress_bar
from .._types import figure, model_file, path
from ._common import dump_json, fmt_num, fmt_vec
from .map import add_map_arguments, grid_of, map_keywords

HELP = """Dimensional synthesis: vary dimensions of a PM (--vary NAME=LOW:HIGH, model lengths,
repeatable) to minimise or maximise an objective over a task, the cells and workloads that
'screwkit size' takes (--grid/--fix/--samples, --force/--torque or --workloads FILE.csv).
Objectives (--objective, default max-actuator-force): max-actuator-force and
max-constraint-force (the largest |value| over the task and workloads, as 'size' computes
it), min-lti (the smallest local transmission index, maximised), gtw-volume (the
good-transmission workspace, LTI >= --lti-threshold, maximised), condition (the largest
normalised condition number), stroke (the largest actuated-joint range). A design counts
only when the whole task is reachable, within the model's limits and of --max-level or
better under every workload, and meets every --constraint (e.g. stroke<=40). One
objective: seeded differential evolution (scipy) polished by Nelder-Mead; several: NSGA-II
(pymoo) and the Pareto front. --seed makes the run reproducible. Prints the best dimensions
and every objective there; --plot draws the search (or the front), --write saves the best
design as a model file; --json: best.dimensions, best.objective, best.objectives,
evaluations, front. --workers/--scheduler evaluate the candidates on Dask."""

EPILOG = """examples:
  screwkit optimize 3RRPRR --vary l=30:120 --grid alpha=-10:10:5 --grid beta=-10:10:5 \\
      --grid Zo=60:100:5 --write best.yaml --plot search.png
  screwkit optimize 3RRPRR --vary l=30:120 --vary L=90:160 --grid alpha=-10:10:5 \\
      --grid beta=-10:10:5 --fix Zo=80 --objective max-actuator-force --objective min-lti \\
      --constraint stroke<=40 --json"""


def register(sub):
    p = sub.add_parser("optimize", help="dimensional synthesis: the best dimensions of a PM "
                       "over a task", description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_map_arguments(p)
    seed = p._option_string_actions["--seed"]
    seed.help = seed.help.replace("seed of --samples", "seed of --samples and of the optimiser")
    p.add_argument("--vary", metavar="NAME=LOW:HIGH", action="append", default=[],
                   help="a dimension to vary and its bounds (model lengths; repeatable)")
    p.add_argument("--objective", action="append", default=[], metavar="NAME",
                   help="max-actuator-force (default), max-constraint-force, min-lti, "
                        "gtw-volume, condition, stroke (repeatable: a Pareto front)")
    p.add_argument("--constraint", action="append", default=[], metavar="EXPR",
                   help="a bound on an objective, e.g. stroke<=40 or min-lti>=0.6 (repeatable)")
    p.add_argument("--workloads", metavar="CSV", type=path,
                   help="workloads (Fx,Fy,Fz,Tx,Ty,Tz[,name]); default: --force, --torque, "
                        "else the model's declared workload")
    p.add_argument("--max-level", choices=("ok", "ill-conditioned", "near-singular"),
                   default="near-singular",
                   help="the worst trust level of a cell of the task (default near-singular: "
                        "every cell that is not singular)")
    p.add_argument("--lti-threshold", type=float, default=None, metavar="X",
                   help="the LTI bound of gtw-volume, as an objective or a constraint "
                        "(default 0.7)")
    p.add_argument("--maxiter", type=int, default=40, metavar="G",
                   help="generations (default 40)")
    p.add_argument("--popsize", type=int, default=10, metavar="P",
                   help="population per varied dimension (default 10)")
    p.add_argument("--no-polish", action="store_true",
                   help="one objective: skip the Nelder-Mead polish of the best design")
    p.add_argument("--plot", metavar="PNG", type=figure, help="draw the search (one objective) or the "
                   "Pareto front (two or more: the first two)")
    p.add_argument("--write", metavar="FILE.yaml", type=model_file,
                   help="write the best design as a model file (.yaml or .yml)")
    p.set_defaults(func=run)


def _vary(items) -> dict:
    from ...maps import parse_range
    if not items:
        raise InputError("give at least one --vary NAME=LOW:HIGH (a dimension and its bounds)")
    out = {}
    for item in items:
        name, rng = parse_range(item, "--vary", pose=False)
        if len(rng) != 2:
            raise InputError(f"--vary {item!r}: give NAME=LOW:HIGH")
        if name in out:
            raise InputError(f"--vary {name} is given twice")
        out[name] = rng
    return out


def run(args) -> int:
    from ...api import optimize
    from ...maps import read_workloads
    from .analyze import resolve_model

    if args.plot:
        from ...viz import require_matplotlib
        require_matplotlib()
    if args.threads is not None:
        raise InputError("--threads: optimize evaluates one candidate at a time per process; "
                         "use --workers N for parallel candidates")
    vary = _vary(args.vary)
    fixed = {item.split("=", 1)[0].strip() for item in args.set}
    both = sorted(fixed & set(vary))
    if both:
        raise InputError(f"--set {both[0]} and --vary {both[0]}: a varied dimension takes the "
                         "optimiser's values (give its bounds with --vary, or fix it with --set)")
    if args.no_polish and len(args.objective or []) > 1:
        raise InputError("--no-polish: several objectives are searched by NSGA-II, which has "
                         "no polish (it applies to one objective)")
    explicit = args.force is not None or args.torque is not None
    if args.workloads and explicit:
        raise InputError("--workloads FILE lists the loads: give it or --force/--torque, "
                         "not both")
    if args.lti_threshold is not None and not 0.0 < args.lti_threshold <= 1.0:
        raise InputError(f"the LTI threshold must be in (0, 1], got {args.lti_threshold!r:.40}")
    if args.lti_threshold is not None and not any(
            "gtw" in x for x in (args.objective or []) + list(args.constraint or [])):
        raise InputError("--lti-threshold bounds the LTI of gtw-volume: add the objective "
                         "gtw-volume or a constraint on it")
    model = resolve_model(args)
    units = None if args.units == "model" else args.units
    if units is not None:
        from ...engine._report import output_scales
        output_scales(model, units)              # fail before a long run, not after it
    grid = grid_of(args)
    with progress_bar(args, "optimize", "generation") as progress:
        kw = map_keywords(args, model, progress,
                          load="required" if not args.workloads else False)
        F, T = kw.pop("force"), kw.pop("torque")
        kw.pop("workers")
        if args.workloads:
            kw["workloads"] = read_workloads(args.workloads)
        elif explicit:
            kw["force"], kw["torque"] = F, T
        res = optimize(model, vary, grid, objective=args.objective or "max-actuator-force",
                       constraints=args.constraint, max_level=args.max_level,
                       lti_threshold=0.7 if args.lti_threshold is None else args.lti_threshold,
                       maxiter=args.maxiter,
                       popsize=args.popsize, polish=not args.no_polish, **kw)
    if args.write and res.model is not None:
        res.write_model(args.write)             # (a model file: in the model's own units)
        print(f"wrote {args.write}", file=sys.stderr)
    res = res.in_units(units)
    if args.plot:
        res.plot(args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.json:
        print(dump_json(res.to_dict()))
    else:
        print_text(res)
    if res.best is None:      # (the report above says what was searched: exit status 2)
        print("screwkit optimize: error: no design in the bounds makes the whole task usable "
              "(reachable, within the limits, regular) and meets the constraints"
              + ("; nothing written" if args.write else ""), file=sys.stderr)
        return 2
    return 0


def print_text(res) -> None:
    from ...design import OBJECTIVES
    u, t = res.units, res.task
    where = ", ".join(f"{k} {g['start']:g}..{g['stop']:g} {t['units'][k]} ({g['count']})"
                      for k, g in t.get("grid", {}).items()) or \
        f"{t['samples']} random samples (seed {t['seed']})"
    fixed = ", ".join(f"{k} = {fmt_num(v)} {t['units'][k]}" for k, v in t["fixed"].items())
    senses = ", ".join(f"{o} ({'max' if OBJECTIVES[o].sense == 'max' else 'min'}imised)"
                       for o in res.objectives)
    print(f"optimize {res.pm}: {senses}")
    print(f"  task: {t['cells']} cells ({where}" + (f"; fixed {fixed}" if fixed else "")
          + f"), {len(t['workloads'])} workload(s), cells of level {t['max_level']} or better")
    for w in t["workloads"]:          # (which loads the forces below are of, in which units)
        print(f"  workload {w['name']}: F = {fmt_vec(w['force'])} {w['force_unit']}, "
              f"T = {fmt_vec(w['torque'])} {w['torque_unit']} at o")
    print("  varied: " + ", ".join(f"{k} in {lo:g}..{hi:g} {u['length']}"
                                   for k, (lo, hi) in res.vary.items())
          + ("; constraints " + ", ".join(f"{n}{op}{v:g}" for n, op, v in res.constraints)
             if res.constraints else ""))
    print(f"  {res.method}, seed {res.seed}: {res.evaluations} designs evaluated")
    if res.best is None:
        print("  no feasible design")
        return
    dims = ", ".join(f"{k} = {fmt_num(v)} {u['length']}" for k, v in res.best["dimensions"].items())
    print(f"  best: {dims}")
    if not res.best.get("feasible", True):
        print("  warning: evaluated again on a model of its own (as screwkit size builds it), "
              "this design leaves some cells of the task unusable or breaks a constraint")
    for o, v in res.best["objectives"].items():
        if v is None:
            continue
        unit = u[o] if u[o] not in ("1", None) else ""
        mark = "  (optimised)" if o in res.objectives else ""
        print(f"    {o:<21} {fmt_num(v):>12} {unit}{mark}")
    skipped = [o for o, v in res.best["objectives"].items() if v is None]
    if skipped:
        print(f"    ({', '.join(skipped)}: not computed; the transmission indices are "
              "computed only where an objective or a constraint names one)")
    if len(res.objectives) > 1:
        shown = res.front
        if len(shown) > 12:                     # ten spread along it, ends included
            shown = [shown[int(round(k))] for k in np.linspace(0, len(shown) - 1, 10)]
        print(f"  Pareto front ({len(res.front)} designs, by {res.objectives[0]}"
              + ("; 10 of them, --json lists all" if len(shown) < len(res.front) else "")
              + "):")
        for f in shown:
            print("    " + ", ".join(f"{k} = {fmt_num(v)} {u['length']}"
                                   for k, v in f["dimensions"].items())
                  + ": " + ", ".join(f"{o} {fmt_num(f['objectives'][o])}"
                                     + (f" {u[o]}" if u[o] not in ("1", None) else "")
                                     for o in res.objectives))
