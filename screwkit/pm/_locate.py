"""The line of a field in a YAML file (private): catalog and model errors name it.

A :class:`~screwkit.errors.CatalogError` names the entry (a PM or a leg type) and the field
(``legs[1].axes.R3``, ``joints[2] (R3)``, ``dimensions.R``); :func:`locate` walks the
composed YAML nodes of the file's text to that field and :func:`with_line` returns the error
with ``line`` set (1-based; the line of the deepest key found on the way).
"""

from __future__ import annotations

import re

import yaml

from ..errors import CatalogError

__all__ = ["locate", "with_line", "field_path"]

_STEP = re.compile(r"\[(\d+)\]|([^.\[\]]+)")


def field_path(field: str | None) -> list:
    """``"legs[1].axes.R3"`` -> ``["legs", 1, "axes", "R3"]``; a trailing ``" (R3)"`` (the
    joint named in ``joints[2] (R3)``) is dropped."""
    if not field:
        return []
    field = re.sub(r"\s*\([^)]*\)", "", str(field)).strip()
    return [int(m.group(1)) if m.group(1) is not None else m.group(2)
            for m in _STEP.finditer(field)]


def _compose(text: str):
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        return yaml.compose(text, Loader=loader)
    except yaml.YAMLError:
        return None


def _walk(node, path) -> int | None:
    """1-based line of the deepest node on ``path`` (a key's line for a mapping step)."""
    line = node.start_mark.line + 1
    for step in path:
        if isinstance(node, yaml.MappingNode) and isinstance(step, str):
            hit = next(((k, v) for k, v in node.value
                        if isinstance(k, yaml.ScalarNode) and k.value == step), None)
            if hit is None:
                break
            line, node = hit[0].start_mark.line + 1, hit[1]
        elif isinstance(node, yaml.SequenceNode) and isinstance(step, int) \
                and 0 <= step < len(node.value):
            node = node.value[step]
            line = node.start_mark.line + 1
        else:
            break
    return line


def _entry_path(root, entry: str) -> list | None:
    """``["pms", NAME]`` or ``["legs", INDEX]`` of an entry of the file, else None."""
    if not isinstance(root, yaml.MappingNode):
        return None
    for k, v in root.value:
        if not isinstance(k, yaml.ScalarNode):
            continue
        if k.value == "pms" and isinstance(v, yaml.MappingNode):
            if any(isinstance(pk, yaml.ScalarNode) and pk.value == entry for pk, _ in v.value):
                return ["pms", entry]
        if k.value == "legs" and isinstance(v, yaml.SequenceNode):
            for i, item in enumerate(v.value):
                if isinstance(item, yaml.MappingNode) and any(
                        isinstance(lk, yaml.ScalarNode) and lk.value == "name"
                        and isinstance(lv, yaml.ScalarNode) and lv.value == entry
                        for lk, lv in item.value):
                    return ["legs", i]
    return None


def locate(text: str, path) -> int | None:
    """1-based line of the field at ``path`` (a list of keys and indices) in YAML ``text``."""
    root = _compose(text)
    return None if root is None else _walk(root, list(path))


def with_line(exc: CatalogError, text: str) -> CatalogError:
    """``exc`` with the line of its entry and field in ``text`` (unchanged when it has one,
    or when neither can be found)."""
    if getattr(exc, "line", None):
        return exc
    root = _compose(text)
    if root is None:
        return exc
    if exc.entry:
        base = _entry_path(root, exc.entry)
        if base is None:
            return exc
    else:
        base = []
    path = base + field_path(exc.field)
    if not path:
        return exc
    line = _walk(root, path)
    if line is None:
        return exc
    out = CatalogError(getattr(exc, "detail", str(exc)), exc.entry, exc.field, exc.source, line)
    return out


def with_line_of_file(exc: CatalogError, path) -> CatalogError:
    """:func:`with_line` with the text of the file at ``path`` (read on error only)."""
    from ..legs._guards import MAX_MODEL_BYTES

    try:
        with open(path, "rb") as fh:
            text = fh.read(MAX_MODEL_BYTES + 1).decode("utf-8")
    except (OSError, UnicodeDecodeError, TypeError, ValueError):
        return exc
    return with_line(exc, text) if len(text) <= MAX_MODEL_BYTES else exc
