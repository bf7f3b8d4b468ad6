"""Whether a passive leg is near a singularity of its own (private).

An actuated leg near its own (input) singularity shows it in its input transmission index;
a passive leg has no actuator and no index, and its constraint rows are its home
constraint system's members at the pose.  Where its joints' twists lose rank the leg can
transmit one more wrench: the platform loses a freedom there and the statics become
indeterminate, while the rows and efforts given still hold home's system.  This is said,
per passive leg, from the condition number of its joint twists at the pose (length-normalised
about the leg's joints' centroid, as the rows are, a translation per length L; an S joint as
the three rotations about its centre, so that the representation of a spherical joint by
three R axes, which locks where two of them align, is not read as the leg's).
"""

from __future__ import annotations

import numpy as np

from ..screws import RANK_RTOL
from ._quality import NEAR_SINGULAR_COND

__all__ = ["passive_leg_conditioning", "passive_warnings", "pose_warnings", "SINGULAR_COND"]

#: The condition number beyond which the leg's twists are taken as singular (as ``J``'s).
SINGULAR_COND = 1e8


def _twists(leg, L: float) -> np.ndarray:
    """The leg's joint twists ``(m, 6)`` about its joints' centroid, lengths over ``L``."""
    rows, done = [], set()
    pts = np.array([j.point for j in leg.joints], float)
    c = pts.mean(axis=0)
    for j, t in zip(leg.joints, np.asarray(leg.twists, float)):
        if j.spec.origin == "S":
            key = (j.spec.origin, j.spec.position)
            if key in done:
                continue
            done.add(key)
            p = np.asarray(j.point, float)
            for w in np.eye(3):              # [p x w; w]: the three rotations of the ball
                rows.append(np.r_[np.cross(p, w), w])
        else:
            rows.append(t)
    T = np.array(rows, float)
    # a translation's unit rate is a length: L of it moves as far as a turn moves a point L
    # away (the rows' and the conditioning's normalisation), so it is taken over L, not 1
    T[np.linalg.norm(T[:, 3:], axis=1) == 0.0] *= L
    v = T[:, :3] + np.cross(T[:, 3:], c)     # (the velocity of the point at c)
    return np.hstack([v / L, T[:, 3:]])


def passive_leg_conditioning(analysis) -> dict:
    """``{leg index: condition number}`` of each passive leg's joint twists at the pose of a
    one-pose analysis (``inf`` where they have lost rank)."""
    model = analysis.model
    passive = tuple(getattr(model, "passive", ()) or ())
    if not passive:
        return {}
    L = float(model.normalisation.length)
    out = {}
    for i in passive:
        # (over the rank the leg has at home: an idle motion, the spin of an S-S link about
        # its line, is the leg's at every pose, not a singularity)
        h = np.linalg.svd(_twists(model.home_legs[i], L), compute_uv=False)
        r = max(1, int(np.sum(h > RANK_RTOL * h[0])))
        s = np.linalg.svd(_twists(analysis.solution.legs[i], L), compute_uv=False)[:r]
        out[i] = float(s[0] / s[-1]) if s[-1] > 0 else float("inf")
    return out


def passive_warnings(analysis) -> list:
    """One line per passive leg near its own singularity at the pose (one pose)."""
    if not analysis.solution.reachable_mask[0]:
        return []
    out = []
    for i, cond in passive_leg_conditioning(analysis).items():
        if cond > NEAR_SINGULAR_COND:
            at = "at" if cond > SINGULAR_COND else "near"
            out.append(f"passive leg {i + 1} is {at} a singularity of its own: the condition "
                       f"number of its joint twists is {cond:.3g} (there it transmits one "
                       "more wrench: the platform loses a freedom and the statics become "
                       "indeterminate; the rows and efforts given hold the leg's constraint "
                       "system of home)")
    return out


def pose_warnings(analysis) -> list:
    """The warnings of a one-pose analysis from its model's declared limits
    (:func:`._limits.limits_warnings`) and its passive legs (:func:`passive_warnings`)."""
    from ._limits import limits_warnings
    return limits_warnings(analysis) + passive_warnings(analysis)
