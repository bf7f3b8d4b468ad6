"""The same poses under another workload: the statics solved again on a batch's J (private).

The closures, the rows of ``J`` and their conditioning do not depend on the workload; only
``F_r = -(J^-1)^T W`` does, and linearly.  :func:`under` re-solves it by the engine's
statics (the same compliances as the analysis: its ``stiffness``, or the least-norm
weights), so a sizing over many workloads analyses its poses once.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..legs._guards import MAX_LOAD, real_vector
from ._pipeline import statics_values, torque_rows, workload_about_origin
from ._statics import StaticsResult

__all__ = ["load_vector", "under", "resolve_workload", "MissingStatics", "no_workload_message"]


def under(analysis, force, torque):
    """``analysis`` with its statics solved for the workload ``(force, torque)`` at ``o``.

    Parameters
    ----------
    analysis : PMAnalysis
    force, torque : array_like (3,)
        The workload at the platform centre ``o`` (model units), as :func:`analyze` takes.

    Returns
    -------
    PMAnalysis
        The same solution and Jacobian; ``statics``, ``force``, ``torque`` and the quality
        (force amplification, trust level) of the new workload.
    """
    load = resolve_workload(analysis.model, force, torque)
    if load is None:
        from ..errors import InputError
        raise InputError(no_workload_message(analysis.model))
    F, T, src = load
    jac, sol = analysis.jacobian, analysis.solution
    if analysis.statics is None:            # one singular pose: no statics, whatever the load
        return dataclasses.replace(analysis, force=F, torque=T, workload_source=src)
    N = len(jac)
    W = workload_about_origin(np.broadcast_to(F, (N, 3)), np.broadcast_to(T, (N, 3)),
                              jac.origin)
    comp = None if analysis.stiffness is None else \
        _compliance(analysis.model, analysis.stiffness, N)
    values, eq, amp = statics_values(jac.matrix, jac.conditioning, torque_rows(jac.info), W,
                                     jac.origin, comp)
    for x in (W, values):
        x.setflags(write=False)
    st = StaticsResult(jac, values, W, sol.base_points, lambda: sol._platform[2],
                       np.ones(N, bool), eq, amp)
    bad = ~sol.reachable_mask | jac.singular_mask
    if bad.any():
        st = _mask(st, bad)
    return dataclasses.replace(analysis, statics=st, force=F, torque=T, workload_source=src)


def no_workload_message(model, options=("force=", "torque=")) -> str:
    """The error of statics asked of a model without a workload, naming ``options``."""
    return (f"{model.name} declares no workload: give one ({options[0]} and/or {options[1]} at "
            f"o; the missing one is zero), or declare its default in the model "
            f"(workload: {{force: [..], torque: [..], units: {{force: .., length: ..}}}})")


def resolve_workload(model, force=None, torque=None, source: str = "given"):
    """The workload of an analysis: ``(F, T, source)``, or ``None`` when there is none.

    A force without a torque (or a torque without a force) means the other is zero; with
    neither, the model's declared default (``model.workload``, source ``"declared
    default"``) is used, else there is no workload (the statics cannot be solved)."""
    if force is None and torque is None:
        w = getattr(model, "workload", None)
        if w is None:
            return None
        return np.array(w.force), np.array(w.torque), w.origin
    F = np.zeros(3) if force is None else load_vector(force, "force")
    T = np.zeros(3) if torque is None else load_vector(torque, "torque")
    return F, T, source


class MissingStatics:
    """The statics of an analysis made without a workload: any use raises the
    :class:`~screwkit.errors.InputError` that says how to give one (kinematics, mobility and
    ``J`` of the analysis are there)."""

    __slots__ = ("message",)

    def __init__(self, message: str):
        object.__setattr__(self, "message", message)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        from ..errors import InputError
        raise InputError(self.message)

    def __getitem__(self, i):
        return self

    def __reduce__(self):
        return (MissingStatics, (self.message,))

    def __repr__(self) -> str:
        return "MissingStatics(no workload)"


_F64 = np.dtype(np.float64)


def load_vector(x, name):
    """A workload vector: 3 real numbers (no booleans or strings), finite, each at most
    ``MAX_LOAD`` (1e12 in the model's units) in magnitude, so that the statics cannot
    overflow to NaN or infinity."""
    # the common case decided without a check per element: three finite float64 numbers
    # within the bound (NaN fails the comparisons and goes to the checks that name it)
    if type(x) is np.ndarray and x.dtype is _F64 and x.shape == (3,):
        a, b, c = x.tolist()
        if abs(a) <= MAX_LOAD and abs(b) <= MAX_LOAD and abs(c) <= MAX_LOAD:
            return x.copy()
    elif type(x) in (list, tuple) and len(x) == 3 and all(type(v) is float for v in x):
        if all(abs(v) <= MAX_LOAD for v in x):
            return np.array(x, float)
    return real_vector(np.asarray(x) if isinstance(x, np.ndarray) else x, name, 3,
                       bound=MAX_LOAD)


def _compliance(model, stiffness, N):
    """Compliances ``(N, m)`` from a stiffness mapping (by row label) or array."""
    from ..errors import InputError
    from ._templates import labels_of, templates_of
    from ._statics import compliance_of
    info = labels_of(templates_of(model))
    labels = [r.label for r in info]
    if isinstance(stiffness, str):
        stiffness = _model_stiffness(model, info, stiffness)
    if isinstance(stiffness, dict):
        bad = sorted(set(stiffness) - set(labels))
        if bad:
            raise InputError(f"{model.name}: no row {bad[0]!r} to give a stiffness; the rows are "
                             f"{', '.join(labels)}")
        L = float(model.normalisation.length)
        k = np.where(torque_rows(info) == 1, L * L, 1.0)     # the least-norm weights
        for lab, v in stiffness.items():
            k[labels.index(lab)] = v
        stiffness = k
    return compliance_of(stiffness, len(labels), N)


#: The poses of a batch whose self-stresses :func:`check_partial_stiffness` reads (spread over
#: the batch: which rows a self-stress loads is the PM's structure, not the pose's).
PARTIAL_SAMPLE = 64


def check_partial_stiffness(model, stiffness, jac, sol) -> None:
    """Refuse row stiffnesses (a mapping by label, or the model's block) that leave out a
    row a self-stress loads: its least-norm weight beside a stiffness would weight the
    compliance-weighted solution by the units' choice (a 4UPU in cm and in mm gave couples 9
    times apart).  Rows that statics alone fixes need none."""
    if not isinstance(stiffness, (dict, str)):      # (first: a warm pose's path, ~1 us)
        return
    from ..errors import InputError
    from ._templates import labels_of, templates_of
    info = labels_of(templates_of(model))
    labels = [r.label for r in info]
    named = set(_model_stiffness(model, info, stiffness) if isinstance(stiffness, str)
                else stiffness)
    if named >= set(labels):
        return
    Jn, _ = jac.normalised()
    rank = np.atleast_1d(jac.conditioning.rank)
    cand = np.flatnonzero(np.asarray(sol.reachable_mask, bool) & (Jn.shape[1] - rank > 0))
    if not cand.size:
        return
    loaded = np.zeros(len(labels), bool)
    for i in cand[np.linspace(0, cand.size - 1, min(PARTIAL_SAMPLE, cand.size)).astype(int)]:
        S = np.linalg.svd(Jn[i].T, full_matrices=True)[2][int(rank[i]):]
        loaded |= np.max(np.abs(S), axis=0) > 1e-9
    missing = [lab for lab, ld in zip(labels, loaded) if ld and lab not in named]
    if missing:
        raise InputError(f"{model.name}: row(s) {', '.join(missing)} carry self-stress "
                         "(statics alone does not fix them) and have no stiffness: give each of "
                         f"{', '.join(lab for lab, ld in zip(labels, loaded) if ld)} a stiffness, "
                         "or none for the least-norm choice (a stiffness weighed against "
                         "another row's least-norm weight would depend on the units)")


def _model_stiffness(model, info, what) -> dict:
    """Row stiffnesses by label from the model's ``dynamics: stiffness:`` block."""
    from ..errors import InputError
    if what != "model":
        raise InputError(f"stiffness must be 'model', a mapping by row label or one value per "
                         f"row, got {what!r}")
    dyn = getattr(model, "dynamics", None)
    if dyn is None or not any(lg.stiffness.given for lg in dyn.legs):
        raise InputError(f"{model.name} declares no stiffness (add 'dynamics: stiffness: "
                         "{actuator: .., force: .., couple: ..}' to its definition)")
    out = {}
    for r in info:
        st = dyn.legs[r.leg].stiffness
        key = "actuator" if r.kind == "actuation" else r.kind
        k = getattr(st, key, None) if key in ("actuator", "force", "couple") else None
        if k is None and st.beam is not None:
            raise InputError(f"{model.name}: leg {r.leg + 1} gives its stiffness as a beam; "
                             f"the statics needs '{key}' for row {r.label} (the beam's value "
                             "depends on the pose: see screwkit stiffness)")
        if k is not None:
            out[r.label] = float(k)
    return out


def _mask(st: StaticsResult, bad) -> StaticsResult:
    """The statics with NaN values where ``bad`` (flagged poses of a batch)."""
    F_r = np.array(st.F_r, float)
    F_r[bad] = np.nan
    F_r.setflags(write=False)
    eq = None if st.eq is None else np.where(bad, np.nan, st.eq)
    amp = None if st.amp is None else np.where(bad, np.nan, st.amp)
    return StaticsResult(st.jacobian, F_r, st.W, st.A, st.a, ~bad, eq, amp)
