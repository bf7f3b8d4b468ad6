"""How much to trust each pose: the conditioning class, the trust level of the efforts, the
force amplification and the assembly mode (private).

* ``conditioning`` (:func:`classify`): THE classification of a pose that every command and
  output uses (analyze, trajectory, map, size, stiffness, dynamics): ``regular``,
  ``near-singular`` (the normalised condition number above :data:`NEAR_SINGULAR_COND`) or
  ``singular`` (above the Jacobian's threshold, :data:`~screwkit.engine.COND_THRESHOLD` by
  default); ``unreachable`` where the pose has no assembly (and no conditioning);
* ``condition_number``: the normalised one of :mod:`screwkit.engine._jacobian`;
* ``amplification``: the largest effort over the size of the workload, in consistent
  units: forces as they are, couples and rotary-actuator torques divided by the
  characteristic length ``L`` of the pose (the normalisation's), the workload's size
  ``sqrt(|F|^2 + |T / L|^2)``; 1 means the legs carry no more than the load;
* ``level``, the trust level of the efforts: the class, made worse by the force
  amplification: ``singular`` above :data:`~screwkit.engine.COND_THRESHOLD`; else
  ``near-singular`` when the condition number exceeds :data:`NEAR_SINGULAR_COND` or the
  amplification :data:`NEAR_SINGULAR_AMPLIFICATION`; else ``ill-conditioned`` above
  :data:`ILL_CONDITIONED_COND` or :data:`ILL_CONDITIONED_AMPLIFICATION`; else ``ok``;
* ``det_sign``: the sign of ``det J`` (square ``J`` only, else 0) and ``home_det_sign``
  the one at the model's home pose, or at its default pose when ``J`` is singular at home
  (``reference``, :func:`det_reference`); a pose whose sign differs lies beyond a singular
  surface from that pose: in another assembly (working) mode of the actuators, reached
  only through a singularity.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..errors import ScrewkitError
from ._frozen import kernel_array

__all__ = ["CONDITIONING", "classify", "LEVELS", "det_reference", "base_side", "trust", "trust_of",
           "ILL_CONDITIONED_COND", "NEAR_SINGULAR_COND",
           "ILL_CONDITIONED_AMPLIFICATION", "NEAR_SINGULAR_AMPLIFICATION", "Quality",
           "quality", "home_det_sign", "det_signs"]

#: The conditioning classes of a reachable pose, from best to worst (:func:`classify`).
CONDITIONING = ("regular", "near-singular", "singular")
#: The levels, from best to worst (an unreachable pose has the level ``unreachable``).
LEVELS = ("ok", "ill-conditioned", "near-singular", "singular")
ILL_CONDITIONED_COND = 1e2
NEAR_SINGULAR_COND = 1e3
ILL_CONDITIONED_AMPLIFICATION = 2.0
NEAR_SINGULAR_AMPLIFICATION = 5.0


def classify(condition_number, singular, reachable=None) -> np.ndarray:
    """The conditioning class of each pose, ``(N,)`` strings: ``regular``, ``near-singular``
    (normalised condition number above :data:`NEAR_SINGULAR_COND`), ``singular`` (flagged
    singular by the Jacobian's threshold), or ``unreachable`` (``reachable`` False: no
    assembly, so no conditioning).  The one classification of every output.

    Examples
    --------
    >>> classify([50.0, 6.3e7, 2e9], [False, False, True]).tolist()
    ['regular', 'near-singular', 'singular']
    """
    cond = np.atleast_1d(np.asarray(condition_number, float))
    sing = np.broadcast_to(np.asarray(singular, bool), cond.shape)
    out = np.full(cond.shape, "regular", dtype="<U13")
    out[~(cond <= NEAR_SINGULAR_COND)] = "near-singular"      # (NaN: not regular)
    out[sing] = "singular"
    if reachable is not None:
        out[~np.broadcast_to(np.asarray(reachable, bool), cond.shape)] = "unreachable"
    return out


def describe_class(cls: str, cond: float) -> str:
    """``near-singular (normalised condition number 6.3e+07 > 1e3)``: a class in words."""
    if cls == "unreachable":
        return "unreachable (no assembly)"
    if cls == "regular":
        return f"regular (normalised condition number {cond:.3g})"
    from ._pipeline import COND_THRESHOLD
    limit = NEAR_SINGULAR_COND if cls == "near-singular" else COND_THRESHOLD
    return f"{cls} (normalised condition number {cond:.3g} > {limit:g})"


def base_side(model, o) -> np.ndarray:
    """Which side of the base plane the platform centre ``o (N, 3)`` is on, ``(N,)``: ``+1``
    the side of home (above the base), ``-1`` the other (below: a mirror assembly), ``0``
    in the base plane (within ``GEOMETRY_RTOL`` of the model's length); all ``+1`` when home
    itself is in the base plane (a planar PM)."""
    from ..screws import GEOMETRY_RTOL
    R0, _ = model.frame
    n = np.asarray(R0, float)[:, 2]
    c = np.asarray(model.world_base_points, float).mean(axis=0)
    tol = GEOMETRY_RTOL * float(model.normalisation.length)
    home = float(n @ (model.platform_home[1] - c))
    o = np.asarray(o, float).reshape(-1, 3)
    if abs(home) <= tol:
        return np.ones(len(o), int)
    h = (o - c) @ n * np.sign(home)
    return np.where(np.abs(h) <= tol, 0, np.where(h < 0, -1, 1)).astype(int)   # (NaN: +1)


@dataclass(frozen=True, eq=False)
class Quality:
    """Per-pose trust report (arrays ``(N,)``; see the module docstring)."""

    condition_number: np.ndarray
    amplification: np.ndarray
    level: np.ndarray
    det_sign: np.ndarray
    home_det_sign: int
    beyond_singular_surface: np.ndarray
    reference: str = "home"
    conditioning: np.ndarray = None
    side: np.ndarray = None

    def take(self, sl) -> "Quality":
        return Quality(self.condition_number[sl], self.amplification[sl], self.level[sl],
                       self.det_sign[sl], self.home_det_sign, self.beyond_singular_surface[sl],
                       self.reference, self.conditioning[sl], self.side[sl])

    def warnings(self, i: int = 0) -> tuple:
        """One line per thing worth a warning at pose ``i``."""
        out = []
        lev = str(self.level[i])
        if lev == "unreachable":
            out.append("unreachable pose: no assembly was found (Newton and continuation from "
                       "home; another branch may exist: start from a solved pose near it); J, its "
                       "conditioning and "
                       "the efforts here are not defined")
        elif lev in ("near-singular", "singular", "ill-conditioned"):
            amp = self.amplification[i]
            cls = None if self.conditioning is None else str(self.conditioning[i])
            # the trust level also weighs the efforts; say so where the class (condition
            # number alone) reads otherwise, so the two lines do not seem to disagree
            why = ("" if cls is None or cls == lev else
                   f" (trust level, from the efforts; conditioning class {cls})")
            out.append(f"{lev} pose{why}: normalised condition number "
                       f"{self.condition_number[i]:.3g}"
                       + ("" if np.isnan(amp) else f", efforts up to {amp:.3g} times the load"))
        if lev != "unreachable" and self.side is not None and self.side[i] <= 0:
            out.append("the platform centre o lies in the base plane (home: above it): "
                       "between the working assembly and its mirror below the base"
                       if self.side[i] == 0 else
                       "the platform centre o is below the base (home: above it): a mirror "
                       "assembly, the legs cross the base plane")
        if self.beyond_singular_surface[i]:
            ref = "home" if self.reference == "home" else "the default pose"
            out.append(f"det J has the opposite sign to {ref}'s: this pose lies beyond a "
                       f"singular surface from {ref} (another assembly mode of the actuators)")
        return tuple(out)

    def as_dict(self, i: int = 0) -> dict:
        amp = float(self.amplification[i])
        return {"class": str(self.conditioning[i]),
                "classes": list(CONDITIONING),
                "condition_number": float(self.condition_number[i]),
                "force_amplification": None if np.isnan(amp) else amp,
                "level": str(self.level[i]),
                "det_sign": int(self.det_sign[i]), "home_det_sign": int(self.home_det_sign),
                "beyond_singular_surface": bool(self.beyond_singular_surface[i]),
                "det_reference": self.reference,
                "side_of_base": {1: "above", 0: "in the base plane", -1: "below"}[
                    int(self.side[i])] if self.side is not None else None,
                "thresholds": {"ill_conditioned": {"condition_number": ILL_CONDITIONED_COND,
                                                   "amplification": ILL_CONDITIONED_AMPLIFICATION},
                               "near_singular": {"condition_number": NEAR_SINGULAR_COND,
                                                 "amplification": NEAR_SINGULAR_AMPLIFICATION},
                               "singular": {"condition_number": 1e8}}}


def levels(cond, amp, singular):
    """The level of each pose from its condition number, amplification and singular flag."""
    lev = np.full(cond.shape, "ok", dtype="<U15")
    ill = (cond > ILL_CONDITIONED_COND) | (amp > ILL_CONDITIONED_AMPLIFICATION)
    near = (cond > NEAR_SINGULAR_COND) | (amp > NEAR_SINGULAR_AMPLIFICATION)
    lev[ill] = "ill-conditioned"
    lev[near] = "near-singular"
    lev[singular] = "singular"
    return lev


def amplification(values, info, W, L, o):
    """Largest |effort| over the workload's size, consistent units (module docstring), by
    the kernel; the largest over a batch of workloads ``W (N, [K,] 6)`` about the base
    origin.  The size takes the torque ``T`` at the platform centre ``o (N, 3)`` (``T = m -
    o x f``), as given: not the moment about the origin, which depends on where the base
    frame is."""
    from ._pipeline import amplification_of, torque_rows
    N = len(L)
    v = np.asarray(values, float).reshape(N, -1, values.shape[-1])
    Wf = np.broadcast_to(np.asarray(W, float).reshape(N, -1, 6), v.shape[:2] + (6,))
    a = amplification_of(np.nan_to_num(v, nan=0.0), torque_rows(info), Wf, o, L)
    return np.max(a, axis=1)


def trust(jac, values, W, o, reachable, amp=None, no_load: bool = False) -> tuple:
    """``(amplification, level)`` of every pose of ``jac`` (a batch) under the workload
    ``W (N, 6)`` about the base origin whose efforts are ``values (N, m)`` (None: no
    statics, amplification infinite); ``o (N, 3)`` the platform centres; ``amp`` the
    amplification when the kernel gave it with the values.  An unreachable pose has no
    conditioning of its own (``J`` is the last iterate's): level ``unreachable``,
    amplification NaN."""
    c = jac.conditioning
    N = len(jac)
    if values is None:
        amp = np.full(N, np.nan if no_load else np.inf)
    elif amp is None:
        amp = amplification(values, jac.info, W, c.length, o)
    sing = jac.singular_mask
    amp = np.where(sing, np.inf, amp)
    lev = levels(c.condition_number, amp, sing)
    unreach = ~np.asarray(reachable, bool).reshape(N)
    lev[unreach] = "unreachable"
    return np.where(unreach, np.nan, amp), lev


def trust_of(analysis) -> tuple:
    """:func:`trust` of every pose of an analysis under its workload, at its solution's
    reachable poses (the amplification the kernel gave with the statics where it did):
    ``(amplification, level)``, formed once and kept in the analysis (its quality and its
    indices both read it)."""
    got = analysis.__dict__.get("_trust")
    if got is None:
        st = analysis.statics
        loaded = st is not None and analysis.has_workload
        reach = np.asarray(analysis.solution.reachable_mask, bool).reshape(len(analysis.jacobian))
        got = trust(analysis.jacobian, st.F_r if loaded else None, st._W if loaded else None,
                    analysis.solution._platform[1], reach,
                    None if not loaded or st.amp is None or st.F_r.ndim != 2 else
                    np.nan_to_num(st.amp, nan=0.0), no_load=not analysis.has_workload)
        analysis.__dict__["_trust"] = got
    return got


_HOME: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: ``(rows, orientation)`` at the model's reference pose (:func:`det_reference`): its ``J``
#: (against which a leg with idle motions is oriented) and its legs' orientation product.
_REF_ROWS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def det_reference(model, analyze) -> tuple:
    """``(sign, name)``: the sign of ``det J`` at the model's reference pose, cached.

    The reference is the home pose; when ``J`` is singular there (several catalog PMs are
    built at a symmetric, singular home, e.g. the 3SPU+SP with its legs in one plane of
    symmetry), the sign there is rounding noise, so the model's default pose is used
    instead. ``sign`` is 0 (no assembly-mode check) for a non-square ``J`` or when both
    poses are singular; ``name`` is ``"home"``, ``"default"`` or ``"none"``.
    """
    s = _HOME.get(model)
    if s is None:
        s = (0, "none")
        for name, full in (("home", model.home_pose), ("default", model.default_pose)):
            pose = {p: full[p] for p in model.independent}
            try:
                res = analyze(model, pose, raise_on_singular=False)
            except ScrewkitError:       # an unreachable reference is no reference
                continue
            J = res.jacobian.J
            if J.shape != (6, 6):
                break
            if not bool(np.atleast_1d(res.jacobian.singular_mask)[0]):
                plain = int(_det_signs(res.jacobian)[0])
                s = (plain, name)
                rows = np.array(J, float).reshape(6, 6)
                # (the legs' orientation there: det_sign is det J's own sign at the reference)
                _REF_ROWS[model] = (rows, float(_oriented(res, rows)[0]) * plain)
                break
        _HOME[model] = s
    return s


def home_det_sign(model, analyze) -> int:
    """Sign of ``det J`` at the model's reference pose (:func:`det_reference`)."""
    return det_reference(model, analyze)[0]


def quality(analysis, analyze) -> Quality:
    """The :class:`Quality` of every pose of an analysis (``analyze``: the engine's analysis
    function, for the home pose's sign)."""
    jac = analysis.jacobian
    N = len(jac)
    cond = jac.conditioning.condition_number
    reach = np.asarray(analysis.solution.reachable_mask, bool).reshape(N)
    amp, lev = trust_of(analysis)
    unreach = ~reach
    det = det_signs(analysis, reach, analyze)
    home, ref = det_reference(analysis.model, analyze)
    beyond = (det != 0) & (home != 0) & (det != home) & ~jac.singular_mask
    cls = classify(cond, jac.singular_mask, reach)
    side = base_side(analysis.model, analysis.solution._platform[1])
    side[unreach] = 1
    if N > 1:                          # (a batch's arrays are constants, as _run.compute's)
        for a in (amp, lev, det, beyond, cls, side):
            if isinstance(a, np.ndarray):
                a.setflags(write=False)
    return Quality(cond, amp, lev, det, home, beyond, ref, cls, side)


def det_signs(analysis, reach, analyze) -> np.ndarray:
    """The sign of ``det J`` of every pose of an analysis (N poses; 0 where unreachable or
    ``J`` is not square), each leg's constraint rows oriented by its joint twists
    (:func:`_oriented`, :mod:`._kernels._orient`), relative to their orientation at the
    model's reference pose, where the sign is then ``det J``'s own: a reference direction
    that passes through zero turns a row over, and with it the sign of ``det J``, where
    ``J`` is not singular; oriented so, only a singularity changes it."""
    got = analysis.__dict__.get("_det_signs")       # (formed once an analysis)
    if got is not None:
        return got
    jac = analysis.jacobian
    N = len(jac)
    det = np.zeros(N)
    if jac.matrix.shape[1:] == (6, 6) and N:
        det_reference(analysis.model, analyze)
        ref, at_ref = _REF_ROWS.get(analysis.model, (None, 1.0))
        det = _oriented(analysis, ref) * at_ref
    det = det.astype(int)
    det[~np.asarray(reach, bool).reshape(N)] = 0
    analysis.__dict__["_det_signs"] = det
    return det


def _oriented(analysis, ref) -> np.ndarray:
    """``(N,)``: the signs of ``det J`` times each leg's orientation (the analysis kernel's
    where its run formed them, ``analyze(lines=True)``; else by :func:`._kernels._orient.
    oriented_range` from the solved unknowns), a leg with idle motions against its rows
    ``ref (6, 6)`` at the reference pose (None: not solved yet); 0 where one is not
    defined."""
    from ._launch import _launch
    from ._kernels import kernels
    from ._kernels import _layout as lay
    c = analysis.solution.closures
    M = c.chains.flat.M
    k, size = M[lay.TPL][:, lay.T_K], M[lay.LEG][:, lay.L_SIZE]
    det = analysis.diagnostics.get("det_sign")
    in_run = det is not None and analysis.diagnostics.get("det_oriented")
    out = np.nan_to_num(np.array(_det_signs(analysis.jacobian) if det is None else det, float))
    legs = np.flatnonzero((k > 0) & ((size + k != 6) if in_run else True))
    if legs.size and len(out):
        cn = analysis.model.normalisation
        _launch(kernels().oriented_range, kernels().oriented_parallel,
                (M, np.ascontiguousarray(c.X[len(c.chains.unknown):].T),
                 kernel_array(analysis.jacobian.matrix), legs.astype(np.int64),
                 np.zeros((6, 6)) if ref is None else ref, kernel_array(cn.centre),
                 float(cn.length), out), len(out), None)
    return out


def _det_signs(jac) -> np.ndarray:
    """The signs of ``det J`` of a square Jacobian (N poses), by the kernel's LU."""
    from ._kernels import kernels
    J = kernel_array(jac.matrix)
    out = np.empty(len(J))
    kernels().det_sign_batch(J, out)
    return out
