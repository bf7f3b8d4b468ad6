"""The generated references in docs/ are current, and the README's commands exist."""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_cli_reference_is_current(monkeypatch):
    monkeypatch.setenv("COLUMNS", "100")
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import gen_cli_md
    finally:
        sys.path.pop(0)
    assert (ROOT / "docs" / "cli.md").read_text(encoding="utf-8") == gen_cli_md.render(), \
        "docs/cli.md is stale: run python docs/gen_cli_md.py"


def test_readme_commands_are_commands():
    """Every `screwkit COMMAND` on a command line of the README is a real sub-command."""
    from screwkit.cli import COMMANDS

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    lines = [ln for ln in text.splitlines() if re.search(r"(^\$ |bin/)screwkit \w", ln.strip())]
    assert lines, "the README shows no screwkit command"
    for line in lines:
        cmd = re.search(r"screwkit (\w+)", line).group(1)
        assert cmd in COMMANDS, f"README uses unknown command {cmd!r}: {line}"


# README.md's code blocks (and every page of docs/): tests/test_docs_run.py


def test_module_docstring_examples():
    import doctest
    import importlib

    mods = ["screwkit.screws._primitives", "screwkit.screws._reciprocal",
            "screwkit.screws._freedoms", "screwkit.legs._explicit", "screwkit.legs._parsing",
            "screwkit.legs._analysis", "screwkit.engine._analysis", "screwkit.api"]
    for name in mods:
        res = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
        assert res.failed == 0, f"doctest failures in {name}"
