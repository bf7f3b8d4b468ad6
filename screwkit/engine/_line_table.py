"""The table of the legs whose linear actuator carries the leg's whole length (private):
the flattened model's ``REV`` (:mod:`._kernels._layout`), which :mod:`._reversal` reads to
find the poses whose solution runs such an actuator through zero length.
"""

from __future__ import annotations

import numpy as np

from ..screws import GEOMETRY_RTOL

__all__ = ["line_table"]


def _off_line(x, point, direction) -> float:
    """The distance of the point ``x`` from the line through ``point`` along ``direction``."""
    d = np.asarray(direction, float)
    return float(np.linalg.norm(np.cross(np.asarray(x, float) - point, d)) / np.linalg.norm(d))


def line_table(legs, passive, nu: int, m: int, q_scale, L: float) -> np.ndarray:
    """The flattened model's ``REV (k, 6)`` table (:mod:`._kernels._layout`) of the placed
    legs ``legs`` at home: one row ``(leg, row, sign, limit, s^home, scale)`` for each leg
    (not in ``passive``) whose actuated joint is a P joint carrying the leg's whole length
    (:mod:`._reversal`): ``row = nu + i m + k`` its unknown in ``X``, ``s^home`` its signed
    home length, ``scale = q_scale[i, k]`` and ``limit = (tol - |s^home|) / scale`` (``tol =
    GEOMETRY_RTOL L``): the leg is reversed where ``sign X[row] <= limit``, that is where
    ``sign (s^home) (s^home + q) <= tol``."""
    tol = GEOMETRY_RTOL * float(L)
    table = []
    for i, lg in enumerate(legs):
        k = lg.actuated_index
        if i in passive or k is None or lg.joints[k].kind != "P":
            continue
        A, a = np.asarray(lg.A, float), np.asarray(lg.a, float)
        P = lg.joints[k]
        u = np.asarray(P.direction, float)
        u = u / np.linalg.norm(u)
        on_line = (_off_line(A, P.point, u) <= tol and _off_line(a, P.point, u) <= tol
                   and all(j.kind == "R" and _off_line(A, j.point, j.direction) <= tol
                           for j in lg.joints[:k])
                   and all(j.kind == "R" and _off_line(a, j.point, j.direction) <= tol
                           for j in lg.joints[k + 1:]))
        s = float((a - A) @ u)
        if not on_line or abs(s) <= tol:
            continue
        scale = float(q_scale[i, k])
        table.append((i, nu + i * m + k, np.sign(s), (tol - abs(s)) / scale, s, scale))
    return np.array(table, float).reshape(-1, 6)
