"""The stiffness of a PM from its unified Jacobian and the compliance of its legs.

Each row ``r`` of ``J = [J_a; J_c]`` (a leg's actuation or constraint wrench) is given a
stiffness ``k_r`` (:func:`row_stiffness`): its effort changes by ``dF_r = -k_r J_r dX``
when the platform moves by the small twist ``dX``.  With the rows written about the
platform centre ``o`` (``[f; m_o]``, ``m_o = m - o x f``) and ``dX = [dp_o; dtheta]``::

    K = J_o^T diag(k) J_o        (6 x 6, [v; w] -> [f; m] about o, symmetric, PSD)

over the rows that have a stiffness; its rank is the number of independent such rows.  A
row without a stiffness is rigid: it carries load without deflecting.  The deflection
under the workload ``W = [F; T]`` at ``o`` minimises the elastic energy subject to the rigid
rows, ``[K J_rig^T; J_rig 0] [dX; mu] = [W; 0]``; the compliance ``C`` (``dX = C W``) is the
top-left block of that system's inverse (``J^-1 diag(1/k) J^-T`` for a square ``J``; rigid
rows have compliance 0).  Principal stiffnesses: the eigenvalues of the translational block
``C_tt`` (the translation of ``o`` per unit force at ``o``) and of the rotational block
``C_rr`` (the rotation per unit couple), inverted; their eigenvectors are the directions.

Where a row's stiffness is not given it may follow from a uniform beam along the leg,
clamped at ``A_i`` and loaded at ``a_i``, of the current length ``l = |a_i - A_i|``
(``beam: {E, G, area, I, J}``): a force ``f`` (unit) of the row has the compliance ``(f .
d)^2 l / (E area) + (1 - (f . d)^2) l^3 / (3 E I)`` (axial ``EA/l``, cantilever bending
``3EI/l^3``), a couple ``t`` (unit) ``(t . d)^2 l / (G J) + (1 - (t . d)^2) l / (E I)``
(torsion ``GJ/l``, bending ``EI/l``), ``d`` the unit leg direction.

The load-dependent (geometric) term ``K_g = -d(J^T F_r + W)/dX`` at constant ``F_r`` (the
rows turn and move with the platform under a preload) is added with ``geometric=True``
(:mod:`~._geometric`); it is of the order of the load over the leg length, so without it a
deflection is right to first order in the load.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..engine import PAPER_FORCE, PAPER_TORQUE
from ..errors import InputError
from ..screws import RANK_RTOL

__all__ = ["StiffnessResult", "row_stiffness", "stiffness", "stiffness_of"]


def row_stiffness(analysis, params=None, *, actuator=None, force=None, couple=None,
                  rows=None):
    """The stiffness of every row of ``J`` at every pose, ``(N, m)`` (``inf``: rigid).

    Parameters
    ----------
    analysis : PMAnalysis
    params : DynamicsParameters, optional
        Per leg :class:`~screwkit.pm.LegStiffness` (given values, then the beam formulas).
    actuator, force, couple : float, optional
        One value for every actuation / constraint force / constraint couple row (model
        units), replacing the parameters'.
    rows : mapping label -> float, optional
        Values of particular rows (``{"F_a1": 2e3, "T_c2": 1e7}``), replacing all others.
    """
    jac, sol = analysis.jacobian, analysis.solution
    J = jac.matrix
    N, m = J.shape[0], J.shape[1]
    info = jac.info
    model = analysis.model
    k = np.full((N, m), np.inf)
    A = sol.base_points
    a = sol._platform[2]
    d = a - A[None]
    ell = np.linalg.norm(d, axis=-1)                      # (N, n)
    d = d / ell[..., None]
    for r, ri in enumerate(info):
        ls = params.legs[ri.leg].stiffness if params is not None else None
        kind = "actuation" if ri.kind == "actuation" else (
            "couple" if ri.kind == "couple" else "force")
        given = {"actuation": actuator, "force": force, "couple": couple}[kind]
        if given is None and ls is not None:
            given = {"actuation": ls.actuator, "force": ls.force, "couple": ls.couple}[kind]
        if given is not None:
            k[:, r] = given
        elif ls is not None and ls.beam is not None:
            b = ls.beam
            li, di = ell[:, ri.leg], d[:, ri.leg]
            if kind == "couple":
                t = J[:, r, 3:] / np.linalg.norm(J[:, r, 3:], axis=-1, keepdims=True)
                c2 = np.einsum("ni,ni->n", t, di) ** 2
                comp = c2 * li / (b["G"] * b["J"]) + (1 - c2) * li / (b["E"] * b["I"])
            else:
                if kind == "actuation" and model.home_legs[ri.leg].actuated_joint.kind != "P":
                    continue                              # a rotary actuator: no beam formula
                f = J[:, r, :3] / np.linalg.norm(J[:, r, :3], axis=-1, keepdims=True)
                c2 = np.einsum("ni,ni->n", f, di) ** 2
                comp = c2 * li / (b["E"] * b["area"]) + (1 - c2) * li ** 3 / (3 * b["E"] * b["I"])
            k[:, r] = 1.0 / comp
    if rows:
        labels = [ri.label for ri in info]
        for lab, v in rows.items():
            if lab not in labels:
                raise InputError(f"{model.name}: no row {lab!r}; the rows are {', '.join(labels)}")
            k[:, labels.index(lab)] = np.inf if v is None else float(v)
    if np.any(~(k > 0)):
        raise InputError("row stiffnesses must be positive (leave a row out for a rigid one)")
    return k


@dataclass(frozen=True, eq=False)
class StiffnessResult:
    """Cartesian stiffness of a PM at N poses (about ``o``, ``[v; w] -> [f; m]``).

    Attributes
    ----------
    analysis : PMAnalysis
    k : ndarray (N, m)
        Row stiffnesses (``inf``: rigid).
    K : ndarray (N, 6, 6)
        ``J_o^T diag(k) J_o`` over the compliant rows (plus ``geometric`` if asked).
    elastic, geometric : ndarray (N, 6, 6)
        The two parts of ``K`` (``geometric`` None unless asked for).
    compliance : ndarray (N, 6, 6)
        ``dX = C W`` with the rigid rows (NaN where the platform is not held).
    deflection : ndarray (N, 6)
        ``[dp_o; dtheta]`` under the workload ``[F; T]`` at ``o``.
    restrained : ndarray (N,) of bool
    force, torque : ndarray (3,)
    """

    analysis: object
    k: np.ndarray
    K: np.ndarray
    compliance: np.ndarray
    deflection: np.ndarray
    restrained: np.ndarray
    force: np.ndarray
    torque: np.ndarray
    notes: tuple = field(default=())
    elastic: np.ndarray = None
    geometric: np.ndarray = None

    @property
    def single(self) -> bool:
        return self.analysis.single

    def _sq(self, x):
        return x[0] if self.single else x

    @cached_property
    def rank(self):
        """Rank of ``K`` (length-normalised, :data:`~screwkit.screws.RANK_RTOL`)."""
        L = float(self.analysis.model.normalisation.length)
        S = np.diag([L, L, L, 1.0, 1.0, 1.0])
        s = np.linalg.svd(S @ self.K @ S, compute_uv=False)
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
        ok = np.all(np.isfinite(C), axis=(1, 2))
        ev, vec = np.linalg.eigh(np.where(ok[:, None, None], C, np.eye(3)))
        top = np.maximum(ev[:, -1:], 1e-300)
        with np.errstate(divide="ignore"):
            k = np.where(ev > RANK_RTOL * top, 1.0 / np.where(ev > 0, ev, 1.0), np.inf)
        k = np.where(ok[:, None], k, np.nan)[:, ::-1]
        vec = vec[:, :, ::-1]
        return self._sq(k), self._sq(vec)

    def to_dict(self) -> dict:
        """JSON of one pose: ``stiffness`` (6x6, [v; w] -> [f; m] about o), ``deflection``,
        ``compliance``, principal stiffnesses, row stiffnesses, ``units``."""
        if not self.single:
            raise TypeError("to_dict describes one pose")
        u = self.analysis.model.units
        kt, dt = self.principal("translational")
        kr, dr = self.principal("rotational")
        jac = self.analysis.jacobian
        row_u = []
        for ri in jac.info:
            rot = ri.kind == "couple" or (ri.kind == "actuation" and ri.joint and ri.joint[0] in "RH")
            row_u.append(u.of("angular stiffness") if rot else u.of("stiffness"))
        p = self.analysis.solution.params_degrees()
        return {
            "pm": self.analysis.model.name,
            "pose": p,
            "about": "o", "order": "[v; w] -> [f; m]",
            "o": self.analysis.solution.position,
            "workload": {"force": self.force, "torque": self.torque, "applied_at": "o"},
            "stiffness": self.K[0],
            **({} if self.geometric is None else {"elastic": self.elastic[0],
                                                  "geometric": self.geometric[0]}),
            "rank": self.rank,
            "compliance": self.compliance[0],
            "deflection": {"translation": self.deflection[0, :3],
                           "rotation": self.deflection[0, 3:]},
            "restrained": bool(self.restrained[0]),
            "principal": {"translational": {"stiffness": kt, "directions": dt.T},
                          "rotational": {"stiffness": kr, "axes": dr.T}},
            "rows": [{"label": ri.label, "stiffness": (None if not np.isfinite(k) else k),
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


def _about_o(J, o):
    """Rows ``[f; m - o x f]`` (N, m, 6) about ``o (N, 3)``."""
    f = J[..., :3]
    return np.concatenate([f, J[..., 3:] - np.cross(o[:, None, :], f)], axis=-1)


def _deflect(Jo, k, W, L, K, symmetric=True):
    """Compliance ``(N, 6, 6)``, deflection ``(N, 6)`` and ``restrained`` with rigid rows."""
    N, m, _ = Jo.shape
    S = np.array([L, L, L, 1.0, 1.0, 1.0])
    Js = Jo * S                                          # rows on [dp / L; dtheta]
    finite = np.isfinite(k)
    Ks = K * S[None, :, None] * S[None, None, :]
    C = np.full((N, 6, 6), np.nan)
    X = np.full((N, 6), np.nan)
    ok = np.zeros(N, bool)
    for pattern in {tuple(row) for row in finite}:
        sel = np.all(finite == np.array(pattern), axis=1)
        rig = np.flatnonzero(~np.array(pattern))
        Jr = Js[sel][:, rig]
        Jr = Jr / np.maximum(np.linalg.norm(Jr, axis=-1, keepdims=True), 1e-300)
        nr = rig.size
        scale = np.maximum(np.abs(Ks[sel]).max(axis=(1, 2)), 1e-300)
        KKT = np.zeros((int(sel.sum()), 6 + nr, 6 + nr))
        KKT[:, :6, :6] = Ks[sel] / scale[:, None, None]
        KKT[:, :6, 6:] = Jr.transpose(0, 2, 1)
        KKT[:, 6:, :6] = Jr
        U, s, Vt = np.linalg.svd(KKT)
        good = s[:, -1] > RANK_RTOL * s[:, 0]
        inv = np.einsum("nji,nj,nkj->nik", Vt, 1.0 / np.where(s > 0, s, 1.0), U)
        Cs = inv[:, :6, :6] / scale[:, None, None]
        Cp = Cs * S[None, :, None] * S[None, None, :]   # back to [dp; dtheta] <- [F; T]
        Cp[~good] = np.nan
        C[sel] = 0.5 * (Cp + Cp.transpose(0, 2, 1)) if symmetric else Cp
        ok[sel] = good
    X = np.einsum("nij,nj->ni", C, W)
    return C, X, ok


def stiffness(model, pose=None, *, params=None, actuator=None, force_stiffness=None,
              couple_stiffness=None, rows=None, force=PAPER_FORCE,
              torque=PAPER_TORQUE, geometric: bool = False,
              degrees: bool = False, **kwargs) -> StiffnessResult:
    """The Cartesian stiffness, compliance and deflection of a PM at one or N poses.

    Parameters
    ----------
    model : PMModel or str
    pose : dict, optional
        As :func:`screwkit.analyze` (default: the model's default pose).
    params : DynamicsParameters, mapping or path, optional
        The legs' stiffnesses (the ``stiffness:`` of a ``dynamics:`` block; default the
        model's own, if it has one).
    actuator, force_stiffness, couple_stiffness : float, optional
        One stiffness for every actuation, constraint force and constraint couple row
        (model units: force/length, torque/rad).
    rows : mapping label -> float, optional
        Stiffness of particular rows (``None``: rigid).
    force, torque : array_like (3,)
        The workload at ``o`` whose deflection is computed (default: the paper's).
    geometric : bool
        Add the load-dependent term ``K_g = -d(J^T F_r + W)/dX`` of the workload as a
        preload (:mod:`~._geometric`): ``K`` is then the tangent stiffness ``J^T diag(k) J +
        K_g`` (``elastic`` and ``geometric`` hold the parts), and the deflection its.
    degrees : bool
    **kwargs
        Passed to :func:`screwkit.engine.analyze` (``guess``, ``overrides``...).

    Returns
    -------
    StiffnessResult
    """
    from ..engine import analyze, load_assembled_pm
    from ..pm import PMModel
    from ._dynamics import resolve_parameters

    if not isinstance(model, PMModel):
        model = load_assembled_pm(model, kwargs.pop("overrides", None))
    if params is not None or model.dynamics is not None:
        params = resolve_parameters(model, params)
    an = analyze(model, pose, force=force, torque=torque, degrees=degrees, **kwargs)
    return stiffness_of(an, params, actuator=actuator, force_stiffness=force_stiffness,
                        couple_stiffness=couple_stiffness, rows=rows, geometric=geometric)


def stiffness_of(an, params=None, *, actuator=None, force_stiffness=None,
                 couple_stiffness=None, rows=None, geometric: bool = False) -> StiffnessResult:
    """:func:`stiffness` of an existing :class:`~screwkit.engine.PMAnalysis` (its poses and
    workload), with ``params`` a resolved :class:`~screwkit.pm.DynamicsParameters` or None."""
    model = an.model
    k = row_stiffness(an, params, actuator=actuator, force=force_stiffness,
                      couple=couple_stiffness, rows=rows)
    J = an.jacobian.matrix
    o = an.solution._platform[1]
    Jo = _about_o(J, o)
    kk = np.where(np.isfinite(k), k, 0.0)
    K = np.einsum("nri,nr,nrj->nij", Jo, kk, Jo)
    K = 0.5 * (K + K.transpose(0, 2, 1))
    elastic, Kg = K, None
    if geometric:
        from ._geometric import geometric_stiffness
        Kg = -geometric_stiffness(model, an)
        K = elastic + Kg
    W = np.broadcast_to(np.concatenate([an.force, an.torque]), (len(J), 6))
    C, X, ok = _deflect(Jo, k, W, float(model.normalisation.length), np.nan_to_num(K),
                        symmetric=not geometric)
    bad = ~an.solution.reachable_mask | an.jacobian.singular_mask
    C[bad], X[bad] = np.nan, np.nan
    notes = []
    if np.all(np.isinf(k)):
        notes.append("no row has a stiffness: the PM is rigid (give stiffnesses with params=, "
                     "actuator=, force_stiffness=, couple_stiffness= or rows=)")
    elif np.any(np.isinf(k)):
        rig = sorted({an.jacobian.info[r].label for r in np.flatnonzero(np.isinf(k).any(axis=0))})
        notes.append(f"rigid rows (no stiffness): {', '.join(rig)}")
    if geometric and model.stated_dof < 6:
        notes.append("the geometric term covers the PM's own motion only (its constrained "
                     "directions move by the legs' deformation)")
    for x in (k, K, C, X):
        x.setflags(write=False)
    return StiffnessResult(an, k, K, C, X, ok & ~bad, np.array(an.force), np.array(an.torque),
                           tuple(notes), elastic, Kg)
