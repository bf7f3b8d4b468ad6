"""The indices of a :class:`~screwkit.engine.PMAnalysis` (private): the result type
:class:`TransmissionIndices` and :func:`transmission`, which feeds the analysis' rows of
``J``, its legs' actuated-joint twists and its conditioning to the batched maths of
:mod:`screwkit.engine._transmission` (definitions and conventions there and in
``docs/design.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._transmission import _all_finite, leg_lines, lines_indices

__all__ = ["TransmissionIndices", "transmission"]


def _squeeze(x, single):
    return x[0] if single else x


_ARRAYS = ("iti_legs", "oti_legs", "cti_rows", "input_arm", "output_arm", "constraint_arm",
           "condition_number", "sigma_min", "amplification")


def _batch(name):
    def get(self):
        return _squeeze(self.data[name], self.single)
    get.__name__ = name
    get.__doc__ = f"``{name}`` (the pose axis dropped for one pose; class docstring)."
    return property(get)


@dataclass(frozen=True, eq=False)
class TransmissionIndices:
    """Transmission and constraint indices and conditioning of N poses (module docstring).

    Every array has the poses first (dropped for one pose, as everywhere in the engine).

    Attributes
    ----------
    iti_legs, oti_legs : ndarray (N, n_a)
        Input and output transmission index of each active leg (actuation-row order).
    cti_rows : ndarray (N, k)
        Constraint transmission index of each constraint row (NaN: a redundant row).
    input_arm, output_arm : ndarray (N, n_a)
        The arms ``d_max`` of those indices (model lengths; NaN for a translation).
    constraint_arm : ndarray (N, k)
    iti, oti, lti, cti : ndarray (N,)
        The smallest ITI and OTI over the active legs, ``LTI = min(ITI, OTI)``, the smallest
        CTI over the non-redundant constraint rows (NaN without one).
    condition_number, sigma_min, amplification : ndarray (N,)
        The normalised condition number of ``J``, its smallest singular value (rows
        length-normalised and of unit norm: 0 at a singularity, at most ``sqrt(m / 6)``
        for ``m`` rows), and the largest effort over the size of the workload.
    legs : tuple of int
        The active legs (0-based) of the columns of ``iti_legs``, ``oti_legs``.
    constraint_labels : tuple of str
        The constraint rows of ``cti_rows`` (``F_c1``, ``T_c2`` ...).
    single : bool
    """

    data: dict = field(repr=False)
    legs: tuple = ()
    constraint_labels: tuple = ()
    single: bool = False

    iti_legs = _batch("iti_legs")
    oti_legs = _batch("oti_legs")
    cti_rows = _batch("cti_rows")
    input_arm = _batch("input_arm")
    output_arm = _batch("output_arm")
    constraint_arm = _batch("constraint_arm")
    condition_number = _batch("condition_number")
    sigma_min = _batch("sigma_min")
    amplification = _batch("amplification")

    def __len__(self) -> int:
        return len(self.data["condition_number"])

    def _min(self, name):
        """The least non-NaN value of each pose (NaN where all are NaN: ``np.nanmin``'s
        values, column by column with ``fmin``, once per array)."""
        cache = self.__dict__.setdefault("_mins", {})
        if name not in cache:
            a = self.data[name]
            if not a.shape[1]:
                m = np.full(a.shape[0], np.nan)
            else:
                m = a[:, 0].copy()
                for k in range(1, a.shape[1]):
                    np.fmin(m, a[:, k], out=m)
            m.setflags(write=False)
            cache[name] = m
        return cache[name]

    @property
    def iti(self):
        return _squeeze(self._min("iti_legs"), self.single)

    @property
    def oti(self):
        return _squeeze(self._min("oti_legs"), self.single)

    @property
    def lti(self):
        i, o = self._min("iti_legs"), self._min("oti_legs")
        return _squeeze(np.where(np.isnan(i) | np.isnan(o), np.nan, np.fmin(i, o)), self.single)

    @property
    def cti(self):
        return _squeeze(self._min("cti_rows"), self.single)

    def as_dict(self, i: int = 0) -> dict:
        """JSON-ready indices of pose ``i`` (arms in model lengths; None: not defined)."""
        d = self.data

        def f(x):
            return None if not np.isfinite(x) else float(x)
        mins = {"iti": self._min("iti_legs"), "oti": self._min("oti_legs"),
                "cti": self._min("cti_rows")}
        lti = np.atleast_1d(self.lti)
        return {
            "iti": f(mins["iti"][i]), "oti": f(mins["oti"][i]), "lti": f(lti[i]),
            "cti": f(mins["cti"][i]), "sigma_min": f(d["sigma_min"][i]),
            "condition_number": f(d["condition_number"][i]),
            "force_amplification": f(d["amplification"][i]),
            "legs": [{"leg": leg + 1, "iti": f(d["iti_legs"][i, k]),
                      "oti": f(d["oti_legs"][i, k]), "input_arm": f(d["input_arm"][i, k]),
                      "output_arm": f(d["output_arm"][i, k])}
                     for k, leg in enumerate(self.legs)],
            "constraints": [{"label": lab, "cti": f(d["cti_rows"][i, k]),
                             "arm": f(d["constraint_arm"][i, k])}
                            for k, lab in enumerate(self.constraint_labels)],
        }


def transmission(analysis) -> TransmissionIndices:
    """The :class:`TransmissionIndices` of a :class:`~screwkit.engine.PMAnalysis`."""
    jac, sol, model = analysis.jacobian, analysis.solution, analysis.model
    info = jac.info
    passive = set(getattr(model, "passive", ()) or ())
    act = [k for k, r in enumerate(info) if r.kind == "actuation" and r.leg not in passive]
    con = [k for k, r in enumerate(info) if r.kind != "actuation"]
    legs = tuple(info[k].leg for k in act)
    N = len(jac)
    cond = jac.conditioning
    J = np.asarray(jac.matrix, float)
    reach = np.asarray(sol.reachable_mask, bool).reshape(N)
    diag = analysis.diagnostics
    lines, in_leg = leg_lines(sol, legs, diag.get("lines"), diag.get("platform"))
    couple = np.array([r.member == "couple" for r in info])
    all_finite = _all_finite(J)                  # (the usual case: J itself, no copy)
    finite = None if all_finite else np.isfinite(J)
    Jf = J if all_finite else np.where(finite, J, 0.0)
    iti, oti, in_arm, out_arm, cti, c_arm, redundant = lines_indices(
        Jf, couple, act, con, lines, in_leg, jac.leg_of_row, cond.centre,
        cond.length, np.where(reach, cond.constraint_rank, len(con)))
    if not all_finite:
        iti = np.where(~np.all(finite[:, act], axis=-1), 0.0, iti)
    sing = np.asarray(jac.singular_mask, bool) & reach
    oti[sing] = 0.0
    cti[sing] = np.where(redundant[sing], np.nan, 0.0)
    out_arm[sing], c_arm[sing] = np.nan, np.nan
    if not reach.all():
        unreached = ~reach
        for x in (iti, oti, in_arm, out_arm, cti, c_arm):
            x[unreached] = np.nan
    s = np.asarray(cond.singular_values, float)
    smin = np.where(reach, s[:, -1] if s.shape[1] >= 6 else 0.0, np.nan)
    amp = _amplification(analysis)
    data = dict(zip(_ARRAYS, (iti, oti, cti, in_arm, out_arm, c_arm,
                              np.asarray(cond.condition_number, float).reshape(N), smin,
                              amp)))
    for v in data.values():
        v.setflags(write=False)
    return TransmissionIndices(data, legs, tuple(info[k].label for k in con),
                               bool(analysis.single))


def _amplification(analysis):
    """The force amplification of every pose under the analysis' workload (the trust rule
    of :mod:`screwkit.engine._quality`, without the home pose's det J sign)."""
    from ._quality import trust_of
    if not analysis.has_workload:
        return np.full(len(analysis.jacobian), np.nan)   # no workload: no amplification
    amp, _ = trust_of(analysis)                 # (the quality's, formed once)
    return np.asarray(amp, float).reshape(len(analysis.jacobian))
