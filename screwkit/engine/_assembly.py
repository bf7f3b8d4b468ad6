"""Loading a PM for use: the model of :mod:`screwkit.pm` and the check that its default pose assembles.

:func:`screwkit.pm.load_pm` builds a :class:`~screwkit.pm.PMModel` without the
engine (the model layer never imports it).  The check that the definition's
default pose can be assembled needs the inverse displacement, so it is made
here, by :func:`check_default_pose`; :func:`load_assembled_pm` is the loader
that every path loading a PM for users goes through (:func:`screwkit.load_pm`,
:func:`screwkit.analyze`, trajectories, the Pinocchio checks, the CLI).
"""

from __future__ import annotations

import dataclasses

from ..errors import CatalogError, ScrewkitError
from ..pm import load_pm
from ._kinematics import solve_pose

__all__ = ["load_assembled_pm", "check_default_pose", "default_full_pose"]


def _default_is_home(model) -> bool:
    return not any(abs(model.default_pose[p] - model.home_pose[p]) > 0 for p in model.independent)


def check_default_pose(model):
    """``model``, after checking that its default pose can be assembled.

    The default pose is solved from the home assembly (unless it is the home
    pose); the notes of that solution are added to the model's ``notes`` as
    ``"default pose: ..."``.

    Raises
    ------
    CatalogError
        ``the default pose cannot be assembled: ...`` (field ``pose``).
    """
    if _default_is_home(model):
        return model
    try:
        sol = solve_pose(model, dict(model.default_pose))
    except ScrewkitError as exc:
        raise CatalogError(f"the default pose cannot be assembled: {exc}", model.name, "pose",
                           model.source) from None
    return dataclasses.replace(model, notes=model.notes + tuple(f"default pose: {t}" for t in sol.notes))


def load_assembled_pm(name_or_path: str, overrides: dict | None = None, catalog=None):
    """:func:`screwkit.pm.load_pm` followed by :func:`check_default_pose`."""
    return check_default_pose(load_pm(name_or_path, overrides, catalog))


def default_full_pose(model) -> dict:
    """All six pose parameters (radians) at the model's default independent values: the
    home pose when they are the home values, else the inverse displacement from home."""
    if _default_is_home(model):
        return dict(model.home_pose)
    return dict(solve_pose(model, dict(model.default_pose)).params)
