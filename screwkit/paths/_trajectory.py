"""Statics along a path: inverse displacement, Jacobian and statics at every sample.

:func:`run_trajectory` takes a PM and a :class:`~screwkit.paths.PathSpec`
(the independent pose parameters sampled at ``t``) and returns a
:class:`TrajectoryResult`: the full pose, leg extensions, active forces,
constraint forces/couples, constraint torques ``T_ri`` and the condition number
at every sample, with a per-sample ``status``:

* ``ok`` - solved, regular;
* ``near-singular`` - solved, but the normalised condition number is above
  :data:`~screwkit.engine.NEAR_SINGULAR_COND` (the conditioning class of
  :func:`screwkit.engine.classify`, as ``analyze`` says): the statics are kept;
* ``singular`` - the pose is assembled but the unified Jacobian is singular
  (condition number above :data:`~screwkit.engine.COND_THRESHOLD`): the
  statics are NaN, the pose, extensions and condition number are kept;
* ``unreachable`` - the loop closures cannot be satisfied: everything but the
  given parameters is NaN.

A flagged sample never aborts the run.  Every sample is a pose of the batched
engine (:func:`screwkit.engine.analyze` with ``path=True``): about 32 anchor
samples are solved one after the other, each warm-started from the previous
one; the samples between are solved level by level, all of a level at once,
from the interpolation of their solved neighbours (a sample that jumps to
another branch is solved again from its left neighbour); then the rows, the
conditioning and the statics of every sample are formed in chunks.  Each sample
therefore equals :func:`screwkit.analyze` at that pose.

Examples
--------
>>> from screwkit.paths import path_from_expressions
>>> from screwkit.paths import run_trajectory
>>> path = path_from_expressions(["alpha=5*sin(2*pi*t)", "beta=3", "Zo=70+20*t"],
...                              ("alpha", "beta", "Zo"), samples=5)
>>> res = run_trajectory("3RRPRR", path)          # 3RRPRR declares the paper's workload
>>> res.status.tolist()
['ok', 'ok', 'ok', 'ok', 'ok']
>>> res.active.shape, res.constraint_labels
((5, 3), ('F_c1', 'F_c2', 'F_c3'))
"""

from __future__ import annotations

import numpy as np

from ..engine import CHUNK, PARAMS
from ..engine._workloads import no_workload_message, resolve_workload
from ..errors import InputError
from ._pathspec import PathSpec
from ._result import STATUSES, TrajectoryResult

__all__ = ["TrajectoryResult", "run_trajectory", "STATUSES"]


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


def run_trajectory(model, path: PathSpec, force=None, torque=None,
                   progress=None, *, overrides: dict | None = None, anchor_every=None,
                   chunk: int = CHUNK, vectorised: bool = True, workers=None,
                   mapper=None) -> TrajectoryResult:
    """Inverse displacement and statics at every sample of a path (the batched engine).

    Parameters
    ----------
    model : PMModel or str
        A loaded model, a catalog PM name or a YAML model path.
    path : PathSpec
        The independent pose parameters at N samples (angles in radians).
    force, torque : array_like (3,), optional
        Workload at ``o`` (model units; one without the other: the other is zero; neither:
        the model's declared default, else an :class:`~screwkit.errors.InputError`).
    progress : callable(done, total), optional
        Called as the work advances (``done`` grows to ``total``: 2 N steps, the closures of
        the path then the rows and statics; N samples with ``vectorised=False``).
    overrides : dict, optional
        Dimension overrides when ``model`` is a name.
    anchor_every : int, optional
        Spacing of the anchor samples solved one after the other (>= 1); the others are
        solved level by level from their neighbours (:func:`screwkit.engine.solve`);
        default about 32 anchors.
    chunk : int
        Samples per chunk of the rows and statics (bounds the memory).
    vectorised : bool
        False: every sample solved on its own by the engine (one pose at a time, each
        warm-started from the previous sample).  Slow; for checks.
    mapper : callable(fn, items) -> list, optional
        Runs the rows and statics of the path's chunks elsewhere (``screwkit trajectory
        --workers``: a Dask cluster), as :func:`screwkit.engine.analyze` says; the result
        equals the serial one bit for bit.

    Returns
    -------
    TrajectoryResult
    """
    from ..engine import analyze, load_assembled_pm

    model = load_assembled_pm(model, overrides)
    load = resolve_workload(model, force, torque)
    if load is None:
        raise InputError(no_workload_message(model))
    F, T, source = load
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
                      workers=workers, progress=progress, mapper=mapper)
        return _result(model, path, res, F, T, res.diagnostics, source)
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
                   {"anchors": 0, "batched": 0, "per_pose": N}, source)


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


def _result(model, path, res, F, T, diag, source="given") -> TrajectoryResult:
    """The :class:`TrajectoryResult` of a batched analysis along the path."""
    from ..engine import CONVERGED, constraint_resultants

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
    from ..engine import classify
    from ..engine._quality import describe_class
    cls = classify(cond, sing_mask, reach)
    status = np.where(cls == "regular", "ok", cls)
    params = {k: col(lambda p, k=k: p.solution._params[k]) for k in PARAMS}
    ext = col(lambda p: p.solution._extensions)
    ext[~reach] = np.nan
    nact = len(model.active)                   # the actuated legs (not the passive ones)
    act_v = col(lambda p: np.asarray(p.solution.actuator_values).reshape(len(p), nact))
    st_ok = reach & ~sing_mask
    vals = col(lambda p: p.statics.F_r)
    legw = col(lambda p: p.statics._derived[2])
    conw = col(lambda p: p.statics._derived[3])
    Tr = col(lambda p: p.statics._derived[4])
    eq = col(lambda p: p.statics._eq)
    cond = np.where(reach, cond, np.nan)
    message = []
    notes = [p.solution.notes if not p.solution.single else (p.solution.notes,) for p in parts]
    flat_notes = [x for group in notes for x in group]
    # the trust level of the efforts and the assembly mode, as analyze warns of them
    level = col(lambda p: np.atleast_1d(p.level))
    amp = col(lambda p: np.atleast_1d(p.quality.amplification))
    beyond = col(lambda p: np.atleast_1d(p.quality.beyond_singular_surface))
    from ..engine._limits import within_limits
    inside = col(within_limits)                 # the model's declared limits (all True: none)
    for i in range(N):
        msg = []
        if not reach[i]:
            if resid[i] > CONVERGED:          # (else a note says why: a reversed actuator)
                msg.append(f"unreachable: closure residual {resid[i]:.3g}")
        elif sing_mask[i]:
            msg.append(f"{kinds_arr[i]} singularity (condition number {cond[i]:.3g})")
        elif cls[i] == "near-singular":
            msg.append(describe_class("near-singular", cond[i]))
        if reach[i] and not sing_mask[i] and level[i] != cls[i].replace("regular", "ok") \
                and level[i] in ("ill-conditioned", "near-singular"):
            msg.append(f"trust level {level[i]}: efforts up to {amp[i]:.3g} times the load")
        if reach[i] and beyond[i]:
            msg.append("beyond a singular surface from home (det J's sign opposite to home's: "
                       "another assembly mode)")
        if reach[i] and resid[i] > CONVERGED:
            msg.append(f"not converged: closure residual {resid[i]:.3g}")
        if reach[i] and not inside[i]:
            msg.append("outside the model's declared limits")
        # (an unreachable sample's dependent angle is its last iterate's: not said)
        msg += [t for t in flat_notes[i] if "taken from the default pose" not in t
                and (reach[i] or "resolved by continuity" not in t)]
        message.append("; ".join(msg))
    info = parts[0].jacobian.info
    cons_info = [r for r in info if r.kind != "actuation"]
    labels = tuple(r.label for r in cons_info)
    kinds = tuple(r.kind for r in cons_info)
    legs = tuple(r.leg for r in cons_info)
    det = col(lambda p: np.asarray(p.statics.determined).reshape(len(p), -1))
    det = np.where(st_ok[:, None], det, True)
    det.setflags(write=False)
    cons_rows = np.array([r.kind != "actuation" for r in info])
    row_legs = np.array([r.leg for r in info])
    res_det = np.stack([det[:, cons_rows & (row_legs == i)].all(axis=1) for i in range(n)],
                       axis=1)
    # a statically indeterminate PM's least-norm values: said per sample, as analyze marks them
    row_labels = [r.label for r in info]
    for i in np.flatnonzero(~det.all(axis=1)):
        free = ", ".join(lab for lab, d in zip(row_labels, det[i]) if not d)
        note = f"not determined by statics (the least-norm choice): {free}"
        message[i] = f"{message[i]}; {note}" if message[i] else note
    res_f, res_m = constraint_resultants(conw, _base_points(parts[0], n))
    out = {
        "status": status.astype(str), "extensions": ext, "actuator_values": act_v,
        "active": vals[:, :nact], "constraint": vals[:, nact:], "T_r": Tr,
        "leg_wrenches": legw, "condition_number": cond, "closure_residual": resid,
        "equilibrium_residual": np.where(st_ok, eq, np.nan),
        "singularity": np.where(sing_mask, kinds_arr, "").astype(str),
        "message": np.array(message, dtype=str),
    }
    out["res_f"], out["res_m"], out["res_det"] = res_f, res_m, res_det
    for k in ("active", "constraint", "T_r", "leg_wrenches", "res_f", "res_m"):
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
                            labels, kinds, legs, F.copy(), T.copy(), dict(diag), model.units,
                            tuple(lg.actuated_joint.kind != "P" for lg in model.home_legs),
                            determined=det,
                            constraint_points=_constraint_points(model, parts, info, st_ok),
                            resultant_force=out["res_f"], resultant_moment=out["res_m"],
                            workload_source=source,
                            resultant_determined=out["res_det"],
                            active_legs=tuple(model.active), analysis=_kept(res, N))


def _kept(res, N):
    """The batched analysis a result keeps for its 3D view (``show``): only when a view can
    hold every sample (no large path keeps its Jacobians alive)."""
    from ..scene import MAX_STATES
    return None if isinstance(res, _Stacked) or N > MAX_STATES else res


def _base_points(part, n):
    """The legs' base points ``A_i`` ``(n, 3)`` (the base is fixed along a path)."""
    A = np.asarray(part.solution.base_points, float)
    return A if A.ndim == 2 else A.reshape(-1, n, 3)[0]


def _constraint_points(model, parts, info, ok) -> tuple:
    """Where each constraint column's force passes, at the first regular sample: ``"A_i"``
    or ``"a_i"`` when its named point is the leg's base or platform point there, else the
    point's name (``"Q (where R1 meets R5)"``); None for a couple (or no regular sample)."""
    from ..legs import point_label

    rows = [k for k, r in enumerate(info) if r.kind != "actuation"]
    start = 0
    for p in parts:
        n = len(p)
        hit = np.flatnonzero(ok[start:start + n])
        if hit.size:
            i = int(hit[0])
            pts = np.asarray(p.jacobian.points).reshape(n, len(info), 3)[i]
            A, a = (np.asarray(x, float) for x in (p.solution.base_points,
                                                    p.solution.platform_points))
            A = A if A.ndim == 2 else A.reshape(n, -1, 3)[i]      # the base is fixed
            a = a if a.ndim == 2 else a.reshape(n, -1, 3)[i]
            break
        start += n
    else:
        return (None,) * len(rows)
    tol = 1e-9 * model.normalisation.length
    out = []
    for k in rows:
        r, q = info[k], pts[k]
        if r.kind == "couple" or not np.all(np.isfinite(q)):
            out.append(None)
        elif np.linalg.norm(q - A[r.leg]) <= tol:
            out.append("A_i")
        elif np.linalg.norm(q - a[r.leg]) <= tol:
            out.append("a_i")
        else:
            out.append(point_label(r.point_name) if r.point_name else None)
    return tuple(out)
