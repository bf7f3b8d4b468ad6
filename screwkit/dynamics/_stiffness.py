"""The stiffness of a PM from its unified Jacobian and the compliance of its legs.

Each row ``r`` of ``J = [J_a; J_c]`` (a leg's actuation or constraint wrench) is given a
stiffness ``k_r`` (:func:`row_stiffness`): its effort changes by ``dF_r = -k_r J_r dX``
when the platform moves by the small twist ``dX``.  With the rows written about the
platform centre ``o`` (``[f; m_o]``, ``m_o = m - o x f``) and ``dX = [dp_o; dtheta]``::

    K = J_o^T diag(k) J_o        (6 x 6, [v; w] -> [f; m] about o, symmetric, PSD)

over the rows that have a stiffness; its rank is the number of independent such rows.  A
row without a stiffness is rigid: it carries load without deflecting.  The compliance ``C``
(``dX = C W`` under the workload ``W = [F; T]`` at ``o``) comes from the rows' compliances
``1 / k`` without inverting ``K`` (:mod:`~._compliance`: ``J^-1 diag(1/k) J^-T`` for a
square ``J``): a rigid row has exactly zero compliance, a PM rigid everywhere exactly zero
deflection, and a pose the engine flags singular has its **unrestrained** directions named
(the twists no row resists), the deflection being solved on the others.  Every pose also
carries the engine's conditioning class (``regular``, ``near-singular``, ``singular``: the
same as ``analyze``).  Principal stiffnesses: the eigenvalues of the translational block
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

import numpy as np

from ..errors import InputError
from ..legs._guards import MAX_STIFFNESS, MIN_STIFFNESS
from ..screws import RANK_RTOL
from ._stiffness_result import StiffnessResult

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
    kinds = {"actuation" if r.kind == "actuation" else ("couple" if r.kind == "couple"
                                                        else "force") for r in info}
    for name, v, kind in (("actuator", actuator, "actuation"), ("force", force, "force"),
                          ("couple", couple, "couple")):
        if v is None:
            continue
        _check_stiffness(v, f"{name} stiffness")
        if kind not in kinds:
            what = {"actuation": "actuation", "force": "constraint force",
                    "couple": "constraint couple"}[kind]
            raise InputError(f"{model.name} has no {what} rows: a {name} stiffness would "
                             f"give nothing a stiffness (its rows: "
                             f"{', '.join(r.label for r in info)})")
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
        if not isinstance(rows, dict):
            raise InputError(f"rows must be a mapping row label -> stiffness, got "
                             f"{type(rows).__name__}")
        labels = [ri.label for ri in info]
        for lab, v in rows.items():
            if lab not in labels:
                raise InputError(f"{model.name}: no row {lab!r}; the rows are {', '.join(labels)}")
            k[:, labels.index(lab)] = np.inf if v is None else _check_stiffness(
                v, f"the stiffness of row {lab}")
    bad = ~(k > 0) | (np.isfinite(k) & ~((k >= MIN_STIFFNESS) & (k <= MAX_STIFFNESS)))
    if np.any(bad):
        r = int(np.flatnonzero(bad.any(axis=0))[0])
        raise InputError(f"{model.name}: row {info[r].label} gets the stiffness "
                         f"{float(k[bad[:, r], r][0]):.3g} (a beam's?), outside "
                         f"{MIN_STIFFNESS:g} .. {MAX_STIFFNESS:g} (leave a row out for a rigid "
                         "one)")
    return k


def _check_stiffness(v, what) -> float:
    """A stiffness value: a real number from MIN_STIFFNESS to MAX_STIFFNESS."""
    from ..legs._guards import real
    x = real(v, what)
    if not MIN_STIFFNESS <= x <= MAX_STIFFNESS:
        raise InputError(f"{what} = {x:g} is outside {MIN_STIFFNESS:g} .. {MAX_STIFFNESS:g} "
                         "(leave a row without a stiffness for a rigid one)")
    return x




def stiffness(model, pose=None, *, params=None, actuator=None, force_stiffness=None,
              couple_stiffness=None, rows=None, force=None, torque=None,
              geometric: bool = False, degrees: bool = False, **kwargs) -> StiffnessResult:
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
        (model units: force/length, torque/rad), from ``MIN_STIFFNESS`` to
        ``MAX_STIFFNESS``; one given for rows the PM does not have is an error.
    rows : mapping label -> float, optional
        Stiffness of particular rows (``None``: rigid).
    force, torque : array_like (3,), optional
        The workload at ``o`` whose deflection is computed (one without the other: the
        other is zero; neither: the model's declared default).  Without any, ``K``, the
        compliance and the principal stiffnesses are computed and ``deflection`` is None.
    geometric : bool
        Add the load-dependent term ``K_g = -d(J^T F_r + W)/dX`` of the workload as a
        preload (:mod:`~._geometric`): ``K`` is then the tangent stiffness ``J^T diag(k) J +
        K_g`` (``elastic`` and ``geometric`` hold the parts), and the deflection its.  Needs
        a workload.
    degrees : bool
    **kwargs
        Passed to :func:`screwkit.engine.analyze` (``guess``, ``overrides``...).

    Returns
    -------
    StiffnessResult
    """
    from ..engine import analyze, load_assembled_pm
    from ..engine._inputs import check_forwarded
    from ._dynamics import resolve_parameters

    check_forwarded("screwkit.dynamics.stiffness", analyze,
                    {k: v for k, v in kwargs.items() if k != "overrides"},
                    ("params", "actuator", "force_stiffness", "couple_stiffness", "rows",
                     "geometric", "overrides"))
    model = load_assembled_pm(model, kwargs.pop("overrides", None))
    if params is not None or model.dynamics is not None:
        params = resolve_parameters(model, params)
    from ..legs._guards import flag
    geometric = flag(geometric, "geometric")
    an = analyze(model, pose, force=force, torque=torque, degrees=degrees, **kwargs)
    return stiffness_of(an, params, actuator=actuator, force_stiffness=force_stiffness,
                        couple_stiffness=couple_stiffness, rows=rows, geometric=geometric)


def stiffness_of(an, params=None, *, actuator=None, force_stiffness=None,
                 couple_stiffness=None, rows=None, geometric: bool = False) -> StiffnessResult:
    """:func:`stiffness` of an existing :class:`~screwkit.engine.PMAnalysis` (its poses and
    workload), with ``params`` a resolved :class:`~screwkit.pm.DynamicsParameters` or None."""
    from ._compliance import flexibility, rows_about_o

    model = an.model
    if geometric and not an.has_workload:
        an.statics.F_r                         # raises: the preload needs a workload
    if geometric and an.statics is None:       # (one pose, singular: no efforts to preload)
        from ..errors import SingularityError
        raise SingularityError("the geometric stiffness needs the efforts under the workload "
                               "(the preload), which a singular pose does not have: drop "
                               "the geometric term (--geometric) to get the elastic stiffness "
                               "and the unrestrained directions there")
    k = row_stiffness(an, params, actuator=actuator, force=force_stiffness,
                      couple=couple_stiffness, rows=rows)
    reach = np.asarray(an.solution.reachable_mask, bool)
    sing = an.jacobian.singular_mask & reach
    Jo = rows_about_o(an)
    kk = np.where(np.isfinite(k), k, 0.0)
    K = np.einsum("nri,nr,nrj->nij", Jo, kk, Jo)
    K = 0.5 * (K + K.transpose(0, 2, 1))
    L = float(model.normalisation.length)
    thr = float(an.jacobian.threshold)
    spare = np.zeros(Jo.shape[1:])                # rows of no pose (unreachable ones)
    spare[:min(6, len(spare))] = np.eye(6)[:len(spare)]
    C, free, n_free = flexibility(np.where(reach[:, None, None], Jo, spare), k, L, sing, thr)
    elastic, Kg = K, None
    if geometric:
        from ._geometric import geometric_stiffness
        Kg = np.nan_to_num(-geometric_stiffness(model, an))
        C = _tangent_compliance(C, Kg, Jo, k, free, n_free, L)
        # a singular pose of a batch has no efforts to preload with: its tangent stiffness
        # is undefined (NaN, flagged by the analysis' singular mask and a note), not the
        # elastic one
        Kg = np.where(sing[:, None, None], np.nan, Kg)
        C = np.where(sing[:, None, None], np.nan, C)
        K = elastic + Kg
    C = np.where(reach[:, None, None], C, 0.0)
    n_free = np.where(reach, n_free, 0)
    X = None
    if an.has_workload:
        W = np.concatenate([an.force, an.torque])
        X = np.einsum("nij,j->ni", C, W)
        X.setflags(write=False)
    notes = _notes(an, k, geometric, model)
    for x in (k, K, C):
        x.setflags(write=False)
    return StiffnessResult(an, k, K, C, X, (n_free == 0) & reach,
                           np.array(an.force) if an.has_workload else None,
                           np.array(an.torque) if an.has_workload else None,
                           tuple(notes), elastic, Kg, free, n_free, an.workload_source)


def _notes(an, k, geometric, model) -> list:
    notes = []
    if np.all(np.isinf(k)):
        notes.append("no row has a stiffness: every row is rigid, the PM is rigid in every "
                     "direction (K infinite; compliance and deflection exactly zero)")
    elif np.any(np.isinf(k)):
        rig = sorted({an.jacobian.info[r].label for r in np.flatnonzero(np.isinf(k).any(axis=0))})
        notes.append(f"rigid rows (no stiffness): {', '.join(rig)}")
    sing = np.flatnonzero(an.jacobian.singular_mask & np.asarray(an.solution.reachable_mask,
                                                                  bool))
    if geometric and sing.size:
        shown = ", ".join(str(i) for i in sing[:10]) + (", ..." if sing.size > 10 else "")
        notes.append(f"the tangent stiffness is undefined at {sing.size} singular pose(s) "
                     f"(index {shown}: no efforts to preload with): K, the compliance and the "
                     "deflection are NaN there, the elastic stiffness is in .elastic")
    if geometric and model.stated_dof < 6:
        notes.append("the geometric term covers the PM's own motion only (its constrained "
                     "directions move by the legs' deformation)")
    if not an.has_workload:
        notes.append("no workload: the deflection is not computed")
    return notes


def _tangent_compliance(Ce, Kg, Jo, k, free, n_free, L):
    """The compliance of the tangent stiffness ``K + K_g`` (not symmetric with a geometric
    term) with the rigid rows and the unrestrained directions held fixed, from the elastic
    compliance ``Ce`` (:func:`._compliance.flexibility`): on the null space ``B`` of the
    rigid rows and free twists (length-normalised), ``C = B (B^T K_t B)^-1 B^T`` and
    ``(B^T K_t B)^-1 = (I + B^T Ce K_g B)^-1 B^T Ce B``: the geometric term enters as the
    perturbation it is, and the elastic compliance keeps its accuracy whatever the spread
    of the row stiffnesses (a pseudo-inverse of ``B^T K_t B`` cut the soft directions of
    rows 1e13 times stiffer than others: their compliance read 0)."""
    S = np.array([L, L, L, 1.0, 1.0, 1.0])
    Kx = S[None, :, None] * Kg * S[None, None, :]
    Cx = Ce / (S[None, :, None] * S[None, None, :])
    Jx = Jo * S
    Jx = Jx / np.maximum(np.linalg.norm(Jx, axis=-1, keepdims=True), 1e-300)
    Fx = free / S[None, :, None]
    N = len(Jo)
    C = np.zeros((N, 6, 6))
    for n in range(N):
        cons = np.vstack([Jx[n][~np.isfinite(k[n])], Fx[n, :, :n_free[n]].T])
        if len(cons):
            _, s, Vt = np.linalg.svd(cons)
            rank = int(np.sum(s > RANK_RTOL * max(s[0], 1e-300)))
            B = Vt[rank:].T
        else:
            B = np.eye(6)
        if B.shape[1] == 0:
            continue
        Er = B.T @ Cx[n] @ B                    # (B^T K_e B)^-1, the elastic part
        M = np.eye(B.shape[1]) + Er @ (B.T @ Kx[n] @ B)
        try:
            C[n] = B @ np.linalg.solve(M, Er) @ B.T
        except np.linalg.LinAlgError:           # (a buckling load: the tangent is singular)
            C[n] = B @ np.linalg.pinv(M) @ Er @ B.T
    return S[None, :, None] * C * S[None, None, :]
