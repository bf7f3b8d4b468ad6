"""Every problem of a catalog or model file at once (``screwkit model check FILE``).

:func:`check_model_file` reads the file strictly (:mod:`screwkit.pm._yaml`), then, to
report all it can rather than the first problem,

1. every duplicate key of the file (YAML would keep the last one silently),
2. the JSON Schema (:func:`screwkit.pm.model_schema`, with ``jsonschema`` when it is
   installed): unknown keys, wrong types, missing fields, all of them,
3. each leg type on its own (its rules, references and expectation),
4. each PM on its own (``load`` it: the definition, the geometry, the home assembly),

and returns one :class:`Problem` per finding, with its line, entry and field, in line
order.  The file is valid when the list is empty.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import CatalogError, ScrewkitError
from ._pm_problems import pm_problems

__all__ = ["Problem", "check_model_file"]


@dataclass(frozen=True)
class Problem:
    """One problem of a model file.

    Attributes
    ----------
    line : int or None
        1-based line in the file.
    entry : str or None
        The PM or leg type at fault.
    field : str or None
        Its field (``legs[1].axes.R3``).
    message : str
        What is wrong (without the location).
    check : str
        ``"yaml"``, ``"schema"``, ``"leg"`` or ``"pm"``.
    """

    line: int | None
    entry: str | None
    field: str | None
    message: str
    check: str

    def __str__(self) -> str:
        where = [f"line {self.line}" if self.line else "", f"entry {self.entry!r}" if self.entry
                 else "", f"field {self.field!r}" if self.field else ""]
        return f"{', '.join(w for w in where if w) or 'file'}: {self.message} [{self.check}]"

    def to_dict(self) -> dict:
        return {"line": self.line, "entry": self.entry, "field": self.field,
                "message": self.message, "check": self.check}


def _from_error(exc: CatalogError, text: str, check: str) -> Problem:
    from ._locate import with_line
    exc = with_line(exc, text)
    return Problem(exc.line, exc.entry, exc.field, getattr(exc, "detail", str(exc)), check)


def _duplicates(text: str) -> list:
    import yaml                             # imported on use (a cold command may not read YAML)

    out = []
    try:
        root = yaml.compose(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.YAMLError:
        return out
    stack = [root] if root is not None else []
    seen_nodes = set()
    while stack:
        node = stack.pop()
        if id(node) in seen_nodes:
            continue
        seen_nodes.add(id(node))
        if isinstance(node, yaml.MappingNode):
            first = {}
            for k, v in node.value:
                if isinstance(k, yaml.ScalarNode):
                    if k.value in first:
                        out.append(Problem(k.start_mark.line + 1, None, k.value,
                                           f"duplicate key {k.value!r} (first at line "
                                           f"{first[k.value]}): YAML would keep only the last one",
                                           "yaml"))
                    else:
                        first[k.value] = k.start_mark.line + 1
                stack.append(v)
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
    return out


def _field_text(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _schema_problems(data, text: str) -> list:
    try:
        import jsonschema
    except ImportError:                      # the loader's checks still run
        return []
    from ._locate import locate
    from ._schema import model_schema

    validator = jsonschema.Draft202012Validator(model_schema())
    out = []
    for e in validator.iter_errors(data):
        path = list(e.absolute_path)
        msg = e.message
        key_path = path
        if e.validator == "additionalProperties" and isinstance(e.instance, dict):
            known = set(e.schema.get("properties", {}))
            extra = [k for k in e.instance if k not in known and not str(k).startswith("x-")]
            if extra:
                key_path = path + [extra[0]]          # the line of the key itself
                if len(path) <= 2:                    # a PM's or the file's own key: named
                    path = key_path                   # as the field (as the loader does)
                msg = (f"unknown key {extra[0]!r}; known: {', '.join(sorted(known))}")
        if len(msg) > 300:
            msg = msg[:297] + "..."
        entry, rest = None, path
        if len(path) >= 2 and path[0] == "pms":
            entry, rest = str(path[1]), path[2:]
        elif len(path) >= 2 and path[0] == "legs" and isinstance(path[1], int):
            legs = data.get("legs") if isinstance(data, dict) else None
            item = legs[path[1]] if isinstance(legs, list) and path[1] < len(legs) else None
            entry = item.get("name") if isinstance(item, dict) and isinstance(item.get("name"), str) \
                else f"legs[{path[1]}]"
            rest = path[2:]
        out.append(Problem(locate(text, key_path), entry, _field_text(rest) or None, msg, "schema"))
    return out


def _file_catalog(data, source):
    """The catalog a file's PMs are read against: the packaged legs and the file's own."""
    from ._catalog import _TOP_KEYS, Catalog, default_catalog
    base = default_catalog()
    own = Catalog.from_mapping({k: v for k, v in data.items() if k in _TOP_KEYS}, source)
    return Catalog({**base.legs, **own.legs}, base.table1, own.pms, source)


def check_model_file(path, load=None) -> list:
    """All the problems of the catalog or model file at ``path``.

    Parameters
    ----------
    path : str or os.PathLike
    load : callable, optional
        ``load(path + "#" + NAME)`` builds one PM (default :func:`screwkit.pm.load_pm`;
        :func:`screwkit.load_pm` also assembles the default pose).

    Returns
    -------
    list of Problem
        In line order; empty when the file is valid.
    """
    from ..legs._guards import MAX_MODEL_BYTES, decode_utf8, read_limited
    from ..legs._rule_check import rule_problems
    from ._catalog import _TOP_KEYS, Catalog, default_catalog, leg_spec_from_mapping
    from ._loader import load_pm as pm_loader
    from ._yaml import load_yaml_text

    load = load or pm_loader
    source = str(path)

    def err(msg):
        return CatalogError(msg, source=source)

    text = decode_utf8(read_limited(path, MAX_MODEL_BYTES, "model file", err), "model file", err)
    problems = []
    try:
        data = load_yaml_text(text, source)
    except CatalogError as exc:
        msg = getattr(exc, "detail", str(exc))
        m = re.match(r"line (\d+), column \d+: ", msg)
        problems.append(Problem(int(m.group(1)) if m else None, None, exc.field,
                                msg[m.end():] if m else msg, "yaml"))
        if not any(w in msg for w in ("duplicate key", "read as a boolean")):
            return problems                 # not readable further (syntax, size, aliases)
        try:                                # go on with a lenient read to find the rest
            import yaml

            from ._yaml import _check_expansion
            loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
            _check_expansion(yaml.compose(text, Loader=loader))   # no alias bomb
            data = yaml.load(text, Loader=loader)
        except Exception:                   # noqa: BLE001 - anything else: the first problem only
            return problems
    dups = _duplicates(text)
    if dups and problems and "duplicate key" in problems[0].message:
        problems = []                      # the walk below reports each of them with its line
    problems += dups
    problems += _schema_problems(data, text)
    if not isinstance(data, dict):
        return problems or [Problem(None, None, None, "the file must be a mapping with legs: "
                                    "and/or pms:", "schema")]
    legs = data.get("legs") if isinstance(data.get("legs"), list) else []
    good, broken = {}, set()
    for i, d in enumerate(legs):
        name = d.get("name") if isinstance(d, dict) else None
        try:
            spec = leg_spec_from_mapping(d, source, i)
            good[spec.name] = spec
            if spec.expect:               # what the type says it is, against the solver
                for why in spec.check_expectation(spec.build().analyze()):
                    problems.append(_from_error(CatalogError(
                        f"the leg's analysis contradicts its 'expect': {why}", name,
                        "expect", source), text, "leg"))
            continue
        except CatalogError as exc:
            problems.append(_from_error(exc, text, "leg"))
        except ScrewkitError as exc:
            problems.append(Problem(None, f"legs[{i}]", None, str(exc), "leg"))
        broken.add(name)
        if isinstance(d, dict) and isinstance(name, str) and isinstance(d.get("string"), str):
            for exc in rule_problems(name, d["string"], d.get("joints"), source,
                                     d.get("expect")):
                problems.append(_from_error(exc, text, "leg"))   # the other joints' rules
    pms = data.get("pms") if isinstance(data.get("pms"), dict) else {}
    if data.get("units") is not None:    # the file's units, for each PM without its own
        pms = {k: ({"units": data["units"], **v} if isinstance(v, dict) else v)
               for k, v in pms.items()}
    if not pms and not legs and not problems:
        problems.append(Problem(None, None, None, "the file defines neither legs: nor pms:",
                                "schema"))
    whole = not any(p.check == "yaml" for p in problems)    # the strict read succeeded
    if pms and whole:
        try:     # the file as a whole (top-level keys, leg names) loads: PMs by its path
            cat = _file_catalog(data, source)
        except ScrewkitError:
            whole = False
    if not whole:                         # the PMs against the legs that do load
        base = default_catalog()
        cat = Catalog({**base.legs, **good}, base.table1,
                      {k: v for k, v in pms.items() if isinstance(k, str)}, source)
    for name, d in pms.items():
        uses = [x.get("leg") if isinstance(x, dict) else x
                for x in (d.get("legs") or [] if isinstance(d, dict) else [])] \
            if isinstance(d, dict) and isinstance(d.get("legs"), list) else []
        if any(isinstance(u, str) and u in broken for u in uses):
            continue                      # its leg types are reported above
        def build(name=name):
            if whole:
                load(f"{source}#{name}")
            else:
                pm_loader(str(name), catalog=cat)
        try:
            found = pm_problems(str(name), d, cat, build)
        except CatalogError as exc:
            found = [exc]
        except ScrewkitError as exc:
            problems.append(Problem(None, str(name), None, str(exc), "pm"))
            continue
        for exc in found:
            problems.append(_from_error(exc, text, "pm"))
    # the loader's problems (with a did-you-mean) hide the schema's at the same line and field
    rank = {"yaml": 0, "leg": 1, "pm": 1, "schema": 2}
    def bare(fld):                       # "joints[2] (S3)" -> "joints[2]"
        return re.sub(r"\s*\([^)]*\)", "", fld) if fld else fld

    located = {(p.line, p.entry, bare(p.field)) for p in problems if p.check != "schema" and p.line}
    seen, out = set(), []
    for p in sorted(problems, key=lambda p: (rank[p.check], p.line or 0)):
        key = (p.line, p.entry, p.field, p.message)
        if key in seen or (p.check == "schema" and (p.line, p.entry, p.field) in located):
            continue
        seen.add(key)
        out.append(p)
    return sorted(out, key=lambda p: (p.line or 0, rank[p.check]))
