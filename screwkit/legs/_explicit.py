"""A leg from explicit joints: kind, axis direction, a point on the axis, pitch (no rules).

Examples
--------
An R-P-S leg (the S written as three R joints through one point):

>>> from screwkit.legs import leg_from_joints
>>> A, a = [100, 0, 0], [50, 0, 80]
>>> leg = leg_from_joints([("R", [0, 1, 0], A), ("P", [-50, 0, 80], A),
...                        ("R", [1, 0, 0], a), ("R", [0, 1, 0], a), ("R", [0, 0, 1], a)],
...                       actuated=1)
>>> leg.string.marked, leg.analyze().summary()
('R_PRRR', '1 force')
>>> leg.analyze().constraints[0].describe()
'force along (0, 1, 0) through a'
"""

from __future__ import annotations

import math

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..screws import as_vector3
from ._chain import Joint, Leg
from ._guards import MAX_MAGNITUDE
from ._parsing import parse_leg

__all__ = ["leg_from_joints", "MAX_JOINTS"]

#: Most joints a leg may have (a bound on what a user sizes).
MAX_JOINTS = 32
_KEYS = {"kind", "axis", "point", "pitch", "bar"}


def _joint_entry(k, entry):
    where = f"joints[{k}]"
    if isinstance(entry, dict):
        bad = set(entry) - _KEYS
        if bad:
            raise InputError(f"{where}: unknown key(s) {sorted(bad)} (expected kind, axis, "
                             "point, pitch, bar)")
        try:
            kind, axis = entry["kind"], entry["axis"]
        except KeyError as exc:
            raise InputError(f"{where}: missing {exc.args[0]!r}") from None
        point, pitch = entry.get("point"), entry.get("pitch", None if kind == "H" else 0.0)
        if kind == "Pa":
            if "pitch" in entry:
                raise InputError(f"{where}: only an H joint has a pitch")
            pitch = entry.get("bar")
    elif isinstance(entry, (list, tuple)) and 2 <= len(entry) <= 4:
        kind, axis = entry[0], entry[1]
        point = entry[2] if len(entry) > 2 else None
        pitch = entry[3] if len(entry) > 3 else (None if kind == "H" else 0.0)
    else:
        raise InputError(f"{where}: a joint is (kind, axis, point[, pitch]) or a mapping with "
                         "kind, axis, point, pitch")
    if kind not in ("R", "P", "H", "Pa"):
        raise InputError(f"{where}: kind must be 'R', 'P', 'H' or 'Pa' (a spherical or "
                         "universal joint is three or two R joints through one point), got "
                         f"{kind!r}")
    if kind == "Pa":
        # axis: the hinge direction; point: a point of the first hinge; 4th item: the bar
        if point is None or pitch is None or isinstance(pitch, (int, float)):
            raise InputError(f"{where}: a Pa is ('Pa', hinge axis, point of the first hinge, "
                             "bar vector) or a mapping with kind, axis, point, bar")
        return kind, axis, point, pitch
    if point is None:
        if kind != "P":
            raise InputError(f"{where}: an {kind} joint needs a point on its axis")
        point = (0.0, 0.0, 0.0)
    if kind == "H" and pitch is None:
        raise InputError(f"{where}: an H joint needs its pitch (length per radian; an H of "
                         "pitch 0 is an R joint)")
    if isinstance(pitch, bool) or not isinstance(pitch, (int, float)) or not math.isfinite(pitch):
        raise InputError(f"{where}: pitch must be a finite number, got {pitch!r}")
    if kind != "H" and pitch != 0:
        raise InputError(f"{where}: only an H joint has a pitch")
    return kind, axis, point, float(pitch)


def leg_from_joints(joints: Sequence[Sequence[Any] | Mapping[str, Any]], A: ArrayLike | None = None,
                    a: ArrayLike | None = None, *, actuated: int = 0, name: str = "") -> Leg:
    """A placed leg from its equivalent 1-DOF joints, base to platform.

    Parameters
    ----------
    joints : sequence
        Each joint as ``(kind, axis, point[, pitch])`` or a mapping with those keys:
        ``kind`` ``"R"``, ``"P"``, ``"H"`` or ``"Pa"``; ``axis`` a direction (normalised here);
        ``point`` a point of the axis (world, model lengths; for P only a drawing
        reference, default the origin); ``pitch`` the lead per radian of an H joint
        (length per radian; required for an H).  A parallelogram is ``("Pa", hinge, point, bar)`` (or a
        mapping with ``bar``): the direction of its four parallel hinges, a point of the
        first hinge axis and the bar vector from the first hinge axis to the second
        (normal to the hinges); its equivalent joint is the translation ``hinge x bar``.
    A, a : array_like (3,), optional
        Base and platform attachment points; default the first and the last joint's point.
    actuated : int
        Index of the actuated joint (0-based).
    name : str
        Default: the string of kinds, e.g. ``"RR_PRR"``.

    Returns
    -------
    Leg
        With the string of kinds (``"R_PR"``), analysable like any leg
        (:meth:`Leg.analyze`, :func:`screwkit.engine.unified_jacobian`).

    Raises
    ------
    InputError
        Naming the joint and field at fault.
    """
    try:
        entries = list(joints)
    except TypeError:
        raise InputError("joints must be a sequence of (kind, axis, point[, pitch])") from None
    if not entries:
        raise InputError("a leg needs at least one joint")
    if len(entries) > MAX_JOINTS:
        raise InputError(f"a leg has at most {MAX_JOINTS} joints, got {len(entries)}")
    parsed = [_joint_entry(k, e) for k, e in enumerate(entries)]
    if isinstance(actuated, bool) or not isinstance(actuated, (int, np.integer)) or \
            not 0 <= actuated < len(parsed):
        raise InputError(f"actuated must be a joint index from 0 to {len(parsed) - 1}, "
                         f"got {actuated!r}")
    # the string carries each H's pitch (H(20)), as a leg type's does: a model written from
    # this leg (PMBuilder) reads its pitches there
    kinds = [f"H({float(p[3])!r})" if p[0] == "H" else p[0] for p in parsed]
    ls = parse_leg("".join(kinds[:actuated]) + "_" + "".join(kinds[actuated:]))
    out = []
    for k, ((kind, axis, point, pitch), spec) in enumerate(zip(parsed, ls.equivalent)):
        try:
            if kind == "Pa":
                hinge = np.asarray(axis, float)
                bar = as_vector3(pitch, "bar", MAX_MAGNITUDE)
                if abs(float(hinge @ bar)) > 1e-9 * np.linalg.norm(hinge) * np.linalg.norm(bar):
                    raise InputError("the bar of a parallelogram is normal to its hinges")
                out.append(Joint(spec, np.cross(hinge, bar), point, 0.0, bar))
                continue
            out.append(Joint(spec, axis, point, pitch))
        except Exception as exc:          # GeometryError / InputError from the value checks
            raise InputError(f"joints[{k}]: {exc}") from None
    A_ = out[0].point if A is None else as_vector3(A, "A", MAX_MAGNITUDE)
    a_ = out[-1].point if a is None else as_vector3(a, "a", MAX_MAGNITUDE)
    return Leg(ls, tuple(out), A_, a_, name or ls.marked)
