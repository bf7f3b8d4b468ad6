"""``screwkit fk PM --actuators q1=...``: forward kinematics (the pose from the actuators)."""

from __future__ import annotations

import argparse
import sys

from ...engine._modes import MAX_SEEDS
from ...errors import InputError
from .._progress import add_quiet_argument, progress_bar
from .._types import integer
from ._common import dump_json, fmt_num
from .analyze import add_pm_arguments, parse_assignments, resolve_model

HELP = """Forward kinematics (direct displacement): the platform pose where the actuated
joints take the given values. --actuators q1=..,q2=.. gives each leg's actuated joint value
from home (the model's lengths for linear actuators, degrees for rotary ones), r1=.. a leg's
extension |a_i - A_i| where that is its linear actuator's value plus a constant. Newton on
the loop closures from home (or from the default pose where home is singular, or --guess),
moving the actuators in small steps (continuation). --all searches --seeds starts in one
batch and lists every distinct real solution found (assembly modes), those above the base
first, each marked: above or below the base (a mirror mode), the sign of det J, and whether
it has the working mode's sign pattern (above the base, det J of home's sign). Exit status
2, with the closure residual on stderr, when no solution is found."""

EPILOG = """examples:
  screwkit fk 3RRPRR --actuators q1=-6.2,q2=-3.1,q3=1.5
  screwkit fk 3RPS --actuators r1=67.1,r2=69.5,r3=64.8 --all --json"""


def register(sub):
    p = sub.add_parser("fk", help="forward kinematics: the pose from the actuator values",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_pm_arguments(p, pose=False)
    p.add_argument("--actuators", metavar="q1=V,q2=V,...", required=True, action="append",
                   help="actuated joint values from home (q<i>) or leg extensions (r<i>), "
                        "comma-separated or repeated")
    p.add_argument("--guess", metavar="NAME=VALUE", action="append", default=[],
                   help="start from this pose (independent parameters, degrees)")
    p.add_argument("--all", action="store_true",
                   help="search many seeds and list every distinct real solution")
    p.add_argument("--seeds", type=integer(1, MAX_SEEDS), default=None,
                   help=f"seeds of --all (1 to {MAX_SEEDS}; default 1000)")
    p.add_argument("--units", choices=["model", "SI"], default="model",
                   help="units of the printed pose (text and JSON): the model's (default) or "
                        "SI (m); --actuators and --guess stay in the model's units")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def actuators_of(text_items) -> dict:
    items = [x for t in text_items for x in t.split(",") if x.strip()]
    return parse_assignments(items, "--actuators")


def run(args) -> int:
    import numpy as np

    from ...api import assembly_modes, forward
    from ...engine._report import output_scales
    model = resolve_model(args)
    units = None if args.units == "model" else args.units
    output_scales(model, units)             # (a model without units: refused before solving)
    act = actuators_of(args.actuators)
    if args.seeds is not None and not args.all:
        raise InputError("--seeds is the number of starts of --all: add --all")
    if args.all:
        if args.guess:
            raise InputError("--all searches from seeds: it takes no --guess")
        K = args.seeds or 1000
        with progress_bar(args, "fk --all", "seed", K) as progress:
            res = assembly_modes(model, act, seeds=K, degrees=True, progress=progress)
        out = res.to_dict(units)
        sols = res.solutions
    else:
        from ...legs._guards import MAX_ANGLE_DEG
        guess = parse_assignments(args.guess, "--guess") or None
        for k, v in (guess or {}).items():       # (said in degrees, as given)
            if k in ("alpha", "beta", "gamma") and abs(v) > MAX_ANGLE_DEG:
                raise InputError(f"--guess {k} = {v:g} deg is beyond +-{MAX_ANGLE_DEG:g} deg")
        sols = forward(model, act, guess, degrees=True)      # (the guess in degrees too)
        out = {"pm": model.name, "count": len(sols), "solved": int(np.sum(sols.success)),
               "solutions": [sols.to_dict(i, units) for i in range(len(sols))]}
    # --all lists what it found: it fails only where no solution is confirmed
    solved = bool(np.any(sols.success) if args.all else np.all(sols.success))
    if args.json:
        print(dump_json(out))
    else:
        _print(model, sols, res if args.all else None, units)
    if not solved:
        bad = [i for i in range(len(sols)) if not sols.success[i]]
        if sols.unsplit is not None and np.all(sols.unsplit[bad]):
            print(f"screwkit fk: error: the solution closes (residual "
                  f"{float(np.min(sols.residual[bad])):.3g}) at beta = 0, a representation "
                  f"singularity of {model.order}, where the model's split of alpha and gamma "
                  "was not found, so the analysis does not confirm it; try --all",
                  file=sys.stderr)
        else:
            print(f"screwkit fk: error: no solution at these actuator values: closure "
                  f"residual {float(np.min(sols.residual[bad])):.3g} (length-normalised) after "
                  "Newton and continuation from the reference; try --guess NAME=VALUE or --all",
                  file=sys.stderr)
        return 2
    return 0


#: Singular solutions of --all listed in the text (the rest in --json): many of them are
#: points of a continuum (a self-motion), counted as often as the seeds land on it.
SINGULAR_SHOWN = 6


def _print(model, sols, res, units=None) -> None:
    import numpy as np
    from ...engine._report import output_scales
    u = output_scales(model, units)[0]
    singular = [] if res is None else [int(i) for i in np.flatnonzero(res.singular)]
    head = (f"{len(sols)} distinct real solutions from {res.seeds} seeds ({res.converged} "
            "converged; a lower bound), above the base first" if res is not None
            else "forward kinematics")
    print(f"{model.name}: {head}; lengths {u['length']}, angles deg"
          + (f" (converted from the model's {model.units.length})" if units else ""))
    hidden = set(singular[SINGULAR_SHOWN:]) if res is not None else set()
    if res is not None and len(singular) > SINGULAR_SHOWN:
        print(f"  {len(singular)} of them singular (J rank-deficient): so many singular "
              "solutions are points of a continuum of poses at these actuator values (a "
              "self-motion), not isolated assembly modes, and their count grows with the "
              f"seeds; the first {SINGULAR_SHOWN} shown, all with --json")
    if res is None:
        print("  one solution: the one Newton and continuation reach from their start; other "
              "assembly modes may close at these values, with the same sign pattern too "
              "(--all searches for them)")
    for i in range(len(sols)):
        if i in hidden:
            continue
        d = sols.to_dict(i, units)
        pose = "  ".join(f"{k}={fmt_num(v, 9)}" for k, v in d["pose"].items())
        print(f"  {i + 1}. {pose}")
        if d["closed_unconfirmed"]:
            print(f"     closes every leg (residual {d['residual']:.2e}), not confirmed: beta = 0 "
                  f"is a representation singularity of {model.order} and the model's split of "
                  "alpha and gamma was not found (the angles shown are one split of the "
                  "rotation); no analysis")
            continue
        if not d["success"]:
            print(f"     not solved: residual {d['residual']:.2e} (the last iterate, not a pose of "
                  "the PM)")
            continue
        level = d.get("level")
        trust = f"; trust level {level}" if level and level != d["conditioning"] and \
            not (level == "ok" and d["conditioning"] == "regular") else ""
        print(f"     solved: residual {d['residual']:.2e}, condition "
              f"{d['condition_number']:.4g} ({d['conditioning']}{trust}); {d['mode']}")
        if not d["within_limits"]:
            from ...engine._limits import limits_warnings
            print(f"     {limits_warnings(sols.analysis[i])[0]}")
