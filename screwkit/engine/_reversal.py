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

import weakref

import numpy as np

from ..screws import GEOMETRY_RTOL

__all__ = ["ActuatorLines", "actuator_lines", "reversed_legs", "resolve", "reversed_note"]

#: How many continuation steps from home a reversed pose is solved again with, finer ones
#: after a track lost on the way (the kernels' rescue tries 4, 16, 64).
CONTINUATION_STEPS = (16, 64)


class ActuatorLines:
    """The legs of a model whose actuator carries the leg's length (module docstring):
    ``legs (k,)`` their indices, ``rows (k,)`` the rows of their actuated joints' unknowns
    in the solver's ``X``, ``scale (k,)`` the unknown's scale (``q = X[row] scale``),
    ``home (k,)`` the signed lengths ``s^home`` (model lengths), ``tol`` the length below
    which a leg counts as passed through zero.  A leg is reversed where ``sign (s^home)
    (s^home + q) <= tol``, that is where ``sign X[row] <= limit = (tol - |s^home|) /
    scale`` (``sign``, ``limit (k,)``): one comparison a leg and pose."""

    __slots__ = ("legs", "rows", "scale", "home", "tol", "sign", "limit", "_plain", "_arrays")

    def __init__(self, legs, rows, scale, home, tol):
        self.legs, self.rows, self.scale, self.home = legs, rows, scale, home
        self.tol = tol
        self.sign = np.sign(home)
        self.limit = (tol - np.abs(home)) / scale if legs.size else np.zeros(0)
        # (one pose's test in plain Python: numpy's calls on arrays of a few values cost
        # more than the arithmetic, some 10 us of a one-pose analysis's 70)
        self._plain = tuple(zip(rows.tolist(), self.sign.tolist(), self.limit.tolist()))
        # (the batch test's arrays, as its kernel takes them)
        self._arrays = (np.asarray(rows, np.int64), np.asarray(self.sign, float),
                        np.asarray(self.limit, float))

    def any_reversed(self, x) -> bool:
        """Whether the unknowns ``x (n_unknowns,)`` of one pose reverse a leg (NaN: no)."""
        v = x.tolist()
        for row, sign, limit in self._plain:
            if v[row] * sign <= limit:
                return True
        return False

    def reversed(self, X) -> np.ndarray:
        """``(N, k)`` bool: which of these legs the unknowns ``X (n_unknowns, N)`` reverse
        (read as ``X.T``, the engine's ``(N, n_unknowns)`` rows; NaN: none)."""
        return self._test(X, True)[0]

    def any_reversed_rows(self, X) -> np.ndarray:
        """``(N,)`` bool: whether the unknowns ``X (n_unknowns, N)`` reverse any of these
        legs (:meth:`reversed`'s rows reduced)."""
        return self._test(X, False)[1]

    def _test(self, X, each):
        from ._kernels import kernels
        rows = np.ascontiguousarray(np.asarray(X, float).T)   # (a view of the engine's rows)
        N, k = rows.shape[0], self.rows.size
        legs = np.empty((N if each else 0, k), bool)
        some = np.empty(N, bool)
        if k:
            kernels().reversed_rows(rows, *self._arrays, legs, some)
        else:
            some[:] = False
        return legs, some


_LINES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _off_line(x, point, direction) -> float:
    """The distance of the point ``x`` from the line through ``point`` along ``direction``."""
    d = np.asarray(direction, float)
    return float(np.linalg.norm(np.cross(np.asarray(x, float) - point, d)) / np.linalg.norm(d))


def actuator_lines(model) -> ActuatorLines:
    """The :class:`ActuatorLines` of a model (built once, kept with the model)."""
    lines = _LINES.get(model)
    if lines is not None:
        return lines
    from ._chains import chains_of
    ch = chains_of(model)
    L = float(model.normalisation.length)
    tol = GEOMETRY_RTOL * L
    nu = len(ch.unknown)
    legs, rows, scale, home = [], [], [], []
    for i, lg in enumerate(model.home_legs):
        k = lg.actuated_index
        if i in ch.passive or k is None or lg.joints[k].kind != "P":
            continue
        A, a = np.asarray(lg.A, float), np.asarray(lg.a, float)
        P = lg.joints[k]
        u = np.asarray(P.direction, float)
        u = u / np.linalg.norm(u)
        on_line = (_off_line(A, P.point, u) <= tol and _off_line(a, P.point, u) <= tol
                   and all(j.kind == "R" and _off_line(A, j.point, j.direction) <= tol
                           for j in lg.joints[:k])
                   and all(j.kind == "R" and _off_line(a, j.point, j.direction) <= tol
                           for j in lg.joints[k + 1:]))
        s = float((a - A) @ u)
        if not on_line or abs(s) <= tol:
            continue
        legs.append(i)
        rows.append(nu + i * ch.m + k)
        scale.append(float(ch.q_scale[i, k]))
        home.append(s)
    lines = ActuatorLines(np.array(legs, int), np.array(rows, int), np.array(scale, float),
                          np.array(home, float), tol)
    _LINES[model] = lines
    return lines


def reversed_legs(model, X) -> np.ndarray:
    """``(N, n)`` bool: the legs whose actuator the unknowns ``X (n_unknowns, N)`` run to a
    negative length, or to zero within ``GEOMETRY_RTOL`` of the model's length (module
    docstring).  False for the legs the test does not apply to."""
    lines = actuator_lines(model)
    X = np.asarray(X, float)
    out = np.zeros((X.shape[1], model.n_legs), bool)
    if lines.legs.size:
        out[:, lines.legs] = lines.reversed(X)
    return out


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
    done = (np.asarray(o["residual"]) <= CONVERGED) & ~reversed_legs(model, Xs).any(axis=1)
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
        good = alive & ~reversed_legs(model, Xs).any(axis=1)
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
