"""A PM's definition as a mapping: read from memory, kept with the model, written back (private).

A model file's ``pms:`` entry is the one description of a PM: :func:`screwkit.pm.load_pm`
reads it from a file, from a mapping in memory or from a :class:`~screwkit.pm.PMBuilder`,
and keeps it, self-contained, as ``PMModel.definition`` (:func:`definition_of`: every leg
type that is not the packaged catalog's own is written inline, dimension overrides are
applied).  ``PMModel.to_mapping()`` / ``to_yaml()`` return it, and reading that again builds
the same model.

* :func:`plain_mapping` turns a mapping from user code into plain data (numpy numbers and
  arrays to Python numbers and lists), bounded as a YAML file is (nesting, node count);
* :func:`inline_leg` reads a leg type written in a leg entry, ``{leg: {name: ..., string:
  ..., joints: [...]}}``, with errors that name the PM's field.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping

import numpy as np

from ..errors import CatalogError
from ..legs._guards import MAX_YAML_DEPTH, MAX_YAML_NODES, shorten

__all__ = ["MEMORY", "plain_mapping", "inline_leg", "definition_of"]

#: The source named in the errors of a PM read from memory.
MEMORY = "<memory>"


def plain_mapping(raw) -> dict:
    """``raw`` as plain data (dicts with text keys, lists, Python numbers, text, booleans,
    None); numpy numbers and arrays become Python numbers and lists.  Refuses anything else,
    a depth beyond ``MAX_YAML_DEPTH`` and more than ``MAX_YAML_NODES`` nodes."""
    count = [0]

    def conv(x, where, depth):
        count[0] += 1
        if count[0] > MAX_YAML_NODES:
            raise CatalogError(f"the mapping has more than {MAX_YAML_NODES} nodes", source=MEMORY)
        if depth > MAX_YAML_DEPTH:
            raise CatalogError(f"nested more than {MAX_YAML_DEPTH} levels deep", None, where,
                               MEMORY)
        if isinstance(x, Mapping):
            out = {}
            for k, v in x.items():
                if not isinstance(k, str):
                    raise CatalogError(f"a key must be a text, got {shorten(k)}", None,
                                       where or None, MEMORY)
                out[k] = conv(v, f"{where}.{k}" if where else k, depth + 1)
            return out
        if isinstance(x, np.ndarray):
            x = x.tolist()
        if isinstance(x, (list, tuple)):
            return [conv(v, f"{where}[{i}]", depth + 1) for i, v in enumerate(x)]
        if isinstance(x, np.generic):
            x = x.item()
        if x is None or isinstance(x, (bool, int, float, str)):
            return x
        raise CatalogError(f"{type(x).__name__} is not plain data (a number, a text, a list or "
                           "a mapping)", None, where or None, MEMORY)

    out = conv(raw, "", 0)
    if not isinstance(out, dict):
        raise CatalogError("a PM definition is a mapping", source=MEMORY)
    return out


def inline_leg(d, ctx, fld):
    """The :class:`~screwkit.pm.LegSpec` of a leg type written inline in a leg entry."""
    from ._catalog import leg_spec_from_mapping
    try:
        return leg_spec_from_mapping(d, ctx.source)
    except CatalogError as exc:
        inner = f"{fld}.{exc.field}" if exc.field else fld
        who = f"leg type {exc.entry!r}: " if exc.entry else ""
        raise ctx.err(f"{who}{exc.detail}", inner) from None


def _is_packaged(spec) -> bool:
    from ._catalog import default_catalog
    try:
        return default_catalog().legs.get(spec.name) is spec
    except CatalogError:
        return False


def definition_of(d: dict, specs, dims=None) -> dict:
    """The self-contained definition of a PM read from ``d`` (its leg types ``specs``, one
    per leg): leg types not from the packaged catalog written inline, and the dimensions
    ``dims`` (the overrides applied) when given."""
    out = copy.deepcopy(d)
    legs = []
    for entry, spec in zip(out["legs"], specs):
        e = dict(entry) if isinstance(entry, dict) else {"leg": entry}
        if not (isinstance(e["leg"], str) and _is_packaged(spec)):
            e["leg"] = copy.deepcopy(spec.definition) if spec.definition is not None \
                else spec.name
        legs.append(e["leg"] if list(e) == ["leg"] and isinstance(e["leg"], str) else e)
    out["legs"] = legs
    if dims is not None:
        old = out.get("dimensions") if isinstance(out.get("dimensions"), Mapping) else {}
        out["dimensions"] = {k: float(v) for k, v in dims.items()}
        changed = [k for k, v in out["dimensions"].items() if not _same_number(old.get(k), v)]
        if changed and out.get("source"):
            # (the source's words describe its own dimensions: the file says which differ)
            said = ", ".join(f"{k} = {out['dimensions'][k]:g}"
                             + (f" (the source's {old[k]})" if k in old else "")
                             for k in changed)
            out["source"] = f"{out['source']}; dimensions changed since: {said}"
    return out


def _same_number(a, b: float) -> bool:
    try:
        return a is not None and float(a) == b
    except (TypeError, ValueError):
        return False
