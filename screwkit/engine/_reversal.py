"""Linear actuators turned inside out (private): a leg whose solution runs its actuator to a
negative length.

A leg whose actuated joint is a P joint carrying the whole leg's length (an SPS, UPS, SPR,
RPS, RRPRR... leg: every joint before it an R joint whose axis passes through the base
point ``A_i``, every joint after it an R joint whose axis passes through the platform point
``a_i``, the P axis through both) keeps ``a_i`` on the P axis through ``A_i``: the signed
distance from ``A_i`` to ``a_i`` along the axis is ``s_i = s_i^home + q_i`` (``q_i`` the
actuator's displacement from home), exactly.  The loop closures have a second solution for
every such leg, its axis turned by half a turn about ``A_i`` and ``s_i`` negative: the same
platform pose, the actuator passed through zero length.  No real actuator assembles that
way, and its effort reads with the opposite sign (its unit twist is reversed).  Newton
from the home predictor can land there at poses far from home.

:func:`reversed_legs` says which legs of which poses did (``s_i`` of the opposite sign to
home's, or zero within ``GEOMETRY_RTOL`` of the model's length); the engine's driver solves
such poses again (:func:`resolve`: the platform's pose as found with the reversed legs'
joints started from home, else by continuation from home;
:func:`screwkit.engine._run.compute`) and flags those whose only assembly found is reversed
(unreachable, with the reason).
"""

from __future__ import annotations

import numpy as np

from ._kernels._layout import REV, RV_HOME, RV_LEG, RV_LIMIT, RV_ROW, RV_SCALE, RV_SIGN

__all__ = ["ActuatorLines", "actuator_lines", "legs_of", "reversed_legs", "resolve",
           "reversed_note"]

#: How many continuation steps from home a reversed pose is solved again with, finer ones
#: after a track lost on the way (the kernels' rescue tries 4, 16, 64).
CONTINUATION_STEPS = (16, 64)


class ActuatorLines:
    """The legs of a model whose actuator carries the leg's length (module docstring), from
    its flattened table ``REV`` (:func:`._line_table.line_table`): ``legs (k,)`` their
    indices, ``rows (k,)`` the rows of their actuated joints' unknowns in the solver's ``X``,
    ``scale (k,)`` the unknown's scale (``q = X[row] scale``), ``home (k,)`` the signed
    lengths ``s^home`` (model lengths), ``sign``, ``limit (k,)`` the test's (a leg is
    reversed where ``sign X[row] <= limit``).  The test itself is the kernels'
    (:mod:`._kernels._reversed`): every analysis returns its poses' reversed legs
    (``reversed_mask``); :meth:`mask` tests unknowns given here."""

    __slots__ = ("table", "legs", "rows", "scale", "home", "sign", "limit")

    def __init__(self, table):
        self.table = table
        self.legs = table[:, RV_LEG].astype(int)
        self.rows = table[:, RV_ROW].astype(int)
        self.sign, self.limit = table[:, RV_SIGN], table[:, RV_LIMIT]
        self.home, self.scale = table[:, RV_HOME], table[:, RV_SCALE]

    def mask(self, X) -> np.ndarray:
        """``(N,)`` int: the legs (bit ``i`` for leg ``i``) the unknowns ``X (n_unknowns,
        N)`` reverse (read as ``X.T``, the engine's ``(N, n_unknowns)`` rows; NaN: none)."""
        from ._kernels import kernels
        rows = np.ascontiguousarray(np.asarray(X, float).T)   # (a view of the engine's rows)
        out = np.zeros(rows.shape[0], np.int64)
        if self.legs.size:
            kernels().reversed_rows(rows, self.table, out)
        return out


def actuator_lines(model) -> ActuatorLines:
    """The :class:`ActuatorLines` of a model (its flattened table,
    :func:`._line_table.line_table`)."""
    from ._flat import flatten
    flat = flatten(model)
    lines = flat.packed.get("lines")
    if lines is None:
        lines = flat.packed["lines"] = ActuatorLines(flat.M[REV])
    return lines


def legs_of(mask, n: int) -> np.ndarray:
    """``(N, n)`` bool: the legs of the masks ``mask (N,)`` (bit ``i`` for leg ``i``)."""
    return (np.asarray(mask, np.int64)[:, None] >> np.arange(n)) & 1 == 1


def reversed_legs(model, X) -> np.ndarray:
    """``(N, n)`` bool: the legs whose actuator the unknowns ``X (n_unknowns, N)`` run to a
    negative length, or to zero within ``GEOMETRY_RTOL`` of the model's length (module
    docstring).  False for the legs the test does not apply to."""
    return legs_of(actuator_lines(model).mask(X), model.n_legs)


def resolve(model, fixed: dict, X, side=None, workers=None) -> tuple:
    """The closures of the poses ``fixed`` (the given parameters, ``(k,)`` each) whose
    solution ``X (n_unknowns, k)`` reverses a leg's actuator, solved again: first from that
    solution with the reversed legs' joints at home (the same platform pose, as a rule,
    its legs' actuators the right way round), then, where that fails, by continuation from
    home: the given parameters moved from home to the pose in :data:`CONTINUATION_STEPS`
    equal steps, each step's Newton run from the last one's solution (finer steps where the
    track was lost on the way, an intermediate residual above 1e-4, as the kernels'
    rescue; or where it ended reversed).  Newton alone in each launch (no rescue of the
    kernels' own).  Returns ``(X (n_unknowns, k), iterations (k,), done (k,))``: ``done``
    where a run converged with no leg reversed (elsewhere ``X`` is the one given)."""
    from ._chains import chains_of
    from ._kernels._layout import CONVERGED
    from ._launch import run_poses
    from ._solve import predictor_of
    ch = chains_of(model)
    Z = predictor_of(ch)
    k = len(next(iter(fixed.values())))
    target = ch.full_params(fixed, k)
    X = np.array(X, float)
    nu = len(ch.unknown)
    start = X.copy()
    rev = reversed_legs(model, X)
    for i in np.flatnonzero(rev.any(axis=0)):
        start[nu + i * ch.m:nu + (i + 1) * ch.m, rev[:, i]] = 0.0
    o = run_poses(ch.flat, Z, target, X0=start.T, side=side, rows=False, continuation=False,
                  workers=workers)
    Xs = np.array(o["X"].T)
    its = np.asarray(o["iterations"], int).copy()
    done = (np.asarray(o["residual"]) <= CONVERGED) & (o["reversed_mask"] == 0)
    X[:, done] = Xs[:, done]
    home = ch.full_params({p: np.full(k, ch.home[p]) for p in fixed}, k)
    for steps in CONTINUATION_STEPS:
        todo = np.flatnonzero(~done)
        if not todo.size:
            break
        Xs, alive, n_its = ch.home_vector(todo.size), np.ones(todo.size, bool), 0
        for step in range(1, steps + 1):
            P6 = home[todo] + (target[todo] - home[todo]) * (step / steps)
            o = run_poses(ch.flat, Z, P6, X0=Xs.T, side=None if side is None else side[todo],
                          rows=False, continuation=False, workers=workers)
            Xs = np.array(o["X"].T)
            n_its = n_its + np.asarray(o["iterations"], int)
            res = np.asarray(o["residual"], float)
            alive &= res <= (CONVERGED if step == steps else 1e-4)
        good = alive & (o["reversed_mask"] == 0)
        X[:, todo[good]] = Xs[:, good]
        its[todo[good]] += n_its[good]
        done[todo[good]] = True
    return X, its, done


def reversed_note(legs) -> str:
    """The note of a pose whose only solution found reverses the actuators of ``legs``
    (``(n,)`` bool): why it is unreachable, and what to do."""
    which = [str(k + 1) for k in np.flatnonzero(legs)]
    return (f"unreachable: the only assembly found runs the linear actuator of leg"
            f"{'s' if len(which) > 1 else ''} {', '.join(which)} to a negative length (the "
            "leg turned through its base point; neither that leg restarted from home nor "
            "continuation from home found another): no real actuator assembles so; start "
            "from a solved pose near it, or reach it along a path")
