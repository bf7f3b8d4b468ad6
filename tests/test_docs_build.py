"""The documentation site builds with ``mkdocs build --strict`` (nav, links, anchors, the API
reference from the numpydoc docstrings). Skipped only when mkdocs is not installed
(``pip install ".[docs]"``; the ``test`` extra has it)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_mkdocs_strict_build(tmp_path):
    pytest.importorskip("mkdocs")
    pytest.importorskip("mkdocstrings_handlers.python")
    site = tmp_path / "site"
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                           "-f", str(ROOT / "mkdocs.yml"), "-d", str(site)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stdout}\n{proc.stderr}"
    # every page of docs/ is in the site, and the reference has the docstrings
    for page in (ROOT / "docs").glob("*.md"):
        name = "" if page.stem == "index" else page.stem + "/"
        assert (site / name / "index.html").is_file(), f"{page.name} missing from the site"
    engine = (site / "reference" / "engine" / "index.html").read_text(encoding="utf-8")
    assert 'id="screwkit.engine.analyze"' in engine and "Parameters" in engine
    root = (site / "reference" / "screwkit" / "index.html").read_text(encoding="utf-8")
    assert 'id="screwkit.api.load_pm"' in root
    # the Sphinx roles of the docstrings are rendered as code (docs/mkdocs_hooks.py)
    for page in (site / "reference").rglob("index.html"):
        assert ":func:<code>" not in page.read_text(encoding="utf-8"), page


def test_every_page_is_in_the_nav():
    yaml = pytest.importorskip("yaml")
    cfg = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))

    def files(nav):
        for item in nav:
            if isinstance(item, str):
                yield item
            elif isinstance(item, dict):
                for v in item.values():
                    yield from ([v] if isinstance(v, str) else files(v))

    listed = set(files(cfg["nav"]))
    pages = {p.relative_to(ROOT / "docs").as_posix() for p in (ROOT / "docs").rglob("*.md")}
    assert pages - listed == set(), f"add these pages to the nav of mkdocs.yml: {sorted(pages - listed)}"
    assert listed - pages == set(), f"the nav lists missing pages: {sorted(listed - pages)}"
