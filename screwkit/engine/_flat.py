"""A model flattened to the arrays the kernels take (private).

:func:`flatten` turns a :class:`~screwkit.pm.PMModel` (or placed legs, :func:`flatten_legs`)
into a :class:`~screwkit.engine._arrays.FlatModel`: the model tuple ``M`` of
:mod:`screwkit.engine._kernels._layout` (joint kinds, axes, points, pitches, leg layout,
passive legs, Pa links, and each leg's row template encoded as tables of named points,
reference directions and member groups) and the pose parametrisation.  It is built once per
model object (cached, weakly) and never changes.  The kernels take these arrays as
arguments: a model with other dimensions is other arrays of the same types, never a
recompilation; :func:`reflatten` rebuilds only the geometric arrays of a model whose
dimensions changed (an optimiser's candidate), keeping the row templates decided at the
first model's home.
"""

from __future__ import annotations

import weakref
from dataclasses import replace

import numpy as np

from ..pm import LENGTH_PARAMS, PARAMS
from ._arrays import FlatModel, build, joint_arrays, platform_array
from ._line_table import line_table
from ._kernels import _layout as lay

__all__ = ["FlatModel", "flatten", "reflatten", "flatten_legs", "base_points_of"]


_FLAT: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def flatten(model) -> FlatModel:
    """The :class:`FlatModel` of a PM model (built once, cached with the model)."""
    f = _FLAT.get(model)
    if f is None:
        from ._templates import labels_of, templates_of
        templates = templates_of(model)
        f = build(model.home_legs, templates, L=float(model.normalisation.length),
                  centre=model.normalisation.centre, frame=model.frame,
                  platform_home=model.platform_home, base_points=model.world_base_points,
                  platform_points=model.platform_points, order=model.order,
                  independent=model.independent, home_pose=model.home_pose,
                  info=labels_of(templates), passive=tuple(getattr(model, "passive", ())))
        _FLAT[model] = f
    return f


def reflatten(like, model) -> FlatModel:
    """The arrays of ``model``, a model of the same legs as ``like`` with other dimensions
    (an optimiser's candidate): the same joints, pose parametrisation and row templates
    (decided at the home of ``like``), the geometry of ``model``.  Cheap: no leg is analysed
    again.  The result is cached for ``model`` (and ``like``'s row templates are taken for
    it), so that every engine call on ``model`` uses it.

    Raises
    ------
    ValueError
        When the legs differ (another number of joints).

    Examples
    --------
    >>> import screwkit
    >>> from screwkit.engine import reflatten
    >>> pm = screwkit.load_pm("3RRPRR")
    >>> cand = pm.with_dimensions({"l": 70})          # no file read, no leg analysed
    >>> _ = reflatten(pm, cand)
    >>> bool(screwkit.analyze(cand, {"alpha": [0.05], "beta": [0.02], "Zo": [80.0]}).ok[0])
    True
    """
    from ._templates import _TEMPLATES, templates_of
    flat = flatten(like)
    L = float(model.normalisation.length)
    sizes, m, geo = joint_arrays(model.home_legs, L)
    if m != flat.m or [int(s) for s in flat.M[lay.LEG][:, 0]] != sizes:
        raise ValueError(f"{model.name}: not the same legs as the flattened model")
    plat = platform_array(model.frame, model.platform_home, model.normalisation.centre, L)
    M = list(flat.M)
    for k, a in enumerate(geo):
        M[k] = np.ascontiguousarray(a)
    M[lay.PLAT] = plat
    M[lay.A] = np.array(model.world_base_points, float, order="C")      # (own copies: the
    M[lay.AP] = np.array(model.platform_points, float, order="C")       # model's are read-only)
    M[lay.REV] = line_table(model.home_legs, tuple(getattr(model, "passive", ())),
                            len(flat.unknown), flat.m, M[lay.QS], L)
    xs = np.array([L if p in LENGTH_PARAMS else 1.0 for p in flat.unknown])
    keep = [k for k, p in enumerate(flat.unknown) if p not in ("alpha", "gamma")]
    p6home = np.array([float(model.home_pose[p]) for p in PARAMS])
    Z = (flat.Z[0], xs, flat.Z[2], xs[keep].copy(), flat.Z[4], flat.Z[5], p6home) + flat.Z[7:]
    out = replace(flat, M=tuple(M), Z=Z, packed={})
    _FLAT[model] = out
    _TEMPLATES[model] = templates_of(like)
    return out


def flatten_legs(legs, templates, o, info, passive=(), frame=None) -> FlatModel:
    """Placed legs at one pose (the base frame ``frame = (R, p)`` in the world, default the
    world's; the platform frame the base frame's axes at ``o``) as a :class:`FlatModel` whose
    home is that pose (``passive``: the indices of the legs without an actuator)."""
    o = np.asarray(o, float)
    R, p = (np.eye(3), np.zeros(3)) if frame is None else frame
    return build(legs, templates, L=1.0, centre=o, frame=(R, p),
                 platform_home=(R, o), base_points=np.array([lg.A for lg in legs]),
                 platform_points=np.array([R.T @ (np.asarray(lg.a, float) - o)
                                           for lg in legs]),
                 order="XYZ", independent=tuple(PARAMS),
                 home_pose=dict(zip(PARAMS, [*(R.T @ (o - p)), 0.0, 0.0, 0.0])), info=info,
                 passive=tuple(passive))


def base_points_of(flat) -> np.ndarray:
    """The world base points ``A_i (n, 3)`` of a flattened model, read-only (one copy per
    model, not one per solution)."""
    A = flat.packed.get("A")
    if A is None:
        A = flat.packed["A"] = np.array(flat.M[lay.A], float)
        A.setflags(write=False)
    return A
