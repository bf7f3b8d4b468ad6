"""The report of one analysed pose (``screwkit analyze --json``), with a unit on every number.

Every quantity is reported in the model's units (``model.units``: the catalog's cm and
kN, torques in kN.cm) or, on request, in SI (m, N, N.m) through pint.  A row's value is a
force (``force``, linear actuators) or a torque (``couple``, rotary actuators); its
``vector`` is always the force (or couple) it applies, on its line.  ``T_r`` is reported
for legs with a linear actuator only, where it is the moment of the leg's constraint
wrench about the leg's own axis (the paper's eq. 13e).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._limits import within_limits
from ..errors import MisuseError

__all__ = ["report", "row_quantity", "constraint_resultants", "resultants_determined",
           "output_scales", "unit_row", "twist_space"]

_POSE = ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")


def row_quantity(r) -> str:
    """``"torque"`` for a couple row or the effort of a rotary (R, H) actuator, else ``"force"``."""
    return "torque" if r.torque else "force"


def constraint_resultants(statics, A):
    """Each leg's constraint resultant: ``(f, m_A)``, both ``(..., n_legs, 3)``.

    ``statics`` is a :class:`~screwkit.engine.StaticsResult` or its ``constraint_wrenches``
    (``(..., n_legs, 6)``, about O).  ``f`` is the total force of the leg's constraint rows
    on the platform and ``m_A`` its moment about the leg's base point ``A_i``
    (``m_O - A_i x f``).  Unlike the row values,
    which depend on the basis chosen for the leg's constraint system, these are fixed by
    the leg's wrench alone: they move with the base frame as vectors and scale with the
    units (forces unchanged, moments by the length factor).  ``m_A . delta_i`` is ``T_r``.

    Examples
    --------
    >>> import numpy as np, screwkit
    >>> from screwkit.engine import constraint_resultants
    >>> res = screwkit.analyze("3SPU+SP")
    >>> f, m = constraint_resultants(res.statics, [lg.A for lg in res.solution.legs])
    >>> f.shape, bool(np.abs(m[3]).max() < 1e-9)     # the SP leg's forces pass through A4
    ((4, 3), True)
    """
    w = np.asarray(getattr(statics, "constraint_wrenches", statics), float)   # or (..., n, 6)
    A = np.asarray(A, float).reshape(-1, 3)
    f = w[..., :3]
    return f, w[..., 3:] - np.cross(A, f)


def resultants_determined(statics, A):
    """``(n_legs, 2)`` bools: whether statics alone fixes each leg's resultant force and
    moment about ``A_i`` (False where a self-stress of an indeterminate pose changes it)."""
    jac = statics.jacobian
    A = np.asarray(A, float).reshape(-1, 3)
    out = np.ones((len(A), 2), bool)
    if not statics.indeterminate:
        return out
    S = np.asarray(statics.self_stress)                       # (k, m)
    J = np.asarray(jac.J)
    cons = np.array([r.kind != "actuation" for r in jac.rows])
    for i in range(len(A)):
        sel = np.array([r.leg == i for r in jac.rows]) & cons
        dw = S[:, sel] @ J[sel]                               # (k, 6) about O
        bound = np.abs(S[:, sel]) @ np.abs(J[sel])            # the size of the sum's terms
        df = dw[:, :3]
        dm = dw[:, 3:] - np.cross(A[i], df)
        tol_f = 1e-9 * bound[:, :3].max(initial=0.0)
        tol_m = 1e-9 * (bound[:, 3:].max(initial=0.0)
                        + np.linalg.norm(A[i]) * bound[:, :3].max(initial=0.0))
        out[i] = (np.abs(df).max(initial=0.0) <= tol_f, np.abs(dm).max(initial=0.0) <= tol_m)
    return out


def output_scales(units_of, units=None, name: str = "the model"):
    """``(unit block, factors)`` of a report in the model's units (``units=None``) or in SI
    (``units="SI"``: m, N, N.m through pint).

    ``units_of`` is a model (its ``units``) or a :class:`~screwkit.pm.Units`; the factors
    (``length``, ``force``, ``torque``, ``angle``) multiply a model-unit value into the
    output unit (1 throughout for the model's units).  A model that declares no units
    cannot be converted (InputError).

    Examples
    --------
    >>> from screwkit.pm import Units
    >>> block, k = output_scales(Units("cm", "kN"), "SI")
    >>> block["torque"], round(k["length"], 12), round(k["force"], 9), round(k["torque"], 9)
    ('N.m', 0.01, 1000.0, 10.0)
    """
    u = getattr(units_of, "units", units_of)
    name = getattr(units_of, "name", name)
    if units is None or units == "model":
        return u.as_dict(), {"length": 1.0, "force": 1.0, "torque": 1.0, "angle": 1.0}
    if str(units).upper() != "SI":
        raise InputError(f"units must be the model's (default) or 'SI', got {units!r}")
    if not u.declared:
        raise InputError(f"{name} declares no units (add 'units: {{length: .., force: ..}}' "
                         "to its definition): they cannot be converted")
    f = u.si_factors()
    return {"length": "m", "force": "N", "torque": "N.m", "angle": "deg", "declared": True}, f


_scales = output_scales


def unit_row(row, quantity: str, k: dict) -> np.ndarray:
    """A row of ``J`` (the wrench ``[f; m]`` about O per unit of the row's effort) in the
    output units: ``f`` scales by ``k_force / k_effort``, ``m`` by ``k_torque / k_effort``,
    ``quantity`` (:func:`row_quantity`) naming the effort.  A force row keeps ``|f| = 1``
    (its moment arm scales by the length factor), a couple row ``|m| = 1``, and a rotary
    actuator's row (force per unit torque) scales its force part by ``1 / k_length``."""
    row = np.asarray(row, float)
    ke = k["torque"] if quantity == "torque" else k["force"]
    return np.concatenate([row[..., :3] * (k["force"] / ke), row[..., 3:] * (k["torque"] / ke)],
                          axis=-1)


def row_units(quantity: str, length: str) -> str:
    """The units of a row of ``J`` for the text report: ``[1; cm]`` for a force effort,
    ``[1/cm; 1]`` for a torque (couples, rotary actuators)."""
    return f"[1/{length}; 1]" if quantity == "torque" else f"[1; {length}]"


def report(analysis, units=None) -> dict:
    """The JSON-ready report of a one-pose :class:`~screwkit.engine.PMAnalysis`."""
    if not analysis.single:
        raise MisuseError("to_dict describes one pose: index the result first (res[i])")
    sol, jac, st, model = analysis.solution, analysis.jacobian, analysis.statics, analysis.model
    if not analysis.has_workload:
        st = None                            # no workload: kinematics and J only
    ublock, k = _scales(model, units)
    kl, kf, kt = k["length"], k["force"], k["torque"]
    p = sol.params_degrees()
    det = st.determined if st is not None else None
    linear = [lg.actuated_joint.kind == "P" for lg in sol.legs]
    if st is not None:
        res_f, res_m = constraint_resultants(st, [lg.A for lg in sol.legs])
        res_det = resultants_determined(st, [lg.A for lg in sol.legs])
    legs = []
    for i, leg in enumerate(sol.legs):
        rows = [k_ for k_, r in enumerate(jac.rows) if r.leg == i]
        act = [k_ for k_ in rows if jac.rows[k_].kind == "actuation"]
        cons = []
        for k_ in rows:
            r = jac.rows[k_]
            if r.kind == "actuation":
                continue
            q = row_quantity(r)
            c = {"kind": r.kind, "label": r.label, "direction": r.direction,
                 "unit_wrench": unit_row(jac.J[k_], q, k),
                 "unit": ublock[q]}
            if st is not None:
                c["value"] = st.values[k_] * (kt if q == "torque" else kf)
                c["vector"] = st.vectors[k_] * (kt if q == "torque" else kf)
                c["determined"] = bool(det[k_])
            if r.point is not None:
                c["point"] = r.point * kl
                c["point_name"] = r.point_name
            cons.append(c)
        entry = {
            "index": i + 1, "leg": leg.name, "string": leg.string.marked,
            "passive": i in model.passive,
            "A": leg.A * kl, "a": leg.a * kl, "extension": sol.extensions[i] * kl,
            # (a P joint's value, a Pa's arc included, is a length; the others radians)
            "joint_values": sol.joint_values[i] * np.array(
                [kl if j.kind == "P" else 1.0 for j in model.home_legs[i].joints]),
            "joint_value_units": [ublock["length"] if j.kind == "P" else "rad"
                                  for j in model.home_legs[i].joints],
            "constraints": cons,
        }
        if i not in model.passive:       # a passive leg has no actuator
            entry["actuator_value"] = (sol.actuator_values[model.active.index(i)]
                                       * (kl if linear[i] else 1.0))
            entry["actuator_value_unit"] = ublock["length"] if linear[i] else "rad"
        if act:
            r = jac.rows[act[0]]
            q = row_quantity(r)
            entry["actuation"] = {"kind": r.member, "direction": r.direction,
                                  "point": None if r.point is None else r.point * kl,
                                  "joint": r.joint, "effort": q, "unit": ublock[q],
                                  "unit_wrench": unit_row(jac.J[act[0]], q, k)}
            if st is not None:
                entry["active"] = st.values[act[0]] * (kt if q == "torque" else kf)
                entry["active_unit"] = ublock[q]
        if st is not None:
            if linear[i]:
                entry["torque"] = st.T_r[i] * kt
                entry["torque_name"] = "T_r: moment of the leg's constraint wrench about its axis"
                entry["torque_unit"] = ublock["torque"]
                entry["torque_determined"] = bool(all(det[k_] for k_ in rows))
            entry["wrench"] = _wrench(st.leg_wrenches[i], kl, kf, kt)
            entry["constraint_resultant"] = {
                "force": res_f[i] * kf, "moment": res_m[i] * kt, "about": f"A{i + 1}",
                "point": leg.A * kl, "force_unit": ublock["force"],
                "moment_unit": ublock["torque"],
                "force_determined": bool(res_det[i, 0]), "moment_determined": bool(res_det[i, 1])}
        legs.append(entry)
    m = analysis.mobility
    twist = twist_space(m, kl, ublock["length"])        # (its lengths in the report's unit)
    out = {
        "pm": model.name,
        "units": ublock,
        "pose": {n: (p[n] * kl if n in ("Xo", "Yo", "Zo") else p[n]) for n in _POSE},
        "independent": list(model.independent),
        "order": model.order,
        "closure_residual": sol.residual,
        "notes": list(sol.notes),
        "warnings": list(analysis.warnings),
        "within_limits": bool(within_limits(analysis)[0]),
        "legs": legs,
        "extensions": sol.extensions * kl,
        "jacobian": np.array([unit_row(row, row_quantity(r), k)
                              for row, r in zip(jac.J, jac.info)]),
        "jacobian_convention": ("rows [f; m] about O per unit of the row's effort, acting on "
                                "[v_O; w], in the report's units ([1; length] for a force "
                                "effort, [1/length; 1] for a torque)"),
        "condition_number": jac.condition_number,
        "conditioning": analysis.quality.as_dict(0),
        "transmission": _transmission(analysis, kl, ublock["length"]),
        "singular": jac.singular,
        "singularity_kind": jac.singularity_kind,
        "mobility": {"dof": m.dof, "motion_type": m.motion_type, "finite": m.finite,
                     "instantaneous_type": twist[0], "instantaneous": twist[1],
                     "redundant": m.redundant,
                     "common": m.common, "constraint_rank": m.constraint_rank,
                     "n_constraints": m.n_constraints, "gruebler": m.gruebler,
                     "stated_dof": model.stated_dof, "actuators": m.actuators,
                     "passive_legs": [i + 1 for i in model.passive]},
        "workload": ({"force": analysis.force * kf, "torque": analysis.torque * kt,
                      "applied_at": "o", "force_unit": ublock["force"],
                      "torque_unit": ublock["torque"], "source": analysis.workload_source}
                     if analysis.has_workload else
                     {"force": None, "torque": None, "applied_at": "o", "source": None}),
        "statics": None,
    }
    if st is not None:
        scale = np.array([kt if row_quantity(r) == "torque" else kf for r in jac.info])
        vals = st.values * scale
        n = jac.n_actuated
        out["statics"] = {
            "labels": list(jac.labels),
            "units": [ublock[row_quantity(r)] for r in jac.info],
            "active": vals[:n], "constraint": vals[n:], "values": vals,
            "T_r": [st.T_r[i] * kt if linear[i] else None for i in range(len(linear))],
            "equilibrium_residual": st.equilibrium_residual,
            "indeterminacy": st.indeterminacy,
            "determined": st.determined,
            "solution": ("unique" if not st.indeterminate else
                         "compliance-weighted" if analysis.stiffness is not None else
                         "least-norm"),
        }
        if st.indeterminate:
            # each basis vector is a set of row values (in the rows' units) balancing zero load
            out["statics"]["self_stress"] = st.self_stress * scale[None, :]
            out["statics"]["self_stress_units"] = out["statics"]["units"]
    return out


def _wrench(w, kl, kf, kt):
    """A wrench ``[f; m]`` in the output units."""
    w = np.asarray(w, float)
    return np.concatenate([w[..., :3] * kf, w[..., 3:] * kt])


def _transmission(analysis, kl, length) -> dict:
    """The transmission and constraint indices of the pose, arms in the report's length."""
    d = analysis.indices.as_dict(0)
    for e in d["legs"]:
        for k in ("input_arm", "output_arm"):
            e[k] = None if e[k] is None else e[k] * kl
    for e in d["constraints"]:
        e["arm"] = None if e["arm"] is None else e["arm"] * kl
    d["arm_unit"] = length
    d["convention"] = ("power coefficients |W.V| / (|f| |v(p) + lambda w|) in [0, 1] (Wang, Wu "
                       "and Liu 2010; Liu, Wu and Wang 2012): ITI of each active leg's "
                       "transmission wrench on its actuated joint's twist, OTI on the platform "
                       "twist with the other actuators locked, LTI = min(ITI, OTI), CTI of each "
                       "constraint row on the twist it alone stops; arms: the distance from the "
                       "wrench's entry point to the twist axis; null: not defined "
                       "(a translation, a redundant row); see docs/design.md")
    return d


def twist_space(mob, kl: float, length: str):
    """The twist-space label and description with their lengths (points, pitches) times
    ``kl`` and labelled ``length``."""
    from dataclasses import replace

    from ..pm._mobility import describe_freedoms

    label, text = mob.instantaneous_type, mob.instantaneous
    if kl != 1.0:
        hel = [f.pitch * kl for f in mob.freedoms if f.kind == "helical"]
        if hel and "H(p=" in label:
            label = label[:label.index("H(p=")] + f"H(p={','.join(f'{h:.4g}' for h in hel)})"
        if mob.translations != 3:      # (3 translations: directions only, no lengths)
            text = describe_freedoms([replace(f, point=None if f.point is None else
                                              np.asarray(f.point) * kl, pitch=f.pitch * kl)
                                      for f in mob.freedoms])
    return label, text.replace("(length/rad)", f"({length}/rad)")
