"""Strict YAML reading of catalogs and model files (private).

:func:`load_yaml_file` reads at most :data:`~screwkit.legs._guards.MAX_MODEL_BYTES`, requires
UTF-8 text, parses with libyaml's parser when present (``CSafeLoader``: the packaged
catalog loads in ~20 ms instead of ~120 ms) and, before building any Python object,
walks the composed node graph once to refuse

* duplicate keys in a mapping (``dof: 3`` twice: YAML would keep the last silently),
* keys that are not plain names, and booleans anywhere (``yes``, ``on``, ``true``: YAML 1.1
  reads them as booleans; quote them when they are text) except ``true`` / ``false`` as the
  value of a key in :data:`BOOLEAN_KEYS` (a leg's ``passive: true``),
* numbers written with more than :data:`~screwkit.legs._guards.MAX_NUMBER_CHARS` characters,
  and ``.nan`` / ``.inf``,
* a document whose aliases expand to more than :data:`~screwkit.legs._guards.MAX_YAML_NODES`
  nodes (an "alias bomb" ``&a [*b, *b, ...]``), recursive aliases, and nesting deeper
  than :data:`~screwkit.legs._guards.MAX_YAML_DEPTH`.

Each refusal is a :class:`~screwkit.errors.CatalogError` naming the file, the field (its
path from the top, ``pms.3PRS.dimensions.R``) and the line and column.
"""

from __future__ import annotations

import re

import yaml

from ..legs._guards import (MAX_MODEL_BYTES, MAX_NUMBER_CHARS, MAX_TEXT, MAX_YAML_DEPTH,
                       MAX_YAML_NODES, decode_utf8, read_limited, shorten)
from ..errors import CatalogError

__all__ = ["load_yaml_file", "load_yaml_text"]

_STR = "tag:yaml.org,2002:str"
_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_BOOL = "tag:yaml.org,2002:bool"
_MERGE = "tag:yaml.org,2002:merge"
_NONFINITE = {".nan", ".inf", "-.inf", "+.inf"}
#: The keys whose value is a boolean, written ``true`` or ``false``.
BOOLEAN_KEYS = frozenset({"passive"})


class _Refused(Exception):
    def __init__(self, message, mark, path):
        super().__init__(message)
        self.mark, self.path = mark, path


def _where(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _check_nodes(root) -> None:
    """The walk over the node graph: see the module docstring.  A document without aliases
    is a tree, walked once; with aliases, the expanded size and depth are counted on the
    graph (each node once) and a node that contains itself is refused."""
    seen = set()
    shared = False
    stack = [(root, (), 1)]
    count = 0
    while stack:
        node, path, level = stack.pop()
        nid = id(node)
        if nid in seen:
            shared = True
            continue
        seen.add(nid)
        count += 1
        if level > MAX_YAML_DEPTH:
            raise _Refused(f"nested more than {MAX_YAML_DEPTH} levels deep", node.start_mark, path)
        _check_node(node, path)
        cls = node.__class__
        if cls is yaml.SequenceNode:
            for i, v in enumerate(node.value):
                stack.append((v, path + (i,), level + 1))
        elif cls is yaml.MappingNode:
            for k, v in node.value:
                stack.append((v, path + (k.value,) if k.tag != _MERGE else path, level + 1))
                if not k.__class__ is yaml.ScalarNode:
                    stack.append((k, path, level + 1))
    if shared:
        _check_expansion(root)


def _check_expansion(root) -> None:
    """Expanded size and depth of a graph with aliases, each node once; recursive aliases."""
    size, depth = {}, {}
    on_stack = set()
    stack = [(root, (), False)]
    while stack:
        node, path, expanded = stack.pop()
        nid = id(node)
        if expanded:
            on_stack.discard(nid)
            kids = _children(node)
            size[nid] = 1 + sum(size[id(k)] for k, _ in kids)
            depth[nid] = 1 + max((depth[id(k)] for k, _ in kids), default=0)
            if size[nid] > MAX_YAML_NODES:
                raise _Refused(f"the document expands to more than {MAX_YAML_NODES} nodes "
                               "(aliases '*name' repeat what they point to)", node.start_mark, path)
            if depth[nid] > MAX_YAML_DEPTH:
                raise _Refused(f"nested more than {MAX_YAML_DEPTH} levels deep", node.start_mark,
                               path)
            continue
        if nid in size:
            continue
        if nid in on_stack:
            raise _Refused("a recursive alias (a node that contains itself)", node.start_mark, path)
        on_stack.add(nid)
        stack.append((node, path, True))
        for kid, step in reversed(_children(node)):
            if id(kid) not in size:
                stack.append((kid, path + (step,) if step is not None else path, False))


def _children(node):
    """``[(child node, path step)]``: sequence items by index, mapping keys (no step) and
    values (by key)."""
    if isinstance(node, yaml.SequenceNode):
        return [(v, i) for i, v in enumerate(node.value)]
    if isinstance(node, yaml.MappingNode):
        out = []
        for k, v in node.value:
            step = k.value if isinstance(k, yaml.ScalarNode) else None
            out.append((k, None))
            out.append((v, step if k.tag != _MERGE else None))
        return out
    return []


def _check_node(node, path) -> None:
    if isinstance(node, yaml.ScalarNode):
        v = node.value
        if node.tag == _BOOL:
            if path and path[-1] in BOOLEAN_KEYS and v in ("true", "false"):
                return
            if path and path[-1] in BOOLEAN_KEYS:
                raise _Refused(f"{v!r} is read as a boolean: write true or false",
                               node.start_mark, path)
            raise _Refused(f"{v!r} is read as a boolean (true/false); no field of a model but "
                           f"'passive' is a boolean: write a number, or quote the text ('{v}')",
                           node.start_mark, path)
        if node.tag in (_INT, _FLOAT):
            if len(v) > MAX_NUMBER_CHARS:
                raise _Refused(f"a number of {len(v)} characters is too long (at most "
                               f"{MAX_NUMBER_CHARS})", node.start_mark, path)
            if node.tag == _FLOAT and v.lower() in _NONFINITE:
                raise _Refused(f"{v} is not a finite number (NaN and infinity are not allowed)",
                               node.start_mark, path)
        elif len(v) > MAX_TEXT:
            raise _Refused(f"a text of {len(v)} characters is too long (at most {MAX_TEXT})",
                           node.start_mark, path)
        return
    if isinstance(node, yaml.MappingNode):
        seen = {}
        for k, _ in node.value:
            if k.tag == _MERGE:
                continue
            if not (isinstance(k, yaml.ScalarNode) and k.tag == _STR):
                what = k.value if isinstance(k, yaml.ScalarNode) else type(k).__name__
                raise _Refused(f"a key must be a name, got {shorten(what, 40)} (quote it if it is "
                               "text)", k.start_mark, path)
            if k.value in seen:
                first = seen[k.value]
                raise _Refused(f"duplicate key {k.value!r} (first at line {first.line + 1}): "
                               "YAML would keep only the last one", k.start_mark, path)
            seen[k.value] = k.start_mark


_Base = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _StrictLoader(_Base):
    """libyaml's parser (when present) with the checks of :func:`_check_nodes`; numbers in
    exponent form without a dot or an exponent sign (``1e-3``, ``2e6``) are numbers, as in
    YAML 1.2 (YAML 1.1 reads them as text)."""

    def construct_document(self, node):
        _check_nodes(node)
        return super().construct_document(node)


_StrictLoader.add_implicit_resolver(
    _FLOAT, re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."))


def load_yaml_text(text: str, source: str):
    """The data of one YAML document, checked; :class:`CatalogError` naming ``source``."""
    try:
        return yaml.load(text, Loader=_StrictLoader)
    except _Refused as exc:
        m = exc.mark
        at = f"line {m.line + 1}, column {m.column + 1}" if m is not None else ""
        field = _where(exc.path) or None
        raise CatalogError(f"{at}: {exc}" if at else str(exc), None, field, source) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        what = " ".join(str(getattr(exc, "problem", None) or exc).split())
        raise CatalogError(f"invalid YAML{where}: {what[:200]}", source=source) from None
    except RecursionError:
        raise CatalogError(f"invalid YAML: nested more than {MAX_YAML_DEPTH} levels deep",
                           source=source) from None
    except (ValueError, OverflowError, TypeError) as exc:   # a constructor's own conversions
        raise CatalogError(f"invalid YAML: {type(exc).__name__}: {shorten(str(exc), 200)}",
                           source=source) from None


def load_yaml_file(path, what: str = "model file"):
    """Read (at most :data:`MAX_MODEL_BYTES`), decode (UTF-8) and load a YAML file.

    Returns
    -------
    (data, source) : the loaded data and the path as text.
    """
    source = str(path) if not isinstance(path, bytes) else path.decode("utf-8", "replace")

    def err(msg):
        return CatalogError(msg, source=shorten(source, 120) if len(source) > 120 else source)

    raw = read_limited(path, MAX_MODEL_BYTES, what, err)
    text = decode_utf8(raw, what, err)
    return load_yaml_text(text, source), source
