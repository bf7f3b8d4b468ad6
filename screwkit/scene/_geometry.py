"""The drawn geometry of a state: each leg's chain and its joints by kind, and the view's box.

A leg's joints are grouped by the letter of its string they come from (an S is three R
axes through one centre, a U two crossed axes, a C a P and an R on one axis), so that the
page draws each letter once, by kind: an R axis, a P sleeve, an S ball, a U cross, an H
axis with its helix, a C sleeve on its axis, a Pa parallelogram.
"""

from __future__ import annotations

import numpy as np

__all__ = ["leg_json", "scene_size", "scene_box", "plate_outline"]


def _v(x) -> list:
    return [float(c) for c in np.asarray(x, float)]


def _joint_json(letter: str, joints) -> dict:
    j0 = joints[0]
    name = f"{letter}{j0.spec.position}"
    act = any(j.actuated for j in joints)
    d = {"name": name, "act": act, "p": _v(j0.point), "d": _v(j0.direction)}
    if j0.spec.parallelogram:
        d.update(k="Pa", bar=_v(j0.bar), hinge=_v(j0.hinge))
    elif letter == "S":
        d["k"] = "S"
    elif letter == "U":
        d.update(k="U", d2=_v(joints[1].direction) if len(joints) > 1 else d["d"])
    elif letter == "C":
        d["k"] = "C"
    elif j0.kind == "H":
        d.update(k="H", pitch=float(j0.pitch))
    else:
        d["k"] = j0.kind                     # R or P
    return d


def leg_json(leg, size: float) -> dict:
    """One placed leg as the page draws it: ``A``, ``a``, the chain through its joint
    points and the joints by letter (``k``: R, P, S, U, H, C or Pa; ``p`` a point, ``d`` the
    axis or sliding direction, ``d2`` a U's second axis, ``pitch`` an H's, ``bar`` and
    ``hinge`` a parallelogram's; ``act`` the actuated letter)."""
    pts = [np.asarray(leg.A, float)]
    for p in [j.point for j in leg.joints] + [leg.a]:
        p = np.asarray(p, float)
        if np.linalg.norm(p - pts[-1]) > 1e-9 * size:
            pts.append(p)
    return {"name": leg.name, "A": _v(leg.A), "a": _v(leg.a),
            "chain": [_v(p) for p in pts],
            "joints": [_joint_json(letter, [j for _, j in js])
                       for letter, js in leg.letters()]}


def scene_size(states) -> float:
    """The drawing's characteristic length: the largest base radius, else the longest leg."""
    size = 0.0
    for s in states:
        B = np.asarray(s.base_points, float)
        if len(B) > 1 and np.all(np.isfinite(B)):
            size = max(size, float(np.max(np.linalg.norm(B - B.mean(axis=0), axis=1))))
    if size == 0.0:
        for s in states:
            for lg in s.legs:
                size = max(size, float(lg.length))
    return size or 1.0


def scene_box(states, size: float):
    """The fixed box of every state (so that the view does not rescale as the pose moves):
    the base, the platform and the legs' chains, padded for the arrows."""
    pts = []
    for s in states:
        pts.append(np.asarray(s.base_points, float).reshape(-1, 3))
        if s.status != "unreachable":
            pts.append(np.asarray(s.platform_points, float).reshape(-1, 3))
            pts += [np.asarray([j.point for j in lg.joints], float).reshape(-1, 3)
                    for lg in s.legs]
    P = np.vstack(pts)
    P = P[np.all(np.isfinite(P), axis=1)]
    lo, hi = P.min(axis=0), P.max(axis=0)
    pad = 0.45 * size
    return lo - pad, hi + pad


def plate_outline(points) -> np.ndarray:
    """The outline of a plate (the base or the platform) through its attachment points
    ``(n, 3)``: the corners of their convex hull, in order around it from the first of them
    that is a corner, so that a point inside (a central column's attachment) is not drawn
    as a corner of a concave polygon.  Fewer than four points, or points on a line, are
    returned as they are.

    Examples
    --------
    >>> plate_outline([[2, 0, 0], [-1, 2, 0], [-1, -2, 0], [0, 0, 0]]).tolist()
    [[2.0, 0.0, 0.0], [-1.0, 2.0, 0.0], [-1.0, -2.0, 0.0]]
    """
    P = np.asarray(points, float).reshape(-1, 3)
    if len(P) < 4 or not np.all(np.isfinite(P)):
        return P
    c = P.mean(axis=0)
    _, s, Vt = np.linalg.svd(P - c)
    if s[1] <= 1e-9 * max(s[0], 1e-300):
        return P
    xy = (P - c) @ Vt[:2].T
    tol = 1e-12 * max(float(np.abs(xy).max()), 1e-300) ** 2

    def half(order):
        out = []
        for i in order:
            while len(out) >= 2:
                (ax, ay), (bx, by) = xy[out[-2]], xy[out[-1]]
                if (bx - ax) * (xy[i][1] - ay) - (by - ay) * (xy[i][0] - ax) > tol:
                    break
                out.pop()
            out.append(i)
        return out
    order = sorted(range(len(P)), key=lambda i: (xy[i][0], xy[i][1]))
    hull = half(order)[:-1] + half(order[::-1])[:-1]          # counter-clockwise
    if len(hull) < 3:
        return P
    k = hull.index(min(hull))
    hull = hull[k:] + hull[:k]
    # (the given turning sense where the points already go around: the same polygon)
    if len(hull) >= 3 and hull[1] > hull[-1]:
        hull = hull[:1] + hull[1:][::-1]
    return P[hull]
