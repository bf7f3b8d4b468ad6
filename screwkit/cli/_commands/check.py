"""``screwkit check PM`` / ``screwkit check --all``: cross-check screwkit with Pinocchio."""

from __future__ import annotations

import sys

import numpy as np

from ...legs._guards import MAX_POSES, MAX_SEED
from .._types import integer, number
from ...errors import InputError
from .._progress import add_quiet_argument, progress_bar
from ._common import dump_json
from .analyze import add_pm_arguments, parse_assignments, resolve_model

HELP = """Cross-check screwkit's analysis of a PM with Pinocchio: the PM is rebuilt with
Pinocchio's own joints (spherical, universal, revolute, prismatic, helical) and loop-closure
constraints, and at each pose the following are compared (largest deviation, relative):
closure (Pinocchio's FK of every leg at screwkit's joint values reaches the platform),
twists (each leg's WORLD-frame Jacobian vs screwkit's joint twists), mobility (DOF and
platform twist space from the closed-loop constraint Jacobian; no motion with the actuators
locked), statics (J^T w of each leg's wrench: 0 on passive joints, the actuator force on the
actuated one; closed-loop virtual work). Exit status 1 when a check fails. --all checks
every catalog PM at regular poses drawn around its default pose (angles +-8 deg, lengths
+-8 % of Zo; singular or unreachable draws skipped)."""


def register(sub):
    p = sub.add_parser("check", help="cross-check a PM (or every catalog PM) with Pinocchio",
                       description=HELP)
    add_pm_arguments(p)
    p.add_argument("--all", action="store_true", help="check every catalog PM")
    p.add_argument("--poses", type=integer(1, MAX_POSES), metavar="N", default=None,
                   help="number of regular poses drawn per PM (default: 3 with --all; for one PM "
                        "the given or default pose only)")
    p.add_argument("--seed", type=integer(0, MAX_SEED), default=None,
                   help="seed of the pose draws of --poses or --all (default 0)")
    p.add_argument("--rtol", type=number(lo=0.0, hi=1.0), default=None, metavar="TOL",
                   help="relative tolerance of every deviation (default 1e-9)")
    p.add_argument("--json", action="store_true", help="print JSON (a list of reports) instead of text")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def _rtol(args) -> float:
    from ...interop import CHECK_RTOL

    if args.rtol is None:
        return CHECK_RTOL
    if not (np.isfinite(args.rtol) and args.rtol >= 0):
        raise InputError(f"--rtol must be a finite number >= 0, got {args.rtol}")
    return float(args.rtol)


def _poses(args, default):
    n = default if args.poses is None else args.poses
    if n is not None and n < 1:
        raise InputError(f"--poses must be a positive integer, got {n}")
    return n


def run(args) -> int:
    from ...interop import PMChecker, check_all, check_analysis, regular_analyses
    from ...engine import analyze_pm

    rtol = _rtol(args)
    note = ""
    if args.all:
        if args.pm or args.model or args.set or args.pose:
            raise InputError("--all checks the catalog's PMs at drawn poses: give no PM, --model, "
                             "--set or --pose with it")
        from ...pm import pm_names

        n = _poses(args, 3)
        total = len(pm_names()) * n
        with progress_bar(args, "check --all", "pose", total) as bar:
            done = []

            def step(report) -> None:
                done.append(report)
                if bar is not None:
                    bar(len(done), total)

            reports = check_all(n, args.seed or 0, rtol=rtol, progress=step)
    else:
        model = resolve_model(args)
        pose = parse_assignments(args.pose, "--pose")
        n = _poses(args, None)
        if n is None and args.seed is not None:
            raise InputError("--seed seeds the poses --poses N draws: add --poses (one PM is "
                             "checked at its --pose, else its default pose)")
        checker = PMChecker.for_model(model)
        from ...interop._check_catalog import check_load
        F, T, note = check_load(model)
        if n is None:
            analyses = (analyze_pm(model, pose, degrees=True, force=F, torque=T),)
            for w in analyses[0].warnings:           # the pose's, as analyze warns of them
                print(f"screwkit check: warning: {w}", file=sys.stderr)
        else:
            centre = None
            if pose:
                centre = analyze_pm(model, pose, degrees=True).solution.params
            analyses = regular_analyses(model, n, args.seed or 0, centre=centre)
        reports = tuple(check_analysis(a, checker, rtol=rtol) for a in analyses)
    if args.json:
        print(dump_json([r.as_dict() for r in reports]))
    else:
        print_table(reports, note)
    return 0 if all(r.passed for r in reports) else 1


def print_table(reports, note: str = "") -> None:
    """Columns PM, pose, check, deviation, tolerance, pass; then a summary line."""
    lines = []
    for r in reports:
        if r.error:
            lines.append((r.pm, "-", "error", "-", "-", "FAIL", r.error))
        for row in r.rows:
            lines.append((r.pm, r.pose_label, row.name, f"{row.deviation:.2e}", f"{row.tolerance:.0e}",
                          "ok" if row.passed else "FAIL", ""))
    head = ("PM", "pose", "check", "deviation", "tolerance", "pass")
    w = [max([len(head[k])] + [len(x[k]) for x in lines]) for k in range(len(head))]
    print("  ".join(h.ljust(w[k]) for k, h in enumerate(head)).rstrip())
    for x in lines:
        print(("  ".join(str(c).ljust(w[k]) for k, c in enumerate(x[:6])) + ("  " + x[6] if x[6] else "")).rstrip())
    n_rows = sum(len(r.rows) for r in reports)
    bad = [r for r in reports if not r.passed]
    pms = len({r.pm for r in reports})
    worst = max(((row.deviation, row.name, r.pm) for r in reports for row in r.rows if row.tolerance > 0),
                default=None)
    summary = (f"{len(reports)} pose(s) of {pms} PM(s), {n_rows} checks: "
               + ("all passed" if not bad else f"{len(bad)} pose(s) FAILED"))
    if worst is not None:
        summary += f"; largest relative deviation {worst[0]:.2e} ({worst[1]}, {worst[2]})"
    units = sorted({r.length_unit or "the model's own" for r in reports if not r.error})
    if units:                        # (the poses' units: angles in degrees, lengths the PM's)
        summary += f"; poses in deg and {', '.join(units)}"
    if note:
        summary += f"; statics under {note}"
    print(summary)
