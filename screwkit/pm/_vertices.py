"""The vertex families of a PM definition and its per-vertex axis overrides (private).

``base:`` / ``platform:`` (triangle, square, rectangle, circle, explicit points, with an
optional ``z``) give the leg end points ``A_i`` / ``a_i``; a leg entry's ``axes:`` replaces
some joint axes of its leg type at that vertex (``{platform_toward: [a3, a1]}``...).  ``ctx``
is the loader's evaluation context (:mod:`screwkit.pm._loader`): the PM's name, source and
dimensions, its error factory and number evaluation.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..legs import LegRules
from ..legs._guards import MAX_LEGS, did_you_mean, shorten
from ._checks import unknown_keys

__all__ = ["vertices", "override_axes"]

_SHAPE_KEYS = {"shape", "side", "circumradius", "radius", "sides", "angles", "count", "start",
               "points", "z"}


def vertices(spec, ctx, fld: str) -> np.ndarray:
    """The vertices ``(n, 3)`` of a vertex family (``base:`` / ``platform:``)."""
    if not isinstance(spec, dict):
        raise ctx.err("must be a mapping with 'shape' (triangle, square, rectangle, circle, points)", fld)
    unknown_keys(spec, _SHAPE_KEYS, ctx.err, fld)
    shape = spec.get("shape", "points" if "points" in spec else None)
    for k in ("angles", "points"):
        if k in spec and not (isinstance(spec[k], list) and len(spec[k]) <= MAX_LEGS):
            raise ctx.err(f"must be a list of at most {MAX_LEGS} items (one per leg)",
                          f"{fld}.{k}")

    def need(k):
        if k not in spec:
            raise ctx.err(f"a {shape} needs {k!r}", f"{fld}.{k}")
        return spec[k]

    def ring(radius, angles):
        a = np.radians(angles)
        return np.column_stack([radius * np.cos(a), radius * np.sin(a), np.zeros(len(a))])

    if shape == "triangle":
        if ("side" in spec) == ("circumradius" in spec):
            raise ctx.err("a triangle needs exactly one of 'side' and 'circumradius'", fld)
        r = (ctx.num(spec["side"], f"{fld}.side") / np.sqrt(3) if "side" in spec
             else ctx.num(spec["circumradius"], f"{fld}.circumradius"))
        ang = [ctx.num(x, f"{fld}.angles") for x in spec.get("angles", [-30, 90, 210])]
        if len(ang) != 3:
            raise ctx.err("a triangle has 3 angles", f"{fld}.angles")
        pts = ring(r, ang)
    elif shape in ("square", "rectangle"):
        if shape == "square":
            s1 = s2 = ctx.num(need("side"), f"{fld}.side")
        else:
            sides = need("sides")
            if not (isinstance(sides, (list, tuple)) and len(sides) == 2):
                raise ctx.err("must be [l1, l2]", f"{fld}.sides")
            s1, s2 = (ctx.num(x, f"{fld}.sides") for x in sides)
        pts = 0.5 * np.array([[s1, -s2, 0], [s1, s2, 0], [-s1, s2, 0], [-s1, -s2, 0]])
    elif shape == "circle":
        r = ctx.num(need("radius"), f"{fld}.radius")
        if "angles" in spec:
            ang = [ctx.num(x, f"{fld}.angles") for x in spec["angles"]]
        else:
            n = need("count")
            if not (isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= MAX_LEGS):
                raise ctx.err(f"must be an integer from 1 to {MAX_LEGS} (one vertex per leg), "
                              f"got {shorten(n)}", f"{fld}.count")
            st = ctx.num(spec.get("start", 0), f"{fld}.start")
            ang = [st + 360.0 * k / n for k in range(n)]
        pts = ring(r, ang)
    elif shape == "points":
        raw = need("points")
        if not isinstance(raw, list) or not raw:
            raise ctx.err("must be a list of [x, y, z]", f"{fld}.points")
        pts = np.array([ctx.vec(p, f"{fld}.points[{k}]") for k, p in enumerate(raw)])
    else:
        shapes = ("triangle", "square", "rectangle", "circle", "points")
        raise ctx.err(f"unknown shape {shorten(shape)}{did_you_mean(shape, shapes)} "
                      f"({', '.join(shapes)})", f"{fld}.shape")
    if "z" in spec:
        pts[:, 2] += ctx.num(spec["z"], f"{fld}.z")
    if len(pts) > 1 and np.max(np.linalg.norm(pts - pts.mean(axis=0), axis=1)) <= 0:
        raise ctx.err("degenerate vertices (all at one point)", fld)
    return pts


def _vertex_vector(names, base_pts, plat_pts, ctx, fld, kind):
    if not (isinstance(names, (list, tuple)) and len(names) == 2):
        raise ctx.err("needs two vertex names, e.g. [a3, a1]", fld)
    pts = []
    for nm in names:
        nm = str(nm)
        if kind == "platform":
            table = {"o": np.zeros(3), **{f"a{k + 1}": p for k, p in enumerate(plat_pts)}}
        else:
            table = {"O": np.zeros(3), **{f"A{k + 1}": p for k, p in enumerate(base_pts)}}
        if nm not in table:
            raise ctx.err(f"unknown vertex {nm!r} (one of {', '.join(table)})", fld)
        pts.append(table[nm])
    v = pts[1] - pts[0]
    if np.linalg.norm(v) == 0:
        raise ctx.err("the two vertices coincide", fld)
    return [float(x) for x in v]


def override_axes(rules: LegRules, axes, base_pts, plat_pts, ctx, fld) -> LegRules:
    """Rules with some joint axes replaced (a PM's per-vertex choice)."""
    if not isinstance(axes, dict):
        raise ctx.err("must be a mapping joint name -> direction rule", fld)
    joints = list(rules.joints)
    for jname, rule in axes.items():
        f = f"{fld}.{jname}"
        if isinstance(rule, dict) and len(rule) == 1 and next(iter(rule)) in ("platform_toward", "base_toward"):
            (k, v), = rule.items()
            kind = k.split("_")[0]
            rule = {kind: _vertex_vector(v, base_pts, plat_pts, ctx, f, kind)}
        jn = str(jname)
        if not (isinstance(jname, str) and 2 <= len(jn) <= 8 and jn[0] in "RPHUSC"):
            raise ctx.err(f"{shorten(jname)} is not a joint name of {rules.string.text} "
                          "(R3, U1a, ...)", f)
        part = jn[-1] if jn[-1] in "abc" and len(jn) > 2 and not jn[-2].isalpha() else ""
        digits = jn[1:len(jn) - len(part)]
        try:
            if not (digits.isascii() and digits.isdigit()):
                raise ValueError(digits)
            pos = int(digits)
        except ValueError:
            raise ctx.err(f"not a joint name of {rules.string.text} (R3, U1a, ...)", f) from None
        if not (1 <= pos <= len(joints)) or joints[pos - 1].letter != jn[0]:
            raise ctx.err(f"{rules.string.text} has no joint {jn!r}", f)
        jr = joints[pos - 1]
        if part:
            if jr.letter not in "US" or not jr.axes:
                raise ctx.err(f"{jn[:-1]} has no listed axes to replace", f)
            ax = list(jr.axes)
            idx = "abc".index(part)
            if idx >= len(ax):
                raise ctx.err(f"{jn[:-1]} has {len(ax)} axes", f)
            ax[idx] = rule
            joints[pos - 1] = dataclasses.replace(jr, axes=tuple(ax))
        else:
            if jr.letter not in "RPHC":
                raise ctx.err(f"name a part of {jn} ({jn}a, {jn}b ...)", f)
            joints[pos - 1] = dataclasses.replace(jr, axis=rule)
    return dataclasses.replace(rules, joints=tuple(joints))
