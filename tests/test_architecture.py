"""The package's layered architecture: import graph without cycles, layer order, module sizes.

Every module of ``screwkit`` is parsed with :mod:`ast`; every import at any depth
(inside functions too, relative or absolute, and ``importlib.import_module`` with
a literal name) is an edge of the graph between screwkit modules.  The layers are
the subpackages, lowest first::

    errors < screws < legs < pm < scene < engine < {paths, synthesis, viz, interop, ...} < api < cli

A module may import only from its own layer's subpackage and the layers below
it; the four layers in braces are peers and do not import each other (except the
edges listed in ALLOWED_PEER_EDGES).  The package ``__init__`` (the public API)
and ``__main__`` are outside the layers: only the CLI and ``__main__`` import them.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "screwkit"

#: Rank of each layer (a subpackage, or a module directly in screwkit/); equal ranks are peers.
LAYERS = {
    "errors": 0,
    "screws": 1,
    "legs": 2,
    "pm": 3,
    "scene": 4,            # the 3D view from plain data: below the engine, whose results show it
    "engine": 5,
    "paths": 6, "synthesis": 6, "viz": 6, "interop": 6, "maps": 6, "dynamics": 6, "design": 6,
    "api": 7,
    "cli": 8,
}

#: Edges between peer layers that are allowed, with the reason.
ALLOWED_PEER_EDGES = {
    ("paths", "viz"): "TrajectoryResult.plot draws the Fig. 5 panels with viz.plot_fig5",
    ("maps", "viz"): "plot_map draws a map's heatmaps with viz.plot_heatmaps",
    ("maps", "dynamics"): "a model with leg stiffnesses gets the stiffness fields of each cell",
    ("dynamics", "paths"): "a motion is read from the path inputs (PathSpec, CSV, expressions)",
    ("dynamics", "viz"): "DynamicsResult.plot draws the dynamic panels with viz.plot_dynamics",
    ("dynamics", "interop"): "check_dynamics builds the closed-loop Pinocchio model of interop",
    ("design", "synthesis"): "the PM type synthesis verifies synthesis's candidate PMs with the engine",
    ("design", "maps"): "dimensional synthesis sizes each candidate over a task's cells as maps.size does",
    ("design", "viz"): "OptimizationResult.plot draws the search or the Pareto front with viz",
}

#: Edges to a lower layer that are nevertheless forbidden.
FORBIDDEN_EDGES = {
    ("viz", "engine"): "drawings take legs, analyses or arrays; they never call the solvers",
    ("synthesis", "engine"): "the synthesis needs legs and the catalog (pm), not the solvers",
}

#: Modules allowed over MAX_LINES (none).
ALLOWED_LONG_MODULES: set = set()
MAX_LINES = 400
#: .py files directly in screwkit/: __init__, __main__, errors, api.
MAX_TOP_LEVEL_FILES = 4

ROOT_IMPORTERS = ("cli", "__main__")   # who may import the package __init__


# --------------------------------------------------------------------------- graph

def module_name(path: Path, pkg: Path = PKG) -> str:
    parts = list(path.relative_to(pkg.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def modules(pkg: Path = PKG) -> dict:
    """``{dotted name: path}`` of every module of the package."""
    return {module_name(p, pkg): p for p in sorted(pkg.rglob("*.py"))}


def _resolve(base: str, level: int, module: str | None) -> str:
    if level:
        parts = base.split(".")
        parts = parts[:len(parts) - (level - 1)]
        return ".".join(parts + ([module] if module else []))
    return module or ""


def imports_of(name: str, path: Path, known) -> set:
    """The screwkit modules that module ``name`` imports, at any depth."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    root = name.split(".")[0]
    out = set()

    def add(target):
        while target and target not in known:      # a.b.c where c is a name in a.b
            target = target.rpartition(".")[0]
        if target:
            out.add(target)

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == root:
                    add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(package, node.level, node.module)
            if target.split(".")[0] != root:
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                add(sub if sub in known else target)
        elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
              and isinstance(node.args[0].value, str)
              and getattr(node.func, "attr", getattr(node.func, "id", None)) == "import_module"):
            spec = node.args[0].value
            level = len(spec) - len(spec.lstrip("."))
            add(_resolve(package, level, spec.lstrip(".") or None) if level else spec)
    out.discard(name)
    return out


def import_graph(pkg: Path = PKG) -> dict:
    mods = modules(pkg)
    return {name: imports_of(name, path, mods) for name, path in mods.items()}


def find_cycle(graph: dict):
    """One cycle of the graph as a list of modules (first == last), or None."""
    WHITE, GREY, BLACK = 0, 1, 2
    colour = {n: WHITE for n in graph}
    stack = []

    def visit(n):
        colour[n] = GREY
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if colour.get(m, WHITE) == GREY:
                return stack[stack.index(m):] + [m]
            if colour.get(m, WHITE) == WHITE and m in graph:
                found = visit(m)
                if found:
                    return found
        stack.pop()
        colour[n] = BLACK
        return None

    for n in sorted(graph):
        if colour[n] == WHITE:
            found = visit(n)
            if found:
                return found
    return None


def layer_of(name: str):
    """The layer of a module (``"screwkit.legs._chain"`` -> ``"legs"``); None for the package
    ``__init__`` and ``__main__``."""
    parts = name.split(".")
    if len(parts) == 1 or parts[1] == "__main__":
        return None
    return parts[1]


def layer_violations(graph: dict) -> list:
    bad = []
    for a, targets in sorted(graph.items()):
        la = layer_of(a)
        for b in sorted(targets):
            lb = layer_of(b)
            if b.endswith(".__main__"):
                bad.append(f"{a} imports {b}")
                continue
            if lb is None:          # the package __init__
                if la not in ROOT_IMPORTERS and not a.endswith(".__main__") and la is not None:
                    bad.append(f"{a} imports the package __init__ (only the CLI may)")
                continue
            if la is None or la == lb:
                continue
            if la not in LAYERS or lb not in LAYERS:
                bad.append(f"{a} -> {b}: {la if la not in LAYERS else lb!r} is not a known layer "
                           "(add it to LAYERS)")
                continue
            if (la, lb) in FORBIDDEN_EDGES:
                bad.append(f"{a} imports {b}: {la} must not import {lb} "
                           f"({FORBIDDEN_EDGES[la, lb]})")
            elif LAYERS[lb] > LAYERS[la]:
                bad.append(f"{a} imports {b}: layer {la} must not import the higher layer {lb}")
            elif LAYERS[lb] == LAYERS[la] and (la, lb) not in ALLOWED_PEER_EDGES:
                bad.append(f"{a} imports {b}: the peer layers {la} and {lb} must not import "
                           "each other")
    return bad


# --------------------------------------------------------------------------- tests

def test_the_graph_sees_imports_at_any_depth():
    g = import_graph()
    assert "screwkit.legs._chain" in g and "screwkit.engine._analysis" in g
    # inside a method (Leg.analyze), relative
    assert "screwkit.legs._analysis" in g["screwkit.legs._chain"]
    # inside a function, across subpackages
    assert "screwkit.engine" in g["screwkit.api"]
    assert "screwkit.screws" in g["screwkit.legs._chain"]
    assert "screwkit" in g["screwkit.cli._main"]          # from .. import __version__


def test_find_cycle_finds_a_planted_cycle():
    g = {k: set(v) for k, v in import_graph().items()}
    assert find_cycle(g) is None
    g["screwkit.screws._tolerance"].add("screwkit.legs._chain")     # legs -> screws -> legs
    cycle = find_cycle(g)
    assert cycle is not None and cycle[0] == cycle[-1]
    assert "screwkit.screws._tolerance" in cycle


def test_no_import_cycles():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_layer_order():
    bad = layer_violations(import_graph())
    assert not bad, "layer violations:\n" + "\n".join(bad)


def test_every_module_is_in_a_known_layer():
    unknown = sorted({layer_of(n) for n in modules()} - set(LAYERS) - {None})
    assert not unknown, f"modules outside the layers: {unknown} (add them to LAYERS)"


def test_modules_are_short():
    long = {}
    for p in PKG.rglob("*.py"):
        n = len(p.read_text(encoding="utf-8").splitlines())
        rel = p.relative_to(PKG).as_posix()
        if n > MAX_LINES and rel not in ALLOWED_LONG_MODULES:
            long[rel] = n
    assert not long, f"modules over {MAX_LINES} lines (split them by concern): {long}"
    stale = sorted(m for m in ALLOWED_LONG_MODULES if not (PKG / m).is_file())
    assert not stale, f"ALLOWED_LONG_MODULES lists missing modules: {stale}"


def test_few_top_level_modules():
    top = sorted(p.name for p in PKG.glob("*.py"))
    assert len(top) <= MAX_TOP_LEVEL_FILES, f"too many modules directly in screwkit/: {top}"
