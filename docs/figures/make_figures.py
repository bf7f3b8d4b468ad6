"""Regenerate the PNG figures of the documentation with the commands the docs show.

Run from the repository root::

    python docs/figures/make_figures.py

Every console line ``$ screwkit ...`` of a Markdown file under ``docs/`` (and README.md)
that writes into ``docs/figures/`` is run as shown (through :func:`screwkit.cli.main`), in
a temporary folder so that the tables the commands also write do not land in the
repository; the figures are then copied here.  A figure under ``docs/figures/`` that no
page links is reported (it is stale).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def commands():
    """``(page, argv)`` of the documented commands that write a figure."""
    pages = sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]
    out = []
    for page in pages:
        for line in page.read_text(encoding="utf-8").splitlines():
            if line.startswith("$ screwkit ") and "docs/figures/" in line:
                out.append((page, shlex.split(line[2:])[1:]))
    return out


def linked():
    """Names of the figures the pages link (``figures/NAME.png``)."""
    names = set()
    for page in sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]:
        names |= set(re.findall(r"figures/([\w.-]+\.png)", page.read_text(encoding="utf-8")))
    return names


def main() -> int:
    from screwkit.cli import main as screwkit_main

    os.environ.setdefault("MPLBACKEND", "Agg")
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "docs" / "figures").mkdir(parents=True)
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            for page, argv in commands():
                print(f"{page.relative_to(ROOT)}: screwkit {shlex.join(argv)}", file=sys.stderr)
                if screwkit_main(argv) != 0:
                    return 1
        finally:
            os.chdir(cwd)
        for png in sorted((Path(tmp) / "docs" / "figures").glob("*.png")):
            shutil.copy(png, HERE / png.name)
            print(HERE / png.name)
    stale = sorted(p.name for p in HERE.glob("*.png") if p.name not in linked())
    for name in stale:
        print(f"stale (linked from no page): docs/figures/{name}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
