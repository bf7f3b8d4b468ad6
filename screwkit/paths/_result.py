"""The result of a trajectory: :class:`TrajectoryResult` and its CSV, JSON and plots."""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..engine import LENGTH_PARAMS, PARAMS
from ..errors import InputError

__all__ = ["TrajectoryResult", "STATUSES"]

#: The values of :attr:`TrajectoryResult.status`: ``ok`` (solved, regular), then the
#: conditioning class of :func:`screwkit.engine.classify` where it is not regular.
STATUSES = ("ok", "near-singular", "singular", "unreachable")



@dataclass(frozen=True, eq=False)
class TrajectoryResult:
    """A PM's statics sampled along a path.

    Every per-sample array has the samples on its first axis (N).

    Attributes
    ----------
    pm : str
        The PM's name.
    independent : tuple of str
    t : ndarray (N,)
    status : ndarray (N,) of str
        ``ok`` (solved, regular), ``near-singular``, ``singular`` or ``unreachable`` (see
        the module docstring): the sample's conditioning class
        (:func:`screwkit.engine.classify`), ``ok`` where it is regular.
    params : dict str -> ndarray (N,)
        ``Xo Yo Zo alpha beta gamma`` (model length unit, radians).
    extensions : ndarray (N, n)
        ``r_i = |a_i - A_i|``.
    actuator_values : ndarray (N, n_a)
        Displacement of each actuated joint from home (the actuated legs, :attr:`actuated`).
    active : ndarray (N, n_a)
        Active forces ``F_ai`` of the actuated legs (> 0 pushes the platform away from
        ``A_i``).
    constraint : ndarray (N, k)
        Constraint force / couple values, columns :attr:`constraint_labels`
        (the value times the row's unit direction is the force on its line).
    T_r : ndarray (N, n)
        Constraint torque each leg carries about its own axis (paper eq. 13e).
    leg_wrenches : ndarray (N, n, 6)
        Total wrench ``[f; m]`` (about ``O``) each leg applies to the platform.
    condition_number : ndarray (N,)
        Normalised condition number of the unified Jacobian.
    closure_residual : ndarray (N,)
        Length-normalised loop-closure residual.
    equilibrium_residual : ndarray (N,)
        Relative residual of the platform's equilibrium.
    singularity : ndarray (N,) of str
        ``""``, ``"actuation"`` or ``"constraint"``.
    message : ndarray (N,) of str
        Why a sample is flagged (and notes such as a representation singularity).
    constraint_labels, constraint_kinds : tuple of str
        Name (``F_c2``, ``T_c1``) and kind (``force``, ``couple``) of each constraint column.
    constraint_legs : tuple of int
        Leg index (0-based) of each constraint column.
    force, torque : ndarray (3,)
        The workload at ``o``.
    workload_source : str
        Where the workload comes from (``given``, ``declared default (...)``).
    units : Units
        The model's units (:class:`screwkit.pm.Units`).
    rotary : tuple of bool
        Per leg: its actuator is rotary (its ``F_ai`` is a torque).
    diagnostics : dict
        How the samples were computed (``batched``, ``per_pose_kinematics``,
        ``per_pose_rows``), for benchmarks.
    determined : ndarray (N, n + k) of bool, optional
        Per sample, for the active then the constraint columns: False where statics does
        not determine the value (a statically indeterminate PM: the least-norm choice).
    constraint_points : tuple of (str or None)
        Where each constraint column's force passes (``"A_i"``, ``"a_i"``, or the name of
        its point; None for a couple), found at the first regular sample.
    resultant_force, resultant_moment : ndarray (N, n, 3), optional
        Each leg's constraint resultant (:func:`screwkit.engine.constraint_resultants`):
        the total force of its constraint rows and its moment about the leg's base point
        ``A_i``; independent of the basis of the leg's constraint rows (NaN where the
        statics is not solved).
    resultant_determined : ndarray (N, n) of bool, optional
        False where a constraint row of the leg is not determined by statics (then the
        resultant may not be either: a conservative flag).
    active_legs : tuple of int, optional
        The actuated legs (0-based; None: every leg), the columns of :attr:`active`.
    analysis : PMAnalysis, optional
        The batched analysis of the samples (the placed legs of :meth:`show`).
    """

    pm: str
    independent: tuple
    t: np.ndarray
    status: np.ndarray
    params: dict
    extensions: np.ndarray
    actuator_values: np.ndarray
    active: np.ndarray
    constraint: np.ndarray
    T_r: np.ndarray
    leg_wrenches: np.ndarray
    condition_number: np.ndarray
    closure_residual: np.ndarray
    equilibrium_residual: np.ndarray
    singularity: np.ndarray
    message: np.ndarray
    constraint_labels: tuple
    constraint_kinds: tuple
    constraint_legs: tuple
    force: np.ndarray
    torque: np.ndarray
    diagnostics: dict = field(default_factory=dict)
    units: object = None
    rotary: tuple = ()
    determined: np.ndarray | None = None
    constraint_points: tuple = ()
    resultant_force: np.ndarray | None = None
    resultant_moment: np.ndarray | None = None
    resultant_determined: np.ndarray | None = None
    workload_source: str = "given"
    active_legs: tuple | None = None
    analysis: object = field(default=None, repr=False, compare=False)

    @property
    def actuated(self) -> tuple:
        """The actuated legs (0-based): every leg but the passive ones."""
        return tuple(range(self.n_legs)) if self.active_legs is None else tuple(self.active_legs)

    @property
    def conditioning(self) -> np.ndarray:
        """The conditioning class of each sample: ``regular``, ``near-singular``,
        ``singular`` or ``unreachable`` (:func:`screwkit.engine.classify`)."""
        return np.where(self.status == "ok", "regular", self.status)

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        c = self.counts()
        return (f"TrajectoryResult({self.pm}: {len(self)} samples, " +
                ", ".join(f"{v} {k}" for k, v in c.items() if v) + ")")

    @property
    def n_legs(self) -> int:
        return self.extensions.shape[1]

    @property
    def ok(self) -> np.ndarray:
        """True at the samples with status ``ok``."""
        return self.status == "ok"

    @property
    def flagged(self) -> np.ndarray:
        """True at near-singular, singular or unreachable samples."""
        return self.status != "ok"

    def counts(self) -> dict:
        """Number of samples of each status."""
        return {s: int(np.sum(self.status == s)) for s in STATUSES}

    def params_degrees(self) -> dict:
        """:attr:`params` with the angles in degrees."""
        return {k: (v if k in LENGTH_PARAMS else np.degrees(v)) for k, v in self.params.items()}

    # -- export ------------------------------------------------------------------------------
    def columns(self) -> list:
        """``(name, (N,) array)`` pairs of the CSV, in order (angles in degrees, the
        model's units)."""
        return [(c, v) for c, v, _ in self.columns_with_units()]

    def columns_with_units(self, units=None) -> list:
        """``(name, (N,) array, unit)`` triples of the CSV in the model's units or
        (``units="SI"``) in m, N, N.m; ``unit`` is ``""`` for a dimensionless column."""
        from ..engine._report import output_scales

        ub, k = output_scales(self._units(), units, self.pm)
        kl, kf, kt = k["length"], k["force"], k["torque"]
        n = self.n_legs
        p = self.params_degrees()
        rot = self.rotary or (False,) * n
        cols = [("t", self.t, "")]
        cols += [(q, p[q] * kl, ub["length"]) if q in LENGTH_PARAMS else (q, p[q], "deg")
                 for q in PARAMS]
        cols += [(f"r{i + 1}", self.extensions[:, i] * kl, ub["length"]) for i in range(n)]
        cols += [(f"{'T' if rot[i] else 'F'}_a{i + 1}",          # a rotary actuator: torque
                  self.active[:, k] * (kt if rot[i] else kf),
                  ub["torque" if rot[i] else "force"]) for k, i in enumerate(self.actuated)]
        cols += [(lab, self.constraint[:, j] * (kt if kind == "couple" else kf),
                  ub["torque" if kind == "couple" else "force"])
                 for j, (lab, kind) in enumerate(zip(self.constraint_labels,
                                                     self.constraint_kinds))]
        # T_ri: about a linear leg's own line only
        cols += [(f"T_r{i + 1}", self.T_r[:, i] * kt, ub["torque"]) for i in range(n) if not rot[i]]
        if self.resultant_force is not None:
            for i in range(n):
                cols += [(f"res{i + 1}_f{x}", self.resultant_force[:, i, j] * kf, ub["force"])
                         for j, x in enumerate("xyz")]
                cols += [(f"res{i + 1}_m{x}", self.resultant_moment[:, i, j] * kt, ub["torque"])
                         for j, x in enumerate("xyz")]
        cols += [("condition_number", self.condition_number, ""),
                 ("closure_residual", self.closure_residual, ""),
                 ("equilibrium_residual", self.equilibrium_residual, "")]
        # the workload the statics are of (at o, the same every sample): the table says it
        N = len(self.t)
        cols += [(f"workload_F{x}", np.full(N, float(self.force[j]) * kf), ub["force"])
                 for j, x in enumerate("xyz")]
        cols += [(f"workload_T{x}", np.full(N, float(self.torque[j]) * kt), ub["torque"])
                 for j, x in enumerate("xyz")]
        return cols

    def to_csv(self, out=None, units=None) -> str | None:
        """CSV with a header row ``name [unit]`` (bare names for ``t``, ``status``, the
        condition number, residuals, ``conditioning`` and ``message``): ``t, status``, the
        pose (angles in degrees), ``r_i``, ``F_ai``, the constraint columns, ``T_ri``, each
        leg's constraint resultant ``res<i>_f<x|y|z>`` and its moment about ``A_i``
        ``res<i>_m<x|y|z>``, the condition number and residuals, the workload at ``o``
        (``workload_F<x|y|z>``, ``workload_T<x|y|z>``), the conditioning class,
        ``message``.  In the
        model's units, or in SI with ``units="SI"``.  NaN is written ``nan``.  Returns the
        text when ``out`` is None, else writes to ``out`` (a path or a text file object).
        ``pandas.read_csv`` reads it as it is."""
        cols = self.columns_with_units(units)
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([cols[0][0], "status"] + [f"{c} [{un}]" if un else c for c, _, un in cols[1:]]
                   + ["conditioning", "message"])
        cls = self.conditioning
        for i in range(len(self)):
            w.writerow([_fmt(cols[0][1][i]), self.status[i]]
                       + [_fmt(v[i]) for _, v, _ in cols[1:]] + [cls[i], self.message[i]])
        return _write(buf.getvalue(), out)

    def to_dict(self, units=None) -> dict:
        """JSON-ready, column-oriented (angles in degrees; NaN stays NaN until
        :func:`screwkit.cli._commands._common.to_jsonable` makes it null), in the model's
        units or (``units="SI"``) in m, N, N.m."""
        from ..engine._report import output_scales

        ub, k = output_scales(self._units(), units, self.pm)
        kl, kf, kt = k["length"], k["force"], k["torque"]
        p = self.params_degrees()
        rot = self.rotary or (False,) * self.n_legs
        cu = ["torque" if kind == "couple" else "force" for kind in self.constraint_kinds]
        out = {
            "pm": self.pm,
            "independent": list(self.independent),
            "units": ub,
            "active_units": [ub["torque"] if rot[i] else ub["force"] for i in self.actuated],
            "active_legs": [i + 1 for i in self.actuated],
            "workload": {"force": self.force * kf, "torque": self.torque * kt,
                         "applied_at": "o", "force_unit": ub["force"],
                         "torque_unit": ub["torque"], "source": self.workload_source},
            "n_samples": len(self),
            "counts": self.counts(),
            "t": self.t,
            "status": self.status.tolist(),
            "conditioning": self.conditioning.tolist(),
            "pose": {q: p[q] * kl if q in LENGTH_PARAMS else p[q] for q in PARAMS},
            "pose_units": {q: ub["length"] if q in LENGTH_PARAMS else "deg" for q in PARAMS},
            "extensions": self.extensions * kl,
            "extensions_unit": ub["length"],
            "active": self.active * np.array([kt if rot[i] else kf for i in self.actuated]),
            "constraint": {"labels": list(self.constraint_labels),
                           "kinds": list(self.constraint_kinds),
                           "legs": [i + 1 for i in self.constraint_legs],
                           "units": [ub[q] for q in cu],
                           "values": self.constraint * np.array([kt if q == "torque" else kf
                                                                 for q in cu])},
            "T_r": [None if r else (self.T_r[:, i] * kt).tolist() for i, r in enumerate(rot)],
            "T_r_name": "T_r: moment of each linear leg's constraint wrench about its axis, "
                        "leg by leg (legs x samples: each leg's series, null for a rotary "
                        "leg; active and extensions are samples x legs)",
            "T_r_unit": ub["torque"],
            "condition_number": self.condition_number,
            "singularity": self.singularity.tolist(),
            "closure_residual": self.closure_residual,
            "equilibrium_residual": self.equilibrium_residual,
            "message": self.message.tolist(),
        }
        if self.determined is not None:     # False: the least-norm choice, not statics'
            nact = len(self.actuated)
            out["determined"] = {"active": np.asarray(self.determined)[:, :nact],
                                 "constraint": np.asarray(self.determined)[:, nact:]}
        if self.resultant_force is not None:
            out["constraint_resultant"] = {
                "force": self.resultant_force * kf, "moment": self.resultant_moment * kt,
                "about": [f"A{i + 1}" for i in range(self.n_legs)],
                "name": "each leg's total constraint force (samples x legs x 3) and its moment "
                        "about the leg's base point A_i",
                "force_unit": ub["force"], "moment_unit": ub["torque"],
                "determined": self.resultant_determined}
        return out

    def in_units(self, units=None) -> "TrajectoryResult":
        """This result with its dimensional arrays in the model's units (``units=None``, the
        result itself) or in SI (``units="SI"``: m, N, N.m; needs pint): the pose lengths,
        ``r_i``, linear actuator values, ``F_ai``, the constraint values, ``T_ri``, the leg
        wrenches, the workload and the resultants.  Angles, the condition number and the
        residuals do not change.  For a plot in SI: ``res.in_units("SI").plot(...)``."""
        if units is None or units == "model":
            return self
        import dataclasses

        from ..engine._report import output_scales
        from ..pm import Units

        ub, k = output_scales(self._units(), units, self.pm)
        kl, kf, kt = k["length"], k["force"], k["torque"]
        rot = self.rotary or (False,) * self.n_legs
        lw = np.array(self.leg_wrenches, float)
        lw[..., :3] *= kf
        lw[..., 3:] *= kt
        scaled = lambda x, f: None if x is None else np.asarray(x, float) * f  # noqa: E731
        return dataclasses.replace(
            self,
            params={q: (np.asarray(v, float) * kl if q in LENGTH_PARAMS else v)
                    for q, v in self.params.items()},
            extensions=self.extensions * kl,
            actuator_values=self.actuator_values * np.array([1.0 if rot[i] else kl
                                                             for i in self.actuated]),
            active=self.active * np.array([kt if rot[i] else kf for i in self.actuated]),
            constraint=self.constraint * np.array([kt if kind == "couple" else kf
                                                   for kind in self.constraint_kinds]),
            T_r=self.T_r * kt, leg_wrenches=lw, force=self.force * kf, torque=self.torque * kt,
            resultant_force=scaled(self.resultant_force, kf),
            resultant_moment=scaled(self.resultant_moment, kt),
            units=Units(ub["length"], ub["force"]))

    def _units(self):
        from ..pm import UNDECLARED
        return self.units if self.units is not None else UNDECLARED

    def plot(self, out=None, *, title=None, units=None, dpi: int = 150):
        """The panels of the paper's Fig. 5 (:func:`screwkit.viz.plot_fig5`) and the
        condition number (see :func:`screwkit.paths.plot_trajectory`)."""
        from ._plotting import plot_trajectory

        return plot_trajectory(self, out, title=title, units=units, dpi=dpi)


    def show(self, *, title=None, start: int = 0):
        """The interactive 3D view of the path (:class:`screwkit.scene.View`): a time slider
        with play/pause over the samples; Jupyter shows it inline, ``.write_html(path)``
        writes the page.  In the model's units.  Needs plotly (``screwkit[view]``)."""
        from ..engine import scene_of
        from ..scene import TimeControls, View, require_plotly

        if self.analysis is None:
            from ..scene import MAX_STATES
            raise InputError(f"this result keeps no batched analysis to show (computed sample "
                             f"by sample, or more than {MAX_STATES} samples): run_trajectory("
                             "..., vectorised=True) on a shorter path")
        require_plotly()
        a = self.analysis
        return View(scene_of(a, TimeControls(np.asarray(self.t, float)), start=start,
                             title=title, source=a.workload_source))


def _math(label: str) -> str:
    """``F_c2`` -> ``$F_{c2}$``; ``F_c1.2`` -> ``$F_{c1,2}$``."""
    head, _, sub = label.partition("_")
    return f"${head}_{{{sub.replace('.', ',')}}}$"


def _fmt(v) -> str:
    """12 significant digits; ``nan``, ``inf``, ``-inf`` as such."""
    return f"{float(v):.12g}"


def _write(text: str, out):
    if out is None:
        return text
    if hasattr(out, "write"):
        out.write(text)
        return None
    try:
        Path(out).parent.mkdir(parents=True, exist_ok=True)      # --out dir/file: make dir
        with open(out, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
    except OSError as exc:
        raise InputError(f"cannot write {str(out)!r}: {exc}") from None
    return None


# ----------------------------------------------------------------------------- the run

