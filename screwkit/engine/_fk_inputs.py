"""The actuator values a forward kinematics is asked for (private): arrays or ``q<i>`` /
``r<i>`` mappings, and which legs' extensions are their actuators' values."""

from __future__ import annotations

import numpy as np

__all__ = ["actuator_targets", "extension_offset"]


def actuator_targets(model, actuators, degrees=False):
    """The actuated joint values ``(N, n)`` (displacements from home) of ``actuators``:
    an array ``(n,)`` / ``(N, n)``, or a mapping ``q<i>`` (the joint value) / ``r<i>`` (the
    extension ``|a_i - A_i|`` of a leg whose actuator is a P joint on the line ``A_i a_i``)
    -> number or array.  Only the actuated legs have an actuator (``model.active``): the
    array's columns are theirs in leg order, and ``q<i>`` / ``r<i>`` name leg ``i``
    (1-based).  Returns ``(values (N, n_active), single)``."""
    from ..errors import InputError
    from ..legs._guards import flag
    degrees = flag(degrees, "degrees")
    active = tuple(model.active)
    n = len(active)
    names = [f"q{i + 1}" for i in active]
    rot = np.array([model.home_legs[i].actuated_joint.kind != "P" for i in active], bool)
    if isinstance(actuators, dict):
        cols, N, single = {}, None, True
        for k, v in actuators.items():
            name = str(k)
            if len(name) < 2 or name[0] not in "qr" or not name[1:].isdigit() or \
                    int(name[1:]) - 1 not in active:
                passive = [f"{i + 1}" for i in model.passive]
                raise InputError(f"{model.name}: actuator {name!r}: use "
                                 f"{', '.join(names)} (actuated joint values from home) or "
                                 f"{', '.join('r' + x[1:] for x in names)} (leg extensions)"
                                 + (f"; leg{'s' * (len(passive) > 1)} {', '.join(passive)} "
                                    "passive (no actuator)" if passive else ""))
            try:
                a = np.asarray(v, float)
                if np.asarray(v).dtype.kind == "b":
                    raise TypeError
            except (TypeError, ValueError):
                raise InputError(f"{model.name}: actuator {name} must be numbers, got "
                                 f"{v!r:.40}") from None
            if a.ndim > 1 or not np.all(np.isfinite(a)):
                raise InputError(f"{model.name}: actuator {name} must be finite numbers")
            single &= a.ndim == 0
            leg = int(name[1:]) - 1
            i = active.index(leg)
            if i in cols:
                raise InputError(f"{model.name}: leg {leg + 1}'s actuator is given twice")
            _check_bounds(model, name, a, rot[i] and name[0] == "q", degrees)
            if name[0] == "r":
                r0 = extension_offset(model, leg)
                a = a - r0
            elif degrees and rot[i]:
                a = np.radians(a)
            cols[i] = a
        missing = [names[i] for i in range(n) if i not in cols]
        if missing:
            raise InputError(f"{model.name}: no value for {', '.join(missing)} (one per "
                             "actuated leg)")
        shapes = {np.shape(v) for v in cols.values() if np.ndim(v)}
        if len(shapes) > 1:
            raise InputError(f"{model.name}: the actuator arrays have different lengths")
        N = shapes.pop()[0] if shapes else 1
        out = np.stack([np.broadcast_to(cols[i], (N,)) for i in range(n)], axis=1)
        return out.astype(float), single
    try:
        a = np.asarray(actuators, float)
        if np.asarray(actuators).dtype.kind == "b":     # (True is not a joint value)
            raise TypeError
    except (TypeError, ValueError):
        raise InputError(f"{model.name}: the actuator values must be numbers (an array (n,) or "
                         f"(N, n), or a mapping q1.. / r1..), got {actuators!r:.40}") from None
    if a.shape[-1:] != (n,) or a.ndim > 2 or not np.all(np.isfinite(a)):
        raise InputError(f"{model.name}: give {n} finite actuated joint values (one per "
                         f"actuated leg: {', '.join(names)}), shape (n,) or (N, n); got shape "
                         f"{a.shape}")
    single = a.ndim == 1
    a = np.atleast_2d(a).copy()
    for i in range(n):
        _check_bounds(model, names[i], a[:, i], bool(rot[i]), degrees)
    if degrees:
        a[:, rot] = np.radians(a[:, rot])
    return a, single


def _check_bounds(model, name, a, rotary, degrees):
    """Refuse values no mechanism can take, naming the actuator: an extension ``r<i>`` must
    be positive; lengths at most ``MAX_LENGTH_FACTOR`` model sizes, angles ten turns."""
    from ..errors import InputError
    from ..legs._guards import MAX_ANGLE_DEG, MAX_LENGTH_FACTOR
    a = np.asarray(a, float)
    big = float(np.max(np.abs(a), initial=0.0))
    if rotary:
        limit = MAX_ANGLE_DEG if degrees else np.radians(MAX_ANGLE_DEG)
        if big > limit:
            raise InputError(f"{model.name}: actuator {name} = {big:g} "
                             f"{'deg' if degrees else 'rad'} is beyond the limit +-{limit:g} "
                             "(ten turns)")
        return
    size = float(model.normalisation.length)
    if big > MAX_LENGTH_FACTOR * size:
        raise InputError(f"{model.name}: actuator {name} = {big:g} {model.units.length} is "
                         f"beyond the limit +-{MAX_LENGTH_FACTOR * size:g} "
                         f"({MAX_LENGTH_FACTOR:g} times the model's size)")
    if name[0] == "r" and a.size and float(np.min(a)) <= 0:
        raise InputError(f"{model.name}: actuator {name} = {float(np.min(a)):g} "
                         f"{model.units.length}: a leg extension |a_i - A_i| must be positive")


def extension_offset(model, i, rtol=1e-9):
    """``r_i`` at home, for a leg whose extension is its actuated P joint's value + ``r0``."""
    from ..errors import InputError
    lg = model.home_legs[i]
    A, a = np.asarray(lg.A, float), np.asarray(lg.a, float)
    r0 = float(np.linalg.norm(a - A))
    j = lg.actuated_index
    jt = lg.joints[j]
    L = float(model.normalisation.length)

    def on_line(p, jn):
        d = np.asarray(jn.direction, float)
        x = p - np.asarray(jn.point, float)
        return np.linalg.norm(x - (x @ d) * d) <= rtol * L

    ok = jt.kind == "P" and r0 > 0 and \
        np.linalg.norm(np.cross(np.asarray(jt.direction, float), (a - A) / r0)) <= rtol and \
        all(on_line(A, lg.joints[k]) for k in range(j)) and \
        all(on_line(a, lg.joints[k]) for k in range(j + 1, len(lg.joints)))
    if not ok:
        raise InputError(f"{model.name}: leg {i + 1}'s extension is not its actuator's value "
                         f"(its actuated joint is not a P on the line A{i + 1} a{i + 1} "
                         f"between joints through A{i + 1} and a{i + 1}): give q{i + 1}")
    return r0


