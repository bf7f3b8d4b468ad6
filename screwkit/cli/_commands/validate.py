"""``screwkit validate``: synthesis by the observation rules, verification by the solver,
over the paper's Table I and the catalog's accepted legs."""

from __future__ import annotations

import csv
import io
import sys

from ...legs._guards import MAX_DRAWS, MAX_ENTRIES, MAX_SEED
from .._types import integer, output, path, scheduler
from .._progress import add_quiet_argument, progress_bar
from ._common import (catalog_with_model_legs, dask_mapper, default_jobs, dump_json,
                      process_mapper, write_output)

HELP = """For every Table I string (or the STRINGs given): analyse a generic geometry, then
for each target constraint system (one force, one couple; for legs with fewer than five
independent joints every mix of forces and couples) synthesize a structural arrangement
from the three observation rules and verify it with the reciprocal-screw solver, over
several random draws. The catalog's accepted legs are checked against their stated
constraint systems. --model FILE adds the leg types of a model file: each is checked like
the catalog's (its 'expect', the observation rules, its actuation wrench) and its string is
validated with the others. Exit status 1 on any disagreement."""

_COLUMNS = [("leg", "Leg"), ("chain", "Equivalent chain"), ("connectivity", "Connectivity"),
            ("generic", "Generic constraints"), ("force", "Constraint force"),
            ("couple", "Constraint couple"), ("combinations", "Targets"),
            ("verified", "Verified")]
_CAT_COLUMNS = [("leg", "Catalog leg"), ("string", "String"), ("expected", "Expected"),
                ("found", "Found (solver)"), ("verified", "Verified")]


def register(sub):
    p = sub.add_parser("validate", help="synthesize and verify the legs of Table I and the catalog",
                       description=HELP)
    p.add_argument("strings", nargs="*", metavar="STRING",
                   help="leg strings to validate instead of Table I (e.g. UPU RR_PRR)")
    p.add_argument("--format", choices=("text", "markdown", "csv", "json"), default="text",
                   help="output format (default text; with --out, the file's suffix: .json, "
                        ".md, .csv)")
    p.add_argument("--json", action="store_true", help="the same as --format json")
    p.add_argument("--out", metavar="FILE", type=output, help="write the table to FILE (the summary line "
                   "still goes to standard output)")
    p.add_argument("--draws", type=integer(1, MAX_DRAWS), default=None,
                   help="random draws per target (default 3)")
    p.add_argument("--seed", type=integer(0, MAX_SEED), default=0, help="seed of the random draws (default 0)")
    p.add_argument("--no-catalog", action="store_true", help="skip the catalog's legs")
    p.add_argument("--model", metavar="FILE", type=path,
                   help="also check the leg types of a model file (its 'legs:' list) and "
                        "validate their strings")
    p.add_argument("--jobs", type=integer(1, 64), metavar="N", default=None,
                   help="local worker processes (default: 2 on Linux with 2 or more cores, else "
                        "1: serial); the report equals the serial one")
    p.add_argument("--workers", type=integer(1, 64), metavar="N",
                   help="validate the strings on a local Dask cluster of N worker processes "
                        "(127.0.0.1; needs screwkit[dask]); the report equals the serial one")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", type=scheduler,
                   help="validate the strings on a running Dask scheduler")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def _escape_md(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def render_markdown(report, rows, cat_rows) -> str:
    out = ["| " + " | ".join(h for _, h in _COLUMNS) + " |",
           "|" + "|".join("---" for _ in _COLUMNS) + "|"]
    for r in rows:
        out.append("| " + " | ".join(_escape_md(r[k]) for k, _ in _COLUMNS) + " |")
    if cat_rows:
        out += ["", "| " + " | ".join(h for _, h in _CAT_COLUMNS) + " |",
                "|" + "|".join("---" for _ in _CAT_COLUMNS) + "|"]
        for r in cat_rows:
            out.append("| " + " | ".join(_escape_md(r[k]) for k, _ in _CAT_COLUMNS) + " |")
    out += ["", report.summary()]
    return "\n".join(out) + "\n"


def render_csv(report, rows, cat_rows) -> str:
    buf = io.StringIO()
    keys = ["section"] + [k for k, _ in _COLUMNS] + ["string", "expected", "found"]
    w = csv.DictWriter(buf, fieldnames=keys, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({"section": "table1", **r})
    for r in cat_rows:
        w.writerow({"section": "catalog", **r})
    return buf.getvalue()


def render_text(report, rows, cat_rows) -> str:
    short = [("leg", "leg"), ("chain", "chain"), ("connectivity", "conn."),
             ("generic", "generic constraints"), ("combinations", "targets")]
    table = []
    for r in rows:
        table.append({**r, "flag": "ok" if r["verified"].startswith("yes") else "FAIL"})
    widths = {k: max(len(h), *(len(t[k]) for t in table)) if table else len(h) for k, h in short}
    lines = ["  ".join(f"{h:<{widths[k]}}" for k, h in short) + "  verified"]
    for t in table:
        lines.append("  ".join(f"{t[k]:<{widths[k]}}" for k, _ in short) + f"  {t['verified']}")
        lines.append(f"    force:  {t['force']}")
        lines.append(f"    couple: {t['couple']}")
    if cat_rows:
        lines.append("")
        lines.append("catalog legs (built by their rules):")
        w = max(len(c["leg"]) for c in cat_rows)
        for c in cat_rows:
            lines.append(f"  {c['leg']:<{w}}  {c['string']:<8} expected {c['expected']:<6} "
                         f"found {c['found']}  -> {c['verified']}")
    lines += ["", report.summary()]
    return "\n".join(lines) + "\n"


def report_json(report) -> dict:
    def ver(v):
        if v is None:
            return None
        return {"ok": v.ok, "problems": list(v.problems), "dimension": v.dimension,
                "expected_dimension": v.expected_dimension, "contained": list(v.contained),
                "same_span": v.same_span, "dependent_joints": list(v.dependent_joints),
                "dependence_allowed": v.dependence_allowed, "actuation": v.actuation,
                "residual": v.residual, "condition_number": v.condition_number}

    legs = []
    for v in report.legs:
        legs.append({
            "leg": v.string.marked, "connectivity": v.connectivity, "constraints": v.k,
            "generic": v.generic_summary, "dependent_joints": list(v.dependent_joints),
            "counting_rank": v.counting, "can_force": v.can_force, "can_couple": v.can_couple,
            "notes": list(v.notes), "problems": list(v.problems), "ok": v.ok,
            "targets": [{
                "composition": {"forces": t.composition[0], "couples": t.composition[1]},
                "label": t.label, "realizable": t.realizable, "layout": t.layout,
                "layout_words": t.layout_words, "how": t.how, "reason": t.reason,
                "proof": t.proof, "consistent": t.consistent, "verified": t.verified,
                "draws": [{"draw": d.draw, "realizable": d.realizable, "layout": d.layout,
                           "verification": ver(d.verification)} for d in t.draws],
            } for t in v.targets],
        })
    return {
        "summary": report.summary(), "counts": report.counts, "draws": report.draws,
        "seed": report.seed, "seconds": report.seconds, "ok": report.ok, "legs": legs,
        "catalog": [{"leg": c.name, "string": c.string, "expected": c.expected,
                     "found": c.found, "problems": list(c.problems), "ok": c.ok}
                    for c in report.catalog],
    }


def run(args) -> int:
    from ...errors import InputError
    from ...synthesis import DEFAULT_DRAWS, catalog_rows, report_rows, validate_table1
    if args.json:                       # (--json: as every other command spells it)
        args.format = "json"

    draws = DEFAULT_DRAWS if args.draws is None else args.draws
    if draws < 1:
        raise InputError(f"--draws must be at least 1, got {draws}")
    if len(args.strings) > MAX_ENTRIES:
        raise InputError(f"{len(args.strings)} leg strings: validate takes at most {MAX_ENTRIES}")
    mapper = dask_mapper(args)
    if mapper is not None and args.jobs is not None:
        raise InputError("give either --jobs N (local processes) or a Dask cluster")
    if mapper is None:
        # by default 2 forked processes on Linux (elsewhere fork is unsafe or unavailable)
        mapper = process_mapper(default_jobs(args.jobs))
    catalog, strings = None, args.strings or None
    if args.model:
        from ...pm import default_catalog

        catalog = catalog_with_model_legs(args.model)
        mine = [s.string.marked for n, s in catalog.legs.items()
                if default_catalog().legs.get(n) is not s]
        strings = list(dict.fromkeys((strings or catalog.table1_distinct()) + mine))
        if args.no_catalog:
            raise InputError("--model checks the file's leg types: not with --no-catalog")
    with progress_bar(args, "validate", "string") as progress:
        report = validate_table1(draws=draws, seed=args.seed, strings=strings,
                                 check_catalog=not args.no_catalog, progress=progress,
                                 mapper=mapper, catalog=catalog)
    rows, cat_rows = report_rows(report), catalog_rows(report)
    fmt = args.format
    if args.out and fmt == "text":           # (the file's suffix says which, as trajectory)
        fmt = {".json": "json", ".md": "markdown", ".csv": "csv"}.get(
            str(args.out).lower()[str(args.out).rfind("."):], "text")
    args.format = fmt
    if args.format == "json":
        text = dump_json(report_json(report)) + "\n"
    elif args.format == "markdown":
        text = render_markdown(report, rows, cat_rows)
    elif args.format == "csv":
        text = render_csv(report, rows, cat_rows)
    else:
        text = render_text(report, rows, cat_rows)
    if args.out:
        write_output(args.out, text)
        print(report.summary())
    else:
        sys.stdout.write(text)
    return 0 if report.ok else 1
