"""``screwkit draw PM``: a 3D drawing of a PM at a pose with its actuation and constraint wrenches."""

from __future__ import annotations

import sys

import numpy as np

from ...legs._guards import MAX_ANGLE_DEG, parse_number, shorten
from .._types import figure, integer, label
from ._common import add_unit_label_arguments, check_unit_labels
from ...errors import InputError
from .analyze import (add_load_arguments, add_pm_arguments, load_source, parse_assignments,
                      require_load,
                      resolve_model)

HELP = """Draw a PM at a pose (the paper's Figs. 3b and 4b): base and platform polygons, the legs
with their joints (P joints as sleeves), the actuation forces on their lines (filled heads, line
dash-dotted), the constraint forces as arrows on their lines (open heads, line dashed) and the
constraint couples as double-headed arrows beside their legs, each arrow scaled by its value in
the statics of the workload (F, T) at o and labelled with it; every leg and its wrenches in the
leg's colour (the colours of `screwkit trajectory --plot`). Values that statics does not
determine (an indeterminate PM) are marked *. Angles in degrees, lengths and forces in the
model's units."""


def register(sub):
    p = sub.add_parser("draw", help="3D drawing of a PM at a pose with its wrenches",
                       description=HELP)
    add_pm_arguments(p)
    add_load_arguments(p)
    p.add_argument("-o", "--out", metavar="PNG", required=True, type=figure, help="output image (PNG)")
    p.add_argument("--view", metavar="ELEV,AZIM",
                   help="camera elevation and azimuth in degrees (default: chosen so that no "
                        "A_i, a_i or o hides behind a leg)")
    p.add_argument("--joint-labels", action="store_true", help="label every joint")
    p.add_argument("--title", type=label(), help="figure title (default: PM, pose and workload)")
    add_unit_label_arguments(p, "on the drawing")
    p.add_argument("--dpi", type=integer(20, 1200), default=150, help="resolution (default 150)")
    p.set_defaults(func=run)


def _title(res, force_unit, length_unit, singular, given=None) -> str:
    """The PM, its pose, the workload and the conditioning; ``given`` (--title) in place of
    the PM and pose line (the workload's line is kept: every figure says its load)."""
    p = res.solution.params_degrees()
    scale = res.model.normalisation.length

    def tidy(k):  # rounding noise of the solver (1e-16 deg) printed as 0
        x = float(p[k])
        return 0.0 if abs(x) < 1e-9 * (1.0 if k in ('alpha', 'beta', 'gamma') else scale) else x

    pose = ", ".join(
        f"{k} = {tidy(k):.4g}{'°' if k in ('alpha', 'beta', 'gamma') else ' ' + length_unit}"
        for k in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma"))
    F = ", ".join(f"{x:g}" for x in res.force)
    T = ", ".join(f"{x:g}" for x in res.torque)
    t = (f"{given or res.model.name + ' at ' + pose}\n"
         f"F = [{F}] {force_unit}, T = [{T}] {force_unit}·{length_unit} at o "
         f"({load_source(res).split(' (')[0]}); "
         f"condition number {res.jacobian.condition_number:.3g}")
    if singular:
        t += f"\n{res.jacobian.singularity_kind.upper()} SINGULARITY: no statics (values n/a)"
    elif res.jacobian.indeterminate:
        t += (f"\nstatically indeterminate ({res.jacobian.indeterminacy} redundant rows): "
              "values marked * are not determined by statics")
    return t


def run(args) -> int:
    from ...viz import draw_pm, require_matplotlib
    from ...engine import analyze_pm, wrench_rows

    require_matplotlib()
    view = None
    if args.view:
        parts = args.view.split(",")
        if len(parts) != 2:
            raise InputError(f"--view {shorten(args.view)} must be ELEV,AZIM in degrees")
        view = tuple(parse_number(x, f"--view {w}", bound=MAX_ANGLE_DEG)
                     for x, w in zip(parts, ("ELEV", "AZIM")))
    if args.dpi < 20 or args.dpi > 1200:
        raise InputError(f"--dpi {args.dpi} must be between 20 and 1200")
    pose = parse_assignments(args.pose, "--pose")
    model = resolve_model(args)
    force, torque = require_load(args, model)
    res = analyze_pm(model, pose, degrees=True, force=force, torque=torque,
                     raise_on_singular=False)
    sol = res.solution
    singular = res.jacobian.singular
    rows, skipped = wrench_rows(res)
    check_unit_labels(model, args.length_unit, args.force_unit)
    fu = args.force_unit or model.units.force
    lu = args.length_unit or model.units.length
    title = _title(res, fu, lu, singular, args.title)
    how = "compliance-weighted" if getattr(res, "stiffness", None) is not None else "least-norm"
    draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position, rows, out=args.out,
            title=title, force_unit=fu, torque_unit=f"{fu}·{lu}", length_unit=lu,
            dpi=args.dpi, joint_labels=args.joint_labels, view=view,
            indeterminate_note=f"not determined by statics\n  ({how} value)")
    for s in skipped:
        print(f"screwkit draw: not drawn: {s}", file=sys.stderr)
    for w in res.warnings if not singular else ():     # one line each, as analyze prints them
        print(f"screwkit draw: warning: {w}", file=sys.stderr)
    if singular:
        print(f"screwkit draw: {res.jacobian.singularity_kind} singularity at this pose "
              f"(condition number {res.jacobian.condition_number:.3g}): no statics",
              file=sys.stderr)
    print(f"wrote {args.out}", file=sys.stderr)
    return 0
