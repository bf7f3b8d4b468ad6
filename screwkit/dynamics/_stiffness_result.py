"""The result of :func:`screwkit.dynamics.stiffness`: :class:`StiffnessResult` (private)."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..errors import InputError
from ..screws import RANK_RTOL
from ..errors import MisuseError

__all__ = ["StiffnessResult", "PRINCIPAL_DEFINITION"]

#: What the principal stiffnesses are (the JSON and the text say it).
PRINCIPAL_DEFINITION = ("1 / the eigenvalues of the compliance's translational (rotational) "
                        "block: the stiffness of o under a force (a couple) alone, the "
                        "platform free to turn (to move) as the legs let it; not the "
                        "eigenvalues of K's own blocks, which hold the other three fixed")


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
        """Rank of ``K`` (length-normalised, :data:`~screwkit.screws.RANK_RTOL`): of the
        compliant rows themselves (``J_o^T diag(k) J_o`` has their rank whatever the spread
        of the stiffnesses, which would hide it from an SVD of ``K``: 2000 and 1e-20 side
        by side; a geometric term perturbs that stiffness, and where it makes the tangent
        lose rank the PM buckles: :attr:`stable`).  Where every row is compliant that is
        the rank of ``J`` the analysis gives (its normalisation, its singular values: the
        rank beside its condition number and its singular flag, never another decision
        near the threshold); where some are not, the compliant rows' rank in the same
        normalisation.  0 at an unreachable pose."""
        jac = self.analysis.jacobian
        reach = np.asarray(self.analysis.solution.reachable_mask, bool).reshape(-1)
        soft = np.isfinite(self.k) & (self.k > 0)
        whole = soft.all(axis=1)
        r = np.where(reach & whole, np.asarray(jac.conditioning.rank).reshape(-1), 0)
        part = np.flatnonzero(reach & ~whole)
        if part.size:
            Jn, _ = jac.normalised()                                  # (N, m, 6)
            M = np.where(soft[part, :, None], np.nan_to_num(Jn[part]), 0.0)
            s = np.linalg.svd(M, compute_uv=False)
            r[part] = np.sum(s > RANK_RTOL * np.maximum(s[:, :1], 1e-300), axis=1)
        return int(r[0]) if self.single else r

    def principal(self, which: str = "translational"):
        """Principal stiffnesses ``(N, 3)`` (ascending; ``inf`` along rigid directions,
        negative along a direction the tangent stiffness of a loaded PM does not hold:
        :attr:`stable`) and their unit directions ``(N, 3, 3)`` (columns) of the
        translational block (force at ``o`` -> translation of ``o``) or the rotational
        block (couple -> rotation); NaN where the tangent stiffness is undefined."""
        if which not in ("translational", "rotational"):
            raise InputError(f"which must be 'translational' or 'rotational', not {which!r}")
        sl = slice(0, 3) if which == "translational" else slice(3, 6)
        C = self.compliance[:, sl, sl]
        C = 0.5 * (C + C.transpose(0, 2, 1))
        undefined = np.isnan(C).any(axis=(1, 2))      # (a singular pose of a batch, tangent)
        ev, vec = np.linalg.eigh(np.where(undefined[:, None, None], 0.0, C))
        top = np.max(np.abs(ev), axis=1, keepdims=True)
        held = np.abs(ev) > RANK_RTOL * top
        with np.errstate(divide="ignore"):
            k = np.where(held, 1.0 / np.where(held, ev, 1.0), np.inf)
        order = np.argsort(k, axis=1, kind="stable")
        k = np.take_along_axis(k, order, axis=1)
        vec = np.take_along_axis(vec, order[:, None, :], axis=2)
        k[undefined], vec[undefined] = np.nan, np.nan
        return self._sq(k), self._sq(vec)

    @cached_property
    def _stable(self) -> np.ndarray:
        # the compliance made unit-free (x_n = [dp / L; dtheta], w_n = [f; m / L]: a
        # congruence diag(a) C diag(a), which keeps the signs of its eigenvalues): its
        # symmetric part has a negative eigenvalue where the tangent stiffness has one;
        # without a geometric term K = J^T diag(k) J is positive on the held directions
        if self.geometric is None:
            return np.ones(len(self.k), bool)
        L = float(self.analysis.model.normalisation.length)
        a = np.array([L ** -0.5] * 3 + [L ** 0.5] * 3)
        Cn = self.compliance * a[None, :, None] * a[None, None, :]
        Cn = 0.5 * (Cn + Cn.transpose(0, 2, 1))
        ev = np.linalg.eigvalsh(np.nan_to_num(Cn))
        top = np.max(np.abs(ev), axis=1)
        defined = ~np.isnan(Cn).any(axis=(1, 2))       # (NaN: a singular pose of a batch)
        return defined & ~np.any(ev < -RANK_RTOL * np.maximum(top, 1e-300)[:, None], axis=1)

    @property
    def stable(self):
        """True where the (tangent) stiffness holds every held direction with a positive
        stiffness: False where a loaded PM's ``K + K_g`` has a negative one (it buckles under
        the workload; its linear deflection means nothing there), or is undefined (a
        singular pose of a batch: NaN)."""
        return bool(self._stable[0]) if self.single else self._stable

    #: A deflection beyond this share of the PM's length, or this many radians, is not small:
    #: the linear stiffness model does not hold (a warning).
    LARGE_DEFLECTION = 0.1

    @property
    def warnings(self) -> list:
        """The warnings of pose 0 (one pose): a tangent stiffness that is not positive
        (:attr:`stable`), a deflection that is not small beside the PM."""
        out = []
        L = float(self.analysis.model.normalisation.length)
        u = self.analysis.model.units
        if not self._stable[0]:
            out.append("the tangent stiffness K + K_g is not positive definite: under this "
                       "workload the PM loses its stability (it buckles) and the linear "
                       "deflection shown means nothing (a negative principal stiffness "
                       "marks the direction)")
        if self.deflection is not None:
            dp = float(np.linalg.norm(self.deflection[0, :3]))
            dt = float(np.linalg.norm(self.deflection[0, 3:]))
            if dp > self.LARGE_DEFLECTION * L or dt > self.LARGE_DEFLECTION:
                out.append(f"the deflection ({dp:.3g} {u.length}, {dt:.3g} rad) is not small "
                           f"beside the PM (its length {L:.4g} {u.length}): the linear "
                           "stiffness model does not hold there")
        return out

    def to_dict(self, units=None) -> dict:
        """JSON of one pose: ``stiffness`` (6x6, [v; w] -> [f; m] about o, None when every
        row is rigid), ``deflection`` (None without a workload), ``compliance``, principal
        stiffnesses, row stiffnesses, ``conditioning``, ``unrestrained``, ``units`` (the
        model's, or SI with ``units="SI"``: m, N, N.m)."""
        if not self.single:
            raise MisuseError("to_dict describes one pose")
        if units is not None and units != "model":
            from ._stiffness_units import in_units
            return in_units(self.to_dict(), self.analysis.model, units)
        from ._compliance import twist_text
        u = self.analysis.model.units
        kt, dt = self.principal("translational")
        kr, dr = self.principal("rotational")
        jac = self.analysis.jacobian
        row_u = []
        for ri in jac.info:
            rot = ri.torque
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
                          "force_unit": u.force, "torque_unit": u.torque,
                          "source": self.workload_source}),
            "conditioning": {"class": str(q.conditioning[0]),
                             "condition_number": float(q.condition_number[0])},
            "rigid_everywhere": self.rigid_everywhere,
            "stiffness": None if self.rigid_everywhere else self.K[0],
            **({} if self.geometric is None else {"elastic": self.elastic[0],
                                                  "geometric": self.geometric[0]}),
            "rank": self.rank,
            "stable": self.stable,
            "warnings": self.warnings,
            "compliance": self.compliance[0],
            "deflection": None if d is None else {"translation": d[:3], "rotation": d[3:]},
            "restrained": bool(self.restrained[0]),
            "unrestrained": [{"twist": t, "description": twist_text(t, u.length)}
                             for t in free],
            "load_on_unrestrained": bool(self.load_on_free),
            "principal": {"translational": {"stiffness": kt, "directions": dt.T},
                          "rotational": {"stiffness": kr, "axes": dr.T},
                          "definition": PRINCIPAL_DEFINITION},
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
