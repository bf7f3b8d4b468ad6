"""The PM assembled at N poses: :class:`PoseSolution` and :func:`solve` (inverse displacement).

Each leg's end pose is the product of exponentials of its joints in the world
frame, ``T_end(q) = exp(xi_1 q_1) ... exp(xi_m q_m) T_end_home``, with
``T_end_home`` the platform pose at home and ``xi_i`` the home unit twists
``[v; w]`` (joint values 0 at home; radians for R and H, lengths for P).  The
inverse displacement solves, for given independent pose parameters, the
dependent ones and every leg's joint values so that every ``T_end_i`` equals
the platform pose (the kernels of ``engine/_kernels/_closures.py``); the residual is the
largest component of the length-normalised error twist ``[d / L; w]``.

Examples
--------
>>> import screwkit
>>> pm = screwkit.load_pm("3RRPRR")
>>> sol = screwkit.solve(pm, {"alpha": [5, 6], "beta": [-3, -3], "Zo": [80, 81]}, degrees=True)
>>> sol.extensions.shape, bool(sol.success.all())
((2, 3), True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ._chains import LENGTH_PARAMS, PARAMS
from ._flat import base_points_of
from ._inputs import check_keywords, pose_index, prepare
from ._kernels._layout import ACCEPTED, CONVERGED
from ._solve import Closures
from ..errors import MisuseError

if TYPE_CHECKING:
    from ..pm import PMModel

__all__ = ["PoseSolution", "Closures", "solve", "STATUSES", "STRUCTURE_TOL"]

#: Largest structure-check residual regarded as satisfied (dimensionless).
STRUCTURE_TOL = 1e-7
#: Per-pose status of a solution (``invalid input``: a pose of a batch given a non-finite or
#: out-of-range value, flagged and not solved; it counts as unreachable).
STATUSES = ("ok", "not converged", "unreachable", "invalid input")


@dataclass(frozen=True, eq=False)
class PoseSolution:
    """The PM assembled at N poses (``single``: one pose, no pose axis on the arrays).

    Attributes
    ----------
    model : PMModel
    closures : Closures
        The solver's unknowns and residuals.
    single : bool
    common_notes : tuple of str ; pose_notes : dict int -> tuple of str
        Notes of every pose (defaults used...) and of particular ones (``invalid input``...).
    """

    model: PMModel
    closures: Closures = field(repr=False)
    single: bool = True
    common_notes: tuple = ()
    pose_notes: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return self.closures.residual.shape[0]

    def _sq(self, x):
        return x[0] if self.single else x

    @cached_property
    def _invalid(self) -> np.ndarray:   # (N,): given invalid inputs (a diverged pose: unreachable)
        out = np.zeros(len(self.closures.residual), bool)
        for i, notes in self.pose_notes.items():
            out[i] = any(n.startswith("invalid input") for n in notes)
        return out

    @cached_property
    def _params(self) -> dict:
        c = self.closures
        ch = c.chains
        bad = ~self.reachable_mask
        given_bad = self._invalid                       # invalid input: no value of its own
        out = {}
        for k in PARAMS:
            if k in c.fixed:
                v = np.array(c.fixed[k], float)
                v[given_bad] = np.nan
            else:
                j = ch.unknown.index(k)
                v = c.X[j] * ch.x_scale[j]
                v[bad] = np.nan
            v.setflags(write=False)
            out[k] = v
        return out

    @cached_property
    def _pose6(self) -> np.ndarray:
        """:attr:`_params` as ``(N, 6)`` in :data:`PARAMS`' order, read-only: a warm start's
        poses, by which the kernels move the start (``_inputs._start_of``)."""
        P = self._params
        out = np.array([[P[k].item() for k in PARAMS]]) if len(P["Zo"]) == 1 else \
            np.stack([P[k] for k in PARAMS], axis=1)      # (one pose: without numpy's stack)
        out.setflags(write=False)
        return out

    @property
    def params(self) -> dict:
        """``Xo Yo Zo alpha beta gamma`` (model lengths, radians): floats for one pose,
        ``(N,)`` arrays otherwise (NaN for the dependent ones of an unreachable pose)."""
        if self.single:
            return {k: float(v[0]) for k, v in self._params.items()}
        return dict(self._params)

    def params_degrees(self) -> dict:
        return {k: (v if k in LENGTH_PARAMS else np.degrees(v)) for k, v in self.params.items()}

    @cached_property
    def _platform(self):
        """World <- platform rotations ``(N, 3, 3)``, centres ``(N, 3)`` and the platform
        points ``a_i`` ``(N, n, 3)`` (the kernels' frames at the solved unknowns; NaN where
        unreachable)."""
        from ._links import platform_arrays              # (kept from the indices' frames
        return platform_arrays(self)                      # where they came first)

    @property
    def rotation(self) -> np.ndarray:
        """World <- platform rotation ``(3, 3)`` / ``(N, 3, 3)``."""
        return self._sq(self._platform[0])

    @property
    def position(self) -> np.ndarray:
        """The platform centre ``o`` (world) ``(3,)`` / ``(N, 3)``."""
        return self._sq(self._platform[1])

    @property
    def platform_points(self) -> np.ndarray:
        """``a_i`` (world), ``(n, 3)`` / ``(N, n, 3)``."""
        return self._sq(self._platform[2])

    @property
    def base_points(self) -> np.ndarray:
        """``A_i`` (world), ``(n, 3)`` (the same at every pose; read-only, kept with the
        model's arrays)."""
        return base_points_of(self.closures.chains.flat)

    @cached_property
    def _extensions(self):
        e = np.linalg.norm(self._platform[2] - self.base_points[None], axis=2)
        e.setflags(write=False)
        return e

    @property
    def extensions(self) -> np.ndarray:
        """``r_i = |a_i - A_i|``, ``(n,)`` / ``(N, n)``."""
        return self._sq(self._extensions)

    @cached_property
    def _q(self):
        ch = self.closures.chains
        nu = len(ch.unknown)
        q = self.closures.X[nu:].reshape(ch.n, ch.m, -1) * ch.q_scale[:, :, None]
        q[:, :, ~self.reachable_mask] = np.nan
        return q

    @property
    def joint_values(self) -> tuple:
        """Each leg's joint values (0 at home): ``(m_i,)`` / ``(N, m_i)`` arrays."""
        out = []
        for i, lg in enumerate(self.model.home_legs):
            v = np.ascontiguousarray(self._q[i, :len(lg.joints)].T)
            v.setflags(write=False)
            out.append(self._sq(v))
        return tuple(out)

    @property
    def actuator_values(self) -> np.ndarray:
        """Each leg's actuated joint value (displacement from home), ``(n,)`` / ``(N, n)``."""
        ch = self.closures.chains
        v = np.ascontiguousarray(self._q[ch.actuator_slots].T)
        v.setflags(write=False)
        return self._sq(v)

    @property
    def residual(self):
        """Largest length-normalised closure error."""
        r = self.closures.residual
        return float(r[0]) if self.single else r

    @property
    def reachable_mask(self) -> np.ndarray:
        return self.closures.reachable

    @property
    def success(self):
        """Residual at most :data:`CONVERGED` (and no actuator reversed, :mod:`._reversal`)."""
        s = self.closures.solved
        return bool(s[0]) if self.single else s

    @property
    def status(self):
        """``ok``, ``not converged`` (residual above CONVERGED, below ACCEPTED) or
        ``unreachable`` (also where the only solution found reverses an actuator,
        :mod:`._reversal`), per pose; ``invalid input`` (not solved)."""
        r = self.closures.residual
        s = np.where(r <= CONVERGED, "ok", np.where(r <= ACCEPTED, "not converged",
                                                    np.where(self._invalid, "invalid input",
                                                             "unreachable")))
        if self.closures.reversed is not None:
            s = np.where(self.closures.reversed, "unreachable", s)
        return str(s[0]) if self.single else s

    @property
    def iterations(self):
        it = self.closures.iterations
        return int(it[0]) if self.single else it

    @cached_property
    def notes(self) -> tuple:
        """Notes of the pose (one pose), or of every pose (tuple of tuples).

        For one pose they include the legs whose catalog structure checks do not hold
        there (computed when first read)."""
        if self.single:
            extra = _structure_notes(self.model, self) if self.reachable_mask.all() else []
            return tuple(self.common_notes) + tuple(self.pose_notes.get(0, ())) + tuple(extra)
        return tuple(tuple(self.common_notes) + tuple(self.pose_notes.get(i, ()))
                     for i in range(len(self)))

    def legs_at(self, i: int) -> tuple:
        """Every leg placed at pose ``i``: joints on their current axes, ``A``, ``a`` (world)."""
        from ..legs import Joint, Leg
        i = pose_index(i, len(self), one=True)
        ch = self.closures.chains
        fr = self.closures.frames(slice(i, i + 1), bars=bool(ch.bars.any()))
        fa = fr["axes_points"][0]
        bars = fr["bars"][0] if fr["bars"].shape[0] else None        # parallelograms
        out = []
        for k, lg in enumerate(self.model.home_legs):
            joints = tuple(Joint(j.spec, fa[k, s, :3], fa[k, s, 3:], j.pitch,
                                 None if j.bar is None or bars is None else bars[k, s])
                           for s, j in enumerate(lg.joints))
            out.append(Leg(lg.string, joints, self.base_points[k], self._platform[2][i, k],
                           lg.name))
        return tuple(out)

    @cached_property
    def legs(self) -> tuple:
        """The placed legs (one pose; see :meth:`legs_at` for several)."""
        if not self.single:
            raise MisuseError("legs is defined for one pose: use legs_at(i) or sol[i]")
        return self.legs_at(0)

    def __getitem__(self, i) -> "PoseSolution":
        """Pose ``i`` as a one-pose solution; a slice, integers or a mask: a sub-batch."""
        if self.single:
            raise MisuseError("a one-pose PoseSolution cannot be indexed")
        i = pose_index(i, len(self))
        if isinstance(i, int):
            return PoseSolution(self.model, self.closures.take(slice(i, i + 1)), True,
                                self.common_notes,
                                {0: self.pose_notes[i]} if i in self.pose_notes else {})
        notes = {j: self.pose_notes[int(k)] for j, k in enumerate(i) if int(k) in self.pose_notes}
        return PoseSolution(self.model, self.closures.take(i), False, self.common_notes, notes)

    def __repr__(self) -> str:
        if not self.single:
            st = self.status
            return (f"PoseSolution({self.model.name}: {len(self)} poses, "
                    f"{int(np.sum(st == 'ok'))} ok, {int(np.sum(st == 'unreachable'))} unreachable)")
        p = ", ".join(f"{k}={v:.6g}" for k, v in self.params_degrees().items())
        return (f"PoseSolution({self.model.name}: {p}; residual {self.residual:.2g}, "
                f"{'ok' if self.success else 'NOT converged'})")


def solve(model, pose=None, guess=None, degrees: bool = False, *, path: bool = False,
          single=None, raise_unreachable=None, **kwargs) -> PoseSolution:
    """Unified inverse displacement at N poses (see the module docstring).

    Parameters
    ----------
    model : PMModel
    pose : dict or DataFrame
        Independent parameters: numbers (one pose) or 1-D arrays (N poses); missing ones
        from the default pose.  Angles in radians unless ``degrees``.
    guess : PoseSolution or dict, optional
        Warm start (the previous pose along a path); default: home.
    path : bool
        The poses are successive samples of a path (warm starts from the neighbours).
    raise_unreachable : bool, optional
        Raise :class:`UnreachablePoseError` (default: one pose; a batch flags, ``status``).

    Returns
    -------
    PoseSolution
    """
    from ._path import check_path
    from ._run import compute

    check_keywords("solve", kwargs, ("chunk", "workers", "anchor_every", "progress"),
                   "guess, degrees, path, single, raise_unreachable, ")
    fixed, N, one, notes, (X0, G6), side, invalid = prepare(model, pose, guess, degrees)
    path, path_notes = check_path(fixed, path, float(model.normalisation.length))
    notes = tuple(notes) + path_notes
    single = one if single is None else single
    comp = compute(model, fixed, X0=X0, G6=G6, side=side, path=path, rows=False, **kwargs)
    sol = make_solution(model, mark_invalid(comp.closures, invalid), single, notes, side,
                        invalid, (comp.diagnostics or {}).get("reversed_legs"))
    if (single if raise_unreachable is None else raise_unreachable):
        check_reachable(sol)
    return sol


def mark_invalid(closures: Closures, invalid: dict) -> Closures:
    """The closures with the poses of ``invalid`` (index -> reasons) marked not solved
    (residual infinite: unreachable, status ``invalid input``)."""
    if not invalid:
        return closures
    import dataclasses
    r = np.array(closures.residual, float)
    r[np.fromiter(invalid, int)] = np.inf
    return dataclasses.replace(closures, residual=r)


def make_solution(model, closures: Closures, single, notes, side=None,
                  invalid=None, reversed_legs=None) -> PoseSolution:
    """The :class:`PoseSolution` of solved closures, with the notes of each pose
    (``reversed_legs (N, n)``: the legs whose actuator the only solution found runs to a
    negative length, :mod:`._reversal`)."""
    ch = closures.chains
    pose_notes: dict[int, tuple[str, ...]] = {
        int(i): (f"invalid input, not solved: {'; '.join(why)}",)
        for i, why in (invalid or {}).items()}
    if reversed_legs is not None:
        from ._reversal import reversed_note
        for j in np.flatnonzero(np.asarray(reversed_legs).any(axis=1)).tolist():
            pose_notes.setdefault(j, (reversed_note(reversed_legs[j]),))
    fixed = closures.fixed
    sb = closures.singular_beta
    for i in ((0,) if sb[0] else ()) if len(sb) == 1 else np.flatnonzero(sb):
        if int(i) in pose_notes or not closures.residual[i] <= ACCEPTED:
            continue                    # (not solved: its dependent angle is no pose's)
        pair = [p for p in ("alpha", "gamma") if p in ch.unknown]
        b = np.degrees(fixed["beta"][i])
        how = ("the one-sided limit from the warm start's side" if side is not None and side[i]
               else "the limit beta -> " + f"{b:.6g} deg (average of both sides)")
        txt = ", ".join(f"{p} = {np.degrees(closures.X[ch.unknown.index(p), i]):.6g} deg"
                        for p in pair)
        pose_notes[int(i)] = pose_notes.get(int(i), ()) + (
            f"beta = {b:.6g} deg is a representation singularity of {model.order} (alpha and "
            f"gamma turn about the same axis): {' and '.join(pair)} resolved by continuity as "
            f"{how}: {txt}",)
    return PoseSolution(model, closures, bool(single), tuple(notes), pose_notes)


def _structure_notes(model, sol):
    """Legs whose catalog structure checks do not hold at the pose (one pose)."""
    from ..legs import structure_vector
    out = []
    pose = sol.params
    for i, (r, lg) in enumerate(zip(model.leg_rules, sol.legs)):
        if not r.structure:
            continue
        v = structure_vector(r, model.placement(i, pose), lg)
        if v.size and float(np.max(np.abs(v))) > STRUCTURE_TOL:
            out.append(f"leg {i + 1} ({r.name}): its structure checks do not hold here (residual "
                       f"{float(np.max(np.abs(v))):.3g}); its constraint wrenches are those of "
                       "the actual geometry")
    return out


def check_reachable(sol: PoseSolution):
    """Raise :class:`UnreachablePoseError` for the first unreachable pose."""
    r = sol.closures.residual
    rev = sol.closures.reversed
    if ((r[0] <= ACCEPTED) if len(r) == 1 else sol.reachable_mask.all()) and (
            rev is None or not rev.any()):
        return
    from .. import errors as err
    i = int(np.flatnonzero(~sol.reachable_mask)[0])
    f = float(sol.closures.residual[i])
    given = ", ".join(f"{k}={_fmt(k, sol.closures.fixed[k][i])}" for k in sol.model.independent)
    bad_input = [n for n in sol.pose_notes.get(i, ()) if n.startswith("invalid input")]
    if bad_input:                     # (not solved at all: say why, not a residual)
        raise err.InputError(f"{sol.model.name}: pose {i}: {bad_input[0]}")
    why = [n for n in sol.pose_notes.get(i, ()) if n.startswith("unreachable: ")]
    if why:
        raise err.UnreachablePoseError(f"{sol.model.name}: pose {given} is {why[0]}", residual=f)
    raise err.UnreachablePoseError(
        f"{sol.model.name}: pose {given} is unreachable from the home assembly: the loop "
        f"closures stop at a length-normalised residual {f:.3g} (> {ACCEPTED:g}); a solution "
        "on another branch may exist (start from a solved pose near it, or reach it along a "
        "path)", residual=f)


def _fmt(k, v):
    return f"{v:.6g}" if k in LENGTH_PARAMS else f"{np.degrees(v):.6g} deg"
