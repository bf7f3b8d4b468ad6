"""How much to trust each pose: condition level, force amplification, assembly mode (private).

* ``condition_number``: the normalised one of :mod:`screwkit.engine._jacobian`;
* ``amplification``: the largest effort over the size of the workload, in consistent
  units: forces as they are, couples and rotary-actuator torques divided by the
  characteristic length ``L`` of the pose (the normalisation's), the workload's size
  ``sqrt(|F|^2 + |T / L|^2)``; 1 means the legs carry no more than the load;
* ``level``: ``singular`` above :data:`~screwkit.engine.COND_THRESHOLD`; else
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

__all__ = ["LEVELS", "det_reference", "trust", "ILL_CONDITIONED_COND", "NEAR_SINGULAR_COND",
           "ILL_CONDITIONED_AMPLIFICATION", "NEAR_SINGULAR_AMPLIFICATION", "Quality",
           "quality", "home_det_sign"]

#: The levels, from best to worst (an unreachable pose has the level ``unreachable``).
LEVELS = ("ok", "ill-conditioned", "near-singular", "singular")
ILL_CONDITIONED_COND = 1e2
NEAR_SINGULAR_COND = 1e3
ILL_CONDITIONED_AMPLIFICATION = 2.0
NEAR_SINGULAR_AMPLIFICATION = 5.0


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

    def take(self, sl) -> "Quality":
        return Quality(self.condition_number[sl], self.amplification[sl], self.level[sl],
                       self.det_sign[sl], self.home_det_sign, self.beyond_singular_surface[sl],
                       self.reference)

    def warnings(self, i: int = 0) -> tuple:
        """One line per thing worth a warning at pose ``i``."""
        out = []
        lev = str(self.level[i])
        if lev == "unreachable":
            out.append("unreachable pose: no assembly was found (Newton and continuation from "
                       "home; another branch may exist: pass guess=); J, its conditioning and "
                       "the efforts here are not defined")
        elif lev in ("near-singular", "singular"):
            out.append(f"{lev} pose: normalised condition number {self.condition_number[i]:.3g}, "
                       f"efforts up to {self.amplification[i]:.3g} times the load")
        elif lev == "ill-conditioned":
            out.append(f"ill-conditioned pose: normalised condition number "
                       f"{self.condition_number[i]:.3g}, efforts up to "
                       f"{self.amplification[i]:.3g} times the load")
        if self.beyond_singular_surface[i]:
            ref = "home" if self.reference == "home" else "the default pose"
            out.append(f"det J has the opposite sign to {ref}'s: this pose lies beyond a "
                       f"singular surface from {ref} (another assembly mode of the actuators)")
        return tuple(out)

    def as_dict(self, i: int = 0) -> dict:
        return {"condition_number": float(self.condition_number[i]),
                "force_amplification": float(self.amplification[i]),
                "level": str(self.level[i]),
                "det_sign": int(self.det_sign[i]), "home_det_sign": int(self.home_det_sign),
                "beyond_singular_surface": bool(self.beyond_singular_surface[i]),
                "det_reference": self.reference,
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


def trust(jac, values, W, o, reachable, amp=None) -> tuple:
    """``(amplification, level)`` of every pose of ``jac`` (a batch) under the workload
    ``W (N, 6)`` about the base origin whose efforts are ``values (N, m)`` (None: no
    statics, amplification infinite); ``o (N, 3)`` the platform centres; ``amp`` the
    amplification when the kernel gave it with the values.  An unreachable pose has no
    conditioning of its own (``J`` is the last iterate's): level ``unreachable``,
    amplification NaN."""
    c = jac.conditioning
    N = len(jac)
    if values is None:
        amp = np.full(N, np.inf)
    elif amp is None:
        amp = amplification(values, jac.info, W, c.length, o)
    sing = jac.singular_mask
    amp = np.where(sing, np.inf, amp)
    lev = levels(c.condition_number, amp, sing)
    unreach = ~np.asarray(reachable, bool).reshape(N)
    lev[unreach] = "unreachable"
    return np.where(unreach, np.nan, amp), lev


_HOME: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


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
                s = (int(_det_signs(res.jacobian)[0]), name)
                break
        _HOME[model] = s
    return s


def home_det_sign(model, analyze) -> int:
    """Sign of ``det J`` at the model's reference pose (:func:`det_reference`)."""
    return det_reference(model, analyze)[0]


def quality(analysis, analyze) -> Quality:
    """The :class:`Quality` of every pose of an analysis (``analyze``: the engine's analysis
    function, for the home pose's sign)."""
    jac, st = analysis.jacobian, analysis.statics
    N = len(jac)
    cond = jac.conditioning.condition_number
    reach = np.asarray(analysis.solution.reachable_mask, bool).reshape(N)
    amp, lev = trust(jac, None if st is None else st.F_r, None if st is None else st._W,
                     analysis.solution._platform[1], reach,
                     None if st is None or st.amp is None or st.F_r.ndim != 2 else
                     np.nan_to_num(st.amp, nan=0.0))
    unreach = ~reach
    det = analysis.diagnostics.get("det_sign")
    if jac.matrix.shape[1:] != (6, 6):
        det = np.zeros(N, int)
    elif det is None:
        det = _det_signs(jac)
    det = np.nan_to_num(np.asarray(det, float)).astype(int)
    home, ref = det_reference(analysis.model, analyze)
    det[unreach] = 0
    beyond = (det != 0) & (home != 0) & (det != home) & ~jac.singular_mask
    return Quality(cond, amp, lev, det, home, beyond, ref)


def _det_signs(jac) -> np.ndarray:
    """The signs of ``det J`` of a square Jacobian (N poses), by the kernel's LU."""
    from ._kernels import kernels
    J = np.ascontiguousarray(jac.matrix, float)
    out = np.empty(len(J))
    kernels().det_sign_batch(J, out)
    return out
