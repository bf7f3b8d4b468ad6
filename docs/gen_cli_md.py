"""Regenerate docs/cli.md from the argparse definitions (run: python docs/gen_cli_md.py).

tests/test_docs.py fails when docs/cli.md is out of date.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HEADER = """# Command-line reference

Generated from the argument parsers by `python docs/gen_cli_md.py`; do not edit by hand.

Conventions: angles in degrees, lengths and forces in the model's units (the paper's examples use
cm and kN, torques in kN.cm). Every command accepts `--json` where it prints results, for scripts.
Errors are printed on one line on stderr with exit status 2 (3 for an internal error); a command
that finds a disagreement (`validate`, `check`) exits with status 1.
"""


def render() -> str:
    from screwkit.cli import build_parser

    parser = build_parser()
    out = [HEADER, "## screwkit", "", "```text", parser.format_help().rstrip(), "```", ""]
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, p in sub.choices.items():
        p.prog = f"screwkit {name}"
        out += [f"## screwkit {name}", "", "```text", p.format_help().rstrip(), "```", ""]
    return "\n".join(out)


if __name__ == "__main__":
    import os
    os.environ.setdefault("COLUMNS", "100")
    target = Path(__file__).with_name("cli.md")
    target.write_text(render(), encoding="utf-8")
    print(f"wrote {target}", file=sys.stderr)
