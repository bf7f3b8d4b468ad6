"""A PM analysed at one pose: inverse displacement, mobility, unified Jacobian, statics.

This is what ``screwkit analyze`` prints; :meth:`PMAnalysis.to_dict` is its JSON.

Examples
--------
>>> import screwkit
>>> res = screwkit.analyze("3RRPRR", pose={"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
>>> res.mobility.dof, res.mobility.motion_type
(3, '1T2R')
>>> bool(res.statics.equilibrium_residual < 1e-9)
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["PAPER_FORCE", "PAPER_TORQUE", "PMAnalysis", "analyze_pm"]

#: The paper's workload (section 5.1): F in kN, T in kN.cm, applied at o.
PAPER_FORCE = (-20.0, -30.0, -60.0)
PAPER_TORQUE = (-30.0, -30.0, 100.0)


@dataclass(frozen=True, eq=False)
class PMAnalysis:
    """Everything screwkit says about one PM at one pose under one workload.

    Attributes
    ----------
    model : PMModel
    solution : PoseSolution
        Pose, placed legs, joint values, extensions, closure residual.
    mobility : Mobility
    jacobian : JacobianResult
        ``J = [J_a; J_c]`` with row metadata and the normalised condition number.
    statics : StaticsResult or None
        None when the pose is singular and ``raise_on_singular`` was false.
    force, torque : ndarray (3,)
        The workload applied at ``o``.
    """

    model: object
    solution: object
    mobility: object
    jacobian: object
    statics: object
    force: np.ndarray
    torque: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready report (angles in degrees, lengths/forces in the model's units)."""
        sol, jac, st = self.solution, self.jacobian, self.statics
        p = sol.params_degrees()
        legs = []
        for i, leg in enumerate(sol.legs):
            rows = [k for k, r in enumerate(jac.rows) if r.leg == i]
            act = [k for k in rows if jac.rows[k].kind == "actuation"]
            cons = []
            for k in rows:
                r = jac.rows[k]
                if r.kind == "actuation":
                    continue
                c = {"kind": r.kind, "direction": r.direction, "unit_wrench": jac.J[k]}
                if st is not None:
                    c["value"] = st.values[k]
                    c["vector"] = st.vectors[k]
                if r.point is not None:
                    c["point"] = r.point
                    c["point_name"] = r.point_name
                cons.append(c)
            entry = {
                "index": i + 1, "leg": leg.name, "string": leg.string.marked,
                "A": leg.A, "a": leg.a, "extension": sol.extensions[i],
                "actuator_value": sol.actuator_values[i],
                "joint_values": sol.joint_values[i],
                "constraints": cons,
            }
            if act:
                r = jac.rows[act[0]]
                entry["actuation"] = {"kind": r.member, "direction": r.direction, "point": r.point,
                                      "joint": r.joint, "unit_wrench": jac.J[act[0]]}
                if st is not None:
                    entry["active"] = st.values[act[0]]
            if st is not None:
                entry["torque"] = st.T_r[i]
                entry["wrench"] = st.leg_wrenches[i]
            legs.append(entry)
        m = self.mobility
        out = {
            "pm": self.model.name,
            "pose": {k: p[k] for k in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")},
            "independent": list(self.model.independent),
            "order": self.model.order,
            "closure_residual": sol.residual,
            "notes": list(sol.notes),
            "legs": legs,
            "extensions": sol.extensions,
            "jacobian": jac.J,
            "condition_number": jac.condition_number,
            "singular": jac.singular,
            "singularity_kind": jac.singularity_kind,
            "mobility": {"dof": m.dof, "motion_type": m.motion_type, "redundant": m.redundant,
                         "common": m.common, "constraint_rank": m.constraint_rank,
                         "n_constraints": m.n_constraints, "gruebler": m.gruebler,
                         "stated_dof": self.model.stated_dof},
            "workload": {"force": self.force, "torque": self.torque},
        }
        if st is not None:
            out["statics"] = {
                "active": st.active, "constraint": st.constraint, "values": st.values,
                "T_r": st.T_r, "equilibrium_residual": st.equilibrium_residual,
                "indeterminacy": st.indeterminacy,
            }
        return out


def _vec3(x, name):
    a = np.asarray(x, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be 3 finite numbers, got {x!r}")
    return a


def analyze_pm(pm, pose: dict | None = None, *, force=PAPER_FORCE, torque=PAPER_TORQUE,
               overrides: dict | None = None, degrees: bool = False, guess=None,
               raise_on_singular: bool = True, catalog=None) -> PMAnalysis:
    """Analyse a PM at a pose.

    Parameters
    ----------
    pm : str or PMModel
        Catalog PM name, path of a YAML model, or a loaded model.
    pose : dict, optional
        Independent pose parameters (missing ones from the model's default pose).
    force, torque : array_like (3,)
        Workload at ``o`` (default: the paper's F = [-20, -30, -60] kN,
        T = [-30, -30, 100] kN.cm).
    overrides : dict, optional
        Dimension overrides, e.g. ``{"L": 150}``.
    degrees : bool
        Angles of ``pose`` in degrees.
    raise_on_singular : bool
        Raise :class:`SingularityError` at a singular pose (default) or return
        the analysis with ``statics=None``.
    """
    from ..pm import PMModel, mobility
    from ._assembly import load_assembled_pm
    from ._jacobian import unified_jacobian
    from ._kinematics import solve_pose
    from ._statics import statics

    model = pm if isinstance(pm, PMModel) else load_assembled_pm(pm, overrides, catalog)
    F, T = _vec3(force, "force"), _vec3(torque, "torque")
    sol = solve_pose(model, pose or {}, guess, degrees)
    mob = mobility(sol)
    jac = unified_jacobian(sol.legs, sol.position)
    st = None
    if raise_on_singular or not jac.singular:
        st = statics(jac, F, T, sol.position, raise_on_singular=raise_on_singular)
    return PMAnalysis(model, sol, mob, jac, st, F, T)
