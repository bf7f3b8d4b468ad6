"""Static check of a leg type's placement rules when the catalog is read (private).

:func:`check_rule_references` walks every ``axis``, ``axes`` and ``at`` rule of a leg type
with the grammar :class:`~screwkit.legs._rule_context._Context` evaluates, and refuses,
naming the entry, the field (``joints[1] (R2).at``) and the culprit with a did-you-mean,

* an unknown key in a rule mapping (``{offset: A, fractoin: 0.4}`` would otherwise place
  the point at ``A`` silently),
* a reference that is neither a frame reference (``base.Z``, ``leg``...), an end point
  (``A``, ``a``, ``O``, ``o``, ``C``) nor a joint of the leg (``R7`` of a 5-joint leg).

Circular references (a joint placed from one placed after it) are found when the leg is
built.
"""

from __future__ import annotations

from ..errors import CatalogError
from ._guards import did_you_mean, shorten
from ._rule_context import _FRAME_REFS, _POINT_NAMES

__all__ = ["check_rule_references", "check_reference"]

_DIRECTION_RULE_KEYS = ("along", "parallel", "perpendicular")
_DIRECTION_KEYS = ("toward", "base", "platform", "world")
_POINT_KEYS = {"between": ("between", "t"), "meet": ("meet",),
               "offset": ("offset", "along", "fraction"),
               # literal points (model lengths): world, base-frame or platform-frame coordinates
               "world": ("world",), "base": ("base",), "platform": ("platform",)}


class _Checker:
    def __init__(self, joint_names, name, source):
        self.joints = set(joint_names)
        self.name, self.source = name, source

    def err(self, msg, fld):
        return CatalogError(msg, self.name, fld, self.source)

    def ref(self, r, kind, fld):
        """A name: a direction (frame references and joints) or a point (end points, joints)."""
        neg = kind == "direction" and r.startswith("-")
        base = r[1:] if neg else r
        known = (_FRAME_REFS if kind == "direction" else _POINT_NAMES | {"C"}) | self.joints
        if base not in known:
            raise self.err(f"unknown {kind} reference {shorten(r, 40)}"
                           f"{did_you_mean(base, sorted(known))} (a "
                           f"{'frame reference' if kind == 'direction' else 'end point'} or a "
                           f"joint of the leg: {', '.join(sorted(self.joints))})", fld)

    def keys(self, rule, allowed, fld, what):
        bad = [k for k in rule if k not in allowed]
        if bad:
            raise self.err(f"unknown key {shorten(bad[0], 40)} in a {what}"
                           f"{did_you_mean(str(bad[0]), list(allowed))}; known: "
                           f"{', '.join(allowed)}", fld)

    def direction_rule(self, rule, fld):
        if isinstance(rule, dict) and len(rule) == 1 and next(iter(rule)) in _DIRECTION_RULE_KEYS:
            (k, v), = rule.items()
            if k == "perpendicular":
                if isinstance(v, (list, tuple)):
                    for x in v:
                        self.direction(x, fld)
                return
            return self.direction(v, fld)
        return self.direction(rule, fld)

    def direction(self, r, fld):
        if isinstance(r, str):
            return self.ref(r, "direction", fld)
        if isinstance(r, dict):
            if len(r) == 1 and "toward" in r:
                v = r["toward"]
                for x in (v if isinstance(v, (list, tuple)) else ()):
                    self.point(x, fld)
                return
            self.keys(r, _DIRECTION_KEYS + _DIRECTION_RULE_KEYS, fld, "direction rule")

    def point(self, r, fld):
        if isinstance(r, str):
            return self.ref(r, "point", fld)
        if not isinstance(r, dict):
            return
        kind = next((k for k in _POINT_KEYS if k in r), None)
        if kind is None:
            raise self.err(f"cannot read point rule {shorten(r, 60)}: a point is a name or a "
                           f"mapping with one of {', '.join(_POINT_KEYS)}", fld)
        self.keys(r, _POINT_KEYS[kind], fld, f"'{kind}' point rule")
        v = r[kind]
        if kind == "between" and isinstance(v, (list, tuple)):
            for x in v:
                self.point(x, fld)
        elif kind == "meet" and isinstance(v, (list, tuple)):
            for x in v:
                if isinstance(x, str) and x not in self.joints:
                    self.ref(x, "direction", fld)
        elif kind == "offset":
            self.point(v, fld)
            if "along" in r:
                self.direction(r["along"], fld)


def check_reference(r, kind: str, joint_names, name, fld, source=None) -> None:
    """One reference (``kind`` ``"point"`` or ``"direction"``) of leg ``name``'s joints."""
    c = _Checker(joint_names, name, source)
    (c.point if kind == "point" else c.direction)(r, fld)


def check_rule_references(rules, source=None) -> None:
    """Every rule of a :class:`~screwkit.legs.LegRules` names known keys and references;
    raises :class:`CatalogError` (entry, field) otherwise."""
    ls = rules.string
    names = {j.name for j in ls.equivalent} | {f"{j.origin}{j.position}" for j in ls.equivalent}
    c = _Checker(names, rules.name, source)
    for jr in rules.joints:
        fld = f"joints[{jr.position - 1}] ({jr.letter}{jr.position})"
        if jr.axis is not None:
            c.direction_rule(jr.axis, f"{fld}.axis")
        for i, ax in enumerate(jr.axes):
            if ax is not None:
                c.direction_rule(ax, f"{fld}.axes[{i}]")
        if jr.at is not None:
            c.point(jr.at, f"{fld}.at")
        if getattr(jr, "to", None) is not None:        # a parallelogram's second hinge
            c.point(jr.to, f"{fld}.to")


def rule_problems(name, string, joints, source=None, expect=None) -> list:
    """Every reference problem of a raw leg entry's ``joints`` (one :class:`CatalogError`
    per joint at fault), for reports that list all problems (``screwkit model check``)."""
    from ._parsing import parse_leg

    try:
        ls = parse_leg(string)
    except Exception:                        # the string itself is reported by the loader
        return []
    eq = ls.equivalent
    names = {j.name for j in eq} | {f"{j.origin}{j.position}" for j in eq}
    c = _Checker(names, name, source)
    out = []
    for k, (letter, entry) in enumerate(zip(ls.letters, joints or ()), start=1):
        if not isinstance(entry, dict):
            continue
        fld = f"joints[{k - 1}] ({letter}{k})"
        for key in ("axis", "axes", "at", "to"):
            rule = entry.get(key)
            try:
                if key in ("at", "to") and rule is not None:
                    c.point(rule, f"{fld}.{key}")
                elif key == "axis" and rule is not None:
                    c.direction_rule(rule, f"{fld}.axis")
                elif key == "axes" and isinstance(rule, (list, tuple)):
                    for i, ax in enumerate(rule):
                        c.direction_rule(ax, f"{fld}.axes[{i}]")
            except CatalogError as exc:
                out.append(exc)
    lines = expect.get("force_lines") if isinstance(expect, dict) else None
    for i, fl in enumerate(lines if isinstance(lines, list) else ()):
        for key, v in (fl.items() if isinstance(fl, dict) else ()):
            try:
                (c.direction if key == "parallel" else c.point)(v, f"expect.force_lines[{i}]")
            except CatalogError as exc:
                out.append(exc)
    return out
