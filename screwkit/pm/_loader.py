"""Parallel manipulators assembled from catalog legs: definitions, home assembly, poses.

A PM is defined in the ``pms:`` section of ``legs_catalog.yaml`` (or in a user
YAML file with ``pms:`` and optionally ``legs:``); ``docs/pm_models.md`` has the
schema.  :func:`load_pm` evaluates the definition with its dimensions, solves the
*home* pose (the dependent pose parameters at the home values of the independent
ones, so that every leg's structure checks hold), builds each leg by its catalog
rules there, and returns a :class:`PMModel`: a constant description, solved at a
pose by :func:`screwkit.solve` (the unified inverse displacement of
:mod:`screwkit.engine`).  This module never calls the engine: the check that the
default pose can be assembled is made by :func:`screwkit.load_pm` (and
:func:`screwkit.engine.load_assembled_pm`, which every loader for users goes
through).

Examples
--------
>>> import screwkit
>>> pm = screwkit.load_pm("3RRPRR")
>>> pm.independent, pm.order, pm.stated_dof
(('alpha', 'beta', 'Zo'), 'XYX', 3)
>>> sol = screwkit.solve(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
>>> bool(sol.success)
True
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from ..legs._guards import MAX_ANGLE_DEG, MAX_LEGS, MAX_MAGNITUDE, did_you_mean, real, shorten
from ..errors import CatalogError, GeometryError, InputError, ScrewkitError
from ..legs import LegRules, build_leg
from ..screws import Normalisation, check_order
from ._checks import (dimensions, find_pm, listing, pm_string, split_path, text_fields,
                      unknown_keys)
from ._home import _solve_home
from ._units import units_from_mapping
from ._limits import limits_from_mapping
from ._physical import dynamics_from_mapping
from ._workload import workload_from_mapping
from ._model import LENGTH_PARAMS, PARAMS, PMModel

__all__ = ["load_pm", "pm_names"]

_PM_KEYS = {"string", "summary", "dimensions", "base", "platform", "legs", "centre", "euler",
            "independent", "pose", "home", "guess", "dof", "motion", "note", "source", "units",
            "limits", "dynamics", "workload"}
_SHAPE_KEYS = {"shape", "side", "circumradius", "radius", "sides", "angles", "count", "start",
               "points", "z"}



def pm_names(catalog=None) -> list:
    """Names of the PMs of the catalog."""
    from ._catalog import default_catalog
    cat = catalog if catalog is not None else default_catalog()
    return sorted(cat.pms)


def load_pm(name_or_path: str, overrides: dict | None = None, catalog=None) -> PMModel:
    """Load a PM by catalog name or from a YAML file.

    Parameters
    ----------
    name_or_path : str
        A catalog PM name (``"3RRPRR"``, ``"3-RRPRR"``), or a path to a YAML
        file with ``pms:`` (and optionally ``legs:``, which add to or shadow the
        catalog's legs); ``path.yaml#NAME`` picks one of several PMs.
    overrides : dict, optional
        Dimension values replacing the defaults, e.g. ``{"L": 150}``.
    catalog : Catalog, optional
        Default: the packaged catalog.

    Raises
    ------
    CatalogError
        Unknown PM or a malformed definition (names the PM and field).
    InputError
        Bad overrides.
    """
    from ._catalog import Catalog, default_catalog, load_catalog

    cat = catalog if catalog is not None else default_catalog()
    if isinstance(name_or_path, os.PathLike):
        name_or_path = os.fspath(name_or_path)
    if not isinstance(name_or_path, str) or not name_or_path.strip():
        raise InputError("a PM name or a path to a YAML file is required")
    path, pick = split_path(name_or_path)
    if path is not None:
        user = load_catalog(path)
        if not user.pms:
            raise CatalogError("the file defines no PM (no 'pms:' mapping)", source=path)
        cat = Catalog({**cat.legs, **user.legs}, cat.table1, user.pms, path)
        if pick is None:
            if len(user.pms) > 1:
                raise CatalogError(f"the file defines {len(user.pms)} PMs ({listing(user.pms)}): "
                                   f"pick one with {path}#NAME", source=path)
            pick = next(iter(user.pms))
        name = pick
    else:
        name = name_or_path.strip()
    key = find_pm(cat, name)
    try:
        try:
            return _build(key, cat.pms[key], cat, overrides or {})
        except GeometryError as exc:
            raise CatalogError(f"the geometry cannot be built: {exc}", key, None,
                               cat.source) from None
    except CatalogError as exc:           # name the line of the entry and field of the file
        if path is None or exc.source != cat.source:
            raise
        from ._locate import with_line_of_file
        raise with_line_of_file(exc, path) from None


class _Ctx:
    """Evaluation context of one PM definition: name, source, dimensions."""

    def __init__(self, name, source, dims):
        self.name, self.source, self.dims = name, source, dims

    def err(self, msg, fld):
        return CatalogError(msg, self.name, fld, self.source)

    def num(self, v, fld) -> float:
        from ._expressions import parse_expression
        if isinstance(v, str):
            try:
                x = float(parse_expression(v, tuple(self.dims))(**self.dims))
            except InputError as exc:
                raise self.err(str(exc), fld) from None
            if not abs(x) <= MAX_MAGNITUDE:
                raise self.err(f"{shorten(v, 40)} = {x:g} is beyond the limit "
                               f"+-{MAX_MAGNITUDE:g}", fld)
            return x
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            raise self.err(f"must be a number or an expression, got {shorten(v)}", fld)
        return real(v, fld.rsplit(".", 1)[-1], bound=MAX_MAGNITUDE,
                    error=lambda m: self.err(m, fld))

    def vec(self, v, fld) -> np.ndarray:
        if not (isinstance(v, (list, tuple)) and len(v) == 3):
            raise self.err("must be a list of 3 numbers", fld)
        return np.array([self.num(x, f"{fld}[{k}]") for k, x in enumerate(v)])


def _vertices(spec, ctx: _Ctx, fld: str) -> np.ndarray:
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


def _override(rules: LegRules, axes, base_pts, plat_pts, ctx, fld) -> LegRules:
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


def _pose_values(raw, ctx, fld, names) -> dict:
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        raise ctx.err("must be a mapping pose parameter -> value (angles in degrees)", fld)
    out = {}
    for k, v in raw.items():
        if k not in PARAMS:
            raise ctx.err(f"unknown pose parameter {shorten(k)}{did_you_mean(k, PARAMS)} (one "
                          f"of {', '.join(PARAMS)})", fld)
        if names is not None and k not in names:
            raise ctx.err(f"{k} is not one of {', '.join(names)}", fld)
        x = ctx.num(v, f"{fld}.{k}")
        if k not in LENGTH_PARAMS and abs(x) > MAX_ANGLE_DEG:
            raise ctx.err(f"{x:g} deg is beyond the limit +-{MAX_ANGLE_DEG:g} deg", f"{fld}.{k}")
        out[k] = x if k in LENGTH_PARAMS else np.radians(x)
    return out


def _build(name: str, d, cat, overrides: dict) -> PMModel:
    src = cat.source
    if not isinstance(d, dict):
        raise CatalogError("must be a mapping", name, None, src)
    unknown_keys(d, _PM_KEYS, lambda m, f: CatalogError(m, name, f, src), None, "field")
    text_fields(d, ("string", "summary", "note", "motion", "euler", "source"), name, src)
    for req in ("base", "platform", "legs", "independent", "dof"):
        if req not in d:
            raise CatalogError(f"missing required field {req!r}", name, req, src)
    # dimensions and overrides
    dims_raw = d.get("dimensions") or {}
    if not isinstance(dims_raw, dict):
        raise CatalogError("must be a mapping name -> length", name, "dimensions", src)
    dims = dimensions(dims_raw, overrides, name, src)
    ctx = _Ctx(name, src, dims)
    base = _vertices(d["base"], ctx, "base")
    plat = _vertices(d["platform"], ctx, "platform")
    n = len(base)
    # legs
    raw_legs = d["legs"]
    if not isinstance(raw_legs, list) or not raw_legs:
        raise ctx.err("must be a list with one leg per vertex", "legs")
    if not (len(raw_legs) == n == len(plat)):
        raise ctx.err(f"{len(raw_legs)} legs for {n} base and {len(plat)} platform vertices", "legs")
    names, rules, bases = [], [], []
    for i, entry in enumerate(raw_legs):
        fld = f"legs[{i}]"
        axes = None
        if isinstance(entry, dict):
            extra = [k for k in entry if k not in ("leg", "axes")]
            if "leg" not in entry or extra:
                hint = did_you_mean(extra[0], ("leg", "axes")) if extra else ""
                raise ctx.err("a leg entry is a name or {leg: NAME, axes: {JOINT: DIRECTION}}"
                              + (f"; unknown key {shorten(extra[0], 40)}{hint}" if extra else ""),
                              fld)
            axes, entry = entry.get("axes"), entry["leg"]
        if not isinstance(entry, str):
            raise ctx.err("must be a leg name", fld)
        spec = cat.find_leg(entry)
        if spec is None:
            raise ctx.err(f"unknown leg {shorten(entry)}{did_you_mean(entry, list(cat.legs))} "
                          "(not in the catalog's legs)", fld)
        r = spec.rules
        if axes:
            r = _override(r, axes, base, plat, ctx, f"{fld}.axes")
        names.append(spec.name)
        rules.append(r)
        bases.append(tuple(spec.basis))
    string, pms = pm_string(d, name, rules, ctx)
    if sorted(ls.text for ls in pms.legs) != sorted(r.string.text for r in rules):
        raise ctx.err(f"the legs {'+'.join(r.string.text for r in rules)} do not make {string}", "legs")
    # pose parametrisation
    order = d.get("euler", "XYX")
    try:
        check_order(order)
    except InputError as exc:
        raise ctx.err(str(exc), "euler") from None
    ind = d["independent"]
    if not (isinstance(ind, list) and ind and all(isinstance(p, str) and p in PARAMS for p in ind)
            and len(set(ind)) == len(ind)):
        raise ctx.err(f"must be a list of distinct names among {', '.join(PARAMS)}", "independent")
    ind = tuple(ind)
    dep = tuple(p for p in PARAMS if p not in ind)
    dof = d["dof"]
    if not (isinstance(dof, int) and not isinstance(dof, bool) and 1 <= dof <= 6):
        raise ctx.err("must be an integer from 1 to 6", "dof")
    if dof != len(ind):
        raise ctx.err(f"dof {dof} but {len(ind)} independent pose parameters", "independent")
    pose = _pose_values(d.get("pose"), ctx, "pose", ind)
    missing = [p for p in ind if p not in pose]
    if missing:
        raise ctx.err(f"no default value for {', '.join(missing)}", "pose")
    home_ind = {**pose, **_pose_values(d.get("home"), ctx, "home", ind)}
    guess = {p: 0.0 for p in PARAMS}
    guess.update(_pose_values(d.get("guess"), ctx, "guess", dep))
    start = {**guess, **home_ind}
    C = (ctx.vec(d["centre"], "centre") if d.get("centre") is not None
         else 0.5 * np.array([start["Xo"], start["Yo"], start["Zo"]]))
    motion = str(d.get("motion", ""))
    pts = np.vstack([base, plat + [start["Xo"], start["Yo"], start["Zo"]]])
    norm = Normalisation.for_points(pts)
    proto = PMModel(name, pms.canonical, tuple(names), tuple(rules), (), start, ind, dep, order,
                    dims, base, plat, C, dof, motion, {}, (np.eye(3), np.zeros(3)), norm,
                    str(d.get("summary", "")), str(d.get("note", "")), (), src)
    home, notes = _solve_home(proto, start, ctx)
    try:
        legs = tuple(build_leg(r, proto.placement(i, home), True) for i, r in enumerate(rules))
    except GeometryError as exc:
        raise ctx.err(f"cannot assemble the legs at the home pose: {exc}", "home") from None
    Rh, oh = proto.pose_matrix(home)
    norm = Normalisation.for_points(np.vstack([base, (Rh @ plat.T).T + oh]))
    # the default pose is only the independent values: assembling it is the engine's job
    # (screwkit.engine.check_default_pose, called by screwkit.load_pm)
    default = {k: float(v) for k, v in pose.items()}
    units = units_from_mapping(d.get("units"), name, src)
    return dataclasses.replace(proto, home_legs=legs, home_pose=home, normalisation=norm,
                               constraint_references=tuple(bases), units=units,
                               dynamics=dynamics_from_mapping(d.get("dynamics"), name, src, dims,
                                                              legs, units),
                               limits=limits_from_mapping(d.get("limits"), ctx, legs),
                               workload=workload_from_mapping(d.get("workload"), name, src,
                                                              units, dims),
                               default_pose=default, notes=tuple(notes))
