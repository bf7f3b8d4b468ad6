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
cm and kN, torques in kN.cm). Errors are printed on one line on stderr with exit status 2 (3 for
an internal error); a command that finds a disagreement (`validate`, `check`) exits with status 1.
Commands that write files (`--out`, `--plot`, `-o`) create the missing folders.
"""


def _options(p) -> dict:
    return {s: a for a in p._actions for s in a.option_strings}


def _nested(p):
    """``{action: parser}`` of a command with actions of its own (``screwkit model check``)."""
    sub = next((a for a in p._actions if isinstance(a, argparse._SubParsersAction)), None)
    return dict(sub.choices) if sub is not None else {}


def conventions(sub) -> str:
    """The JSON and progress conventions, read off the parsers (so they cannot go stale)."""
    flag = [n for n, p in sub.choices.items() if "--json" in _options(p)]
    flag += [f"{n} {a}" for n, p in sub.choices.items() for a, q in _nested(p).items()
             if "--json" in _options(q)]
    fmt = [n for n, p in sub.choices.items()
           if "--format" in _options(p) and "json" in (_options(p)["--format"].choices or ())]
    quiet = [n for n, p in sub.choices.items() if "--quiet" in _options(p)]
    code = lambda names: ", ".join(f"`{n}`" for n in names)      # noqa: E731
    return (f"JSON for scripts: `--json` on {code(flag)}; `--format json` on {code(fmt)}. "
            f"The long commands ({code(quiet)}) show a progress bar (tqdm) on a terminal, with "
            "the rate and the time left, once the work lasts half a second; it is drawn only when "
            "standard error is a terminal (a widget in a Jupyter notebook), and `--quiet` turns "
            "it off.\n")


def render() -> str:
    from screwkit.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = [HEADER, conventions(sub), "## screwkit", "", "```text", parser.format_help().rstrip(),
           "```", ""]
    for name, p in sub.choices.items():
        p.prog = f"screwkit {name}"
        out += [f"## screwkit {name}", "", "```text", p.format_help().rstrip(), "```", ""]
        for action, q in _nested(p).items():
            q.prog = f"screwkit {name} {action}"
            out += [f"### screwkit {name} {action}", "", "```text", q.format_help().rstrip(),
                    "```", ""]
    return "\n".join(out)


if __name__ == "__main__":
    import os
    os.environ.setdefault("COLUMNS", "100")
    target = Path(__file__).with_name("cli.md")
    target.write_text(render(), encoding="utf-8")
    print(f"wrote {target}", file=sys.stderr)
