"""Every problem of one PM definition, field by field (private, for ``screwkit model check``).

:func:`screwkit.pm.load_pm` stops at the first problem of a definition, which is what a
loader must do.  :func:`pm_problems` checks each field of the definition on its own with
the loader's very checks (so the two cannot disagree), collecting every
:class:`~screwkit.errors.CatalogError`: unknown keys (all of them), text fields, missing
fields, the dimensions, the base and the platform, each leg entry, the PM string, the pose
parametrisation, the units, the workload, and in the ``dynamics:`` block its units, gravity,
platform, each leg's links and friction and each leg's stiffness.  A field that depends on
another one that failed is left out (its problem would only repeat the first).  When the
fields are all sound, the PM is built as a whole (the home assembly, the limits) and the
first problem of that is the last one reported.
"""

from __future__ import annotations

import re

from ..errors import CatalogError, InputError, ScrewkitError

__all__ = ["pm_problems"]

#: The fields the home assembly (and so the dynamics: block's check) depends on.
_GEOMETRY = ("dimensions", "base", "platform", "legs", "string", "independent", "dof", "pose",
             "home", "guess", "centre", "euler", "units")


def pm_problems(name: str, d, cat, build) -> list:
    """The problems of the PM ``name`` defined by ``d`` in catalog ``cat`` (list of
    :class:`CatalogError`), ``build()`` loading it whole once its fields are sound."""
    from ..legs._guards import did_you_mean, shorten
    from ._checks import dimensions, pm_string, text_fields, unused_dimensions
    from ._loader import _PM_KEYS, _Ctx, _override, _pose_values, _vertices
    from ._model import PARAMS

    src = cat.source
    out = []

    def attempt(fn, *args):
        try:
            return True, fn(*args)
        except CatalogError as exc:
            out.append(exc)
        except InputError as exc:            # a value given outside a field's checks
            out.append(CatalogError(str(exc), name, None, src))
        return False, None

    if not isinstance(d, dict):
        return [CatalogError("must be a mapping", name, None, src)]
    for k in d:
        if k not in _PM_KEYS:
            where = k if isinstance(k, str) else None
            out.append(CatalogError(f"unknown field {shorten(k, 40)}"
                                    f"{did_you_mean(k, _PM_KEYS)}; known: "
                                    f"{', '.join(sorted(_PM_KEYS))}", name, where, src))
    for k in ("string", "summary", "note", "motion", "euler", "source"):
        attempt(text_fields, {k: d.get(k)}, (k,), name, src)
    for req in ("base", "platform", "legs", "independent", "dof"):
        if req not in d:
            out.append(CatalogError(f"missing required field {req!r}", name, req, src))
    raw = d.get("dimensions") or {}
    ok, dims = attempt(_dims, raw, name, src, dimensions)
    if not ok:                                # go on with the names: no follow-on errors
        dims = {k: 1.0 for k in (raw if isinstance(raw, dict) else {})
                if isinstance(k, str) and k.isidentifier()}
    ctx = _Ctx(name, src, dims)
    if ok:
        for k in unused_dimensions(d):
            out.append(CatalogError(f"dimension {k} is declared but no expression of the PM "
                                    "uses it, so it changes nothing: use it, or remove it",
                                    name, f"dimensions.{k}", src))
    verts = {}
    for part in ("base", "platform"):
        if part in d:
            good, v = attempt(_vertices, d[part], ctx, part)
            if good:
                verts[part] = v
    got = _legs(d, ctx, cat, verts, attempt, _override)
    if got is not None and not any(e.field == "string" for e in out):
        attempt(pm_string, d, name, got[0], ctx, got[1])
    ind = d.get("independent")
    good_ind = isinstance(ind, list) and ind and all(isinstance(p, str) and p in PARAMS
                                                     for p in ind) and len(set(ind)) == len(ind)
    if "independent" in d and not good_ind:
        out.append(ctx.err(f"must be a list of distinct names among {', '.join(PARAMS)}",
                           "independent"))
    dof = d.get("dof")
    if "dof" in d and not (isinstance(dof, int) and not isinstance(dof, bool) and 1 <= dof <= 6):
        out.append(ctx.err("must be an integer from 1 to 6", "dof"))
    elif good_ind and isinstance(dof, int) and dof != len(ind):
        out.append(ctx.err(f"dof {dof} but {len(ind)} independent pose parameters",
                           "independent"))
    if good_ind:
        dep = tuple(p for p in PARAMS if p not in ind)
        for fld, names in (("pose", tuple(ind)), ("home", tuple(ind)), ("guess", dep)):
            attempt(_pose_values, d.get(fld), ctx, fld, names)
    if d.get("centre") is not None:
        attempt(ctx.vec, d["centre"], "centre")
    order = d.get("euler", "XYX")
    attempt(_euler, order, ctx)
    units = _units(d, name, src, attempt)
    if units is not None:
        from ._workload import workload_from_mapping
        attempt(workload_from_mapping, d.get("workload"), name, src, units, dims)
    if out:
        geometry = [e for e in out if e.field is None or
                    re.split(r"[.\[]", e.field)[0] in _GEOMETRY]
        if not geometry and units is not None and d.get("dynamics") is not None:
            bare = {k: v for k, v in d.items() if k in _PM_KEYS and k not in
                    ("workload", "limits")}
            out += _dynamics_problems(bare, name, src, cat)
        return out
    try:                                      # the fields are sound: the PM as a whole
        build()
    except CatalogError as exc:
        if exc.field == "dynamics" or (exc.field or "").startswith("dynamics."):
            return _dynamics_problems(d, name, src, cat) or [exc]
        out.append(exc)
    except ScrewkitError as exc:
        out.append(CatalogError(str(exc), name, None, src))
    return out


def _dims(raw, name, src, dimensions):
    if not isinstance(raw, dict):
        raise CatalogError("must be a mapping name -> length", name, "dimensions", src)
    return dimensions(raw, {}, name, src)


def _euler(order, ctx):
    from ..screws import check_order
    try:
        check_order(order)
    except InputError as exc:
        raise ctx.err(str(exc), "euler") from None


def _units(d, name, src, attempt):
    from ._units import units_from_mapping
    ok, units = attempt(units_from_mapping, d.get("units"), name, src)
    return units if ok else None


def _legs(d, ctx, cat, verts, attempt, override):
    """Each leg entry on its own; ``(rules, passive)`` when every entry is sound, else None."""
    from ._loader import leg_entry
    raw = d.get("legs")
    if raw is None:
        return None
    if not isinstance(raw, list) or not raw:
        attempt(_raise, ctx.err("must be a list with one leg per vertex", "legs"))
        return None
    rules, passive, good = [], [], True
    for i, entry in enumerate(raw):
        fld = f"legs[{i}]"
        ok, got = attempt(leg_entry, entry, i, ctx, cat)
        if not ok:
            good = False
            continue
        spec, axes, flag = got
        if flag:
            passive.append(i)
        r = spec.rules
        if axes and len(verts) == 2:
            ok, r = attempt(override, spec.rules, axes, verts["base"], verts["platform"], ctx,
                            f"{fld}.axes")
            good &= ok
        rules.append(r)
    n = [len(v) for v in verts.values()]
    if len(verts) == 2 and not (len(raw) == n[0] == n[1]):
        attempt(_raise, ctx.err(f"{len(raw)} legs for {n[0]} base and {n[1]} platform "
                                "vertices", "legs"))
    return (rules, passive) if good else None


def _raise(exc):
    raise exc


def _dynamics_problems(d, name, src, cat) -> list:
    """Every problem of the ``dynamics:`` block of a PM whose other fields are sound: the
    block's parts read one by one against the PM built without it."""
    import numpy as np

    from ._inertia import LegStiffness
    from ._loader import _build
    from ._physical import (_BLOCK_KEYS, _Reader, _factors, _leg, _per_leg, _platform,
                            _stiffness)
    raw = d.get("dynamics")
    try:
        model = _build(name, {k: v for k, v in d.items() if k != "dynamics"}, cat, {})
    except ScrewkitError:
        return []
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    legs = tuple(lg.moved(R0.T, -R0.T @ p0) for lg in model.home_legs)
    r = _Reader(name, src, model.dimensions, (1.0, 1.0, 1.0))
    out = []

    def attempt(fn, *args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except CatalogError as exc:
            out.append(exc)
        except InputError as exc:
            out.append(r.err(str(exc), ""))
        return None

    if attempt(r.mapping, raw, "", _BLOCK_KEYS) is None:
        return out
    units = model.units
    if not units.declared and raw.get("units") != "model":
        return [r.err("the model declares no units: declare them (units: {length: .., force: "
                      "..}) or write the block in the model's consistent units with 'units: "
                      "model'", "units")]
    got = attempt(_factors, raw.get("units"), units, r)
    if got is None:
        return out
    r.f = got[0]
    r.problems = out                          # a bad number is recorded, the rest read on
    if raw.get("gravity") is not None:
        attempt(r.vec, raw["gravity"], "gravity", length=1, time=-2)
    attempt(_platform, raw.get("platform"), r)
    n = len(legs)
    per = attempt(_per_leg, raw.get("stiffness"), "stiffness", r, n) or []
    for (v, f), lg in zip(per, legs):
        attempt(_stiffness, v, f, r, lg)
    per = attempt(_per_leg, raw.get("legs"), "legs", r, n) or []
    for (v, f), lg in zip(per, legs):
        attempt(_leg, v, f, r, lg, LegStiffness())
    return out
