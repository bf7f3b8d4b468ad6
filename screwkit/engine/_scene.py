"""An analysis as the data of a drawing: the wrench rows to draw (``screwkit draw``) and the
states of a 3D view (:class:`screwkit.scene.Scene`, ``PMAnalysis.show``).

Both read the analysis's public results (the rows of ``J``, their points and directions,
the statics' values, the placed legs, the quality level); nothing is computed a second way.
"""

from __future__ import annotations

import numpy as np

from ..pm import LENGTH_PARAMS, PARAMS

__all__ = ["wrench_rows", "scene_rows", "scene_of", "ROUND_OFF", "zero_round_off"]

#: A row value below this fraction of its pose's statics scale (the workload and the largest
#: effort at the pose, torques divided by the model's characteristic length) is the round-off
#: of an exact zero (the least-norm couples of a Delta under a central force come out as
#: 1e-13 N.mm): drawings show it as 0, as ``analyze`` prints it, not as a value with an arrow
#: scaled up to the longest of its kind.
ROUND_OFF = 1e-9


def zero_round_off(values, torque_rows, force, torque, length):
    """``values (N, m)`` (or ``(m,)``) with the round-off of exact zeros set to 0.

    Parameters
    ----------
    values : array_like (..., m)
        Row values of each pose (NaN where not solved: kept).
    torque_rows : array_like (m,) of bool
        Rows whose value is a torque (a couple, a rotary actuator's effort).
    force, torque : array_like (3,)
        The workload at ``o``.
    length : float
        The model's characteristic length (a torque over it is a force).
    """
    v = np.array(values, float)
    as_force = np.where(np.asarray(torque_rows, bool), np.abs(v) / length, np.abs(v))
    load = max(float(np.linalg.norm(force)), float(np.linalg.norm(torque)) / length)
    finite = np.where(np.isfinite(as_force), as_force, 0.0)
    scale = np.maximum(finite.max(axis=-1, initial=0.0), load)
    v[as_force <= ROUND_OFF * scale[..., None]] = 0.0         # NaN compares False: kept
    return v


def wrench_rows(analysis, values: bool = True):
    """The rows of :func:`screwkit.viz.draw_pm` from a one-pose :class:`PMAnalysis`.

    Returns
    -------
    rows : list of dict
        ``kind`` (actuation | force | couple), ``leg``, ``direction``, ``point``,
        ``value`` (the statics' value; NaN when singular or ``values`` is False),
        ``label`` (``F_a1``, ``F_c2``, ``T_c3``; an actuation torque is ``T_a1``),
        ``quantity`` (force | torque), ``determined`` (False where a self-stress of an
        indeterminate PM can change the value: it is the least-norm or compliance-weighted
        choice).
    skipped : list of str
        Rows that cannot be drawn (finite-pitch wrenches, a dependent actuator).
    """
    jac = analysis.jacobian
    st = analysis.statics if analysis.has_workload else None      # no load: no values
    have = st is not None and values
    vals = st.values if have else np.full(len(jac.rows), np.nan)
    det = st.determined if have else np.ones(len(jac.rows), bool)
    kinds, skipped = scene_rows(analysis.model, jac.rows)
    vals = _shown(analysis, vals, jac.info)
    rows = []
    for k, sr in kinds:
        r = jac.rows[k]
        rows.append(dict(kind=sr.kind, leg=r.leg, direction=r.direction,
                         point=None if sr.kind == "couple" else r.point, value=vals[k],
                         label=f"${sr.label[0]}_{{{sr.label[2:]}}}$", quantity=sr.quantity,
                         actuation=sr.actuation, determined=bool(det[k])))
    return rows, skipped


def scene_rows(model, info):
    """What each drawable row of ``J`` is: ``[(row index, SceneRow)]`` and the notes of the
    rows that cannot be drawn.  ``info``: the rows' :class:`RowInfo` or
    :class:`JacobianRow` (``leg``, ``kind``, ``member``, ``joint``, ``label``)."""
    from ..scene import SceneRow

    out, skipped = [], []
    for k, r in enumerate(info):
        i = r.leg + 1
        if r.kind == "actuation":
            rotary = r.torque
            if r.member == "force":
                # a rotary actuator's effort is a torque: its row is the force it transmits
                out.append((k, SceneRow(f"T_a{i}" if rotary else f"F_a{i}", "actuation", r.leg,
                                        "torque" if rotary else "force", True)))
            elif r.member == "couple":
                out.append((k, SceneRow(f"T_a{i}", "couple", r.leg, "torque", True)))
            else:
                skipped.append(f"leg {i}: actuation {r.member}")
        elif r.kind in ("force", "couple"):
            out.append((k, SceneRow(r.label, r.kind, r.leg,
                                    "force" if r.kind == "force" else "torque", False)))
        else:
            skipped.append(f"leg {i}: constraint {r.kind} {r.label}")
    labels = [sr.label for _, sr in out]
    count = {}
    for n, (k, sr) in enumerate(out):
        if labels.count(sr.label) > 1:
            count[sr.label] = count.get(sr.label, 0) + 1
            out[n] = (k, SceneRow(f"{sr.label}.{count[sr.label]}", sr.kind, sr.leg,
                                  sr.quantity, sr.actuation))
    return out, skipped


def _torque_rows(info):
    """Which rows' values are torques: couples and rotary actuators' efforts."""
    return np.array([r.torque for r in info], bool)


def _shown(analysis, values, info):
    """The values as the pictures show them: round-off of exact zeros set to 0."""
    return zero_round_off(values, _torque_rows(info), analysis.force, analysis.torque,
                          float(analysis.model.normalisation.length))


def _line_points(J, points, force_rows):
    """A point of each force row's line: its named point, else the line's point nearest
    the origin (``f x m / |f|^2``); ``(N, m, 3)``."""
    f, m = J[..., :3], J[..., 3:]
    nearest = np.cross(f, m) / np.maximum(np.einsum("...i,...i", f, f), 1e-300)[..., None]
    missing = ~np.all(np.isfinite(points), axis=-1) & force_rows[None, :]
    return np.where(missing[..., None], nearest, points)


#: The source of a view without a workload (the scene says "none (...)" with it, once).
NO_WORKLOAD = "the model declares none and none was given"


def scene_of(analysis, controls=None, *, start: int = 0, title: str | None = None,
             notes=(), source: str = ""):
    """The :class:`~screwkit.scene.Scene` of an analysis: one state per pose.

    Parameters
    ----------
    analysis : PMAnalysis
        One pose or N.
    controls : GridControls or TimeControls, optional
        How the page moves between the poses (default: a slider over the pose index).
    start : int
        The pose shown first.
    title : str, optional
    notes : sequence of str
        Shown under the view.
    source : str
        Where the workload comes from (the analysis' ``workload_source``).
    """
    from ..scene import PoseState, Scene, TimeControls

    model, sol, jac = analysis.model, analysis.solution, analysis.jacobian
    st = analysis.statics if analysis.has_workload else None      # no load: no values
    N = 1 if analysis.single else len(analysis)
    m = len(jac.info)

    def per_pose(x, shape):
        return np.asarray(x, float).reshape((N,) + shape)

    rows, skipped = scene_rows(model, jac.info)
    idx = np.array([k for k, _ in rows], int)
    force_rows = np.array([r.member != "couple" for r in jac.info])
    J = per_pose(jac.J, (m, 6))
    points = _line_points(J, per_pose(jac.points, (m, 3)), force_rows)
    dirs = per_pose(jac.directions, (m, 3))
    if st is None:
        values, det = np.full((N, m), np.nan), np.ones((N, m), bool)
    else:
        values = _shown(analysis, per_pose(st.values, (m,)), jac.info)
        det = np.asarray(st.determined, bool).reshape(N, m)
    reach = np.asarray(sol.reachable_mask, bool).reshape(N)
    cls = np.asarray(analysis.conditioning).reshape(N)             # the one classification
    level = np.asarray(analysis.level).reshape(N)
    cond = per_pose(jac.conditioning.condition_number, ())
    L = float(model.normalisation.length)
    params = {k: np.array(v, float).reshape(N) for k, v in sol.params_degrees().items()}
    for k, v in params.items():        # rounding noise of the solver (1e-22 deg) shown as 0
        v[np.abs(v) < 1e-9 * (L if k in LENGTH_PARAMS else 1.0)] = 0.0
    plat = per_pose(sol.platform_points, (model.n_legs, 3))
    o = per_pose(sol.position, (3,))
    base = np.asarray(sol.base_points, float)
    pose_notes = (sol.notes,) if analysis.single else sol.notes
    states = []
    for i in range(N):
        ok = bool(reach[i])
        legs = (sol.legs if analysis.single else sol.legs_at(i)) if ok else ()
        states.append(PoseState(
            pose={k: float(params[k][i]) for k in PARAMS},
            status="unreachable" if not ok else "ok" if cls[i] == "regular" else str(cls[i]),
            level=str(level[i]) if ok else "unreachable",
            condition_number=float(cond[i]), legs=tuple(legs), base_points=base,
            platform_points=plat[i], o=o[i],
            values=values[i, idx], points=points[i, idx], directions=dirs[i, idx],
            determined=det[i, idx], notes=tuple(pose_notes[i])))
    if controls is None:
        controls = TimeControls(np.arange(N, dtype=float))
    units = model.units
    lead = [f"not drawn: {s}" for s in skipped]
    loaded = getattr(analysis, "has_workload", True)     # an analysis without a workload
    return Scene(model.name, tuple(lg.name for lg in model.home_legs),
                 tuple(sr for _, sr in rows), tuple(states), controls,
                 {"length": units.length, "force": units.force, "torque": units.torque},
                 np.asarray(analysis.force, float) if loaded else None,
                 np.asarray(analysis.torque, float) if loaded else None,
                 source,
                 tuple(sorted(getattr(model, "passive", ()) or ())), int(start),
                 title or model.name, tuple(lead) + tuple(notes))

