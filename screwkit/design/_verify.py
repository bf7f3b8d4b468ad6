"""Verification of a candidate PM with the engine: full-cycle mobility and actuation.

A candidate (a ``pms:`` definition from :func:`screwkit.synthesis.pm_definition`) is
loaded as a model (home assembly, default pose, :func:`screwkit.engine.check_default_pose`)
and moved from home along a closed-form path through its independent pose parameters
(:func:`verification_path`: ``PATH_SAMPLES`` samples solved by ``engine.analyze`` as one
batch from the home assembly, with the engine's continuation from home where Newton
fails; not ``path=True``, whose polynomial predictor is fitted once per model on a grid
of poses, a cost that one short path does not repay).  The samples are one continuous
motion when no joint value jumps between neighbours (at most ``MAX_JUMP`` times the
median step).  Before that batch the samples are marched by Newton alone, each started at
the previous one's assembly (:func:`_march`): a candidate Newton cannot carry along the
path is rejected where it stops, without the continuation, which is most of the cost of a
rejection.  It is accepted when

* every sample of the path is assembled (``status`` ``ok``), by the march and by the batch;
* at home and at ``CHECK_POSES`` poses spread along the path the instantaneous mobility
  (:func:`screwkit.pm.mobility`: ``6 - rank`` of the union of the legs' constraint
  wrenches at the solved pose) has the motion's DOF, its number of independent pure
  translations and the rank of its rotations (``3T``: 3 and 0; ``1T2R``: 1 and 2 ...);
* the finite motion has the pattern's invariant where it has one: the rotation stays the
  home rotation (3T), the platform normal stays the base normal (3T1R, 2T1R), or one
  base-fixed point stays fixed (3R: the least-squares centre of the displacements has a
  residual below ``FINITE_RTOL`` times the characteristic length);
* at home ``J = [J_a; J_c]`` is non-singular (rank 6, length-normalised condition number
  below the engine's ``COND_THRESHOLD``): the actuators control the motion;
* the finite motion type computed from motions sampled from home
  (:func:`screwkit.engine.finite_motion`) has the pattern's translations and rotations.

A candidate with passive legs (no actuator, :func:`screwkit.synthesis.passive_compositions`)
is loaded with the actuated joint its leg type marks, and its ``J`` is the engine's
unified Jacobian without those legs' actuation rows (:func:`actuation_condition`): the
actuated legs' actuation rows and every leg's constraint rows, normalised and
row-equilibrated by the engine's own normalisation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..engine import COND_THRESHOLD, analyze, check_default_pose, finite_motion
from ..errors import ScrewkitError
from ..pm import load_pm, mobility
from ..screws import RANK_RTOL

__all__ = ["CHECK_POSES", "FINITE_RTOL", "PATH_SAMPLES", "PoseCheck", "Verdict",
           "actuation_condition", "verify_model", "verification_path"]

#: Samples of the verification path (home first).
PATH_SAMPLES = 13
#: Poses along the path (besides home) where the mobility is checked.
CHECK_POSES = 6
#: Path amplitudes: angles (degrees) and lengths (fraction of the characteristic length).
AMPLITUDE_DEG = 8.0
AMPLITUDE_LENGTH = 0.08
#: Largest jump of the joint values between neighbouring path samples, over the median one.
MAX_JUMP = 4.0
#: Tolerance of the finite-motion invariants, relative (rotations) or to the length ``L``.
FINITE_RTOL = 1e-7


@dataclass(frozen=True)
class PoseCheck:
    """The mobility at one checked pose of the path.

    Attributes
    ----------
    pose : dict
        Independent pose parameters (degrees and the model's lengths).
    dof : int
    motion_type : str
        The instantaneous type at the pose, as :func:`screwkit.pm.mobility` labels it
        (helical freedoms with their pitch: the 3-RPS's twist space is ``1T1R1H(p=...)``
        away from home, its rotations coupled with parasitic translations).
    translations, rotations : int
        Independent pure translations and the rank of the angular parts of the twist
        space: the counts compared with the motion pattern's.
    condition_number : float
        Length-normalised condition number of ``J`` (``inf`` where singular).
    """

    pose: dict
    dof: int
    motion_type: str
    translations: int
    rotations: int
    condition_number: float


@dataclass(frozen=True)
class Verdict:
    """Result of :func:`verify_model`.

    Attributes
    ----------
    success : bool
    reason : str
        Why it failed (empty on success).
    checks : tuple of PoseCheck
        Home first, then the poses along the path.
    condition_home : float
    finite : str
        The finite-motion invariant checked and its largest deviation.
    reached : int
        Path samples assembled (of ``PATH_SAMPLES``).
    singular_on_path : int
        Path samples where ``J`` is singular (allowed, reported).
    notes : tuple of str
    motion : str
        The finite motion type computed from home (:func:`screwkit.engine.finite_motion`),
        with its parasitic motions and invariants.
    check : str
        The check that failed (empty on success): ``"workspace"``, ``"continuity"``,
        ``"actuation"`` (``J`` at home), ``"mobility"`` or ``"finite"``.  All but
        ``"actuation"`` are properties of the platform's motion alone, which legs without
        constraint do not change.
    """

    success: bool
    reason: str
    checks: tuple = ()
    condition_home: float = float("inf")
    finite: str = ""
    reached: int = 0
    singular_on_path: int = 0
    notes: tuple = ()
    motion: str = ""
    check: str = ""


def verification_path(model, samples: int = PATH_SAMPLES) -> dict:
    """The independent pose parameters along the verification path ``(samples,)`` arrays.

    ``p_k(t) = home_k + A_k t cos(2 pi t + 2 pi k / n)`` for ``t`` in ``[0, 1]`` and the
    ``n`` independent parameters ``k``: a spiral out of home that moves every parameter
    (``A_k``: ``AMPLITUDE_DEG`` for angles, ``AMPLITUDE_LENGTH`` times the model's
    characteristic length for lengths).  Radians and lengths.
    """
    t = np.linspace(0.0, 1.0, samples)
    ind = model.independent
    L = float(model.normalisation.length)
    out = {}
    for k, p in enumerate(ind):
        amp = np.radians(AMPLITUDE_DEG) if p in ("alpha", "beta", "gamma") else AMPLITUDE_LENGTH * L
        out[p] = model.home_pose[p] + amp * t * np.cos(2 * np.pi * t + 2 * np.pi * k / len(ind))
    return out


def _finite(motion, R, o, L) -> tuple:
    """(description, largest deviation, ok) of the pattern's finite invariant, from the
    rotations ``R (N, 3, 3)`` and positions ``o (N, 3)`` along the path."""
    if motion.fixed_rotation == "all":
        err = float(np.max(np.abs(R - R[0])))
        return "rotation constant (3T)", err, err <= FINITE_RTOL
    if motion.fixed_rotation == "z":
        err = float(np.max(np.abs(R[:, :, 2] - R[0][:, 2])))
        return "platform normal constant", err, err <= FINITE_RTOL
    if motion.fixed_point:
        # o_i = p + R_i R_0^T (o_0 - p): (I - Q_i) p = o_i - Q_i o_0, Q_i = R_i R_0^T
        Q = R @ R[0].T
        A = (np.eye(3) - Q).reshape(-1, 3)
        b = (o - np.einsum("nij,j->ni", Q, o[0])).reshape(-1)
        p, *_ = np.linalg.lstsq(A, b, rcond=None)
        err = float(np.max(np.abs(A @ p - b))) / L
        return f"a base-fixed centre ({', '.join(f'{x:.4g}' for x in p)})", err, err <= FINITE_RTOL
    return "", 0.0, True


def _march(model, path) -> int:
    """The path samples closed one after the other, each by Newton started at the previous
    one's assembly (home for the first), without the engine's continuation; ``n`` when all
    (or when Newton from home closes every sample).

    Neighbouring samples are a twelfth of the amplitudes apart: where the closure
    equations are regular along the path Newton converges there in a few iterations;
    where it does not, the candidate cannot follow the path (it is immobile beyond first
    order, or meets a bifurcation).  This costs a few milliseconds a sample, while the
    engine's continuation from home (4, 16 and 64 smaller steps for each failing sample)
    was most of the cost of a rejected candidate.  Measured on the default 3T, 1T2R and
    3T1R searches (266, 366 and 411 candidates verified), every candidate the march
    stopped was rejected by the batch with the continuation too: the continuation rescued
    none (``docs/synthesis.md``)."""
    # the engine's closures without its continuation (analyze always continues)
    from ..engine._chains import chains_of
    from ..engine._solve import solve_closures

    ch = chains_of(model)
    n = len(next(iter(path.values())))

    def closes(ks, X):
        fixed = {p: np.asarray(path[p][ks], float) for p in ch.fixed}
        c = solve_closures(model, fixed, X, continuation=False)
        return bool(np.all(np.asarray(c.how) == 0)), c.X

    # every sample from home at once first (one batched solve): where all close, the
    # march is not needed (the batch analysis does the same, and checks the continuity)
    if closes(slice(1, n), ch.home_vector(n - 1))[0]:
        return n
    X = ch.home_vector(1)
    for k in range(1, n):
        ok, X = closes(slice(k, k + 1), X)
        if not ok:
            return k
    return n


def _walk(model, path):
    """The analysis of the path's samples as one batch, each pose started from the home
    assembly (with the engine's continuation from home where Newton fails), and the
    largest jump of the joint values between neighbouring samples relative to the median
    one (a jump to another assembly branch shows as a large ratio); first the samples are
    marched by Newton alone (:func:`_march`): ``(k, None, 0)`` when it stops at sample
    ``k``, else ``(n, analysis, jump)``."""
    k = _march(model, path)
    if k < len(next(iter(path.values()))):
        return k, None, 0.0
    res = analyze(model, path, guess=dict(model.home_pose), raise_on_singular=False)
    q = np.concatenate([np.asarray(v, float).reshape(len(res), -1)
                        for v in res.solution.joint_values], axis=1)
    dq = np.max(np.abs(np.diff(q, axis=0)), axis=1)
    med = float(np.median(dq)) if len(dq) else 0.0
    jump = float(np.max(dq) / med) if med > 0 else 0.0
    return k, res, jump


def actuation_condition(jacobian, passive=()) -> tuple:
    """``(condition_number (N,), singular (N,))`` of the unified Jacobian without the
    actuation rows of the ``passive`` legs (0-based leg indices).

    ``jacobian`` is the engine's :class:`~screwkit.engine.JacobianResult` of N poses; the
    rows kept are normalised with its own normalisation (centroid and characteristic
    length of the legs, ``conditioning.normalised``), and the condition number is
    ``s_1 / s_6`` of their singular values, ``inf`` below rank 6 (``RANK_RTOL``), as the
    engine defines it for the whole ``J``.  Singular: rank below 6 or condition number
    not below ``COND_THRESHOLD``.
    """
    passive = set(passive)
    keep = [i for i, r in enumerate(jacobian.info)
            if not (r.kind == "actuation" and r.leg in passive)]
    from ..engine._pipeline import conditioning_of
    c = jacobian.conditioning
    n_act = sum(1 for i in keep if jacobian.info[i].kind == "actuation")
    out = conditioning_of(np.asarray(jacobian.matrix, float)[:, keep], n_act, c.centre, c.length)
    s = out.singular_values
    cond = np.array(out.condition_number, float)
    if s.shape[1] >= 6:
        cond[~(s[:, 5] > RANK_RTOL * np.maximum(s[:, 0], 1e-300))] = np.inf
    return cond, ~(cond < COND_THRESHOLD)


def verify_model(model, motion, passive=()) -> Verdict:
    """Verify a loaded model (``screwkit.pm.PMModel``) for ``motion`` (see the module);
    ``passive``: 0-based indices of passive legs (their actuation rows are left out of
    ``J``)."""
    passive = tuple(passive)
    if any(isinstance(i, bool) or not isinstance(i, (int, np.integer))
           or not 0 <= i < len(model.legs) for i in passive):
        from ..errors import InputError
        raise InputError(f"{model.name}: passive legs are 0-based leg indices below "
                         f"{len(model.legs)}, got {passive!r:.60}")
    path = verification_path(model)
    n = len(next(iter(path.values())))
    marched, res, jump = _walk(model, path)
    if res is None:
        return Verdict(False, f"the path leaves the workspace at sample {marched} of {n} "
                       "(Newton from the previous sample's assembly does not close it)",
                       reached=marched, check="workspace")
    okay = np.asarray(res.solution.success, bool)
    reached = int(np.argmin(okay)) if not okay.all() else n
    if reached < n:
        return Verdict(False, f"the path leaves the workspace at sample {reached} of {n}",
                       reached=reached, check="workspace")
    if jump > MAX_JUMP:
        return Verdict(False, f"the joint values jump between neighbouring path samples "
                       f"({jump:.3g} times the median step): not one continuous motion",
                       reached=reached, check="continuity")
    if passive:
        cond, sing = actuation_condition(res.jacobian, passive)
    else:
        cond = np.asarray(res.jacobian.condition_number, float)
        sing = np.asarray(res.singular, bool)
    if sing[0] or not cond[0] < COND_THRESHOLD:
        return Verdict(False, f"J is singular at home (condition number {cond[0]:.3g}): the "
                       "actuators do not control the motion", reached=reached,
                       condition_home=float(cond[0]), check="actuation")
    idx = [0] + [int(round(i)) for i in np.linspace(n / CHECK_POSES, n - 1, CHECK_POSES)]
    checks = []
    for i in idx:
        m = mobility(res.solution[i])
        pose = {p: float(np.degrees(path[p][i]) if p in ("alpha", "beta", "gamma") else path[p][i])
                for p in model.independent}
        checks.append(PoseCheck(pose, int(m.dof), str(m.instantaneous_type), int(m.translations),
                                int(m.rotations), float(cond[i])))
    notes = []
    bad = [c for c in checks if c.dof != motion.dof]
    if bad:
        return Verdict(False, f"{bad[0].dof} DOF instead of {motion.dof} at a pose of the path",
                       tuple(checks), float(cond[0]), reached=reached, check="mobility")
    want = (motion.translations, motion.rotations)
    wrong = [c for c in checks if (c.translations, c.rotations) != want]
    if wrong:
        return Verdict(False, f"the twist space is {wrong[0].motion_type} ({wrong[0].translations}"
                       f" translations, {wrong[0].rotations} independent rotations), not "
                       f"{motion.name}, at a pose of the path", tuple(checks), float(cond[0]),
                       reached=reached, check="mobility")
    L = float(model.normalisation.length)
    R = np.asarray(res.solution.rotation, float)
    o = np.asarray(res.solution.position, float)
    what, err, ok = _finite(motion, R, o, L)
    finite = f"{what}: largest deviation {err:.2g}" if what else ""
    if not ok:
        return Verdict(False, f"the finite motion breaks the {motion.name} invariant ({finite})",
                       tuple(checks), float(cond[0]), finite, reached, check="finite")
    fm = finite_motion(model)
    if (fm.translations, fm.rotations) != (motion.translations, motion.rotations):
        return Verdict(False, f"the finite motion computed from home is {fm.label}, not "
                       f"{motion.name} ({fm.text})", tuple(checks), float(cond[0]), finite,
                       reached, check="finite")
    if passive:
        notes.append(f"J without the actuation row of passive leg "
                     f"{', '.join(str(i + 1) for i in passive)}")
    n_sing = int(np.sum(sing))
    if n_sing:
        notes.append(f"J is singular at {n_sing} of {n} path samples")
    return Verdict(True, "", tuple(checks), float(cond[0]), finite, reached, n_sing, tuple(notes),
                   fm.text)


def load_candidate(name: str, catalog):
    """``(model, None)``: the model ``name`` of ``catalog`` (its home assembly; the
    candidates' default pose is home), or ``(None, error)``: the
    :class:`~screwkit.errors.ScrewkitError` that says why it cannot be built."""
    try:
        # the finite motion type is checked by verify_model, once the path holds
        return check_default_pose(load_pm(name, None, catalog), check_motion=False), None
    except ScrewkitError as exc:
        return None, exc
