"""The limits a model declares (``limits:``), and the test of N poses against them.

A PM definition may bound its joints, its actuators' strokes and the distance between its
legs::

    limits:
      joints: {R1: [-60, 60], S3a: [-45, 45]}   # every leg's joints of these names
      actuators: [-20, 30]                      # each actuated joint's value from home
      extensions: [50, 120]                     # each leg's length |a_i - A_i|
      min_leg_distance: 4                       # between the segments A_i a_i of two legs

Joint and actuator values are displacements from home (joint values are 0 at home):
degrees for R and H joints, model lengths for P joints; extensions and distances are model
lengths.  ``joints`` may instead be a list with one mapping per leg, and ``actuators`` /
``extensions`` a list with one ``[min, max]`` (or ``null``) per leg; ``null`` for either
bound leaves it open.  Values may be expressions of the dimensions (``2*L/3``).

:meth:`Limits.check` takes the joint values, extensions and end points of N poses (the
engine's :class:`~screwkit.engine.PoseSolution` gives them) and says, per pose, which limit
holds; a pose whose values are NaN (unreachable) is within no limit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Limits", "NO_LIMITS", "limits_from_mapping", "segment_distances"]

_KEYS = ("joints", "actuators", "extensions", "min_leg_distance")


@dataclass(frozen=True)
class Limits:
    """Joint, stroke and leg-distance limits (radians for R/H joints, model lengths else).

    Attributes
    ----------
    joints : tuple of tuple of (int, float, float, str, bool)
        Per leg: ``(slot, min, max, name, rotary)`` of each bounded joint.
    actuators, extensions : tuple of (float, float) or None
        Per leg (``-inf`` / ``inf`` for an open bound); empty: none declared.
    min_leg_distance : float or None
    """

    joints: tuple = ()
    actuators: tuple = ()
    extensions: tuple = ()
    min_leg_distance: float | None = None

    @property
    def declared(self) -> bool:
        return bool(any(self.joints) or any(x is not None for x in self.actuators)
                    or any(x is not None for x in self.extensions)
                    or self.min_leg_distance is not None)

    def check(self, joint_values, actuator_values, extensions, A, a) -> dict:
        """Which limits hold at N poses.

        Parameters
        ----------
        joint_values : sequence of ndarray (N, m_i)
            Each leg's joint values from home.
        actuator_values, extensions : ndarray (N, n)
            Per leg (a passive leg's actuator value is NaN: it has no actuator limit).
        A : ndarray (n, 3) ; a : ndarray (N, n, 3)
            The legs' end points (world).

        Returns
        -------
        dict
            ``within`` (N,) bool: every limit holds; ``joints``, ``actuators``,
            ``extensions``, ``leg_distance`` (N,) bool each; ``min_leg_distance`` (N,) the
            smallest distance between two legs' segments (NaN without that limit).
        """
        ext = np.asarray(extensions, float)
        N = ext.shape[0]
        out = {}
        ok = np.ones(N, bool)
        for i, bounds in enumerate(self.joints):
            q = np.asarray(joint_values[i], float)
            for slot, lo, hi, *_ in bounds:
                ok &= (q[:, slot] >= lo) & (q[:, slot] <= hi)
        out["joints"] = ok
        out["actuators"] = _within(self.actuators, np.asarray(actuator_values, float))
        out["extensions"] = _within(self.extensions, ext)
        dmin = np.full(N, np.nan)
        dist_ok = np.ones(N, bool)
        if self.min_leg_distance is not None:
            dmin = segment_distances(np.asarray(A, float), np.asarray(a, float))
            dist_ok = dmin >= self.min_leg_distance
        out["leg_distance"] = dist_ok
        out["min_leg_distance"] = dmin
        finite = np.all(np.isfinite(ext), axis=1)
        out["within"] = (out["joints"] & out["actuators"] & out["extensions"] & dist_ok
                         & finite)
        return out

    def as_dict(self) -> dict:
        """JSON-ready (degrees for R/H joints)."""
        return {"joints": [{name: [_deg(lo, rot), _deg(hi, rot)] for _, lo, hi, name, rot in b}
                           for b in self.joints],
                "actuators": [None if x is None else list(x) for x in self.actuators],
                "extensions": [None if x is None else list(x) for x in self.extensions],
                "min_leg_distance": self.min_leg_distance}

def _deg(x, rot):
    return float(np.degrees(x)) if rot and np.isfinite(x) else float(x)


NO_LIMITS = Limits()


def _within(bounds, values):
    N = values.shape[0]
    ok = np.ones(N, bool)
    for i, b in enumerate(bounds):
        if b is not None:
            ok &= (values[:, i] >= b[0]) & (values[:, i] <= b[1])
    return ok


def segment_distances(A, a) -> np.ndarray:
    """The smallest distance between the segments ``A_i a_i`` of two legs, ``(N,)``.

    ``A (n, 3)`` fixed, ``a (N, n, 3)``; closest points of two segments clamped to their
    ends (parallel segments handled)."""
    N, n = a.shape[0], a.shape[1]
    best = np.full(N, np.inf)
    for i in range(n):
        for j in range(i + 1, n):
            p1, q1 = np.broadcast_to(A[i], (N, 3)), a[:, i]
            p2, q2 = np.broadcast_to(A[j], (N, 3)), a[:, j]
            best = np.minimum(best, _seg_seg(p1, q1, p2, q2))
    return best if n > 1 else np.full(N, np.nan)


def _seg_seg(p1, q1, p2, q2):
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    den = a * e - b * b
    tiny = 1e-14 * np.maximum(a * e, 1e-300)
    s = np.where(den > tiny, np.clip((b * f - c * e) / np.where(den > tiny, den, 1.0), 0, 1), 0.0)
    t = (b * s + f) / np.where(e > 0, e, 1.0)
    # t outside [0, 1]: clamp it and recompute s
    t_c = np.clip(t, 0.0, 1.0)
    s = np.where(t != t_c, np.clip((t_c * b - c) / np.where(a > 0, a, 1.0), 0, 1), s)
    c1 = p1 + s[:, None] * d1
    c2 = p2 + t_c[:, None] * d2
    return np.linalg.norm(c1 - c2, axis=1)


def _pair(v, ctx, fld, rotary=False):
    if v is None:
        return None
    if not (isinstance(v, (list, tuple)) and len(v) == 2):
        raise ctx.err("must be [min, max] (null for an open bound)", fld)
    lo = -np.inf if v[0] is None else ctx.num(v[0], f"{fld}[0]")
    hi = np.inf if v[1] is None else ctx.num(v[1], f"{fld}[1]")
    if rotary:
        lo, hi = np.radians(lo), np.radians(hi)
    if not lo <= hi:
        raise ctx.err(f"min {v[0]} is above max {v[1]}", fld)
    return (float(lo), float(hi))


def _per_leg(raw, ctx, fld, n, rotary):
    """A ``[min, max]`` for every leg, or a list of one ``[min, max]`` (or null) per leg."""
    if raw is None:
        return ()
    if isinstance(raw, (list, tuple)) and any(isinstance(v, (list, tuple)) for v in raw):
        if not all(v is None or isinstance(v, (list, tuple)) for v in raw) or len(raw) != n:
            raise ctx.err(f"[min, max] for every leg, or a list of {n} such pairs (null: no "
                          "limit)", fld)
        return tuple(_pair(v, ctx, f"{fld}[{i}]", rotary[i]) for i, v in enumerate(raw))
    return tuple(_pair(raw, ctx, fld, rotary[i]) for i in range(n))


def limits_from_mapping(raw, ctx, home_legs, passive=()) -> Limits:
    """The :class:`Limits` of a definition's ``limits:`` mapping (``ctx``: the loader's
    evaluation context, for expressions and errors naming the field; ``passive``: the
    passive legs, which have no actuator to limit)."""
    if raw is None:
        return NO_LIMITS
    if not isinstance(raw, dict):
        raise ctx.err(f"must be a mapping with some of {', '.join(_KEYS)}", "limits")
    bad = sorted(set(raw) - set(_KEYS))
    if bad:
        raise ctx.err(f"unknown key(s) {bad} (known: {', '.join(_KEYS)})", "limits")
    n = len(home_legs)
    rot_act = [lg.actuated_joint.kind != "P" for lg in home_legs]
    joints = [[] for _ in range(n)]
    jr = raw.get("joints")
    if jr is not None:
        per_leg = jr if isinstance(jr, list) else [jr] * n
        if len(per_leg) != n:
            raise ctx.err(f"a mapping for every leg, or a list of {n} mappings", "limits.joints")
        for i, (m, lg) in enumerate(zip(per_leg, home_legs)):
            if m is None:
                continue
            if not isinstance(m, dict):
                raise ctx.err("must be a mapping joint name -> [min, max]",
                              f"limits.joints[{i}]")
            names = [j.name for j in lg.joints]
            for name, v in m.items():
                fld = f"limits.joints.{name}"
                if str(name) not in names:
                    if isinstance(jr, list) or not any(str(name) in [j.name for j in g.joints]
                                                       for g in home_legs):
                        raise ctx.err(f"no joint {name!r} in leg {i + 1} ({', '.join(names)})",
                                      fld)
                    continue
                slot = names.index(str(name))
                rot = lg.joints[slot].kind != "P"
                lo, hi = _pair(v, ctx, fld, rot)
                joints[i].append((slot, lo, hi, str(name), rot))
    acts = _per_leg(raw.get("actuators"), ctx, "limits.actuators", n, rot_act)
    if acts and passive:
        listed = isinstance(raw["actuators"], (list, tuple)) and \
            any(isinstance(v, (list, tuple)) for v in raw["actuators"])
        bad = [i for i in passive if listed and acts[i] is not None]
        if bad:
            raise ctx.err(f"leg {bad[0] + 1} is passive: it has no actuator (null here; limit "
                          "its joints under 'joints')", f"limits.actuators[{bad[0]}]")
        acts = tuple(None if i in passive else b for i, b in enumerate(acts))
    exts = _per_leg(raw.get("extensions"), ctx, "limits.extensions", n, [False] * n)
    dmin = raw.get("min_leg_distance")
    if dmin is not None:
        dmin = ctx.num(dmin, "limits.min_leg_distance")
        if dmin < 0:
            raise ctx.err("must be a length >= 0", "limits.min_leg_distance")
    return Limits(tuple(tuple(b) for b in joints), acts, exts, dmin)
