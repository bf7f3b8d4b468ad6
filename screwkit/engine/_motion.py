"""The finite motion type of a model: motions sampled from home, solved, classified.

:func:`finite_motion` solves a fixed set of poses around home (:func:`sample_poses`) in one
batch and hands the rotations, positions and pose parameters to
:func:`screwkit.pm.classify_finite_motion`.  :func:`check_declared_motion` compares the
result with what the model declares (``motion``, ``independent``): a mismatch is a
:class:`~screwkit.errors.CatalogError` that names both.  Results are cached per model
object and per model *content* (the home legs, the parametrisation), so a model loaded
again costs nothing; across processes, in a file keyed by a digest of the whole model and of
the code that computes it (:mod:`screwkit.engine._motion_cache`).
"""

from __future__ import annotations

import re
import weakref
from collections import OrderedDict

import numpy as np

from ..errors import CatalogError
from ..pm import FiniteMotion, classify_finite_motion, register_finite_motion, rotation_vectors

__all__ = ["finite_motion", "check_declared_motion", "sample_poses", "AMPLITUDE_DEG",
           "AMPLITUDE_LENGTH", "STEP"]

#: Sample amplitudes: angles (degrees) and lengths (fraction of the characteristic length).
AMPLITUDE_DEG = 5.0
AMPLITUDE_LENGTH = 0.05
#: Central-difference step of the rotation derivative (radians, or times the length).
STEP = 1e-3

_ANGLES = ("alpha", "beta", "gamma")
_BY_MODEL: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_BY_CONTENT: OrderedDict = OrderedDict()
_MAX_CONTENT = 256


def sample_poses(model) -> tuple:
    """``(poses, n_samples, bases)``: the independent parameters ``{name: (M,)}`` to solve
    (radians, lengths): home, two base poses, the ends of every parameter's range and two
    corners (the ``n_samples`` samples whose invariants are checked), then ``+-STEP`` along
    each parameter at home and at the two base poses (``bases``: their indices)."""
    ind = tuple(model.independent)
    L = float(model.normalisation.length)
    home = np.array([model.home_pose[p] for p in ind], float)
    amp = np.array([np.radians(AMPLITUDE_DEG) if p in _ANGLES else AMPLITUDE_LENGTH * L
                    for p in ind])
    step = np.array([STEP if p in _ANGLES else STEP * L for p in ind])
    d = len(ind)
    s1 = np.array([(-1.0) ** k for k in range(d)])
    s2 = np.array([1.0 if k % 3 == 0 else -1.0 for k in range(d)])
    rows = [home, home + 0.6 * amp * s1, home + 0.6 * amp * s2]
    for k in range(d):
        e = np.zeros(d)
        e[k] = 1.0
        rows += [home + amp * e, home - amp * e]
    rows += [home + amp * s1, home + amp * s2]
    n_samples = len(rows)
    for b in range(3):
        for k in range(d):
            e = np.zeros(d)
            e[k] = step[k]
            rows += [rows[b] + e, rows[b] - e]
    X = np.array(rows).reshape(-1, d)
    return {p: X[:, k] for k, p in enumerate(ind)}, n_samples, (0, 1, 2)


def _content_key(model) -> tuple:
    legs = tuple((tuple(np.round(np.asarray(lg.twists, float), 9).ravel()),
                  lg.string.marked) for lg in model.home_legs)
    R0, p0 = model.frame
    return (legs, tuple(model.independent), tuple(model.dependent), model.order,
            tuple(np.round(np.asarray(R0, float), 12).ravel()),
            tuple(np.round(np.asarray(p0, float), 9)), float(model.normalisation.length),
            tuple(sorted((k, round(float(v), 12)) for k, v in model.home_pose.items())))


def finite_motion(model) -> FiniteMotion:
    """The finite motion type of ``model`` (see the module docstring), cached."""
    hit = _BY_MODEL.get(model)
    if hit is not None:
        return hit
    key = _content_key(model)
    hit = _BY_CONTENT.get(key)
    if hit is None:
        from . import _motion_cache
        from ..pm import _finite
        constants = (AMPLITUDE_DEG, AMPLITUDE_LENGTH, STEP, _finite.FINITE_RTOL,
                     _finite.RANK_FD_RTOL)
        digest, hit = _motion_cache.load(model, constants)
        if hit is None:
            hit = _compute(model)
            _motion_cache.store(digest, hit)
        _BY_CONTENT[key] = hit
        while len(_BY_CONTENT) > _MAX_CONTENT:
            _BY_CONTENT.popitem(last=False)
    _BY_MODEL[model] = hit
    register_finite_motion(model, hit)
    return hit


def _compute(model) -> FiniteMotion:
    from ._solution import solve

    ind = tuple(model.independent)
    poses, n, bases = sample_poses(model)
    sol = solve(model, poses, guess=dict(model.home_pose))
    ok = np.asarray(sol.success, bool)
    R = np.asarray(sol.rotation, float)
    o = np.asarray(sol.position, float)
    L = float(model.normalisation.length)
    d = len(ind)
    scale = np.array([1.0 if p in _ANGLES else L for p in ind])
    jac = []
    for b in bases:
        cols = []
        rows = [n + 2 * (b * d + k) for k in range(d)]
        if not ok[b] or not all(ok[i] and ok[i + 1] for i in rows):
            if b == 0:
                break                   # home's neighbours not assembled: counted at home
            continue
        for k, i in enumerate(rows):
            rp = rotation_vectors(R[i] @ R[b].T)[0]
            rm = rotation_vectors(R[i + 1] @ R[b].T)[0]
            cols.append((rp - rm) / (2 * STEP))      # per radian, or per L
        jac.append(np.array(cols).T.reshape(3, d))
    keep = np.flatnonzero(ok[:n])
    params = sol.params
    dep = {p: np.asarray(params[p], float)[keep] for p in model.dependent}
    from ..screws import is_singular
    singular = (is_singular(model.order, model.home_pose["beta"])
                and {"alpha", "gamma"} <= set(ind))
    counts = None
    if not jac:
        # the poses next to home are not assembled (e.g. dependent Euler angles at their
        # representation singularity there): the counts of the twist space at home
        from ..pm import mobility_of_legs
        mob = mobility_of_legs(model.home_legs)
        counts = (int(mob.translations), int(mob.rotations))
    return classify_finite_motion(ind, np.array(jac).reshape(-1, 3, d), R[keep], o[keep], dep, L,
                                  singular, counts)


def _counts(label: str):
    """``(translations, rotations)`` of a label ``"1T2R"`` / ``"2R1T"`` / ``"3T"``, or None;
    a helical freedom counts as a rotation (``"2T1H(p=20)"``, ``"2T1H"``: its pitch is not
    compared)."""
    text = label.strip().upper().replace("-", "").replace(" ", "")
    text = re.sub(r"(\d)H(\(P=[^)]*\))?", r"\1R", text)
    m = re.fullmatch(r"(?:(\d)T)?(?:(\d)R)?|(?:(\d)R)?(?:(\d)T)?", text)
    if not text or m is None:
        return None
    t = m.group(1) or m.group(4) or 0
    r = m.group(2) or m.group(3) or 0
    return int(t), int(r)


def check_declared_motion(model) -> FiniteMotion:
    """The finite motion of ``model``, after checking it against the declared ``motion``
    and the declared ``independent`` parameters (their translations and angles).

    Raises
    ------
    CatalogError
        Field ``motion`` (or ``independent``): what the model declares and what its
        finite motion is, both named.
    """
    fm = finite_motion(model)
    got = (fm.translations, fm.rotations)
    t, r = fm.declared(model.independent)
    if (t, r) != got:
        raise CatalogError(
            f"the independent parameters {', '.join(model.independent)} declare "
            f"{t} translation(s) and {r} rotation(s), but the finite motion computed from "
            f"home is {fm.label} ({fm.text})", model.name, "independent", model.source)
    stated = str(getattr(model, "motion", "") or "")
    if stated:
        counts = _counts(stated)
        if counts != got:
            raise CatalogError(f"the model declares motion {stated}, but the finite motion "
                               f"computed from home is {fm.label} ({fm.text})", model.name,
                               "motion", model.source)
    return fm
