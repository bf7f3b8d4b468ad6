"""A PM analysed at N poses: inverse displacement, unified Jacobian, conditioning, statics.

This is what ``screwkit analyze`` prints; :meth:`PMAnalysis.to_dict` is its JSON.
One pose is N = 1: scalar pose parameters give a one-pose result whose arrays
have no pose axis; arrays of N values give a result whose arrays start with N,
with per-pose flags (``ok``, ``singular``, ``unreachable``) instead of errors.

Examples
--------
>>> import screwkit
>>> res = screwkit.analyze("3RRPRR", pose={"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
>>> res.mobility.dof, res.mobility.motion_type
(3, '1T2R')
>>> bool(res.statics.equilibrium_residual < 1e-9)
True
>>> many = screwkit.analyze("3RRPRR", {"alpha": [0, 0.09], "beta": [0, -0.05], "Zo": [80, 80]})
>>> many.statics.active.shape, many.ok.tolist()      # (radians, cm)
((2, 3), [True, True])
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from ._jacobian import COND_THRESHOLD, JacobianResult
from ._pipeline import workload_about_origin
from ._run import CHUNK, compute, row_points
from ._inputs import pose_index
from ._path import check_path
from ._solution import PoseSolution, check_reachable, make_solution, mark_invalid, prepare
from ._statics import StaticsResult
from ._analysis_options import check_options as _options, stiffness_of_poses as _stiffness_of_poses
from ._passive import pose_warnings
from ._workloads import (MissingStatics, _compliance, _mask, check_partial_stiffness,
                         no_workload_message, resolve_workload)
from ..errors import MisuseError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..pm import PMModel

__all__ = ["PAPER_FORCE", "PAPER_TORQUE", "PMAnalysis", "analyze"]

#: The paper's workload (section 5.1): F in kN, T in kN.cm, applied at o; the declared default
#: workload of the paper's two PMs (3RRPRR, 2SPS+2SPR), and of no other.
PAPER_FORCE = (-20.0, -30.0, -60.0)
PAPER_TORQUE = (-30.0, -30.0, 100.0)


@dataclass(frozen=True, eq=False)
class PMAnalysis:
    """Everything screwkit says about a PM at N poses under one workload.

    Attributes
    ----------
    model : PMModel
    solution : PoseSolution
    jacobian : JacobianResult
    statics : StaticsResult or None
        None for one singular pose analysed with ``raise_on_singular=False``; for N poses
        the values of singular and unreachable poses are NaN (flagged).  Without a workload
        (none given, none declared by the model) any use of it raises the
        :class:`~screwkit.errors.InputError` that says how to give one.
    force, torque : ndarray (3,)
        The workload applied at ``o`` (zeros when there is none: see ``workload``).
    workload_source : str
        Where the workload comes from: ``"given"``, ``"declared default (...)"``, or ``""``
        when there is none.
    """

    model: PMModel
    solution: PoseSolution
    jacobian: JacobianResult
    statics: StaticsResult | None
    force: np.ndarray
    torque: np.ndarray
    diagnostics: dict = field(default_factory=dict, repr=False)
    stiffness: object = field(default=None, repr=False)
    workload_source: str = "given"

    @property
    def single(self) -> bool:
        return self.solution.single

    @property
    def workload(self):
        """The :class:`~screwkit.pm.Workload` of the statics (force, torque, source), or
        None when the analysis has none (its statics cannot be used)."""
        if isinstance(self.statics, MissingStatics):
            return None
        from ..pm import Workload
        src, _, note = self.workload_source.partition(" (")
        return Workload(self.force, self.torque, src, note[:-1] if note else "")

    @property
    def has_workload(self) -> bool:
        return not isinstance(self.statics, MissingStatics)

    def __len__(self) -> int:
        return len(self.solution)

    def __getitem__(self, i) -> "PMAnalysis":
        """Pose ``i`` alone; a slice, integers or a boolean mask: those poses (``res[res.ok]``)."""
        if self.single:
            raise MisuseError("a one-pose PMAnalysis cannot be indexed")
        i = pose_index(i, len(self))
        st = self.statics[i] if self.statics is not None else None     # (MissingStatics too)
        diag = dict(self.diagnostics)
        for key in ("rows_ok", "structure_ok", "det_sign", "twists", "lines", "platform"):
            if diag.get(key) is not None:
                diag[key] = diag[key][i:i + 1] if isinstance(i, int) else diag[key][i]
        return PMAnalysis(self.model, self.solution[i], self.jacobian[i], st, self.force,
                          self.torque, diag, _stiffness_of_poses(self.stiffness, i, len(self)),
                          self.workload_source)

    # -- per-pose flags -----------------------------------------------------------------
    @property
    def unreachable(self):
        u = ~self.solution.reachable_mask
        return bool(u[0]) if self.single else u

    @property
    def singular(self):
        s = self.jacobian.singular_mask & self.solution.reachable_mask
        return bool(s[0]) if self.single else s

    @property
    def rows_ok(self):
        """False where a row of ``J`` could not be formed as its template says (a dependent
        actuator, a basis whose reference directions degenerate): flagged, see ``ok``."""
        r = self.diagnostics.get("rows_ok")
        r = np.ones(len(self), bool) if r is None else r
        return bool(r[0]) if self.single else r

    @property
    def structure_ok(self):
        """Per pose and leg: True where the leg's constraint members have the structure
        they have at home; False where the generic rule of :mod:`screwkit.engine._generic`
        gave them (a leg that lost its catalog structure: a note, not an error)."""
        s = self.diagnostics.get("structure_ok")
        s = np.ones((len(self), self.model.n_legs), bool) if s is None else s
        return s[0] if self.single else s

    @property
    def ok(self):
        """Reachable, converged, not singular, rows formed, the load balanced (api.md)."""
        good = self.solution.closures.solved & ~self.jacobian.singular_mask & \
            np.atleast_1d(self.rows_ok)
        if self.statics is None:
            good &= False
        elif self.has_workload:                          # (no load: the kinematics decide)
            eq = np.asarray(self.statics.equilibrium_residual if not self.single
                            else [self.statics.equilibrium_residual])
            good &= eq.reshape(len(eq), -1).max(axis=1) <= 1e-8
        return bool(good[0]) if self.single else good

    @property
    def residual(self):
        return self.solution.residual

    @cached_property
    def _actuated_twists(self):
        tw = self.diagnostics.get("twists")
        if tw is None:
            from ._launch import run_poses
            c = self.solution.closures
            flat = c.chains.flat
            tw = run_poses(flat, flat.Z, c.params(), X=c.X.T, statics=False,
                           twists=True)["twists"]
            tw[~self.solution.reachable_mask] = np.nan
        tw.setflags(write=False)
        return tw

    @property
    def actuated_twists(self) -> np.ndarray:
        """Each actuated leg's actuated-joint unit twist ``[v; w]`` about ``O``, in the order
        of the actuation rows of ``J``: ``(n_actuated, 6)`` / ``(N, n_actuated, 6)`` (NaN where
        unreachable).  With ``J`` it gives the transmission indices."""
        tw = self._actuated_twists
        return tw[0] if self.single else tw

    @cached_property
    def quality(self):
        """How much to trust each pose: condition level, force amplification, the sign of
        ``det J`` against home (:mod:`screwkit.engine._quality`)."""
        from ._quality import quality
        return quality(self, analyze)

    @cached_property
    def indices(self):
        """Motion/force transmission, constraint and conditioning indices of every pose:
        ``iti``, ``oti``, ``lti``, ``cti``, ``sigma_min``, ``condition_number``,
        ``amplification`` (:class:`~screwkit.engine.TransmissionIndices`; ``docs/design.md``)."""
        from ._indices import transmission
        return transmission(self)

    @property
    def conditioning(self):
        """THE conditioning class of each pose: ``regular``, ``near-singular``, ``singular``
        or ``unreachable`` (:func:`~screwkit.engine._quality.classify`; the same in every
        command and output)."""
        c = self.quality.conditioning
        return str(c[0]) if self.single else c

    @property
    def level(self):
        """``ok``, ``ill-conditioned``, ``near-singular`` or ``singular`` per pose."""
        lev = self.quality.level
        return str(lev[0]) if self.single else lev

    @property
    def warnings(self) -> tuple:
        """One line per warning of the pose (one pose): level, assembly mode, rows."""
        if not self.single:
            raise MisuseError("warnings describe one pose: index the result first (res[i])")
        out = list(self.quality.warnings(0))
        if self.solution.status == "not converged":
            from ._kernels._layout import CONVERGED
            out.insert(0, f"not converged: closure residual {self.solution.residual:.3g} above "
                          f"{CONVERGED:g} (the pose is solved only to that, length-normalised)")
        if not self.rows_ok:
            out.append("a row of J could not be formed as its leg's template says (see the "
                       "notes): the pose is flagged")
        for i, good in enumerate(self.structure_ok):
            if not good:
                out.append(f"leg {i + 1}: its constraint members do not have their home "
                           "structure here; the generic rule gave them")
        return tuple(out + pose_warnings(self))

    @cached_property
    def mobility(self):
        """Instantaneous mobility at the pose (one pose): :func:`screwkit.pm.mobility`."""
        if not self.single:
            raise MisuseError("mobility is defined for one pose: index the result first (res[i])")
        from ..pm import mobility
        from ._motion import finite_motion
        return mobility(self.solution, finite=finite_motion(self.model))

    def __repr__(self) -> str:
        if self.single:
            return (f"PMAnalysis({self.model.name}, residual {self.solution.residual:.2g}, "
                    f"{self.jacobian!r})")
        return (f"PMAnalysis({self.model.name}: {len(self)} poses, {int(np.sum(self.ok))} ok, "
                f"{int(np.sum(self.singular))} singular, {int(np.sum(self.unreachable))} "
                "unreachable)")

    def under(self, force: "ArrayLike", torque: "ArrayLike") -> "PMAnalysis":
        """The same poses under the workload ``(force, torque)`` at ``o``: the statics
        solved again on this ``J`` (see :func:`~screwkit.engine._workloads.under`)."""
        from ._workloads import under
        return under(self, force, torque)

    def to_dict(self, units: str | None = None) -> dict:
        """JSON-ready report of one pose (angles in degrees; the model's units, or SI with
        ``units="SI"``): see :func:`screwkit.engine._report.report`."""
        from ._report import report
        if self.single:
            check_reachable(self.solution)      # an unreachable pose of a batch has no report
        return report(self, units)

    def to_frame(self) -> Any:
        """A long ``pandas.DataFrame``: one row per pose and quantity (pose parameters,
        extensions, every row value of ``F_r``, the condition number) with its unit; see
        :func:`screwkit.engine._frames.to_frame`.  Needs pandas."""
        from ._frames import to_frame
        return to_frame(self)

    def show(self, *, title: str | None = None, start: int = 0) -> Any:
        """The interactive 3D view of these poses (:class:`screwkit.scene.View`): Jupyter
        shows it inline; ``.write_html(path)`` writes the self-contained page.  One pose is
        one state; N poses get a slider over the pose index (a grid of poses with one
        slider per parameter: :func:`screwkit.view`).  Needs plotly
        (``pip install "screwkit[view]"``)."""
        from ..scene import View, require_plotly
        from ._scene import NO_WORKLOAD, scene_of
        require_plotly()
        return View(scene_of(self, start=start, title=title, source=self.workload_source
                             if self.has_workload else NO_WORKLOAD))

    def _repr_html_(self) -> str:
        """The HTML table Jupyter shows for a result."""
        from ._frames import to_html
        return to_html(self)


def analyze(model, pose=None, *, force=None, torque=None, degrees: bool = False,
            guess=None, raise_on_singular: bool = True, threshold: float = COND_THRESHOLD,
            path: bool = False, anchor_every=None, chunk: int = CHUNK, workers=None,
            progress=None, stiffness=None, mapper=None, twists: bool = False,
            lines: bool = False) -> PMAnalysis:
    """Analyse a PM model at one or N poses.

    Parameters
    ----------
    model : PMModel
    pose : dict or DataFrame, optional
        Independent pose parameters: numbers (one pose) or arrays ``(N,)``; missing ones
        from the default pose.
    force, torque : array_like (3,), optional
        Workload at ``o`` (model units, world axes).  One without the other means the other
        is zero.  Neither: the model's declared default (``model.workload``), else no
        workload: the pose, ``J`` and mobility are computed, and any use of ``statics``
        raises an :class:`~screwkit.errors.InputError` (``res.under(force, torque)`` adds
        the statics later, on the same ``J``).
    degrees : bool
        Angles of ``pose`` in degrees.
    guess : PoseSolution or dict, optional
        Warm start.
    raise_on_singular : bool
        One pose: raise :class:`SingularityError` at a singular pose (default) or return
        the analysis with ``statics=None``.  N poses never raise: singular and unreachable
        poses are flagged and their statics are NaN.
    path : bool
        The poses are successive samples of a continuous path: each is warm-started from
        its neighbours (:func:`~screwkit.engine.solve`).  Poses that are not (32 or more
        whose median step exceeds a quarter of their spread) are solved each from home,
        with a note in ``res.solution.common_notes``.
    chunk, workers : int
        Poses per chunk and threads (default: 2 threads when there are many chunks).
    progress : callable(done, total), optional
        Called as the work advances: ``done`` grows to ``total`` (N poses; 2 N steps with
        ``path=True``: the closures of the path, then the rows and statics).
    stiffness : mapping, array_like (m,) or "model", optional
        Stiffness of each row of ``J`` (a mapping by row label, ``{"F_a1": 2e3, "T_c1": 5e6}``,
        naming every row a self-stress loads, or one value per row), in model units,
        or ``"model"``: the ``actuator``, ``force`` and ``couple`` stiffnesses of the model's
        ``dynamics: stiffness:`` block.  A statically indeterminate PM then takes the
        compliance-weighted solution (:func:`~screwkit.engine.statics`).
    mapper : callable(fn, items) -> list, optional
        With ``path=True``: computes ``[fn(x) for x in items]`` elsewhere (e.g.
        ``functools.partial(screwkit.maps.run_tasks, 2)`` on a Dask cluster); the path's
        closures are solved here, the rows and statics of its chunks by the mapper, equal
        to the serial run bit for bit.
    twists : bool
        Also keep, from the same kernel run, each actuated leg's actuated-joint unit twist
        (:attr:`PMAnalysis.actuated_twists`; formed on first read otherwise).
    lines : bool
        Keep from this run what maps read: the indices' joints, platform, det_sign orientation.
    """
    _options(threshold, chunk, workers, degrees, path, progress, anchor_every,
             raise_on_singular, twists, lines)
    load = resolve_workload(model, force, torque)
    F, T, source = load if load is not None else (np.zeros(3), np.zeros(3), "")
    fixed, N, single, notes, (X0, G6), side, invalid = prepare(model, pose, guess, degrees)
    path, path_notes = check_path(fixed, path, float(model.normalisation.length))
    notes = tuple(notes) + path_notes
    compliance = None if stiffness is None else _compliance(model, stiffness, N)
    comp = compute(model, fixed, X0=X0, G6=G6, side=side, path=path, anchor_every=anchor_every,
                   F=F, T=T, chunk=chunk, workers=workers, progress=progress,
                   compliance=compliance, mapper=mapper if path else None, twists=bool(twists),
                   lines=bool(lines), orient=bool(lines))
    sol = make_solution(model, mark_invalid(comp.closures, invalid), single, notes, side,
                        invalid, (comp.diagnostics or {}).get("reversed_legs"))
    cond = comp.conditioning
    unreach = None
    if single:
        check_reachable(sol)            # (one pose: raised where unreachable, nothing to flag)
    else:
        unreach = ~sol.reachable_mask
    if unreach is not None and unreach.any():
        # J there is the last unconverged iterate's: no conditioning of the pose (NaN, flagged)
        nan = lambda x: np.where(unreach, np.nan, x)            # noqa: E731
        cond = dataclasses.replace(
            cond, condition_number=nan(cond.condition_number),
            constraint_condition_number=nan(cond.constraint_condition_number),
            singular_values=np.where(unreach[:, None], np.nan, cond.singular_values))
    jac = JacobianResult(comp.J, comp.info, comp.n_actuated, comp.scale,
                         lambda sl: row_points(model, sol.closures.take(sl), chunk),
                         lambda: sol._platform[1], cond,
                         float(threshold), bool(single), sol.legs_at)
    check_partial_stiffness(model, stiffness, jac, sol)
    # one pose: singular as jac.singular says, read once (a batch is never refused)
    singular = single and not cond.condition_number[0] <= jac.threshold
    if singular and raise_on_singular:
        jac.check()
    st: Any = None
    if not singular:
        st = StaticsResult(jac, comp.values,
                           lambda: workload_about_origin(np.broadcast_to(F, (N, 3)),
                                                         np.broadcast_to(T, (N, 3)),
                                                         sol._platform[1]),
                           sol.base_points, lambda: sol._platform[2],
                           np.array([True]) if N == 1 else np.ones(N, bool),
                           comp.equilibrium, comp.amplification)
        if not single:                  # (one pose here is reachable and regular)
            bad = unreach | jac.singular_mask
            if bad.any():
                st = _mask(st, bad)
        if load is None:
            st = MissingStatics(no_workload_message(model))
    diag = dict(comp.diagnostics or {}, rows_ok=comp.rows_ok, structure_ok=comp.structure_ok,
                det_sign=comp.det_sign, twists=comp.twists, lines=comp.lines,
                platform=comp.platform)
    return PMAnalysis(model, sol, jac, st, F, T, diag, stiffness, source)
