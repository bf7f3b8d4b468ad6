"""Forward kinematics (direct displacement) of N poses: the platform pose from the actuators.

The loop closures of :mod:`screwkit.engine._kernels._newton` are solved the other way round: the
actuated joint values are given (frozen) and the unknowns are the platform's pose and
every passive joint.  The platform moves by its own twist (the six columns of the
identity, length-normalised about the model's centroid), so the iteration has no
representation singularity; the pose is read off as the model's Euler angles at the end.
The Gauss-Newton step is the engine's (:func:`~screwkit.engine._kernels._newton.newton_step` with
the platform's twist and the actuated joints frozen), with per-pose convergence and step
halving.

Starts.  From home (or a guess: a pose, a :class:`PoseSolution`), the actuated values move
from the start's to the targets in steps of at most :data:`STEP` (continuation), each step
started from the last, then in 4 times as many steps where that fails, then by Newton
straight from the start, and last by a seed search (:mod:`screwkit.engine._modes`) keeping
the solution nearest the start's pose: those may be other assembly modes, and the result
says how each pose was found (``steps``, ``tracked``).  The solution found
from home is the assembly mode connected to home along that path; :func:`assembly_modes`
(:mod:`screwkit.engine._modes`) searches many seeds at once for the others.

At the solutions the PM is analysed by :func:`screwkit.engine.analyze` (warm-started from
the forward solution), which gives the conditioning and the sign of ``det J``.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np

from ._chains import LENGTH_PARAMS, PARAMS, chains_of
from ._kernels._layout import CONVERGED
from ._fk_inputs import actuator_targets
from ._fk_newton import STEP, continuation
from ._limits import within_limits
from ._pose_params import SPLIT_TOL, pose_params, split_singular, unsplit_notes

__all__ = ["ForwardResult", "forward_kinematics", "actuator_targets", "reference", "finish",
           "split_singular", "STEP", "SPLIT_TOL"]




@dataclass(frozen=True, eq=False)
class ForwardResult:
    """Platform poses solved from actuated joint values (N poses; ``single``: one).

    Attributes
    ----------
    model : PMModel
    params : dict str -> ndarray (N,)
        The six pose parameters (radians, model lengths).
    rotation : ndarray (N, 3, 3) ; position : ndarray (N, 3)
        World <- platform, and ``o``.
    actuators : ndarray (N, n)
        The actuated joint values asked for (from home).
    residual : ndarray (N,)
        Length-normalised closure residual.
    success : ndarray (N,) of bool
        Converged and confirmed by the analysis at the pose.
    iterations : ndarray (N,)
    steps : ndarray (N,)
        Continuation steps that solved the pose: 0 Newton straight from the start, -2 a seed
        search (no path from the start: the solution nearest the start's pose), -1 not
        solved.
    condition_number : ndarray (N,)
        Normalised condition number of ``J`` at the solution.
    det_sign : ndarray (N,) ; reference_det_sign : int
        Signs of ``det J`` (0: not square) at the solutions and at the start without a
        guess (:func:`reference`: home, or the default pose where home is singular); a sign
        unlike the reference's is another assembly mode.
    reference : str
        ``"home"`` or ``"the default pose"``.
    analysis : PMAnalysis
        The engine's analysis at the solved poses.
    notes : tuple of str
    unsplit : ndarray (N,) of bool
        Closed poses (every leg's closure holds) at a representation singularity whose split
        of ``alpha`` and ``gamma`` was not found (:func:`split_singular`): ``success`` is
        False for them, as the analysis does not confirm them, but they are poses of the PM.
    """

    model: object
    params: dict
    rotation: np.ndarray
    position: np.ndarray
    actuators: np.ndarray
    residual: np.ndarray
    success: np.ndarray
    iterations: np.ndarray
    steps: np.ndarray
    condition_number: np.ndarray
    det_sign: np.ndarray
    reference_det_sign: int
    analysis: object = field(repr=False)
    notes: tuple = ()
    single: bool = False
    reference: str = "home"
    unsplit: np.ndarray = None

    def __len__(self):
        return len(self.residual)

    @property
    def independent(self) -> dict:
        """The model's independent pose parameters (radians, model lengths)."""
        return {k: self.params[k] for k in self.model.independent}

    @property
    def tracked(self) -> np.ndarray:
        """Solved by continuation from the start along the straight actuator path (the
        start's assembly mode, unless the path crosses a singularity)."""
        return self.steps > 0

    @property
    def same_mode_as_reference(self) -> np.ndarray:
        """``det J`` has the reference's sign (its assembly mode; True where undefined)."""
        return (self.det_sign == self.reference_det_sign) | (self.det_sign == 0) | \
            (self.reference_det_sign == 0)

    @property
    def side(self) -> np.ndarray:
        """Which side of the base plane each solution's platform centre is on: ``+1`` home's
        side (above the base), ``-1`` the other (below: a mirror mode), ``0`` in the plane
        (:func:`~screwkit.engine._quality.base_side`)."""
        from ._quality import base_side
        return base_side(self.model, np.asarray(self.position, float).reshape(-1, 3))

    @property
    def working_mode(self) -> np.ndarray:
        """The working mode's sign pattern: above the base and ``det J`` of the reference's
        sign (where the PM is built to work)."""
        return (self.side > 0) & self.same_mode_as_reference

    def mode_text(self, i: int = 0) -> str:
        """``above the base, det J -1 (the working mode's sign pattern)``: solution ``i``'s
        mode in words."""
        side = {1: "above the base", 0: "in the base plane", -1: "below the base (mirror)"}[
            int(self.side[i])]
        sign = f"det J {int(self.det_sign[i]):+d}" if self.det_sign[i] else "J not square"
        tail = ("the working mode's sign pattern" if self.working_mode[i] else
                f"not the working mode ({self.reference}: above the base, det J "
                f"{self.reference_det_sign:+d})")
        return f"{side}, {sign}: {tail}"

    def pose(self, i: int = 0, degrees: bool = False) -> dict:
        """The six pose parameters of solution ``i`` (radians, or degrees with ``degrees``;
        model lengths)."""
        return {k: float(np.degrees(v[i]) if (degrees and k not in LENGTH_PARAMS) else v[i])
                for k, v in self.params.items()}

    def to_dict(self, i: int = 0, units=None) -> dict:
        """JSON-ready description of solution ``i`` (degrees; lengths in the model's units,
        or in m with ``units="SI"``)."""
        from ._report import output_scales
        u, k = output_scales(self.model, units)
        pose = {p: v * k["length"] if p in LENGTH_PARAMS else v
                for p, v in self.pose(i, degrees=True).items()}
        if not self.success[i]:         # not a confirmed solution: no mode, no conditioning
            closed = bool(self.unsplit is not None and self.unsplit[i])
            return {"pose": pose, "units": u,
                    "residual": float(self.residual[i]), "success": False,
                    "closed_unconfirmed": closed,
                    "mode": ("closes every leg at a representation singularity, not confirmed "
                             "by the analysis" if closed else
                             "not solved: the last iterate, not a pose of the PM"),
                    "condition_number": None, "det_sign": None,
                    "reference": self.reference,
                    "reference_det_sign": int(self.reference_det_sign),
                    "same_assembly_mode_as_reference": None, "side_of_base": None,
                    "working_mode": None, "conditioning": "unreachable",
                    "level": "unreachable", "extensions": None,
                    "continuation_steps": int(self.steps[i]),
                    "tracked": bool(self.tracked[i]), "iterations": int(self.iterations[i]),
                    "within_limits": None}
        return {"pose": pose, "units": u,
                "residual": float(self.residual[i]), "success": bool(self.success[i]),
                "closed_unconfirmed": bool(self.unsplit is not None and self.unsplit[i]),
                "condition_number": float(self.condition_number[i]),
                "det_sign": int(self.det_sign[i]),
                "reference": self.reference, "reference_det_sign": int(self.reference_det_sign),
                "same_assembly_mode_as_reference": bool(self.same_mode_as_reference[i]),
                "side_of_base": {1: "above", 0: "in the base plane", -1: "below"}[
                    int(self.side[i])],
                "working_mode": bool(self.working_mode[i]), "mode": self.mode_text(i),
                "conditioning": str(np.atleast_1d(self.analysis.conditioning)[i]),
                "level": str(np.atleast_1d(self.analysis.level)[i]),
                "extensions": (np.atleast_2d(self.analysis.solution.extensions)[i]
                               * k["length"]).tolist(),
                "continuation_steps": int(self.steps[i]), "tracked": bool(self.tracked[i]),
                "iterations": int(self.iterations[i]),
                "within_limits": bool(within_limits(self.analysis)[i])}

    def __repr__(self):
        return (f"ForwardResult({self.model.name}: {len(self)} poses, "
                f"{int(np.sum(self.success))} solved)")


_REFERENCE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def reference(model):
    """Where the forward kinematics starts without a guess: ``(name, pose, det_sign)`` of
    home, or of the model's default pose where home is near-singular (for instance a
    platform similar to its base: the architecture is singular at the symmetric home)."""
    out = _REFERENCE.get(model)
    if out is None:
        from ._analysis import analyze
        from ._quality import NEAR_SINGULAR_COND
        for name, pose in (("home", {p: model.home_pose[p] for p in model.independent}),
                           ("the default pose", dict(model.default_pose))):
            an = analyze(model, {p: np.array([v]) for p, v in pose.items()},
                         raise_on_singular=False)
            cond = float(an.jacobian.condition_number[0])
            if cond <= NEAR_SINGULAR_COND and bool(an.ok[0]):
                break
        out = (name, pose, int(an.quality.det_sign[0]))
        _REFERENCE[model] = out
    return out


def _start_state(model, ch, guess, N):
    """``(R, o, q)`` of the start and its actuated values ``(n, N)``."""
    from ..errors import InputError
    if guess is None and reference(model)[0] != "home":
        guess = reference(model)[1]
    if guess is None:
        Rh, ph = (np.asarray(x, float) for x in model.platform_home)
        R = np.repeat(Rh[:, :, None], N, axis=2)
        o = np.repeat(ph[:, None], N, axis=1)
        q = np.zeros((ch.n, ch.m, N))
        return (R, o, q), np.zeros((len(ch.active), N))
    from ._solution import solve
    sol = guess if hasattr(guess, "closures") else None
    if sol is None:
        if not isinstance(guess, dict):
            raise InputError(f"{model.name}: guess must be a pose (dict of the independent "
                             "parameters, radians) or a PoseSolution")
        try:
            # (the values as they are: the pose's checks say what is wrong with one)
            sol = solve(model, {k: [v] if np.ndim(v) == 0 else v for k, v in guess.items()},
                        raise_unreachable=True)
        except InputError as e:
            raise InputError(f"the guess: {e}") from None
    c = sol.closures
    if not np.all(c.residual <= CONVERGED):
        raise InputError(f"{model.name}: the guess does not assemble")
    nu = len(ch.unknown)
    q = c.X[nu:].reshape(ch.n, ch.m, -1) * ch.q_scale[:, :, None]
    Rp = np.ascontiguousarray(np.atleast_3d(sol._platform[0]).transpose(1, 2, 0))
    o = np.ascontiguousarray(np.atleast_2d(sol._platform[1]).T)
    if q.shape[-1] == 1 and N > 1:
        q, Rp, o = (np.repeat(x, N, axis=-1) for x in (q, Rp, o))
    if q.shape[-1] != N:
        raise InputError(f"{model.name}: the guess has {q.shape[-1]} poses for {N}")
    return (Rp, o, q), q[ch.actuator_slots]


def forward_kinematics(model, actuators, guess=None, *, degrees: bool = False):
    """Forward kinematics: the platform poses where the actuated joints take ``actuators``.

    Parameters
    ----------
    model : PMModel
    actuators : array_like (n,) or (N, n), or mapping
        Actuated joint values, displacements from home (radians for rotary actuators unless
        ``degrees``, model lengths for linear ones); a mapping ``q1..qn`` / ``r1..rn`` (leg
        extensions ``|a_i - A_i|`` where that is the actuator's value + a constant).
    guess : dict or PoseSolution, optional
        Start (default: home), then continuation (module docstring); a dict's angles in
        radians unless ``degrees``.

    Returns
    -------
    ForwardResult
    """
    from ..legs._guards import flag
    if flag(degrees, "degrees") and isinstance(guess, dict):
        guess = {k: (v if k in LENGTH_PARAMS else np.radians(np.asarray(v, float)))
                 for k, v in guess.items()}
    ch = chains_of(model)
    target, single = actuator_targets(model, actuators, degrees)
    N = target.shape[0]
    start, qa0 = _start_state(model, ch, guess, N)
    R, o, q, res, its, how = continuation(ch, start, qa0, target.T)
    lost = np.flatnonzero(~(res <= CONVERGED))
    if lost.size:                    # no path from the start: the nearest solution of a search
        from ._fk_newton import nearest_solutions
        Rn, on, qn, rn, itn = nearest_solutions(model, ch, target[lost], start, lost)
        better = rn < res[lost]
        k = lost[better]
        R[..., k], o[:, k], q[..., k], res[k], its[k] = Rn[..., better], on[:, better], \
            qn[..., better], rn[better], its[k] + itn[better]
        how[k] = -2
    ref = {p: (np.full(N, model.home_pose[p]) if guess is None or not isinstance(guess, dict)
               else np.full(N, float(np.asarray(guess.get(p, model.home_pose[p])).ravel()[0])))
           for p in ("alpha", "beta", "gamma")}
    return finish(model, ch, R, o, q, res, its, how, target, single, ref)


def finish(model, ch, R, o, q, res, its, how, target, single, ref, notes=()):
    """Pose parameters, the analysis at the solutions and the :class:`ForwardResult`."""
    from ._analysis import analyze
    from ._solution import make_solution
    from ._solve import Closures
    N = res.shape[0]
    params, sing, unsplit = pose_params(model, ch, R, o, ref, q)
    nu = len(ch.unknown)
    X = np.empty((ch.n_unknowns, N))
    for k, u in enumerate(ch.unknown):
        X[k] = params[u] / ch.x_scale[k]
    X[nu:] = (q / ch.q_scale[:, :, None]).reshape(ch.n * ch.m, N)
    fixed = {p: np.nan_to_num(params[p]) for p in ch.fixed}
    guess = make_solution(model, Closures(ch, X, fixed, res, its, np.zeros(N, int),
                                          np.zeros(N, bool)), False, [])
    an = analyze(model, fixed, guess=guess, raise_on_singular=False)
    sol = an.solution
    same = (np.max(np.abs(sol._platform[0] - R.transpose(2, 0, 1)), axis=(1, 2)) <= 1e-8) & \
        (np.max(np.abs(sol._platform[1] - o.T), axis=1) <= 1e-8 * ch.length)
    ok = (res <= CONVERGED) & sol.reachable_mask & same
    unsplit_mask = np.zeros(N, bool)
    unsplit_mask[unsplit] = res[unsplit] <= CONVERGED
    q_an = np.nan_to_num(np.asarray(sol.actuator_values), nan=np.inf)
    linear = np.array([model.home_legs[i].actuated_joint.kind == "P" for i in ch.active], bool)
    ok &= np.max(np.abs(q_an - target) / np.where(linear, ch.length, 1.0), axis=1) <= 1e-8
    det = an.quality.det_sign
    out = ForwardResult(model, {p: params[p] for p in PARAMS}, R.transpose(2, 0, 1).copy(),
                        o.T.copy(), target, res, ok, its, how,
                        np.asarray(an.jacobian.conditioning.condition_number), det,
                        reference(model)[2], an,
                        tuple(notes) + (("beta at a representation singularity of "
                                         f"{model.order}: the determined combination of alpha "
                                         "and gamma split as the model does",) if sing.any()
                                        else ()) + unsplit_notes(model, unsplit, res),
                        single, reference(model)[0], unsplit_mask)
    return out
