"""``screwkit model check FILE`` / ``screwkit model schema`` / ``screwkit model write PM``:
model files, their schema, and a model written back as a self-contained file."""

from __future__ import annotations

import sys

from .._types import output, path
from ._common import dump_json, write_output

HELP = """Check a catalog or model file (every problem at once, each with its line, entry and
field), print the JSON Schema of model files (for editors: completion and validation), or write
a model (a catalog PM, a file's PM, with --set overrides) back as a self-contained model file
to edit: its leg types that are not the catalog's are written inline."""


def register(sub):
    p = sub.add_parser("model", help="check a model file; print the model-file JSON Schema",
                       description=HELP)
    msub = p.add_subparsers(dest="model_command", metavar="ACTION")
    c = msub.add_parser("check", help="report every problem of a model file",
                        description="Report every problem of a catalog or model file: YAML "
                                    "(duplicate keys), the JSON Schema (unknown keys, types; "
                                    "needs jsonschema), each leg type and each PM. Exit status "
                                    "0 when the file is valid, 2 otherwise.")
    c.add_argument("file", type=path, help="the YAML file")
    c.add_argument("--json", action="store_true", help="print JSON instead of text")
    c.set_defaults(func=run_check)
    s = msub.add_parser("schema", help="print the JSON Schema of model files",
                        description="Print (or write) the JSON Schema of catalog and model "
                                    "files, the one shipped as screwkit/pm/model.schema.json.")
    s.add_argument("--out", type=output, help="write it to this file instead")
    s.add_argument("--path", action="store_true", help="print the packaged file's path and exit")
    s.set_defaults(func=run_schema)
    w = msub.add_parser("write", help="write a model back as a self-contained model file",
                        description="Write a PM (a catalog name or --model FILE, with --set "
                                    "overrides applied) as a model file: its definition under "
                                    "pms:, leg types that are not the catalog's written inline. "
                                    "Reading the file again gives the same model.")
    from .analyze import add_pm_arguments
    add_pm_arguments(w, pose=False)
    w.add_argument("--out", type=output, help="write it to this file instead of printing it")
    w.set_defaults(func=run_write)
    p.set_defaults(func=lambda args: (p.print_help(), print(
        "screwkit model: error: an action is needed (check, schema or write: listed above)",
        file=sys.stderr), 2)[2])


def run_write(args) -> int:
    from .analyze import resolve_model

    pm = resolve_model(args)
    if args.out:
        write_output(args.out, pm.to_yaml())
        print(f"wrote {args.out} ({pm.name}: {len(pm.legs)} legs)")
    else:
        print(pm.to_yaml(), end="")
    return 0


def run_check(args) -> int:
    from ... import load_pm
    from ...pm import check_model_file

    problems = check_model_file(args.file, load=load_pm)
    if args.json:
        print(dump_json({"file": args.file, "valid": not problems,
                         "problems": [p.to_dict() for p in problems]}))
    elif problems:
        print(f"{args.file}: {len(problems)} problem{'s' if len(problems) != 1 else ''}")
        for p in problems:
            print(f"  {p}")
    else:
        print(f"{args.file}: valid")
    if problems:                        # the one-line error of every exit status 2
        print(f"screwkit model check: error: {args.file}: {len(problems)} "
              f"problem{'s' if len(problems) != 1 else ''} (listed above)", file=sys.stderr)
        return 2
    return 0


def run_schema(args) -> int:
    from ...pm import schema_path, schema_text

    if args.path:
        if args.out:
            from ...errors import InputError
            raise InputError("--path prints the packaged schema's path: --out writes the "
                             "schema; give one or the other")
        print(schema_path())
        return 0
    if args.out:
        write_output(args.out, schema_text())
        print(f"wrote {args.out}")
    else:
        print(schema_text(), end="")
    return 0
