"""Every code block of README.md and docs/*.md runs, and the outputs it shows are what it prints.

One test per page (new pages are picked up automatically), each in a fresh temporary
working directory with one namespace for the page's Python blocks; the conventions are in
``tests/docs_run.py`` (``# ->`` outputs, ``$`` commands, ``<!-- docs-run: skip|slow -->``).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from docs_run import DocsRunError, blocks, commands, run_page, run_python

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@pytest.mark.parametrize("page", PAGES, ids=[p.relative_to(ROOT).as_posix() for p in PAGES])
def test_page_runs_and_shows_what_it_prints(page, tmp_path, monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("COLUMNS", "100")
    monkeypatch.chdir(tmp_path)
    t0 = time.perf_counter()
    counts = run_page(page, tmp_path, slow=os.environ.get("SCREWKIT_DOCS_SLOW") == "1")
    print(page.name, counts, f"{time.perf_counter() - t0:.1f} s")


def test_pages_have_checked_outputs():
    """The collector really compares: the pages show outputs, and the big pages run commands."""
    text = "".join(p.read_text(encoding="utf-8") for p in PAGES)
    assert text.count("# ->") >= 40
    tut = blocks((ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8"))
    assert sum(len(commands(b.text)) for b in tut if b.lang == "console") >= 8


def test_a_wrong_shown_output_fails():
    ns: dict = {}
    run_python("x = [1, 2]\nprint(len(x))   # -> 2\n", ns, "t.md", 1)
    with pytest.raises(DocsRunError, match="shown output differs"):
        run_python("print(len(x))   # -> 3\n", ns, "t.md", 10)
    with pytest.raises(DocsRunError, match="shown output differs"):
        run_python("x  # -> [1, 3]\n", ns, "t.md", 10)
    with pytest.raises(DocsRunError, match="not a '# ->' output"):
        run_python("print(len(x))   # 2\n", ns, "t.md", 10)
    # continued outputs (the '#' in the marker's column), ellipsis and whitespace
    code = "print('a\\nb  c\\nd')  # -> a\n"
    pad = " " * code.index("#")
    run_python(code + pad + "#    b c\n" + pad + "#    ...\n", ns, "t.md", 1)
    with pytest.raises(DocsRunError, match="shown output differs"):
        run_python(code + pad + "#    b X\n" + pad + "#    ...\n", ns, "t.md", 1)
    loop = "for i in range(3):\n    print(i)   # -> 0\n"
    run_python(loop + " " * loop.splitlines()[1].index("#") + "#      1 2\n", ns, "t.md", 1)


def test_a_failing_command_fails(tmp_path):
    from docs_run import run_shell

    run_shell("$ screwkit leg SPR\nleg SPR ...\n...\n", "t.md", 1, tmp_path)
    with pytest.raises(DocsRunError, match="exited with 2"):
        run_shell("$ screwkit leg XQZ\n", "t.md", 1, tmp_path)
    run_shell("$ screwkit leg XQZ\nscrewkit leg: error: ...\n[exit 2]\n", "t.md", 1, tmp_path)
    with pytest.raises(DocsRunError, match="shown output differs"):
        run_shell("$ screwkit leg SPR\nleg SPS ...\n", "t.md", 1, tmp_path)
    run_shell("$ printf 'a\\nb\\n' > f.txt\n$ cat f.txt\na\nb\n", "t.md", 1, tmp_path)


def test_validation_table_is_current(tmp_path):
    """docs/validation_table.md is what `screwkit validate --format markdown` writes (no timings)."""
    import re

    from screwkit.cli import main

    out = tmp_path / "table.md"
    assert main(["validate", "--format", "markdown", "--out", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    assert not re.search(r"\d\s*s\)|seconds", text), "the generated table carries a run time"
    assert (ROOT / "docs" / "validation_table.md").read_text(encoding="utf-8") == text, \
        "docs/validation_table.md is stale: run screwkit validate --format markdown --out docs/validation_table.md"
