"""Checks of a PM definition's names and dimensions (private, for :mod:`screwkit.pm._loader`):
a name or a path, unknown keys with a did-you-mean, text fields, dimensions and overrides."""

from __future__ import annotations

from pathlib import Path

from ..errors import CatalogError, InputError
from ..legs._guards import (MAX_MAGNITUDE, MAX_NAME, MAX_PATH_CHARS, did_you_mean, parse_number,
                            real, shorten)

__all__ = ["split_path", "listing", "find_pm", "unknown_keys", "text_fields", "dimensions",
           "check_overrides_used", "pm_string"]


def split_path(name_or_path: str):
    """``(path, pick)`` of ``path.yaml#NAME`` (or an existing file, whose name may hold a
    ``#``), else ``(None, None)``."""
    s = str(name_or_path)
    if _is_file(s):
        return s, None
    # the first '#' after the file's name: the PM's name may hold one too (a#b), as may a
    # file's (my#arm.yaml#a#b)
    at = s.find("#")
    while at >= 0:
        base, pm = s[:at], s[at + 1:]
        if base.endswith((".yaml", ".yml")) or _is_file(base):
            return base, (pm or None)
        at = s.find("#", at + 1)
    if s.endswith((".yaml", ".yml")):        # a model file that is not there: the loader says so
        return s, None
    return None, None


def _is_file(text: str) -> bool:
    try:                       # a name such as 3RRPRR, or an over-long / odd string: no file
        return "\x00" not in text and len(text) <= MAX_PATH_CHARS and Path(text).is_file()
    except (OSError, ValueError):
        return False


def listing(names, limit: int = 12) -> str:
    """``"a, b, c and 5 more"``: a list of names in a message, cut at ``limit``."""
    names = sorted(map(str, names))
    more = f" and {len(names) - limit} more" if len(names) > limit else ""
    return ", ".join(names[:limit]) + more if names else "none"


def find_pm(cat, name: str) -> str:
    """The catalog key of PM ``name`` (``3-RPS`` finds ``3RPS``); a CatalogError with a hint
    (upper-case joint letters, the closest name) otherwise."""
    if name in cat.pms:
        return name
    if len(name) > MAX_NAME:
        raise CatalogError(f"a PM name of {len(name)} characters is too long (at most {MAX_NAME}; "
                           f"or a model file: PATH.yaml)", source=cat.source)
    canon = name.replace("-", "").replace(" ", "")
    for k in cat.pms:
        kc = k.replace("-", "").replace(" ", "")
        if kc == canon:
            return k
        if kc.lower() == canon.lower():
            raise CatalogError(f"unknown PM {name!r}: joint letters are upper case: did you mean "
                               f"{k!r}?", source=cat.source)
    hint = did_you_mean(name, list(cat.pms))
    raise CatalogError(f"unknown PM {shorten(name)}{hint}; known: {listing(cat.pms)}",
                       source=cat.source)


def unknown_keys(d: dict, known, err, fld, what: str = "key") -> None:
    """``err(message, field)`` on the first key of ``d`` not in ``known``, with a
    did-you-mean; the field is ``fld``, or the key itself when ``fld`` is None."""
    bad = [k for k in d if k not in known]
    if bad:
        k = bad[0]
        where = fld if fld is not None else (k if isinstance(k, str) else None)
        raise err(f"unknown {what} {shorten(k, 40)}{did_you_mean(k, known)}; known: "
                  f"{', '.join(sorted(known))}", where)


def text_fields(d: dict, keys, name, src) -> None:
    """Each of ``keys`` present in ``d`` is a text."""
    for k in keys:
        if d.get(k) is not None and not isinstance(d[k], str):
            raise CatalogError(f"must be a text, got {shorten(d[k])}", name, k, src)


def dimensions(dims_raw: dict, overrides, name, src) -> dict:
    """The dimensions ``{name: positive length}`` with the overrides applied: names are
    identifiers, values numbers (or decimal text such as ``"1e3"``), positive, at most
    ``MAX_MAGNITUDE``; an override names an existing dimension."""
    if not isinstance(overrides, dict):
        raise InputError(f"{name}: overrides must be a mapping dimension -> value")
    unknown = [k for k in overrides if k not in dims_raw]
    if unknown:
        raise InputError(f"{name}: unknown dimension {shorten(unknown[0], 40)}"
                         f"{did_you_mean(unknown[0], list(dims_raw))}; the dimensions are "
                         f"{listing(dims_raw)}")
    dims = {}
    for k, v in {**dims_raw, **overrides}.items():
        if not isinstance(k, str) or not k.isidentifier() or len(k) > MAX_NAME:
            raise CatalogError(f"a dimension name must be a name such as L or R1, got "
                               f"{shorten(k)}", name, "dimensions", src)
        if k in overrides:
            def bad(m, k=k):
                return InputError(f"{name}: override {k}: {m}")
        else:
            def bad(m, fld=f"dimensions.{k}"):
                return CatalogError(m, name, fld, src)
        if isinstance(v, str):            # "150", "1e3"
            try:
                x = parse_number(v, k, bound=MAX_MAGNITUDE)
            except InputError as exc:
                raise bad(str(exc).removeprefix(f"{k}: ")) from None
        else:
            x = real(v, k, bound=MAX_MAGNITUDE, error=bad)
        if not x > 0:
            raise bad(f"{k} = {x:g} must be a positive length")
        dims[k] = x
    return dims


def unused_dimensions(d: dict) -> list:
    """The dimensions the definition ``d`` declares (``dimensions:``) that no expression of
    its other fields names: they change nothing."""
    import re
    raw = d.get("dimensions") if isinstance(d, dict) else None
    if not isinstance(raw, dict):
        return []
    texts = []

    def walk(v):
        if isinstance(v, str):
            texts.append(v)
        elif isinstance(v, dict):
            for x in v.values():
                walk(x)
        elif isinstance(v, (list, tuple)):
            for x in v:
                walk(x)
    walk({k: v for k, v in d.items() if k != "dimensions"})
    text = "\n".join(texts)
    return [k for k in raw if isinstance(k, str)
            and not re.search(rf"(?<![\w.]){re.escape(k)}(?!\w)", text)]


def check_overrides_used(d: dict, overrides, name) -> None:
    """Refuse an override of a dimension no expression of the definition ``d`` names (its
    fields other than ``dimensions:``): it would change nothing, silently."""
    if not overrides:
        return
    unused = unused_dimensions(d)
    for k in overrides:
        if k in unused:
            raise InputError(f"{name}: override {k}: no expression of the model uses the "
                             f"dimension {k}, so changing it changes nothing")


def pm_string(d, name, rules, ctx, passive=()):
    """The PM string: ``string:`` when given; else the name when it is one that the legs
    make (``3RRPRR``); else the legs' own (``my3SPR`` of three SPR legs is ``3SPR``; a
    passive leg written ``LEG/passive``)."""
    from ..errors import ScrewkitError
    from ..legs import parse_pm

    if "string" in d:
        string = str(d["string"])
        try:
            return string, parse_pm(string)
        except ScrewkitError as exc:
            raise ctx.err(str(exc), "string") from None
    declared = sorted((r.string.text, i in passive) for i, r in enumerate(rules))
    try:
        pms = parse_pm(name)
        if sorted((ls.text, k in pms.passive) for k, ls in enumerate(pms.legs)) == declared:
            return name, pms
    except ScrewkitError:
        pass                          # a name, not a PM string: the legs say what it is
    counts: dict = {}
    for i, r in enumerate(rules):
        t = r.string.text + ("/passive" if i in passive else "")
        counts[t] = counts.get(t, 0) + 1
    string = "+".join(f"{c if c > 1 else ''}{t}" for t, c in counts.items())
    try:
        return string, parse_pm(string)
    except ScrewkitError as exc:
        raise ctx.err(str(exc), "legs") from None
