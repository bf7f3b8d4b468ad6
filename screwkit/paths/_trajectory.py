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
from bisect import bisect_left
from dataclasses import dataclass, field

import numpy as np

from ..engine import CONVERGED, LENGTH_PARAMS, PAPER_FORCE, PAPER_TORQUE, PARAMS, solve_pose
from ..errors import InputError, ScrewkitError
from ..screws import GEOMETRY_RTOL
from ._pathspec import PathSpec

__all__ = ["TrajectoryResult", "run_trajectory", "STATUSES"]

#: The values of :attr:`TrajectoryResult.status`.
STATUSES = ("ok", "singular", "unreachable")

_ROW_SYMBOL = {"force": "F_c", "couple": "T_c", "screw": "W_c"}
#: Ratio of the sample spacings of two successive refinement levels (see :func:`run_trajectory`).
_REFINE = 16


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
                   progress=None, *, overrides: dict | None = None, anchor_every: int = 256,
                   chunk: int = 1024, vectorised: bool = True) -> TrajectoryResult:
    """Inverse displacement and statics at every sample of a path.

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
    anchor_every : int
        Spacing of the anchor samples solved one by one (>= 1; 1 solves every
        sample by :func:`screwkit.engine.solve_pose`); at most N // 8.
    chunk : int
        Samples processed together (bounds the memory of the vectorised steps).
    vectorised : bool
        False: every sample by the per-pose pipeline (:func:`analyze_pm`'s steps,
        warm-started from the previous sample).  Slow; for checks.

    Returns
    -------
    TrajectoryResult
    """
    from ..engine import load_assembled_pm
    from ..pm import PMModel

    if not isinstance(model, PMModel):
        model = load_assembled_pm(model, overrides)
    F, T = _vec3(force, "force"), _vec3(torque, "torque")
    path = _check_path(model, path)
    try:
        K = int(anchor_every)
        C = int(chunk)
    except (TypeError, ValueError):
        raise InputError("anchor_every and chunk must be integers") from None
    if K < 1 or C < 1:
        raise InputError(f"anchor_every ({anchor_every}) and chunk ({chunk}) must be >= 1")
    run = _Run(model, path, F, T)
    N = len(path)
    if not vectorised:
        for i in range(N):
            run.per_pose(i)
            if progress:
                progress(i + 1, N)
    else:
        K = min(K, max(1, N // 8))          # at least ~8 anchor intervals on a short path
        anchors = sorted(set(range(0, N, K)) | {N - 1})
        step = max(K, (C // K) * K)
        for c0 in range(0, N, step):
            c1 = min(c0 + step, N)
            run.chunk(c0, c1, [a for a in anchors if c0 <= a <= c1])
            if progress:
                progress(c1, N)
    return run.result()


class _Run:
    """State of one run: the outputs, the per-pose solutions kept as warm starts."""

    def __init__(self, model, path, F, T):
        from ..engine import LegTemplate, unified_jacobian

        self.model, self.path, self.F, self.T = model, path, F, T
        N, n = len(path), model.n_legs
        self.fixed = {k: np.asarray(path.values[k], float) for k in model.independent}
        analyses = [lg.analyze() for lg in model.home_legs]
        self.templates = [LegTemplate(lg, an) for lg, an in zip(model.home_legs, analyses)]
        self.trackable = all(t.trackable for t in self.templates)
        _, oh = model.platform_home
        home_rows = unified_jacobian(model.home_legs, oh, analyses).rows
        self.layout = tuple((r.leg, r.kind) for r in home_rows if r.kind != "actuation")
        self.kinds_at = {}      # sample -> constraint kinds where they differ from home
        k = len(self.layout)
        self.leg_of_row = np.array(list(range(n)) + [leg for leg, _ in self.layout], int)
        nan = np.nan
        self.out = {
            "status": np.full(N, "unreachable", dtype=object),
            "params": {p: np.full(N, nan) for p in PARAMS},
            "extensions": np.full((N, n), nan), "actuator_values": np.full((N, n), nan),
            "active": np.full((N, n), nan), "constraint": np.full((N, k), nan),
            "T_r": np.full((N, n), nan), "leg_wrenches": np.full((N, n, 6), nan),
            "condition_number": np.full(N, nan), "closure_residual": np.full(N, nan),
            "equilibrium_residual": np.full(N, nan), "singularity": np.full(N, "", dtype=object),
            "message": np.full(N, "", dtype=object),
        }
        for p, v in self.fixed.items():
            self.out["params"][p][:] = v
        self.core = {}          # sample -> PoseSolution (or None when unreachable)
        self.core_keys = []     # sorted keys of solved samples
        self.diag = {"batched": 0, "per_pose_kinematics": 0, "per_pose_rows": 0,
                     "anchors": 0, "trackable_legs": sum(t.trackable for t in self.templates)}
        self.messages = {}

    # -- per-pose pieces ----------------------------------------------------------------------
    def _independent(self, i):
        return {k: float(v[i]) for k, v in self.fixed.items()}

    def _guess(self, i):
        j = bisect_left(self.core_keys, i) - 1
        while j >= 0:
            s = self.core[self.core_keys[j]]
            if s is not None:
                return s
            j -= 1
        return None

    def core_solve(self, i):
        """The inverse displacement (:func:`screwkit.engine.solve_pose`) at sample i, warm-started from the nearest earlier solved sample."""
        if i in self.core:
            return self.core[i]
        try:
            sol = solve_pose(self.model, self._independent(i), self._guess(i))
        except ScrewkitError as exc:
            sol = None
            res = getattr(exc, "residual", None)
            self.messages[i] = (f"unreachable: closure residual {res:.3g}" if res is not None
                                else f"unreachable: {exc}")
        self.core[i] = sol
        self.core_keys.insert(bisect_left(self.core_keys, i), i)
        return sol

    def per_pose(self, i):
        """Sample i by the per-pose pipeline (solve_pose, Leg.analyze, unified_jacobian)."""
        sol = self.core_solve(i)
        self.diag["per_pose_kinematics"] += 1
        if sol is None:
            self.out["message"][i] = self.messages.get(i, "unreachable")
            return
        o = self.out
        for p in PARAMS:
            o["params"][p][i] = sol.params[p]
        o["extensions"][i] = sol.extensions
        o["actuator_values"][i] = sol.actuator_values
        o["closure_residual"][i] = sol.residual
        self.full_rows(i, sol.legs, sol.position, "; ".join(sol.notes))

    def full_rows(self, i, legs, position, note=""):
        from ..engine import statics, unified_jacobian

        o = self.out
        jac = unified_jacobian(legs, position)
        o["condition_number"][i] = jac.condition_number
        layout = tuple((r.leg, r.kind) for r in jac.rows if r.kind != "actuation")
        same_legs = [leg for leg, _ in layout] == [leg for leg, _ in self.layout]
        if jac.singular or not same_legs:
            o["status"][i] = "singular"
            kind = jac.singularity_kind or "constraint"
            o["singularity"][i] = kind
            why = (f"{kind} singularity (condition number {jac.condition_number:.3g})"
                   if jac.singular else "the legs' constraint wrenches change type here "
                   f"({', '.join(k for _, k in layout) or 'none'})")
            o["message"][i] = "; ".join(x for x in (why, note) if x)
            return
        if layout != self.layout:
            self.kinds_at[i] = tuple(k for _, k in layout)
        st = statics(jac, self.F, self.T, raise_on_singular=False)
        n = self.model.n_legs
        o["status"][i] = "ok"
        o["active"][i] = st.values[:n]
        o["constraint"][i] = st.values[n:]
        o["T_r"][i] = st.T_r
        o["leg_wrenches"][i] = st.leg_wrenches
        o["equilibrium_residual"][i] = st.equilibrium_residual
        o["message"][i] = note

    # -- vectorised chunk -------------------------------------------------------------------------
    def _rep_singular(self, beta):
        """Samples where beta is at the representation singularity with alpha/gamma dependent."""
        order = self.model.order
        dep_pair = any(p in self.model.dependent for p in ("alpha", "gamma"))
        if not dep_pair:
            return np.zeros(len(beta), bool)
        proper = order[0].lower() == order[2].lower()
        return np.abs(np.sin(beta) if proper else np.cos(beta)) <= GEOMETRY_RTOL * 1e3

    def _x_of(self, sol):
        return np.concatenate([[sol.params[p] for p in self.model.dependent]]
                              + [np.asarray(q, float) for q in sol.joint_values])

    def chunk(self, c0, c1, anchors):
        """Samples c0..c1-1: core-solve the anchors (and sample c1 when it is one, for the
        interpolation), then refine level by level (spacing / _REFINE) with the batched
        Newton started from the linear interpolation of the samples already solved."""
        from ..engine import BatchProblem, assemble_batch

        model = self.model
        end = min(c1, len(self.path) - 1)
        idx = np.arange(c0, end + 1)                       # c1 included for interpolation
        nx = len(model.dependent) + sum(len(lg.joints) for lg in model.home_legs)
        X = np.full((len(idx), nx), np.nan)
        have = np.zeros(len(idx), bool)
        beta_fixed = "beta" in self.fixed
        rep = (self._rep_singular(self.fixed["beta"][idx]) if beta_fixed
               else np.zeros(len(idx), bool))
        for a in anchors:
            sol = self.core_solve(a)
            if sol is not None:
                X[a - c0], have[a - c0] = self._x_of(sol), True
        self.diag["anchors"] += sum(1 for a in anchors if a < c1)
        spacing = max(1, anchors[1] - anchors[0]) if len(anchors) > 1 else 1
        while spacing > 1:
            spacing = max(1, spacing // _REFINE)
            targets = np.flatnonzero((idx % spacing == 0) & ~have & ~rep)
            self._refine(idx, X, have, targets)
        if not beta_fixed and "beta" in model.dependent:
            jb = model.dependent.index("beta")
            have &= ~self._rep_singular(np.where(np.isfinite(X[:, jb]), X[:, jb], 1.0))
        inside = idx < c1
        S = np.flatnonzero(have & ~rep & inside)
        if S.size:
            prob = BatchProblem(model, {k: v[idx] for k, v in self.fixed.items()})
            kb = assemble_batch(model, prob, X[S], rows=S)
            self._batch_rows(idx[S], kb)
        for j in np.flatnonzero(~(have & ~rep) & inside):
            self.per_pose(int(idx[j]))

    def _refine(self, idx, X, have, targets):
        """Solve ``targets`` (positions in idx) from the interpolation of their solved
        neighbours; a sample that fails (no convergence, or a step from the guess larger
        than half the change between its neighbours: another branch) is core-solved."""
        from ..engine import newton_batch

        if targets.size == 0:
            return
        t = self.path.t[idx]
        known = np.flatnonzero(have)
        pos = np.searchsorted(known, targets)
        both = (pos > 0) & (pos < len(known))
        lo = known[np.clip(pos - 1, 0, len(known) - 1)]
        hi = known[np.clip(pos, 0, len(known) - 1)]
        s = np.where(both, (t[targets] - t[lo]) / np.where(hi != lo, t[hi] - t[lo], 1.0), 0.0)
        X0 = X[lo] + s[:, None] * (X[hi] - X[lo])
        scale = self._scale()
        span = np.max(np.abs(X[hi] - X[lo]) / scale, axis=1)
        good = np.zeros(len(targets), bool)
        cand = np.flatnonzero(both)
        if cand.size:
            fixed = {k: v[idx[targets[cand]]] for k, v in self.fixed.items()}
            Xc, res, _ = newton_batch(self.model, fixed, X0[cand])
            dev = np.max(np.abs(Xc - X0[cand]) / scale, axis=1)
            ok = (res <= CONVERGED) & (dev <= 0.5 * span[cand] + 1e-8)
            X[targets[cand[ok]]] = Xc[ok]
            have[targets[cand[ok]]] = True
            good[cand[ok]] = True
        for j in targets[~good]:
            sol = self.core_solve(int(idx[j]))
            if sol is not None:
                X[j], have[j] = self._x_of(sol), True

    def _scale(self):
        L = self.model.normalisation.length
        sc = [L if p in LENGTH_PARAMS else 1.0 for p in self.model.dependent]
        for lg in self.model.home_legs:
            sc += [L if j.kind == "P" else 1.0 for j in lg.joints]
        return np.array(sc)

    def _legs_at(self, kb, s):
        """Leg objects of batch sample s (for the per-pose rows)."""
        from ..legs import Joint, Leg

        legs = []
        for i, h in enumerate(self.model.home_legs):
            joints = tuple(Joint(j.spec, kb.Dc[i][s, k], kb.Pc[i][s, k], j.pitch)
                           for k, j in enumerate(h.joints))
            legs.append(Leg(h.string, joints, kb.A[i], kb.a[s, i], h.name))
        return tuple(legs)

    def _batch_rows(self, samples, kb):
        from ..engine import jacobian_statics_batch

        o = self.out
        M = len(samples)
        n = self.model.n_legs
        for p in PARAMS:
            o["params"][p][samples] = kb.params[p]
        o["extensions"][samples] = np.linalg.norm(kb.a - kb.A[None], axis=2)
        o["actuator_values"][samples] = np.column_stack(
            [kb.q[i][:, h.actuated_index] for i, h in enumerate(self.model.home_legs)])
        o["closure_residual"][samples] = kb.residual
        rows_ok = np.full(M, self.trackable)
        if self.trackable:
            act, cons = [], []
            for i, tpl in enumerate(self.templates):
                a_row, _, c_rows, ok = tpl.rows(kb.Dc[i], kb.Pc[i], kb.A[i], kb.a[:, i])
                act.append(a_row)
                cons.append(c_rows)
                rows_ok &= ok
            J = np.concatenate([np.stack(act, axis=1)] + cons, axis=1)
            pts = np.concatenate(
                [np.concatenate([np.broadcast_to(kb.A[i], (M, 1, 3)), kb.a[:, i, None],
                                 kb.Pc[i]], axis=1) for i in range(n)] + [kb.o[:, None]], axis=1)
            sel = np.flatnonzero(rows_ok)
            if sel.size:
                bs = jacobian_statics_batch(J[sel], self.leg_of_row, n, pts[sel], kb.A,
                                            kb.a[sel], kb.o[sel], self.F, self.T)
                g = samples[sel]
                o["condition_number"][g] = bs.condition_number
                o["status"][g] = np.where(bs.singular, "singular", "ok")
                o["singularity"][g] = bs.kind
                o["message"][g] = [f"{k} singularity (condition number {c:.3g})" if k else ""
                                   for k, c in zip(bs.kind, bs.condition_number)]
                o["active"][g] = bs.values[:, :n]
                o["constraint"][g] = bs.values[:, n:]
                o["T_r"][g] = bs.T_r
                o["leg_wrenches"][g] = bs.leg_wrenches
                o["equilibrium_residual"][g] = bs.equilibrium_residual
                self.diag["batched"] += int(sel.size)
        for s in np.flatnonzero(~rows_ok):
            self.diag["per_pose_rows"] += 1
            self.full_rows(int(samples[s]), self._legs_at(kb, s), kb.o[s])

    def _columns(self, o):
        """Kind and label of each constraint column: the kind found at most ok samples
        (the kinds at home otherwise); samples where a row has another kind say so."""
        home = tuple(k for _, k in self.layout)
        ok = np.flatnonzero(o["status"] == "ok")
        kinds = []
        for j, hk in enumerate(home):
            seen = [self.kinds_at.get(int(i), home)[j] for i in ok]
            kinds.append(max(set(seen), key=seen.count) if seen else hk)
        kinds = tuple(kinds)
        for i, ks in self.kinds_at.items():
            if ks != kinds:
                txt = "constraint rows here: " + ", ".join(ks)
                o["message"][i] = "; ".join(x for x in (o["message"][i], txt) if x)
        labels = [f"{_ROW_SYMBOL.get(k, 'W_c')}{leg + 1}" for (leg, _), k in zip(self.layout, kinds)]
        dup = {lab for lab in labels if labels.count(lab) > 1}
        seen = {}
        for j, lab in enumerate(labels):
            if lab in dup:
                seen[lab] = seen.get(lab, 0) + 1
                labels[j] = f"{lab}.{seen[lab]}"
        return kinds, tuple(labels)

    def result(self) -> TrajectoryResult:
        o = self.out
        arrays = {}
        for k, v in o.items():
            if k == "params":
                continue
            if v.dtype == object:
                v = v.astype(str)
            v.setflags(write=False)
            arrays[k] = v
        for v in o["params"].values():
            v.setflags(write=False)
        kinds, labels = self._columns(o)
        legs = tuple(leg for leg, _ in self.layout)
        t = np.array(self.path.t, float)
        t.setflags(write=False)
        return TrajectoryResult(self.model.name, tuple(self.model.independent), t,
                                arrays["status"], o["params"], arrays["extensions"],
                                arrays["actuator_values"], arrays["active"], arrays["constraint"],
                                arrays["T_r"], arrays["leg_wrenches"], arrays["condition_number"],
                                arrays["closure_residual"], arrays["equilibrium_residual"],
                                arrays["singularity"], arrays["message"], labels, kinds, legs,
                                self.F.copy(), self.T.copy(), dict(self.diag))
