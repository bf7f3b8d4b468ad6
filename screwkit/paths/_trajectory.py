"""Statics along a path: inverse displacement, Jacobian and statics at every sample.

:func:`run_trajectory` takes a PM and a :class:`~screwkit.paths.PathSpec`
(the independent pose parameters sampled at ``t``) and returns a
:class:`TrajectoryResult`: the full pose, leg extensions, active forces,
constraint forces/couples, constraint torques ``T_ri`` and the condition number
at every sample, with a per-sample ``status``:

* ``ok`` - solved, regular;
* ``singular`` - the pose is assembled but the unified Jacobian is singular
  (condition number above :data:`~screwkit.engine.COND_THRESHOLD`): the
  statics are NaN, the pose, extensions and condition number are kept;
* ``unreachable`` - the loop closures cannot be satisfied: everything but the
  given parameters is NaN.

A flagged sample never aborts the run.  Every sample equals what
:func:`screwkit.engine.analyze_pm` (``screwkit analyze``) gives at that
pose (for a leg with two or more constraint wrenches of one kind the split
between them is a basis choice of the per-pose analysis; their total, the leg's
wrench, and the active forces are what is defined).  The computation is
organised for speed (``docs/tutorial.md``, "Speed"):

1. *anchor* samples (every ``anchor_every``-th, at least ~8 per path) are
   solved one after the other by :func:`screwkit.engine.solve_pose`, each warm-started from
   the previous one;
2. the other samples are solved level by level (the spacing divided by 16 at
   each level) by a Gauss-Newton vectorised over samples
   (:func:`screwkit.engine.newton_batch`), started from the linear
   interpolation of the samples already solved;
3. each leg's Jacobian rows are recomputed for all samples at once from the
   structure of its analysis at the home pose
   (:class:`~screwkit.engine.LegTemplate`), then the conditioning and
   the statics (:func:`~screwkit.engine.jacobian_statics_batch`);
4. every sample where a step is not clear-cut (no convergence, a jump to
   another branch, a representation singularity, a rank or orientation decision
   near its threshold, a leg whose analysis is not tracked) is recomputed by the
   per-pose pipeline.

Examples
--------
>>> from screwkit.paths import path_from_expressions
>>> from screwkit.paths import run_trajectory
>>> path = path_from_expressions(["alpha=5*sin(2*pi*t)", "beta=3", "Zo=70+20*t"],
...                              ("alpha", "beta", "Zo"), samples=5)
>>> res = run_trajectory("3RRPRR", path)
>>> res.status.tolist()
['ok', 'ok', 'ok', 'ok', 'ok']
>>> res.active.shape, res.constraint_labels
((5, 3), ('F_c1', 'F_c2', 'F_c3'))
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field

import numpy as np

from ..engine import LENGTH_PARAMS, PAPER_FORCE, PAPER_TORQUE, PARAMS
from ..errors import InputError
from ._pathspec import PathSpec

__all__ = ["TrajectoryResult", "run_trajectory", "STATUSES"]

#: The values of :attr:`TrajectoryResult.status`.
STATUSES = ("ok", "singular", "unreachable")



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
        ``ok``, ``singular`` or ``unreachable`` (see the module docstring).
    params : dict str -> ndarray (N,)
        ``Xo Yo Zo alpha beta gamma`` (model length unit, radians).
    extensions : ndarray (N, n)
        ``r_i = |a_i - A_i|``.
    actuator_values : ndarray (N, n)
        Displacement of each actuated joint from home.
    active : ndarray (N, n)
        Active forces ``F_ai`` (> 0 pushes the platform away from ``A_i``).
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
    diagnostics : dict
        How the samples were computed (``batched``, ``per_pose_kinematics``,
        ``per_pose_rows``), for benchmarks.
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
        """True at singular or unreachable samples."""
        return self.status != "ok"

    def counts(self) -> dict:
        """Number of samples of each status."""
        return {s: int(np.sum(self.status == s)) for s in STATUSES}

    def params_degrees(self) -> dict:
        """:attr:`params` with the angles in degrees."""
        return {k: (v if k in LENGTH_PARAMS else np.degrees(v)) for k, v in self.params.items()}

    # -- export ------------------------------------------------------------------------------
    def columns(self) -> list:
        """``(name, (N,) array)`` pairs of the CSV, in order (angles in degrees)."""
        n = self.n_legs
        p = self.params_degrees()
        cols = [("t", self.t)]
        cols += [(k, p[k]) for k in PARAMS]
        cols += [(f"r{i + 1}", self.extensions[:, i]) for i in range(n)]
        cols += [(f"F_a{i + 1}", self.active[:, i]) for i in range(n)]
        cols += [(lab, self.constraint[:, j]) for j, lab in enumerate(self.constraint_labels)]
        cols += [(f"T_r{i + 1}", self.T_r[:, i]) for i in range(n)]
        cols += [("condition_number", self.condition_number),
                 ("closure_residual", self.closure_residual),
                 ("equilibrium_residual", self.equilibrium_residual)]
        return cols

    def to_csv(self, out=None) -> str | None:
        """CSV with a header row: ``t, status``, the pose (angles in degrees), ``r_i``,
        ``F_ai``, the constraint columns, ``T_ri``, the condition number and residuals,
        ``message``.  NaN is written ``nan``.  Returns the text when ``out`` is None,
        else writes to ``out`` (a path or a text file object)."""
        cols = self.columns()
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([cols[0][0], "status"] + [c for c, _ in cols[1:]] + ["message"])
        for i in range(len(self)):
            w.writerow([_fmt(cols[0][1][i]), self.status[i]]
                       + [_fmt(v[i]) for _, v in cols[1:]] + [self.message[i]])
        return _write(buf.getvalue(), out)

    def to_dict(self) -> dict:
        """JSON-ready, column-oriented (angles in degrees; NaN stays NaN until
        :func:`screwkit.cli._commands._common.to_jsonable` makes it null)."""
        p = self.params_degrees()
        return {
            "pm": self.pm,
            "independent": list(self.independent),
            "units": {"angles": "deg", "lengths": "model length unit",
                      "forces": "model force unit", "torques": "force x length"},
            "workload": {"force": self.force, "torque": self.torque, "applied_at": "o"},
            "n_samples": len(self),
            "counts": self.counts(),
            "t": self.t,
            "status": self.status.tolist(),
            "pose": {k: p[k] for k in PARAMS},
            "extensions": self.extensions,
            "active": self.active,
            "constraint": {"labels": list(self.constraint_labels),
                           "kinds": list(self.constraint_kinds),
                           "legs": [i + 1 for i in self.constraint_legs],
                           "values": self.constraint},
            "T_r": self.T_r,
            "condition_number": self.condition_number,
            "singularity": self.singularity.tolist(),
            "closure_residual": self.closure_residual,
            "equilibrium_residual": self.equilibrium_residual,
            "message": self.message.tolist(),
        }

    def plot(self, out=None, *, title=None, units=None, dpi: int = 150):
        """The panels of the paper's Fig. 5 (:func:`screwkit.viz.plot_fig5`).

        (a) the independent pose parameters, (b) the extensions ``r_i``, (c) the
        active forces ``F_ai``, (d) the constraint forces and torques (``F_c``,
        couples ``T_c`` and the ``T_ri``, which are left out when they vanish
        identically, e.g. legs whose constraint force passes through ``A_i``).
        Flagged samples are shaded grey.
        """
        from ..viz import plot_fig5

        p = self.params_degrees()
        pose = {k: p[k] for k in self.independent}
        force_cols = [j for j, k in enumerate(self.constraint_kinds) if k != "couple"]
        couple_cols = [j for j, k in enumerate(self.constraint_kinds) if k == "couple"]
        Fc = self.constraint[:, force_cols] if force_cols else None
        torques, tlabels = [], []
        for j in couple_cols:
            torques.append(self.constraint[:, j])
            tlabels.append(_math(self.constraint_labels[j]))
        Tr = self.T_r
        scale = max(float(np.nanmax(np.abs(self.leg_wrenches), initial=0.0)), 1e-300)
        zero_tr = bool(np.all(~np.isfinite(Tr) | (np.abs(Tr) <= 1e-9 * scale)))
        note = ""
        if not zero_tr:
            for i in range(self.n_legs):
                torques.append(Tr[:, i])
                tlabels.append(f"$T_{{r{i + 1}}}$")
        elif self.ok.any():
            note = "all $T_{ri}$ = 0 (constraint forces through $A_i$)"
        Tc = np.column_stack(torques) if torques else None
        labels = {"extensions": [f"$r_{{{i + 1}}}$" for i in range(self.n_legs)],
                  "active": [f"$F_{{a{i + 1}}}$" for i in range(self.n_legs)]}
        if Fc is not None:
            labels["constraint_forces"] = [_math(self.constraint_labels[j]) for j in force_cols]
        if Tc is not None:
            labels["constraint_torques"] = tlabels
        if title is None:
            from ..viz import DEFAULT_UNITS
            u = {**DEFAULT_UNITS, **(units or {})}
            F, T = self.force, self.torque
            title = (f"{self.pm}: F = [{', '.join(f'{x:g}' for x in F)}] {u['force']}, "
                     f"T = [{', '.join(f'{x:g}' for x in T)}] {u['torque']} at o")
        if note:
            title = f"{title}\n{note}"
        return plot_fig5(self.t, pose, self.extensions, self.active, Fc, Tc, labels=labels,
                         units=units, flags=self.flagged, out=out, title=title, dpi=dpi)


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
        with open(out, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
    except OSError as exc:
        raise InputError(f"cannot write {str(out)!r}: {exc}") from None
    return None


# ----------------------------------------------------------------------------- the run

def _vec3(x, name):
    a = np.asarray(x, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be 3 finite numbers, got {x!r}")
    return a


def _check_path(model, path) -> PathSpec:
    if not isinstance(path, PathSpec):
        raise InputError(f"the path must be a PathSpec (see screwkit.paths), got "
                         f"{type(path).__name__}")
    if len(path) == 0:
        raise InputError("the path has no samples")
    given, need = set(path.values), set(model.independent)
    if given != need:
        raise InputError(f"{model.name}: the path gives {', '.join(sorted(given)) or 'nothing'}; "
                         f"the independent pose parameters are {', '.join(model.independent)}")
    return path


def run_trajectory(model, path: PathSpec, force=PAPER_FORCE, torque=PAPER_TORQUE,
                   progress=None, *, overrides: dict | None = None, anchor_every=None,
                   chunk: int = 4096, vectorised: bool = True, workers=None) -> TrajectoryResult:
    """Inverse displacement and statics at every sample of a path (the batched engine).

    Parameters
    ----------
    model : PMModel or str
        A loaded model, a catalog PM name or a YAML model path.
    path : PathSpec
        The independent pose parameters at N samples (angles in radians).
    force, torque : array_like (3,)
        Workload at ``o`` (default: the paper's F = [-20, -30, -60] kN,
        T = [-30, -30, 100] kN.cm).
    progress : callable(done, total), optional
        Called as samples are completed (``done`` increases to ``total = N``).
    overrides : dict, optional
        Dimension overrides when ``model`` is a name.
    anchor_every : int, optional
        Spacing of the anchor samples solved one after the other (>= 1); the others are
        solved level by level from their neighbours (:func:`screwkit.engine.solve`);
        default about 64 anchors.
    chunk : int
        Samples per chunk of the rows and statics (bounds the memory).
    vectorised : bool
        False: every sample solved on its own by the engine (one pose at a time, each
        warm-started from the previous sample).  Slow; for checks.

    Returns
    -------
    TrajectoryResult
    """
    from ..engine import analyze, load_assembled_pm
    from ..pm import PMModel

    if not isinstance(model, PMModel):
        model = load_assembled_pm(model, overrides)
    F, T = _vec3(force, "force"), _vec3(torque, "torque")
    path = _check_path(model, path)
    try:
        K = None if anchor_every is None else int(anchor_every)
        C = int(chunk)
    except (TypeError, ValueError):
        raise InputError("anchor_every and chunk must be integers") from None
    if (K is not None and K < 1) or C < 1:
        raise InputError(f"anchor_every ({anchor_every}) and chunk ({chunk}) must be >= 1")
    N = len(path)
    pose = {k: np.asarray(path.values[k], float) for k in model.independent}
    if vectorised:
        res = analyze(model, pose, force=F, torque=T, path=True, anchor_every=K, chunk=C,
                      workers=workers, progress=progress)
        return _result(model, path, res, F, T, res.diagnostics)
    parts, prev = [], None
    for i in range(N):
        r = analyze(model, {k: v[i:i + 1] for k, v in pose.items()}, force=F, torque=T,
                    guess=prev)
        if bool(r.solution.reachable_mask[0]):
            prev = r.solution
        parts.append(r)
        if progress:
            progress(i + 1, N)
    return _result(model, path, _Stacked(parts), F, T,
                   {"anchors": 0, "batched": 0, "per_pose": N})


class _Stacked:
    """Per-sample analyses of the per-pose mode, read like one batched analysis."""

    def __init__(self, parts):
        self.parts = parts

    def __len__(self):
        return len(self.parts)

    def __getitem__(self, i):
        return self.parts[i][0]

    def column(self, get):
        return np.concatenate([np.asarray(get(p)) for p in self.parts], axis=0)


def _result(model, path, res, F, T, diag) -> TrajectoryResult:
    """The :class:`TrajectoryResult` of a batched analysis along the path."""
    from ..engine import CONVERGED

    parts = res.parts if isinstance(res, _Stacked) else [res]

    def col(get):
        return np.concatenate([np.asarray(get(p)) for p in parts], axis=0)

    N, n = len(path), model.n_legs
    sols = [p.solution for p in parts]
    reach = col(lambda p: p.solution.reachable_mask)
    resid = col(lambda p: p.solution.closures.residual)
    sing_mask = col(lambda p: p.jacobian.singular_mask) & reach
    kinds_arr = col(lambda p: p.jacobian.kind_array)
    cond = col(lambda p: p.jacobian.conditioning.condition_number)
    status = np.where(~reach, "unreachable", np.where(sing_mask, "singular", "ok"))
    params = {k: col(lambda p, k=k: p.solution._params[k]) for k in PARAMS}
    ext = col(lambda p: p.solution._extensions)
    ext[~reach] = np.nan
    act_v = col(lambda p: np.asarray(p.solution.actuator_values).reshape(len(p), n))
    st_ok = reach & ~sing_mask
    vals = col(lambda p: p.statics.F_r)
    legw = col(lambda p: p.statics._derived[2])
    Tr = col(lambda p: p.statics._derived[4])
    eq = col(lambda p: p.statics._derived[5])
    nact = n
    cond = np.where(reach, cond, np.nan)
    message = []
    notes = [p.solution.notes if not p.solution.single else (p.solution.notes,) for p in parts]
    flat_notes = [x for group in notes for x in group]
    for i in range(N):
        msg = []
        if not reach[i]:
            msg.append(f"unreachable: closure residual {resid[i]:.3g}")
        elif sing_mask[i]:
            msg.append(f"{kinds_arr[i]} singularity (condition number {cond[i]:.3g})")
        elif resid[i] > CONVERGED:
            msg.append(f"not converged: closure residual {resid[i]:.3g}")
        msg += [t for t in flat_notes[i] if "taken from the default pose" not in t]
        message.append("; ".join(msg))
    info = parts[0].jacobian.info
    cons_info = [r for r in info if r.kind != "actuation"]
    labels = tuple(r.label for r in cons_info)
    kinds = tuple(r.kind for r in cons_info)
    legs = tuple(r.leg for r in cons_info)
    out = {
        "status": status.astype(str), "extensions": ext, "actuator_values": act_v,
        "active": vals[:, :nact], "constraint": vals[:, nact:], "T_r": Tr,
        "leg_wrenches": legw, "condition_number": cond, "closure_residual": resid,
        "equilibrium_residual": np.where(st_ok, eq, np.nan),
        "singularity": np.where(sing_mask, kinds_arr, "").astype(str),
        "message": np.array(message, dtype=str),
    }
    for k in ("active", "constraint", "T_r", "leg_wrenches"):
        out[k] = np.array(out[k], float)
        out[k][~st_ok] = np.nan
    for v in list(out.values()) + list(params.values()):
        v.setflags(write=False)
    t = np.array(path.t, float)
    t.setflags(write=False)
    return TrajectoryResult(model.name, tuple(model.independent), t, out["status"], params,
                            out["extensions"], out["actuator_values"], out["active"],
                            out["constraint"], out["T_r"], out["leg_wrenches"],
                            out["condition_number"], out["closure_residual"],
                            out["equilibrium_residual"], out["singularity"], out["message"],
                            labels, kinds, legs, F.copy(), T.copy(), dict(diag))
