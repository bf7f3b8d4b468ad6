"""The result of :func:`screwkit.dynamics.stiffness`: :class:`StiffnessResult` (private)."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..errors import InputError
from ..screws import RANK_RTOL

__all__ = ["StiffnessResult"]


@dataclass(frozen=True, eq=False)
class StiffnessResult:
    """Cartesian stiffness of a PM at N poses (about ``o``, ``[v; w] -> [f; m]``).

    Attributes
    ----------
    analysis : PMAnalysis
    k : ndarray (N, m)
        Row stiffnesses (``inf``: rigid).
    K : ndarray (N, 6, 6)
        ``J_o^T diag(k) J_o`` over the compliant rows (plus ``geometric`` if asked); the
        rigid rows add an infinite stiffness along their own directions.
    elastic, geometric : ndarray (N, 6, 6)
        The two parts of ``K`` (``geometric`` None unless asked for).
    compliance : ndarray (N, 6, 6)
        ``dX = C W`` with the rigid rows (exactly 0 along rigid directions; solved on the
        held directions where the pose is singular).
    deflection : ndarray (N, 6) or None
        ``[dp_o; dtheta]`` under the workload ``[F; T]`` at ``o``; None without a workload.
    restrained : ndarray (N,) of bool
        No unrestrained direction (the legs hold the platform in every direction).
    free : ndarray (N, 6, 6)
        The unrestrained twists ``[v; w]`` about ``o`` of each pose (the first ``n_free``
        columns, ``|w| = 1`` or, for a translation, ``|v| = 1``).
    n_free : ndarray (N,) of int
    force, torque : ndarray (3,) or None
        The workload (None without one).
    workload_source : str
    """

    analysis: object
    k: np.ndarray
    K: np.ndarray
    compliance: np.ndarray
    deflection: np.ndarray | None
    restrained: np.ndarray
    force: np.ndarray | None
    torque: np.ndarray | None
    notes: tuple = field(default=())
    elastic: np.ndarray = None
    geometric: np.ndarray = None
    free: np.ndarray = None
    n_free: np.ndarray = None
    workload_source: str = ""

    @property
    def single(self) -> bool:
        return self.analysis.single

    def _sq(self, x):
        return x[0] if self.single else x

    @property
    def conditioning(self):
        """The pose's conditioning class (``regular``, ``near-singular``, ``singular``,
        ``unreachable``): the engine's, as ``analyze`` says it."""
        return self.analysis.conditioning

    @property
    def rigid_everywhere(self):
        """True where no row has a stiffness: the PM is rigid (``C = 0``, no deflection)."""
        r = ~np.isfinite(self.k).any(axis=1)
        return bool(r[0]) if self.single else r

    @property
    def load_on_free(self):
        """True where the workload works on an unrestrained direction: the legs cannot
        balance it (no static equilibrium; the deflection shown is the held part's)."""
        if self.deflection is None:
            return False if self.single else np.zeros(len(self.k), bool)
        F, T = np.asarray(self.force, float), np.asarray(self.torque, float)
        v, w = self.free[:, :3, :], self.free[:, 3:, :]                # (N, 3, 6)
        work = np.abs(np.einsum("a,nak->nk", F, v) + np.einsum("a,nak->nk", T, w))
        size = (np.linalg.norm(F) * np.linalg.norm(v, axis=1)
                + np.linalg.norm(T) * np.linalg.norm(w, axis=1))
        used = np.arange(6)[None, :] < self.n_free[:, None]
        out = np.any(used & (work > 1e-9 * size) & (size > 0), axis=1)
        return bool(out[0]) if self.single else out

    def unrestrained(self, i: int = 0) -> np.ndarray:
        """The unrestrained twists of pose ``i``, ``(n_free, 6)`` (``[v; w]`` about ``o``)."""
        return np.array(self.free[i, :, :self.n_free[i]].T)

    @cached_property
    def rank(self):
        """Rank of ``K`` (length-normalised, :data:`~screwkit.screws.RANK_RTOL`)."""
        L = float(self.analysis.model.normalisation.length)
        S = np.diag([L, L, L, 1.0, 1.0, 1.0])
        s = np.linalg.svd(S @ np.nan_to_num(self.K) @ S, compute_uv=False)
        r = np.sum(s > RANK_RTOL * np.maximum(s[:, :1], 1e-300), axis=1)
        return int(r[0]) if self.single else r

    def principal(self, which: str = "translational"):
        """Principal stiffnesses ``(N, 3)`` (ascending; ``inf`` along rigid directions) and
        their unit directions ``(N, 3, 3)`` (columns) of the translational block (force at
        ``o`` -> translation of ``o``) or the rotational block (couple -> rotation)."""
        if which not in ("translational", "rotational"):
            raise InputError(f"which must be 'translational' or 'rotational', not {which!r}")
        sl = slice(0, 3) if which == "translational" else slice(3, 6)
        C = self.compliance[:, sl, sl]
        C = 0.5 * (C + C.transpose(0, 2, 1))
        ev, vec = np.linalg.eigh(C)
        top = np.maximum(ev[:, -1:], 0.0)
        soft = (ev > RANK_RTOL * top) & (ev > 0)
        with np.errstate(divide="ignore"):
            k = np.where(soft, 1.0 / np.where(soft, ev, 1.0), np.inf)[:, ::-1]
        vec = vec[:, :, ::-1]
        return self._sq(k), self._sq(vec)

    def to_dict(self) -> dict:
        """JSON of one pose: ``stiffness`` (6x6, [v; w] -> [f; m] about o, None when every
        row is rigid), ``deflection`` (None without a workload), ``compliance``, principal
        stiffnesses, row stiffnesses, ``conditioning``, ``unrestrained``, ``units``."""
        if not self.single:
            raise TypeError("to_dict describes one pose")
        from ._compliance import twist_text
        u = self.analysis.model.units
        kt, dt = self.principal("translational")
        kr, dr = self.principal("rotational")
        jac = self.analysis.jacobian
        row_u = []
        for ri in jac.info:
            rot = ri.kind == "couple" or (ri.kind == "actuation" and ri.joint and ri.joint[0] in "RH")
            row_u.append(u.of("angular stiffness") if rot else u.of("stiffness"))
        p = self.analysis.solution.params_degrees()
        q = self.analysis.quality
        free = self.unrestrained(0)
        d = None if self.deflection is None else self.deflection[0]
        return {
            "pm": self.analysis.model.name,
            "pose": p,
            "about": "o", "order": "[v; w] -> [f; m]",
            "o": self.analysis.solution.position,
            "workload": (None if self.force is None else
                         {"force": self.force, "torque": self.torque, "applied_at": "o",
                          "source": self.workload_source}),
            "conditioning": {"class": str(q.conditioning[0]),
                             "condition_number": float(q.condition_number[0])},
            "rigid_everywhere": self.rigid_everywhere,
            "stiffness": None if self.rigid_everywhere else self.K[0],
            **({} if self.geometric is None else {"elastic": self.elastic[0],
                                                  "geometric": self.geometric[0]}),
            "rank": self.rank,
            "compliance": self.compliance[0],
            "deflection": None if d is None else {"translation": d[:3], "rotation": d[3:]},
            "restrained": bool(self.restrained[0]),
            "unrestrained": [{"twist": t, "description": twist_text(t, u.length)}
                             for t in free],
            "load_on_unrestrained": bool(self.load_on_free),
            "principal": {"translational": {"stiffness": kt, "directions": dt.T},
                          "rotational": {"stiffness": kr, "axes": dr.T}},
            "rows": [{"label": ri.label, "stiffness": k,       # ("inf" in JSON: rigid)
                      "rigid": not bool(np.isfinite(k)), "unit": un}
                     for ri, k, un in zip(jac.info, self.k[0], row_u)],
            "units": {"stiffness": {"f_per_v": f"{u.force}/{u.length}",
                                    "f_per_w": f"{u.force}/rad", "m_per_v": u.force,
                                    "m_per_w": f"{u.torque}/rad"},
                      "compliance": {"v_per_f": f"{u.length}/{u.force}",
                                     "v_per_m": f"{u.length}/{u.torque}",
                                     "w_per_f": f"rad/{u.force}",
                                     "w_per_m": f"rad/{u.torque}"},
                      "deflection": {"translation": u.length, "rotation": "rad"},
                      "principal": {"translational": f"{u.force}/{u.length}",
                                    "rotational": f"{u.torque}/rad"},
                      "length": u.length, "force": u.force, "torque": u.torque, "angle": "deg"},
            "notes": list(self.notes),
        }
