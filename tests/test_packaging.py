"""Packaging: the package data a wheel ships, one version, ``python -m screwkit``, the licence,
the changelog, type hints on the public API and mypy on the modules behind it.

The wheel itself is not built here (slow); ``pyproject.toml``'s package-data is checked
against what ``importlib.resources`` finds in the installed package.
"""

from __future__ import annotations

import importlib.metadata
import importlib.resources
import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import screwkit

try:
    import tomllib
except ImportError:                        # Python 3.10
    tomllib = pytest.importorskip("tomli")

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_package_data_is_shipped():
    files = importlib.resources.files("screwkit")
    assert files.joinpath("py.typed").is_file()
    catalog = files.joinpath("legs_catalog.yaml").read_text(encoding="utf-8")
    assert "legs:" in catalog and "pms:" in catalog and "table1:" in catalog
    data = PYPROJECT["tool"]["setuptools"]["package-data"]["screwkit"]
    assert "py.typed" in data and "legs_catalog.yaml" in data
    # every data file in the package (a JSON schema, YAML, ...) is covered by package-data
    pkg = ROOT / "screwkit"
    shipped = [p for p in pkg.rglob("*") if p.is_file() and p.suffix in (".json", ".yaml", ".yml", ".typed")
               and "__pycache__" not in p.parts]
    for p in shipped:
        rel = p.relative_to(pkg).as_posix()
        assert any(Path(rel).match(pat) for pat in data), f"{rel} is not in [tool.setuptools.package-data]"


def test_one_version():
    assert "version" not in PYPROJECT["project"]
    assert "version" in PYPROJECT["project"]["dynamic"]
    assert PYPROJECT["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "screwkit.__version__"}
    assert re.fullmatch(r"\d+\.\d+\.\d+(\.dev\d+|rc\d+)?", screwkit.__version__)
    assert importlib.metadata.version("screwkit") == screwkit.__version__
    # the changelog has a section for the current version
    assert f"## [{screwkit.__version__}]" in (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")


def test_metadata_licence_authors_extras():
    proj = PYPROJECT["project"]
    assert proj["license"] == "BSD-3-Clause" and proj["license-files"] == ["LICENSE"]
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert "BSD 3-Clause" in text and "Copyright (c) 2026, screwkit developers" in text
    assert proj["authors"] == [{"name": "screwkit developers"}]
    extras = proj["optional-dependencies"]
    for name in ("plot", "docs", "test"):
        assert name in extras, f"extra {name!r} missing"
    test = " ".join(extras["test"])
    for dep in ("mkdocs", "mkdocstrings-python", "mypy"):
        assert dep in test, f"{dep} is not in the test extra"
    assert any(d.startswith("tqdm") for d in proj["dependencies"])
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert "Keep a Changelog" in changelog and "## [Unreleased]" in changelog


def test_python_m_screwkit_help():
    proc = subprocess.run([sys.executable, "-m", "screwkit", "--help"], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("usage: screwkit")
    for cmd in ("analyze", "trajectory", "validate"):
        assert cmd in proc.stdout
    ver = subprocess.run([sys.executable, "-m", "screwkit", "--version"], capture_output=True,
                         text=True, timeout=60)
    assert ver.stdout.strip() == f"screwkit {screwkit.__version__}"


def _public_callables():
    for name in screwkit.__all__:
        obj = getattr(screwkit, name)
        if inspect.isfunction(obj):
            yield name, obj
        elif inspect.isclass(obj):
            for k, v in vars(obj).items():
                if inspect.isfunction(v) and (not k.startswith("_") or k == "__init__"):
                    yield f"{name}.{k}", v


def test_public_api_is_annotated():
    """Every function of ``screwkit.__all__`` and every public method of its classes has
    annotated parameters and a return annotation."""
    missing = []
    for name, fn in _public_callables():
        sig = inspect.signature(fn)
        bare = [p for p, v in sig.parameters.items()
                if p not in ("self", "cls") and v.annotation is inspect.Parameter.empty]
        if bare or sig.return_annotation is inspect.Signature.empty:
            missing.append(f"{name}: {bare or 'return'}")
    assert not missing, "unannotated public API:\n" + "\n".join(missing)


def test_mypy_is_clean_on_the_public_modules(tmp_path):
    """``python -m mypy`` with ``[tool.mypy]`` of pyproject.toml (the modules of the public API)."""
    pytest.importorskip("mypy")
    files = PYPROJECT["tool"]["mypy"]["files"]
    for name, fn in _public_callables():
        mod = inspect.getmodule(fn).__name__
        path = mod.replace(".", "/") + ("/__init__.py" if mod == "screwkit" else ".py")
        assert path in files, f"{name} is defined in {path}, which [tool.mypy] files leaves out"
    proc = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "cache"),
                           "--no-error-summary"], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, f"mypy:\n{proc.stdout}\n{proc.stderr}"


def test_the_built_wheel_ships_typing_licence_schema_and_catalog(tmp_path):
    """Build the wheel (``pip wheel --no-deps --no-build-isolation``, from a copy of the
    sources so that the tree stays clean) and look inside it."""
    import shutil
    import zipfile

    setuptools = pytest.importorskip("setuptools")
    major = int(setuptools.__version__.split(".")[0])
    if major < 77:
        pytest.skip(f"setuptools {setuptools.__version__} < 77 (the test extra has setuptools>=77)")
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(ROOT / "screwkit", src / "screwkit",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    proc = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps",
                           "--no-build-isolation", "--no-index", "-q", "-w", str(tmp_path / "dist"),
                           str(src)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    wheel, = (tmp_path / "dist").glob("screwkit-*.whl")
    assert wheel.name.startswith(f"screwkit-{screwkit.__version__}-py3-none-any")
    names = set(zipfile.ZipFile(wheel).namelist())
    for member in ("screwkit/py.typed", "screwkit/legs_catalog.yaml", "screwkit/pm/model.schema.json",
                   "screwkit/__main__.py", "screwkit/cli/_commands/export.py"):
        assert member in names, f"{member} is not in {wheel.name}"
    info = f"screwkit-{screwkit.__version__}.dist-info"
    assert any(n.startswith(f"{info}/licenses/LICENSE") for n in names), sorted(n for n in names if "dist-info" in n)
    meta = zipfile.ZipFile(wheel).read(f"{info}/METADATA").decode()
    assert "License-Expression: BSD-3-Clause" in meta and "Provides-Extra: plot" in meta
    assert "Provides-Extra: dask" in meta and "Provides-Extra: test" in meta
    # the packaged schema in the wheel is the one the code generates
    from screwkit.pm import schema_text
    assert zipfile.ZipFile(wheel).read("screwkit/pm/model.schema.json").decode() == schema_text()
