"""``screwkit fk PM --actuators q1=...``: forward kinematics (the pose from the actuators)."""

from __future__ import annotations

import argparse

from ...errors import InputError
from ._common import dump_json, fmt_num
from .analyze import add_pm_arguments, parse_assignments, resolve_model

HELP = """Forward kinematics (direct displacement): the platform pose where the actuated
joints take the given values. --actuators q1=..,q2=.. gives each leg's actuated joint value
from home (the model's lengths for linear actuators, degrees for rotary ones), r1=.. a leg's
extension |a_i - A_i| where that is its linear actuator's value plus a constant. Newton on
the loop closures from home (or from the default pose where home is singular, or --guess),
moving the actuators in small steps (continuation). --all searches --seeds starts in one
batch and lists every distinct real solution found (assembly modes) with the sign of det J."""

EPILOG = """examples:
  screwkit fk 3RRPRR --actuators q1=-6.2,q2=-3.1,q3=1.5
  screwkit fk 3RPS --actuators r1=67.1,r2=69.5,r3=64.8 --all --json"""


def register(sub):
    p = sub.add_parser("fk", help="forward kinematics: the pose from the actuator values",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_pm_arguments(p, pose=False)
    p.add_argument("--actuators", metavar="q1=V,q2=V,...", required=True,
                   help="actuated joint values from home (q<i>) or leg extensions (r<i>), "
                        "comma-separated or repeated")
    p.add_argument("--guess", metavar="NAME=VALUE", action="append", default=[],
                   help="start from this pose (independent parameters, degrees)")
    p.add_argument("--all", action="store_true",
                   help="search many seeds and list every distinct real solution")
    p.add_argument("--seeds", type=int, default=1000, help="seeds of --all (default 1000)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)


def actuators_of(text_items) -> dict:
    items = [x for t in text_items for x in t.split(",") if x.strip()]
    return parse_assignments(items, "--actuators")


def run(args) -> int:
    import numpy as np

    from ...api import assembly_modes, forward
    model = resolve_model(args)
    act = actuators_of([args.actuators])
    if args.all:
        if args.guess:
            raise InputError("--all searches from seeds: it takes no --guess")
        res = assembly_modes(model, act, seeds=args.seeds, degrees=True)
        out = res.to_dict()
        sols = res.solutions
    else:
        guess = parse_assignments(args.guess, "--guess") or None
        if guess:
            from ...engine import LENGTH_PARAMS
            guess = {k: (v if k in LENGTH_PARAMS else np.radians(v)) for k, v in guess.items()}
        sols = forward(model, act, guess, degrees=True)
        out = {"pm": model.name, "count": len(sols),
               "solutions": [sols.to_dict(i) for i in range(len(sols))]}
    if args.json:
        print(dump_json(out))
        return 0 if bool(np.all(sols.success)) else 1
    u = model.units
    head = (f"{len(sols)} distinct real solutions from {res.seeds} seeds ({res.converged} "
            "converged; a lower bound)" if args.all else "forward kinematics")
    print(f"{model.name}: {head}; lengths {u.length}, angles deg")
    for i in range(len(sols)):
        d = sols.to_dict(i)
        pose = "  ".join(f"{k}={fmt_num(v, 9)}" for k, v in d["pose"].items())
        mode = "" if d["same_assembly_mode_as_reference"] else \
            f"  (det J sign unlike {d['reference']}'s: another assembly mode)"
        print(f"  {i + 1}. {pose}")
        print(f"     {'solved' if d['success'] else 'NOT SOLVED'}: residual "
              f"{d['residual']:.2e}, condition {d['condition_number']:.4g} ({d['level']}), "
              f"det J sign {d['det_sign']:+d}{mode}")
    return 0 if bool(np.all(sols.success)) else 1
