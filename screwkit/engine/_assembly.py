"""Loading a PM for use: the model of :mod:`screwkit.pm` and the check that its default pose
assembles; the one-pose and list-of-poses conveniences of the inverse displacement.

:func:`screwkit.pm.load_pm` builds a :class:`~screwkit.pm.PMModel` without the
engine (the model layer never imports it).  The check that the definition's
default pose can be assembled needs the inverse displacement, so it is made
here, by :func:`check_default_pose`; :func:`load_assembled_pm` is the loader
that every path loading a PM for users goes through.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import CatalogError, InputError, ScrewkitError, UnreachablePoseError
from ..legs._guards import real
from ..pm import PARAMS, PMModel, load_pm
from ._analysis import analyze
from ._solution import solve
from ._inputs import check_forwarded

__all__ = ["load_assembled_pm", "check_default_pose", "default_full_pose", "solve_pose",
           "solve_path", "analyze_pm"]


def _default_is_home(model) -> bool:
    return not any(abs(model.default_pose[p] - model.home_pose[p]) > 0 for p in model.independent)


def check_default_pose(model, check_motion: bool = True):
    """``model``, after checking that its default pose can be assembled.

    The default pose is solved from the home assembly (unless it is the home pose); the
    notes of that solution are added to the model's ``notes`` as ``"default pose: ..."``.

    With ``check_motion``, its finite motion type is computed from motions sampled from
    home (:func:`~screwkit.engine.finite_motion`) and checked against what the model
    declares (its ``motion`` and the translations and angles among its ``independent``
    parameters).

    Raises
    ------
    CatalogError
        ``the default pose cannot be assembled: ...`` (field ``pose``); the declared
        motion is not the computed one (field ``motion`` or ``independent``, naming both).
    """
    from ._motion import check_declared_motion

    fm = check_declared_motion(model) if check_motion else None
    if _default_is_home(model):
        return model
    notes = _default_pose_notes(model)
    out = dataclasses.replace(model, notes=model.notes + tuple(f"default pose: {t}"
                                                               for t in notes))
    _share_engine(model, out)
    if fm is not None:
        from ..pm import register_finite_motion
        register_finite_motion(out, fm)
    return out


def _default_pose_notes(model) -> tuple:
    """The notes of the default pose's solution, or the CatalogError saying why it cannot
    be assembled: solved, or read where this model's verdict is kept on disk (a model file
    checked again computes nothing, :mod:`._motion_cache`)."""
    from . import _motion_cache
    digest, kept = _motion_cache.load_record(model, ("default pose",))
    if not (kept and (isinstance(kept.get("error"), str) or (
            isinstance(kept.get("notes"), list) and "error" not in kept))):
        try:
            kept = {"notes": [str(t) for t in solve_pose(model, dict(model.default_pose)).notes]}
        except ScrewkitError as exc:
            kept = {"error": str(exc)}
        _motion_cache.store_record(digest, kept)
    if isinstance(kept.get("error"), str):
        raise CatalogError(f"the default pose cannot be assembled: {kept['error']}", model.name,
                           "pose", model.source) from None
    return tuple(str(t) for t in kept.get("notes", ()))


def _share_engine(model, out) -> None:
    """``out``, ``model`` with other notes, takes ``model``'s row templates, flattened
    arrays, chains and home predictor (made from the geometry alone) instead of deciding
    and fitting them again on its first computation."""
    from ._chains import _CACHE
    from ._flat import _FLAT
    from ._templates import _TEMPLATES
    for table in (_TEMPLATES, _FLAT, _CACHE):
        hit = table.get(model)
        if hit is not None:
            table.setdefault(out, hit)


def load_assembled_pm(name_or_path, overrides=None, catalog=None):
    """:func:`screwkit.pm.load_pm` followed by :func:`check_default_pose`; a model given
    as it is, or with ``overrides`` its :meth:`~screwkit.pm.PMModel.with_dimensions` (never
    the overrides left unused)."""
    if isinstance(name_or_path, PMModel):
        if not overrides:
            return name_or_path
        if not isinstance(overrides, dict):
            from ..errors import InputError
            raise InputError(f"overrides must be a mapping of dimensions to values, got "
                             f"{overrides!r:.60}")
        return check_default_pose(name_or_path.with_dimensions(dict(overrides)))
    return check_default_pose(load_pm(name_or_path, overrides, catalog))


def default_full_pose(model) -> dict:
    """All six pose parameters (radians) at the model's default independent values."""
    if _default_is_home(model):
        return dict(model.home_pose)
    return dict(solve_pose(model, dict(model.default_pose)).params)


def solve_pose(model, independent=None, guess=None, degrees: bool = False):
    """Inverse displacement at one pose (numbers) or N poses (arrays): :func:`solve`;
    raises :class:`UnreachablePoseError` for an unreachable single pose."""
    return solve(model, independent, guess, degrees)


def solve_path(model, poses, guess=None, degrees: bool = False) -> tuple:
    """Solve a list of independent-parameter mappings as successive samples of a path
    (each warm-started from its neighbours); one :class:`PoseSolution` per sample.

    Raises
    ------
    InputError
        No samples, a sample that is not a mapping, an unknown or a missing parameter.
    UnreachablePoseError
        ``path sample k: ...`` for the first unreachable sample.
    """
    poses = list(poses)
    if not poses:
        # (as solve and analyze refuse empty arrays: an empty path is a mistake upstream)
        raise InputError(f"{model.name}: no path samples given (an empty sequence)")
    for k, p in enumerate(poses):
        if not isinstance(p, dict):
            raise InputError(f"{model.name}: path sample {k} must be a mapping of the "
                             f"independent pose parameters, got {type(p).__name__}")
    keys = set().union(*poses)
    arrays = {}
    for name in keys:
        if name not in PARAMS:
            raise InputError(f"{model.name}: unknown pose parameter {name!r} (one of "
                             f"{', '.join(PARAMS)})")
        values = []
        for k, p in enumerate(poses):
            if name not in p:
                raise InputError(f"{model.name}: path sample {k} has no {name}")
            values.append(real(p[name], f"{model.name}: path sample {k}: {name}"))
        arrays[name] = np.array(values)
    sol = solve(model, arrays, guess, degrees, path=True, single=False)
    bad = ~sol.reachable_mask
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        try:
            solve(model, {n: v[k] for n, v in arrays.items()}, degrees=degrees)
        except UnreachablePoseError as exc:
            raise UnreachablePoseError(f"path sample {k}: {exc}", residual=exc.residual) from None
        raise UnreachablePoseError(f"path sample {k}: unreachable from its neighbours",
                                   residual=float(sol.residual[k]))
    return tuple(sol[i] for i in range(len(sol)))


def analyze_pm(pm, pose=None, *, force=None, torque=None,
               overrides: dict | None = None, degrees: bool = False, guess=None,
               raise_on_singular: bool = True, catalog=None, **kwargs):
    """:func:`analyze` of a PM given by name, YAML path or model (see :func:`screwkit.analyze`)."""
    if kwargs:
        check_forwarded("screwkit.analyze", analyze, kwargs,
                        ("force", "torque", "overrides", "degrees", "guess",
                         "raise_on_singular", "catalog"))
    model = load_assembled_pm(pm, overrides, catalog)
    return analyze(model, pose, force=force, torque=torque, degrees=degrees, guess=guess,
                   raise_on_singular=raise_on_singular, **kwargs)
