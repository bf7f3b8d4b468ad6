"""Inverse dynamics of a PM along a motion (the paper's section 5.2): :func:`dynamics`.

The poses of the motion are solved by the batched engine (:func:`screwkit.engine.analyze`
with ``path=True``); per chunk of samples, the velocity and acceleration equations of the
loop closures and the Newton-Euler equations of every leg link and of the platform give
the dynamic workload (:mod:`~._kinematics`); the engine's unified statics (eq. 9,
:func:`screwkit.engine.statics`) under that workload gives the dynamic active forces and
constraint values.  The static columns are the same statics under the external workload
alone.

Examples
--------
>>> import screwkit
>>> from screwkit.dynamics import dynamics, motion_from_expressions
>>> pm = screwkit.load_pm("3RRPRR")
>>> mass = {"platform": {"mass": 40, "inertia": {"disc": {"radius": 30, "thickness": 3}}},
...         "legs": {"cylinder": {"mass": 4, "length": 50, "radius": 4},
...                  "piston": {"mass": 2, "length": 50, "radius": 2.5}}}
>>> motion = motion_from_expressions(["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)",
...                                   "Zo=75+10*t"], pm.independent, samples=21)
>>> res = dynamics(pm, motion, params=mass, force=[0, 0, 0], torque=[0, 0, 0])
>>> res.dynamic_active.shape, bool(res.ok.all())
((21, 3), True)
"""

from __future__ import annotations

import numpy as np

from ..engine import PARAMS, link_frames, statics
from ..errors import InputError
from ..pm import DynamicsParameters, dynamics_for
from ..paths import PathSpec
from ._kinematics import KIN_COND, Context, chunk_dynamics
from ._legs import setup_legs
from ._motion import Motion, motion_from_path
from ._singular import limit_rates, near_singular
from ._result import DynamicsResult

__all__ = ["dynamics", "resolve_parameters", "CHUNK"]

#: Samples per chunk of the dynamics (bounds the working memory).
CHUNK = 4096


def resolve_parameters(model, params=None, gravity=None) -> DynamicsParameters:
    """The dynamics parameters to use: ``params`` (a :class:`DynamicsParameters`, a
    ``dynamics:`` mapping or a YAML file with one), else the model's own; ``gravity``
    (3 numbers, base frame, model length / s^2) replaces theirs."""
    if params is None:
        params = model.dynamics
        if params is None:
            raise InputError(f"{model.name} declares no masses (no 'dynamics:' block): give "
                             "params= (a mapping or a YAML file with 'dynamics:'), or --mass "
                             "FILE at the command line")
    elif not isinstance(params, DynamicsParameters):
        params = dynamics_for(model, params)
    if len(params.legs) != model.n_legs:
        raise InputError(f"the dynamics parameters have {len(params.legs)} legs, "
                         f"{model.name} has {model.n_legs}")
    for i, (ld, lg) in enumerate(zip(params.legs, model.home_legs)):
        if len(ld.viscous) != len(lg.joints):
            raise InputError(f"the dynamics parameters of leg {i + 1} have {len(ld.viscous)} "
                             f"joints, {lg.name} has {len(lg.joints)}")
    if gravity is not None:
        from ..legs._guards import MAX_MAGNITUDE, real_vector
        params = params.with_gravity(real_vector(gravity, "gravity", 3, bound=MAX_MAGNITUDE))
    return params


def _motion(model, motion) -> Motion:
    if isinstance(motion, PathSpec):
        motion = motion_from_path(motion, length_unit=model.units.length)
    if not isinstance(motion, Motion):
        raise InputError(f"the motion must be a screwkit.dynamics.Motion or a PathSpec, got "
                         f"{type(motion).__name__}")
    if set(motion.names) != set(model.independent):
        raise InputError(f"{model.name}: the motion gives {', '.join(sorted(motion.names))}; "
                         f"the independent pose parameters are {', '.join(model.independent)}")
    return motion


def dynamics(model, motion, *, params=None, force=None, torque=None,
             gravity=None, overrides=None, chunk: int = CHUNK, workers=None,
             progress=None) -> DynamicsResult:
    """Inverse dynamics of a PM along a motion: dynamic active forces, constraint wrenches,
    leg reactions, joint rates and accelerations, energies.

    Parameters
    ----------
    model : PMModel or str
        A model or a catalog name / YAML path (with ``overrides``).
    motion : Motion or PathSpec
        The independent pose parameters and their time derivatives (``t`` in seconds); a
        :class:`~screwkit.paths.PathSpec` is splined (:func:`motion_from_path`).
    params : DynamicsParameters, mapping or path, optional
        Masses, inertias, friction, gravity (default: the model's ``dynamics:`` block).
    force, torque : array_like (3,), optional
        External workload at ``o`` besides gravity and inertia (model units; one without the
        other: the other is zero; neither: the model's declared default workload, else an
        :class:`~screwkit.errors.InputError`).
    gravity : array_like (3,), optional
        Replaces the parameters' gravity (base frame, model length / s^2).
    chunk, workers, progress :
        As :func:`screwkit.engine.analyze` (``progress(done, total)`` counts the poses, then
        the dynamics).

    Returns
    -------
    DynamicsResult
    """
    from ..engine import analyze, load_assembled_pm

    model = load_assembled_pm(model, overrides)
    params = resolve_parameters(model, params, gravity)
    motion = _motion(model, motion)
    from ..engine._workloads import no_workload_message, resolve_workload
    load = resolve_workload(model, force, torque)
    if load is None:
        raise InputError(no_workload_message(model))
    F, T, source = load
    try:
        C = int(chunk)
    except (TypeError, ValueError):
        raise InputError(f"chunk must be an integer, not {chunk!r}") from None
    if C < 1:
        raise InputError(f"chunk must be >= 1, not {chunk!r}")
    N = len(motion)
    pose = {k: np.asarray(motion.values[k], float) for k in model.independent}
    an = analyze(model, pose, force=F, torque=T, path=True, chunk=C, workers=workers,
                 progress=(lambda d, tot: progress(d, tot + N)) if progress else None)  # 2 N + N
    jac = an.jacobian
    R0 = np.asarray(model.frame[0], float)
    ind = np.array([PARAMS.index(p) for p in PARAMS if p in model.independent])
    dep = np.array([PARAMS.index(p) for p in PARAMS if p not in model.independent], int)
    row_leg = np.array([r.leg for r in jac.info[jac.n_actuated:]], int)
    ctx = Context(setup_legs(model, params), ind, dep, jac.n_actuated, row_leg, params.platform,
                  R0 @ params.gravity, np.asarray(model.normalisation.centre, float),
                  float(model.normalisation.length), F, T)
    names = [PARAMS[k] for k in ind]
    thd = np.column_stack([motion.rates[k] for k in names])
    thdd = np.column_stack([motion.accelerations[k] for k in names])
    J = jac.matrix
    out = {}
    for s in range(0, N, C):
        sl = slice(s, min(s + C, N))
        part = chunk_dynamics(ctx, link_frames(an.solution, sl), J[sl], thd[sl], thdd[sl])
        for k, v in part.items():
            if k not in out:
                out[k] = np.empty((N,) + v.shape[1:])
            out[k][sl] = v
        if progress:
            progress(2 * N + sl.stop, 3 * N)
    reach = an.solution.reachable_mask
    near, bs = near_singular(model, an.solution._params["beta"])
    near &= reach & ~jac.singular_mask
    out["limit"] = np.zeros(N, bool)
    if near.any():
        idx = np.flatnonzero(near)
        td, tdd, good, cond = limit_rates(model, an, idx, bs[idx], ctx, thd, thdd,
                                          chunk_dynamics, link_frames)
        part = chunk_dynamics(ctx, link_frames(an.solution, idx), J[idx], thd[idx], thdd[idx],
                              dependent=(td, tdd))
        part["kinematic_condition"] = np.where(good, cond, np.inf)
        for k, v in part.items():
            out[k][idx] = v
        out["limit"][idx] = good
    undetermined = reach & ~(out["kinematic_condition"] <= KIN_COND)
    bad = ~reach | jac.singular_mask | undetermined
    W = np.where(bad[:, None], 0.0, out["workload"])
    o = np.where(bad[:, None], 0.0, an.solution._platform[1])
    Fd = W[:, :3]
    Td = W[:, 3:] - np.cross(o, Fd)
    dyn = statics(jac, Fd, Td, o, raise_on_singular=False, base_points=an.solution.base_points,
                  platform_points=an.solution._platform[2])
    for k in ("qd", "qdd", "ID", "mapped", "theta_dot", "theta_ddot", "twist", "acceleration",
              "platform_wrench", "workload", "kinetic", "potential", "kinetic_platform"):
        out[k][undetermined | ~reach] = np.nan
    return DynamicsResult(model, motion, params, an, dyn, out, bad, undetermined, F, T, source)
