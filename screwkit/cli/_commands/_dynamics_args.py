"""``screwkit trajectory PM ... --dynamics``: the options and the run of the dynamic columns."""

from __future__ import annotations

import sys

__all__ = ["add_dynamics_arguments", "run_dynamics"]


def add_dynamics_arguments(p) -> None:
    """``--dynamics``, ``--mass FILE``, ``--gravity``, ``--smoothing`` on a parser."""
    from .._types import number, path
    g = p.add_argument_group("dynamics (t is time in seconds)")
    g.add_argument("--dynamics", action="store_true",
                   help="also the inverse dynamics: the static and the dynamic (gravity, "
                        "inertia and friction of the platform and the legs) active forces and "
                        "constraint values, actuator rates and accelerations, energy and power, "
                        "the workload (a table of its own: without the static table's T_r, "
                        "resultants and residuals); "
                        "the masses are the model's 'dynamics:' block or --mass FILE")
    g.add_argument("--mass", metavar="FILE", type=path,
                   help="a YAML file with a 'dynamics:' mapping (masses, inertias, friction, "
                        "gravity; the schema of a PM's dynamics: block)")
    g.add_argument("--gravity", metavar="GX,GY,GZ",
                   help="gravity in the base frame, model length/s^2 (default: the mass "
                        "model's, else standard gravity along -Z)")
    g.add_argument("--smoothing", type=number(lo=0.0, hi=1e12), metavar="LAM",
                   help="smoothing of the spline through a CSV path (0 interpolates; default: "
                        "chosen by generalised cross-validation)")


def run_dynamics(args, model, fmt, progress, force=None, torque=None) -> int:
    """The dynamic run of ``screwkit trajectory --dynamics`` (table, plot)."""
    from ...dynamics import dynamics, motion_from_args
    from ._common import dump_json, emit_table
    from ...legs._guards import MAX_MAGNITUDE
    from .analyze import parse_triple

    if args.mass is None and model.dynamics is None:
        from ...errors import InputError
        raise InputError(f"{model.name} declares no masses (no 'dynamics:' block): give "
                         "--mass FILE (a YAML file with a 'dynamics:' mapping)")
    motion = motion_from_args(args, model.independent, model.units.length)
    gravity = parse_triple(args.gravity, "--gravity", bound=MAX_MAGNITUDE) \
        if args.gravity is not None else None
    res = dynamics(model, motion, params=args.mass, force=force, torque=torque,
                   gravity=gravity, progress=progress)
    said = [n for n in res.params.notes if n.startswith(("dynamics parameters", "gravity"))]
    if said:                      # the units and gravity taken, never silently
        print("screwkit trajectory: " + "; ".join(said), file=sys.stderr)
    units = None if getattr(args, "units", "model") == "model" else args.units
    text = dump_json(res.to_dict(units)) + "\n" if fmt == "json" else res.to_csv(units=units)
    emit_table(args.out, text)
    from .analyze import workload_note
    if sys.stderr.isatty() and not getattr(args, "quiet", False):   # (JSON: workload.source)
        print(workload_note("trajectory", model, res.force, res.torque, res,
                            "external workload"), file=sys.stderr)
    if args.plot:
        res.plot(args.plot, title=args.title, units=units)
        print(f"wrote {args.plot}", file=sys.stderr)
    c = res.counts()
    # (near-singular samples are computed; the others' dynamic values are NaN)
    near = c.get("near-singular", 0)
    flagged = {k: v for k, v in c.items() if k not in ("ok", "near-singular") and v}
    if near:
        print(f"screwkit trajectory: {near} near-singular of {len(res)} samples (status column; "
              "their efforts are large and sensitive)", file=sys.stderr)
    if flagged:
        print("screwkit trajectory: " + ", ".join(f"{v} {k}" for k, v in flagged.items())
              + f" of {len(res)} samples (status column; their values are NaN)", file=sys.stderr)
    return 0
