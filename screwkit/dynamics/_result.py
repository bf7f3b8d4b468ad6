"""The result of :func:`screwkit.dynamics.dynamics`: :class:`DynamicsResult`, with static
and dynamic columns, CSV, JSON and the Fig. 5-style plot."""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..engine import LENGTH_PARAMS, PARAMS
from ._table import mass_in_kg as _kg
from ._table import unit_converter as _converter
from ._table import write_text as _write

__all__ = ["DynamicsResult", "STATUSES"]

#: The values of :attr:`DynamicsResult.status`: ``ok`` (solved, regular), the conditioning
#: class of :func:`screwkit.engine.classify` where it is not regular, or ``undetermined``.
STATUSES = ("ok", "near-singular", "singular", "unreachable", "undetermined")


def _ro(a):
    a = np.array(a, float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class DynamicsResult:
    """Inverse dynamics of a PM along a motion (N samples; arrays have the samples first).

    Attributes
    ----------
    model : PMModel
    motion : Motion
    params : DynamicsParameters
    analysis : PMAnalysis
        The engine's analysis along the motion; ``analysis.statics`` are the **static**
        values (the external workload alone).
    statics : StaticsResult
        The unified statics under the **dynamic** workload (:attr:`workload`).
    data : dict
        The arrays of the chunks (see the properties).
    flagged, undetermined : ndarray (N,) of bool
    force, torque : ndarray (3,)
        External workload at ``o``.
    workload_source : str
        Where it comes from (``given``, ``declared default (...)``).

    All values are in the model's units and seconds (angles in radians).
    """

    model: object
    motion: object
    params: object
    analysis: object
    statics: object
    data: dict = field(repr=False)
    flagged: np.ndarray = field(repr=False)
    undetermined: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    torque: np.ndarray = field(repr=False)
    workload_source: str = "given"

    def __len__(self) -> int:
        return len(self.motion)

    def __repr__(self) -> str:
        c = self.counts()
        return (f"DynamicsResult({self.model.name}: {len(self)} samples, "
                + ", ".join(f"{v} {k}" for k, v in c.items() if v) + ")")

    # -- status -----------------------------------------------------------------------
    @property
    def t(self) -> np.ndarray:
        return self.motion.t

    @cached_property
    def status(self) -> np.ndarray:
        """``ok`` (regular), ``near-singular``, ``singular`` (J singular), ``unreachable``
        (the conditioning class of :func:`screwkit.engine.classify`, as every command says
        it), or ``undetermined`` (the rates of the dependent parameters are not determined
        there: a representation singularity of the Euler angles or a constraint
        singularity), per sample."""
        cls = self.conditioning
        s = np.where((cls == "near-singular") & self.undetermined, "undetermined", cls)
        s = np.where(cls == "regular", np.where(self.undetermined, "undetermined", "ok"), s)
        return s.astype(str)

    @property
    def conditioning(self) -> np.ndarray:
        """The conditioning class of each sample (``regular``, ``near-singular``,
        ``singular``, ``unreachable``): :attr:`PMAnalysis.conditioning` of the samples."""
        return np.atleast_1d(self.analysis.conditioning)

    @property
    def ok(self) -> np.ndarray:
        return self.status == "ok"

    def counts(self) -> dict:
        return {s: int(np.sum(self.status == s)) for s in STATUSES}

    # -- kinematics ---------------------------------------------------------------------
    @property
    def params_values(self) -> dict:
        """``Xo Yo Zo alpha beta gamma`` at every sample (radians)."""
        return self.analysis.solution.params

    @property
    def rates(self) -> dict:
        """Time derivatives of the six pose parameters (per s)."""
        return {k: self.data["theta_dot"][:, i] for i, k in enumerate(PARAMS)}

    @property
    def accelerations(self) -> dict:
        return {k: self.data["theta_ddot"][:, i] for i, k in enumerate(PARAMS)}

    @property
    def twist(self) -> np.ndarray:
        """Platform twist ``[v; w]`` about ``O`` ``(N, 6)``."""
        return self.data["twist"]

    @property
    def acceleration(self) -> np.ndarray:
        """Platform spatial acceleration ``dV/dt`` about ``O`` ``(N, 6)``."""
        return self.data["acceleration"]

    @property
    def velocity_o(self) -> np.ndarray:
        """Velocity of the platform centre ``o`` ``(N, 3)``."""
        V, o = self.twist, self.analysis.solution._platform[1]
        return V[:, :3] + np.cross(V[:, 3:], o)

    @property
    def acceleration_o(self) -> np.ndarray:
        """Acceleration of the platform centre ``o`` ``(N, 3)``."""
        V, A, o = self.twist, self.acceleration, self.analysis.solution._platform[1]
        w = V[:, 3:]
        return A[:, :3] + np.cross(A[:, 3:], o) + np.cross(w, self.velocity_o)

    def _per_leg(self, key):
        return tuple(self.data[key][:, i, :len(lg.joints)]
                     for i, lg in enumerate(self.model.home_legs))

    @property
    def joint_rates(self) -> tuple:
        """Each leg's joint rates ``(N, m_i)``."""
        return self._per_leg("qd")

    @property
    def joint_accelerations(self) -> tuple:
        return self._per_leg("qdd")

    @property
    def joint_efforts(self) -> tuple:
        """Each leg's joint efforts for its own links ``(N, m_i)``: inertia minus gravity,
        plus friction (the leg's balance: with its wrench ``w`` on the platform, ``ID +
        T^T w`` is 0 at every passive joint and ``F_a`` at the actuated one)."""
        return self._per_leg("ID")

    def _actuated(self, key):
        legs = list(self.model.active)                 # a passive leg has no actuator
        act = [self.model.home_legs[i].actuated_index for i in legs]
        return self.data[key][:, legs, act]

    @property
    def actuator_rates(self) -> np.ndarray:
        """``(N, n_a)``: the actuated joints' rates (the actuated legs, ``model.active``)."""
        return self._actuated("qd")

    @property
    def actuator_accelerations(self) -> np.ndarray:
        return self._actuated("qdd")

    # -- forces -------------------------------------------------------------------------
    def _mask(self, x):
        x = np.array(x, float)
        x[self.flagged] = np.nan
        return x

    @cached_property
    def static_active(self) -> np.ndarray:
        """Active forces under the external workload alone ``(N, n)``."""
        return self._mask(self.analysis.statics.active)

    @cached_property
    def dynamic_active(self) -> np.ndarray:
        """Active forces with gravity, inertia and friction ``(N, n)``."""
        return self._mask(self.statics.active)

    @cached_property
    def static_constraint(self) -> np.ndarray:
        return self._mask(self.analysis.statics.constraint)

    @cached_property
    def dynamic_constraint(self) -> np.ndarray:
        """Constraint values of the dynamic statics ``(N, m - n)`` (of the static part
        ``w_s`` of each leg's wrench; :attr:`leg_wrenches` adds the mapped part)."""
        return self._mask(self.statics.constraint)

    @cached_property
    def leg_wrenches(self) -> np.ndarray:
        """The wrench ``[f; m]`` about ``O`` each leg applies to the platform, inertia
        included: ``w = sum_rows F_r J_r + u`` ``(N, n, 6)``."""
        return self._mask(self.statics.leg_wrenches + self.data["mapped"])

    @property
    def mapped_wrenches(self) -> np.ndarray:
        """Each leg's dynamics mapped into the workload, ``u`` ``(N, n, 6)``."""
        return self.data["mapped"]

    @property
    def workload(self) -> np.ndarray:
        """The dynamic workload about ``O``: ``W_ext - W_platform + sum u`` ``(N, 6)``."""
        return self.data["workload"]

    @property
    def platform_wrench(self) -> np.ndarray:
        """The wrench the platform needs for its motion (inertia minus gravity) ``(N, 6)``."""
        return self.data["platform_wrench"]

    @cached_property
    def T_r(self) -> np.ndarray:
        return self._mask(self.statics.T_r)

    # -- energy -------------------------------------------------------------------------
    @property
    def kinetic_energy(self) -> np.ndarray:
        return self.data["kinetic"]

    @property
    def potential_energy(self) -> np.ndarray:
        """Gravity's potential energy ``-sum m g . c`` (zero at ``O``)."""
        return self.data["potential"]

    @cached_property
    def actuator_power(self) -> np.ndarray:
        """``sum_i F_ai rdot_i`` ``(N,)``."""
        return np.sum(self.dynamic_active * self.actuator_rates, axis=1)

    @cached_property
    def external_power(self) -> np.ndarray:
        """Power of the external workload on the platform ``W_ext . V`` ``(N,)``."""
        o = self.analysis.solution._platform[1]
        W = np.concatenate([np.broadcast_to(self.force, o.shape),
                            self.torque + np.cross(o, self.force)], axis=1)
        return np.sum(W * self.twist, axis=1)

    # -- residuals ----------------------------------------------------------------------
    @property
    def residuals(self) -> dict:
        """Per sample: closure ``velocity`` and ``acceleration`` residuals of the legs,
        each leg's ``balance`` (``|ID + T^T u|`` relative), the dynamic statics'
        ``equilibrium``, the ``kinematic_condition`` of the dependent-rate system."""
        return {"velocity": self.data["velocity_residual"],
                "acceleration": self.data["acceleration_residual"],
                "balance": self.data["balance_residual"],
                "equilibrium": self._mask(self.statics.equilibrium_residual),
                "kinematic_condition": self.data["kinematic_condition"]}

    # -- export -------------------------------------------------------------------------
    @property
    def rotary(self) -> tuple:
        return tuple(lg.actuated_joint.kind != "P" for lg in self.model.home_legs)

    def columns(self, units=None) -> list:
        """``(name, (N,) array, unit)`` of the CSV (angles in degrees), in the model's units
        (``units`` None or ``"model"``) or in SI (``"SI"``: m, N, N.m, kg; angles and times
        as they are)."""
        if units is not None and units != "model":
            conv = _converter(self.model, units)
            return [(c, v * conv(un)[0], conv(un)[1]) for c, v, un in self.columns()]
        u = self.model.units
        n = self.model.n_legs
        act = self.model.active                        # the actuated legs
        sol = self.analysis.solution
        cols = [("t", self.t, "s")]
        for k in PARAMS:
            v = self.params_values[k]
            cols.append((k, v if k in LENGTH_PARAMS else np.degrees(v),
                         u.length if k in LENGTH_PARAMS else "deg"))
        ext = self._mask(sol._extensions)
        cols += [(f"r{i + 1}", ext[:, i], u.length) for i in range(n)]
        # a rotary actuator's joint angle q_i (the extension r_i is not what it drives: its
        # rates are the angle's, qdot_i, as screwkit.forward names the angle q_i)
        qa = self._mask(np.asarray(sol.actuator_values, float).reshape(len(self), -1))
        cols += [(f"q{i + 1}", np.degrees(qa[:, k]), "deg") for k, i in enumerate(act)
                 if self.rotary[i]]
        rv = ["q" if r else "r" for r in self.rotary]
        act_u = [u.torque if r else u.force for r in self.rotary]
        rate_u = [f"{'rad' if r else u.length}/s" for r in self.rotary]
        cols += [(f"{rv[i]}dot{i + 1}", self.actuator_rates[:, k], rate_u[i])
                 for k, i in enumerate(act)]
        acc_u = [f"{'rad' if r else u.length}/s^2" for r in self.rotary]
        cols += [(f"{rv[i]}ddot{i + 1}", self.actuator_accelerations[:, k], acc_u[i])
                 for k, i in enumerate(act)]
        fa = ["T_a" if r else "F_a" for r in self.rotary]         # a rotary actuator: torque
        cols += [(f"{fa[i]}{i + 1}", self.static_active[:, k], act_u[i])
                 for k, i in enumerate(act)]
        cols += [(f"{fa[i]}{i + 1}_dyn", self.dynamic_active[:, k], act_u[i])
                 for k, i in enumerate(act)]
        info = self.analysis.jacobian.info[len(act):]
        cu = [u.torque if r.kind == "couple" else u.force for r in info]
        cols += [(r.label, self.static_constraint[:, j], cu[j]) for j, r in enumerate(info)]
        cols += [(f"{r.label}_dyn", self.dynamic_constraint[:, j], cu[j])
                 for j, r in enumerate(info)]
        e = f"{u.force}.{u.length}"
        cols += [("kinetic_energy", self.kinetic_energy, e),
                 ("potential_energy", self.potential_energy, e),
                 ("actuator_power", self.actuator_power, f"{e}/s")]
        # the external workload at o the static columns (and the dynamic ones, beside the
        # inertia and gravity) carry: a table says which load it is of
        N = len(self.t)
        F = np.zeros(3) if self.force is None else np.asarray(self.force, float)
        T = np.zeros(3) if self.torque is None else np.asarray(self.torque, float)
        cols += [(f"workload_F{x}", np.full(N, F[j]), u.force) for j, x in enumerate("xyz")]
        cols += [(f"workload_T{x}", np.full(N, T[j]), u.torque) for j, x in enumerate("xyz")]
        return cols

    def to_csv(self, out=None, units=None):
        """CSV: a header row (``name [unit]``), ``status`` after ``t``, ``conditioning``
        last; NaN as ``nan``; ``units``: as :meth:`columns`."""
        cols = self.columns(units)
        cls = self.conditioning
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([f"{cols[0][0]} [s]", "status"] + [f"{c} [{un}]" for c, _, un in cols[1:]]
                   + ["conditioning"])
        for i in range(len(self)):
            w.writerow([f"{cols[0][1][i]:.12g}", self.status[i]]
                       + [f"{float(v[i]):.12g}" for _, v, _ in cols[1:]] + [cls[i]])
        text = buf.getvalue()
        if out is None:
            return text
        _write(text, out)
        return None

    def to_dict(self, units=None) -> dict:
        """JSON-ready (column-oriented; angles in degrees, a unit for every column);
        ``units``: as :meth:`columns`."""
        cols = self.columns(units)
        u = self.model.units
        block = {**u.as_dict(), "time": "s", "mass": self.params.mass_unit}
        F, T = self.force, self.torque
        fu, tu = u.force, u.torque
        if units is not None and units != "model":
            conv = _converter(self.model, units)
            block.update(length="m", force="N", torque="N.m", mass=conv(block["mass"])[1],
                         converted_from=f"{u.length}, {u.force}")
            F = None if F is None else np.asarray(F, float) * conv(u.force)[0]
            T = None if T is None else np.asarray(T, float) * conv(u.torque)[0]
            fu, tu = "N", "N.m"
        return {"pm": self.model.name, "n_samples": len(self), "counts": self.counts(),
                "units": block,
                "workload": {"force": F, "torque": T, "applied_at": "o",
                             "source": self.workload_source, "force_unit": fu,
                             "torque_unit": tu},
                "gravity": self.params.gravity, "motion": {"source": self.motion.source,
                                                           "derivatives": self.motion.method},
                "notes": list(self.params.notes) + list(self.motion.notes),
                "status": self.status.tolist(),
                "conditioning": self.conditioning.tolist(),
                "columns": {c: {"unit": un, "values": v} for c, v, un in cols},
                "residuals": {k: v for k, v in self.residuals.items()}}

    def plot(self, out=None, *, title=None, dpi: int = 150, units=None):
        """Fig. 5-style panels with the dynamic curves beside the static ones
        (:func:`screwkit.viz.plot_dynamics`); ``units``: as :meth:`columns`."""
        from ..viz import plot_dynamics
        u = self.model.units
        si = units is not None and units != "model"
        conv = _converter(self.model, units) if si else (lambda x: (1.0, x))
        (kl, lu), (kf, fu), (kt, tu) = conv(u.length), conv(u.force), conv(u.torque)
        p = self.params_values
        pose = {k: (p[k] * kl if k in LENGTH_PARAMS else np.degrees(p[k]))
                for k in self.model.independent}
        n_a = len(self.model.active)
        info = self.analysis.jacobian.info
        labels = [r.label for r in info[n_a:]]
        kinds = [r.kind for r in info[n_a:]]
        ka = np.array([kt if self.rotary[i] else kf for i in self.model.active])
        kc = np.array([kt if r.kind == "couple" else kf for r in info[n_a:]])
        if title is None:
            title = (f"{self.model.name}: static (dashed) and dynamic (solid); "
                     f"F = [{', '.join(f'{x * kf:g}' for x in self.force)}] {fu}, "
                     f"T = [{', '.join(f'{x * kt:g}' for x in self.torque)}] {tu} at o, "
                     f"platform mass {_kg(self.model.units, self.params.platform.mass)}")
        return plot_dynamics(self.t, pose, self.static_active * ka, self.dynamic_active * ka,
                             self.static_constraint * kc, self.dynamic_constraint * kc,
                             labels, kinds, (self.kinetic_energy + self.potential_energy) * kt,
                             self.actuator_power * kt,
                             units={"length": lu, "force": fu, "torque": tu,
                                    "energy": tu.replace(".", "·")},
                             flags=~self.ok, out=out, title=title, dpi=dpi,
                             active_legs=self.model.active,
                             active_rotary=[self.rotary[i] for i in self.model.active],
                             constraint_legs=[r.leg for r in self.analysis.jacobian.info[n_a:]])
