"""The model's declared limits at an analysis' poses (private): which hold, and in words.

A model's ``limits:`` (:class:`screwkit.pm.Limits`: joint ranges, actuator strokes, leg
extensions, the least distance between two legs) bound where the PM may work.  A map counts
its cells outside them (``within_limits``); one pose says so in its warnings, so that
``analyze``, ``stiffness``, ``fk`` and the others never report a pose beyond them as fine.
"""

from __future__ import annotations

import numpy as np

__all__ = ["limits_check", "within_limits", "limits_warnings"]


def limits_check(an) -> dict | None:
    """:meth:`screwkit.pm.Limits.check` at the poses of ``an`` (None: no limits declared)."""
    model = an.model
    lim = model.limits
    if not lim.declared:
        return None
    sol = an.solution
    ext = np.atleast_2d(np.asarray(sol.extensions, float))
    per_leg = np.full(ext.shape, np.nan)                       # NaN: a passive leg
    per_leg[:, list(model.active)] = np.atleast_2d(np.asarray(sol.actuator_values, float))
    q = [np.atleast_2d(v) for v in sol.joint_values]
    a = np.asarray(sol._platform[2], float).reshape(ext.shape[0], -1, 3)
    return lim.check(q, per_leg, ext, sol.base_points, a)


def within_limits(an) -> np.ndarray:
    """``(N,)`` bool: every declared limit holds (True where the model declares none)."""
    chk = limits_check(an)
    n = np.atleast_2d(np.asarray(an.solution.extensions)).shape[0]
    return np.ones(n, bool) if chk is None else np.asarray(chk["within"], bool)


def limits_warnings(an) -> list:
    """The limits pose 0 of ``an`` breaks, one line (empty: none, or none declared)."""
    chk = limits_check(an)
    if chk is None or chk["within"][0]:
        return []
    model, lim = an.model, an.model.limits
    u = model.units.length
    sol = an.solution
    parts = []
    if not chk["joints"][0]:
        q = [np.atleast_2d(v)[0] for v in sol.joint_values]
        for i, bounds in enumerate(lim.joints):
            for slot, lo, hi, name, rot in bounds:
                v = q[i][slot]
                if not lo <= v <= hi:
                    f = np.degrees if rot else float
                    parts.append(f"leg {i + 1} joint {name} = {f(v):.4g} not in "
                                 f"[{f(lo):.4g}, {f(hi):.4g}] {'deg' if rot else u}")
    for what, vals, bounds in (("actuator", np.atleast_2d(sol.actuator_values)[0],
                                lim.actuators),
                               ("extension r", np.atleast_2d(sol.extensions)[0],
                                lim.extensions)):
        legs = list(model.active) if what == "actuator" else range(len(bounds))
        for k, i in enumerate(legs):
            b = bounds[i] if i < len(bounds) else None
            v = vals[k] if what == "actuator" else vals[i]
            if b is None or b[0] <= v <= b[1]:
                continue
            rot = what == "actuator" and model.home_legs[i].actuated_joint.kind in "RH"
            f = np.degrees if rot else float
            parts.append(f"leg {i + 1} {what} = {f(v):.4g} not in [{f(b[0]):.4g}, "
                         f"{f(b[1]):.4g}] {'deg' if rot else u}")
    if not chk["leg_distance"][0]:
        parts.append(f"two legs {chk['min_leg_distance'][0]:.4g} {u} apart, less than "
                     f"{lim.min_leg_distance:.4g} {u}")
    return ["outside the model's declared limits: " + "; ".join(parts or ["(a limit)"])]
