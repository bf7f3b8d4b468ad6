"""Residuals of a leg's structure checks (``perpendicular``, ``parallel``, ``meets``, ``through``).

:func:`structure_residuals` reports each check of a leg type's rules at a
placement (the catalog's validation, :func:`screwkit.legs.build_leg`);
:func:`structure_vector` is their smooth vector form, which vanishes where the
leg's structure holds (the home assembly of a PM, the notes of a pose solution).
"""

from __future__ import annotations

import numpy as np

from ..errors import GeometryError
from ..screws import Line
from ._chain import Leg
from ._placement import Placement
from ._rule_context import _Context, _Unresolved
from ..screws import cross

__all__ = ["structure_residuals", "structure_vector"]

# ``rules`` arguments are :class:`screwkit.legs.LegRules` (the rules module imports this one).


def structure_residuals(rules: "LegRules", placement: Placement, leg: Leg) -> list:
    """Dimensionless residuals of the structure checks, ``[(check, value), ...]``.

    ``perpendicular``: ``d1 . d2``; ``parallel``: ``|d1 x d2|``; ``meets``: the
    distance between the axes (0 when parallel is not allowed... parallel axes
    count as meeting at infinity) divided by the leg length; ``through``: the
    distance from the point to the axis divided by the leg length.
    """
    ctx = _Context(rules, placement)
    for j in leg.joints:
        ctx.dirs[j.name] = j.direction
        ctx.pts[j.name] = j.point
        ctx.dirs.setdefault(f"{j.spec.origin}{j.spec.position}", j.direction)
        ctx.pts.setdefault(f"{j.spec.origin}{j.spec.position}", j.point)
    L = max(placement.length, 1e-300)
    out = []
    for chk in rules.structure:
        (k, v), = chk.items()
        label = f"{k}: {v}"
        try:
            if k == "perpendicular":
                r = float(np.dot(ctx.direction(v[0]), ctx.direction(v[1])))
            elif k == "parallel":
                r = float(np.linalg.norm(cross(ctx.direction(v[0]), ctx.direction(v[1]))))
            elif k == "meets":
                l1 = Line.through(ctx.point(v[0]), ctx.direction(v[0]))
                l2 = Line.through(ctx.point(v[1]), ctx.direction(v[1]))
                r = 0.0 if l1.is_parallel(l2) else l1.distance_to_line(l2) / L
            else:  # through
                r = Line.through(ctx.point(v[0]), ctx.direction(v[0])).distance_to_point(ctx.point(v[1])) / L
        except _Unresolved as exc:
            raise GeometryError(f"leg {rules.name}: structure check {label} names unknown "
                                f"reference {exc.args[0]!r}") from None
        out.append((label, r))
    return out


def structure_vector(rules: "LegRules", placement: Placement, leg) -> np.ndarray:
    """Smooth residuals of a leg's structure checks (vectors where the check is 2-D).

    ``perpendicular``: ``d1 . d2``; ``parallel``: ``d1 x d2`` (3); ``meets``:
    the signed distance of the axes over the leg length; ``through``: the
    offset of the point from the axis over the leg length (3).
    """
    ctx = _Context(rules, placement)
    for j in leg.joints:
        for key in (j.name, f"{j.spec.origin}{j.spec.position}"):
            ctx.dirs.setdefault(key, j.direction)
            ctx.pts.setdefault(key, j.point)
    L = max(placement.length, 1e-300)
    out = []
    for chk in rules.structure:
        (k, v), = chk.items()
        if k == "perpendicular":
            out.append([float(ctx.direction(v[0]) @ ctx.direction(v[1]))])
        elif k == "parallel":
            out.append(cross(ctx.direction(v[0]), ctx.direction(v[1])))
        elif k == "meets":
            d1, d2 = ctx.direction(v[0]), ctx.direction(v[1])
            n = cross(d1, d2)
            nn = np.linalg.norm(n)
            out.append([0.0 if nn < 1e-9 else float(n @ (ctx.point(v[1]) - ctx.point(v[0]))) / nn / L])
        else:
            d, p, x = ctx.direction(v[0]), ctx.point(v[0]), ctx.point(v[1])
            r = x - p
            out.append((r - (r @ d) * d) / L)
    return np.concatenate([np.ravel(o) for o in out]) if out else np.zeros(0)
