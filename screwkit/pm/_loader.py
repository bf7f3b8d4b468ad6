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
from collections.abc import Mapping

import numpy as np

from ..legs._guards import MAX_ANGLE_DEG, MAX_MAGNITUDE, MAX_NAME, did_you_mean, real, shorten
from ..errors import CatalogError, GeometryError, InputError, ScrewkitError
from ..legs import build_leg
from ..screws import Normalisation, check_order
from ._checks import (check_overrides_used, dimensions, find_pm, listing, pm_string,
                      split_path, text_fields, unknown_keys)
from ._home import _solve_home
from ._units import units_from_mapping
from ._limits import limits_from_mapping
from ._physical import dynamics_from_mapping
from ._workload import workload_from_mapping
from ._model import LENGTH_PARAMS, PARAMS, PMModel
from ._variants import Definition
from ._vertices import _SHAPE_KEYS, override_axes as _override, vertices as _vertices  # noqa: F401
from ._definition import MEMORY, definition_of, inline_leg, plain_mapping
from ._catalog import LegSpec

__all__ = ["load_pm", "pm_names"]

_PM_KEYS = {"string", "summary", "dimensions", "base", "platform", "legs", "centre", "euler",
            "independent", "pose", "home", "guess", "dof", "motion", "note", "source", "units",
            "limits", "dynamics", "workload"}
#: The keys of a leg entry of ``legs:`` written as a mapping.
_PM_LEG_KEYS = ("leg", "axes", "passive")



def pm_names(catalog=None) -> list:
    """Names of the PMs of the catalog."""
    from ._catalog import default_catalog
    cat = catalog if catalog is not None else default_catalog()
    return sorted(cat.pms)


def load_pm(name_or_path, overrides: dict | None = None, catalog=None, *,
            name: str | None = None) -> PMModel:
    """Load a PM by catalog name, from a YAML file, or from a mapping in memory.

    Parameters
    ----------
    name_or_path : str, path, mapping or PMBuilder
        A catalog PM name (``"3RRPRR"``, ``"3-RRPRR"``), or a path to a YAML
        file with ``pms:`` (and optionally ``legs:``, which add to or shadow the
        catalog's legs); ``path.yaml#NAME`` picks one of several PMs.  Or one PM's
        mapping exactly as it stands under ``pms:`` in a model file (its leg types by
        catalog name or written inline, ``{leg: {name: ..., string: ..., joints: [...]}}``),
        or a whole model file's mapping (``{legs: [...], pms: {...}}``), or a
        :class:`~screwkit.pm.PMBuilder`.  A mapping is read by the very same loader as a
        file: the same checks and the same errors (without a line number).
    overrides : dict, optional
        Dimension values replacing the defaults, e.g. ``{"L": 150}``.
    catalog : Catalog, optional
        Default: the packaged catalog.
    name : str, optional
        The model's name for one PM's mapping (default its ``string``), or the PM to pick
        from a file's mapping.

    Raises
    ------
    CatalogError
        Unknown PM or a malformed definition (names the PM and field).
    InputError
        Bad overrides.
    """
    from ._catalog import Catalog, default_catalog, load_catalog

    cat = catalog if catalog is not None else default_catalog()
    if hasattr(name_or_path, "to_mapping") and not isinstance(name_or_path, PMModel):
        b = name_or_path                                  # a PMBuilder
        return load_pm(b.to_mapping(), overrides, cat, name=name or b.name)
    if isinstance(name_or_path, Mapping):
        return _from_mapping(name_or_path, overrides, cat, name)
    if isinstance(name_or_path, os.PathLike):
        name_or_path = os.fspath(name_or_path)
    if isinstance(name_or_path, (list, tuple)) and name_or_path and \
            all(type(x).__name__ == "Leg" for x in name_or_path):
        raise InputError("a list of legs is not a PM: assemble one with screwkit.PMBuilder "
                         "(its legs, their base and platform attachments, the pose "
                         "parametrisation; docs/building_pms.md)")
    if not isinstance(name_or_path, str) or not name_or_path.strip():
        raise InputError("a PM name, a path to a YAML file, a PM mapping or a PMBuilder is "
                         f"required, got {type(name_or_path).__name__}")
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
    return _load_entry(cat, name, overrides, path)


def _load_entry(cat, name, overrides, path=None) -> PMModel:
    """The PM ``name`` of ``cat`` (a catalog, a file or a mapping read as one)."""
    key = find_pm(cat, name)
    try:
        try:
            return _build(key, cat.pms[key], cat, overrides or {})
        except GeometryError as exc:
            raise CatalogError(f"the geometry cannot be built: {exc}", key, None,
                               cat.source) from None
    except CatalogError as exc:           # name the line of the entry and field of the file
        if overrides and exc.source == cat.source:
            # (the entry is built with other dimensions than it says: say which)
            given = ", ".join(f"{k}={v:g}" if isinstance(v, (int, float)) else f"{k}={v}"
                              for k, v in overrides.items())
            exc = CatalogError(f"{exc.detail} (with the overrides {given})", exc.entry,
                               exc.field, exc.source, exc.line)
        if path is None or exc.source != cat.source:
            raise exc from None
        from ._locate import with_line_of_file
        raise with_line_of_file(exc, path) from None


def _from_mapping(raw, overrides, cat, name) -> PMModel:
    """A PM from a mapping: one PM's entry (under ``pms:`` in a file) or a whole file's."""
    from ._catalog import Catalog
    d = plain_mapping(raw)
    if "pms" in d:                                     # a model file's mapping
        user = Catalog.from_mapping(d, MEMORY)
        if not user.pms:
            raise CatalogError("the mapping defines no PM (its 'pms:' is empty)", source=MEMORY)
        if name is None:
            if len(user.pms) > 1:
                raise CatalogError(f"the mapping defines {len(user.pms)} PMs "
                                   f"({listing(user.pms)}): pick one with name=", source=MEMORY)
            name = next(iter(user.pms))
        return _load_entry(Catalog({**cat.legs, **user.legs}, cat.table1, user.pms, MEMORY),
                           name, overrides)
    if name is None:
        s = d.get("string")
        name = s if isinstance(s, str) and s.strip() else "pm"
    if not isinstance(name, str) or not name.strip() or len(name) > MAX_NAME:
        raise InputError(f"name must be a non-empty text of at most {MAX_NAME} characters")
    return _load_entry(Catalog(cat.legs, cat.table1, {name: d}, MEMORY), name, overrides)


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


def leg_entry(entry, i: int, ctx, cat):
    """One entry of a PM's ``legs:`` (a leg name, an inline leg type, or ``{leg: ...,
    axes: ..., passive: ...}``): ``(spec, axes, passive)``.

    Raises
    ------
    CatalogError
        Naming ``legs[i]`` (or its key) and what is wrong.
    """
    fld = f"legs[{i}]"
    axes, flag = None, False
    if isinstance(entry, dict):
        extra = [k for k in entry if k not in _PM_LEG_KEYS]
        if "leg" not in entry or extra:
            hint = did_you_mean(extra[0], _PM_LEG_KEYS) if extra else ""
            raise ctx.err("a leg entry is a name or {leg: NAME, axes: {JOINT: DIRECTION}, "
                          "passive: true}"
                          + (f"; unknown key {shorten(extra[0], 40)}{hint}" if extra else ""),
                          fld)
        flag = entry.get("passive", False)
        if not isinstance(flag, bool):
            raise ctx.err(f"must be true or false, got {shorten(flag)}", f"{fld}.passive")
        axes, entry = entry.get("axes"), entry["leg"]
        if isinstance(entry, dict):                 # a leg type written inline
            entry = inline_leg(entry, ctx, f"{fld}.leg")
    if not isinstance(entry, (str, LegSpec)):
        raise ctx.err("must be a leg name or a leg type's mapping", fld)
    spec = entry if isinstance(entry, LegSpec) else cat.find_leg(entry)
    if spec is None:
        raise ctx.err(f"unknown leg {shorten(entry)}{did_you_mean(entry, list(cat.legs))} "
                      "(not in the catalog's legs)", fld)
    return spec, axes, flag


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
    check_overrides_used(d, overrides, name)
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
    names, rules, bases, passive, specs = [], [], [], [], []
    for i, entry in enumerate(raw_legs):
        spec, axes, flag = leg_entry(entry, i, ctx, cat)
        if flag:
            passive.append(i)
        fld = f"legs[{i}]"
        r = spec.rules
        if axes:
            r = _override(r, axes, base, plat, ctx, f"{fld}.axes")
        names.append(spec.name)
        rules.append(r)
        bases.append(tuple(spec.basis))
        specs.append(spec)
    string, pms = pm_string(d, name, rules, ctx, passive)
    declared = sorted((r.string.text, i in passive) for i, r in enumerate(rules))
    if sorted((ls.text, k in pms.passive) for k, ls in enumerate(pms.legs)) != declared:
        legs_text = "+".join(r.string.text + ("/passive" if i in passive else "")
                             for i, r in enumerate(rules))
        raise ctx.err(f"the legs {legs_text} do not make {string}"
                      + (" (a passive leg is written LEG/passive in the string and "
                         "{leg: LEG, passive: true} in the legs)"
                         if passive or pms.passive else ""), "legs")
    if len(passive) == len(rules):
        raise ctx.err("every leg is passive: a PM needs at least one actuated leg", "legs")
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
                               limits=limits_from_mapping(d.get("limits"), ctx, legs, passive),
                               workload=workload_from_mapping(d.get("workload"), name, src,
                                                              units, dims),
                               default_pose=default, notes=tuple(notes), passive=tuple(passive),
                               definition=Definition(
                                   name, d, cat, dict(overrides), _build,
                                   definition_of(d, specs, dims if overrides else None)))
