"""PM reports of the Pinocchio cross-check: one row per check, regular poses drawn around a PM's
default pose, and the whole catalog (``screwkit check``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._check_rows import _TINY, CHECK_RTOL, CheckReport, CheckRow, _RowLookup
from ._pinocchio_check import PMChecker, _is_analysis, check_pm

__all__ = ["SUMMARY_CHECKS", "PMCheckReport", "summarize", "check_analysis", "regular_analyses",
           "check_all"]


# ---------------------------------------------------------------------------
# PM reports: one row per check, regular poses, the whole catalog
# ---------------------------------------------------------------------------

#: The summary checks of a PM report, in order: (name, what it gathers).
SUMMARY_CHECKS = (
    ("closure", "every leg's FK reaches the platform pose (and its S centre); the loop closures"),
    ("twists", "WORLD-frame Jacobian columns = screwkit's joint twists (S: same span)"),
    ("mobility", "platform DOF from Pinocchio's closed loop = screwkit's DOF, also as nv - rank(J_c) - idle"),
    ("mobility.twists", "the platform twist spaces are the same"),
    ("locked", "no platform motion left with the actuators locked"),
    ("statics.passive", "J^T w = 0 on every passive joint of every leg"),
    ("statics.actuator", "J^T w = the actuator force on the actuated joint"),
    ("statics.work", "closed-loop virtual work: sum F_a qdot_a + W . V = 0 on every loop motion"),
)


def _group(name: str) -> str:
    base = name.split(".", 1)[1] if name.startswith("leg") and "." in name else name
    if base.startswith("closure") or base == "loop.closure":
        return "closure"
    if base.startswith("twists"):
        return "twists"
    if base == "mobility.locked":
        return "locked"
    return base


def summarize(report: CheckReport) -> tuple:
    """One :class:`CheckRow` per summary check (see :data:`SUMMARY_CHECKS`): the largest
    deviation of its detail rows, passed when every one passed."""
    out = []
    for key, _ in SUMMARY_CHECKS:
        rows = [r for r in report.rows if _group(r.name) == key]
        if rows:
            worst = max(rows, key=lambda r: (not r.passed, r.deviation / max(r.tolerance, _TINY)
                                             if r.tolerance else r.deviation))
            out.append(CheckRow(key, max(r.deviation for r in rows), worst.tolerance,
                                all(r.passed for r in rows)))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class PMCheckReport(_RowLookup):
    """The Pinocchio cross-check of one PM at one pose.

    Attributes
    ----------
    pm : str
    pose : dict
        The independent pose parameters (degrees for angles, model units for lengths).
    rows : tuple of CheckRow
        One row per summary check (:data:`SUMMARY_CHECKS`).
    detail : CheckReport or None
        Every per-leg row and the measured values (DOF, ranks...).
    error : str
        Why the check could not run (empty when it ran).
    length_unit : str
        The PM's length unit (empty where it declares none: its own).
    """

    pm: str
    pose: dict
    rows: tuple
    detail: object = None
    error: str = ""
    length_unit: str = ""
    workload: dict | None = None

    @property
    def passed(self) -> bool:
        return not self.error and bool(self.rows) and all(r.passed for r in self.rows)

    @property
    def pose_label(self) -> str:
        """The pose (angles in degrees, lengths in :attr:`length_unit`)."""
        return ",".join(f"{k}={v:.4g}" for k, v in self.pose.items()) or "-"

    def as_dict(self) -> dict:
        out = {"pm": self.pm, "pose": dict(self.pose), "passed": self.passed,
               "units": {"angle": "deg", "length": self.length_unit or None},
               "rows": [{"check": r.name, "deviation": r.deviation, "tolerance": r.tolerance,
                         "passed": r.passed} for r in self.rows]}
        out["workload"] = self.workload         # (the statics rows' load; None: no statics)
        if self.detail is not None:
            out["detail"] = self.detail.as_dict()
        if self.error:
            out["error"] = self.error
        return out

    def __str__(self) -> str:
        head = f"{self.pm} at {self.pose_label}: {'passed' if self.passed else 'FAILED'}"
        if self.error:
            return f"{head} ({self.error})"
        return "\n".join([head] + [f"  {'ok ' if r.passed else 'BAD'} {r.name:<18} {r.deviation:.3e} "
                                   f"(tol {r.tolerance:.0e})" for r in self.rows])


def _pose_of(solution) -> dict:
    p = solution.params_degrees()
    ind = getattr(solution.model, "independent", tuple(p))
    return {k: float(p[k]) for k in ind}


def check_analysis(analysis, checker=None, *, rtol: float = CHECK_RTOL) -> PMCheckReport:
    """Cross-check a :class:`screwkit.engine.PMAnalysis` (pose, statics, mobility).

    Parameters
    ----------
    analysis : PMAnalysis
        Its statics may be None (a singular pose analysed with
        ``raise_on_singular=False``): the statics rows are then left out.
    checker : PMChecker, optional
        Models built once for the PM (:meth:`PMChecker.for_model`), reused across poses.
    rtol : float

    Returns
    -------
    PMCheckReport
    """
    if not _is_analysis(analysis):
        raise InputError(f"check_analysis needs a PMAnalysis, got {type(analysis).__name__}")
    detail = check_pm(analysis, checker=checker, rtol=rtol)
    sol = analysis.solution
    units = getattr(analysis.model, "units", None)
    load = None
    if analysis.statics is not None and analysis.has_workload:
        F0, T0, note = check_load(analysis.model)
        same = np.array_equal(analysis.force, F0) and np.array_equal(analysis.torque, T0)
        load = {"force": [float(x) for x in analysis.force],
                "torque": [float(x) for x in analysis.torque], "applied_at": "o",
                "force_unit": units.force if units is not None else "",
                "torque_unit": units.torque if units is not None else "",
                "source": note if same else analysis.workload_source}
    return PMCheckReport(str(getattr(analysis.model, "name", "")), _pose_of(sol),
                         summarize(detail), detail,
                         length_unit=units.length if units is not None and units.declared else "",
                         workload=load)


def check_load(model) -> tuple:
    """``(force, torque, note)``: the workload the statics rows of a check use: the model's
    declared one, else the *check load* (any load serves the identities checked; this one
    is a unit force along ``(1, 2, 3) / sqrt(14)`` and a torque of ``L`` times it, ``L`` the
    model's length), said in ``note``."""
    w = getattr(model, "workload", None)
    if w is not None:
        return np.array(w.force), np.array(w.torque), f"the {w.origin} workload"
    u = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    L = float(model.normalisation.length)
    return u, L * u, ("the check load (the model declares no workload; any load serves "
                      "the identities): a unit force along (1, 2, 3)/sqrt(14), torque L times "
                      "it")


def regular_analyses(pm, n: int = 10, seed: int = 0, *, centre: dict | None = None,
                     angle: float = np.radians(8.0), length_fraction: float = 0.08,
                     max_draws: int | None = None, **analyze_kwargs) -> tuple:
    """The first ``n`` regular poses drawn around a PM's default pose, analysed.

    Each independent parameter is drawn uniformly around its centre value:
    angles within ``+-angle`` (radians), lengths within ``+-length_fraction`` of
    the centre's ``|Zo|``.  Draws that are singular (:class:`SingularityError`) or
    unreachable (:class:`UnreachablePoseError`) are skipped.  The generator is
    seeded by ``seed`` and the PM's name, so each PM's draws do not depend on
    which other PMs are drawn.

    Parameters
    ----------
    pm : str or PMModel
    n : int
    seed : int
    centre : dict, optional
        Pose (radians) to draw around: its independent parameters, and ``Zo``
        for the length scale; default: the default pose (``pm.default_pose``,
        with ``Zo`` of the assembled default pose when it is dependent).
    angle, length_fraction : float
    max_draws : int, optional
        Give up after this many draws (default ``5 n + 20``).
    **analyze_kwargs
        Passed to :func:`screwkit.engine.analyze_pm` (``force``, ``torque``).

    Returns
    -------
    tuple of PMAnalysis

    Raises
    ------
    GeometryError
        Fewer than ``n`` regular poses in ``max_draws`` draws.
    """
    import zlib

    from ..engine import LENGTH_PARAMS, analyze_pm, default_full_pose, load_assembled_pm
    from ..errors import GeometryError, SingularityError, UnreachablePoseError
    from ..pm import PMModel

    model = pm if isinstance(pm, PMModel) else load_assembled_pm(pm)
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError(f"the number of poses must be a positive integer, got {n!r}")
    c = dict(model.default_pose if centre is None else centre)
    if centre is None and "Zo" not in c:
        c = default_full_pose(model)     # its |Zo| is the length scale of the draws
    zref = abs(float(c.get("Zo", 0.0))) or float(model.normalisation.length)
    rng = np.random.default_rng([int(seed), zlib.crc32(model.name.encode())])
    limit = 5 * int(n) + 20 if max_draws is None else int(max_draws)
    if "force" not in analyze_kwargs and "torque" not in analyze_kwargs:
        F, T, _ = check_load(model)
        analyze_kwargs = dict(analyze_kwargs, force=F, torque=T)
    out = []
    for _ in range(limit):
        pose = {}
        for p in model.independent:
            span = length_fraction * zref if p in LENGTH_PARAMS else angle
            pose[p] = float(c[p]) + float(rng.uniform(-span, span))
        try:
            out.append(analyze_pm(model, pose, **analyze_kwargs))
        except (SingularityError, UnreachablePoseError):
            continue
        if len(out) == n:
            return tuple(out)
    raise GeometryError(f"{model.name}: only {len(out)} regular poses in {limit} draws around the "
                        f"default pose (wanted {n})")


def check_all(poses_per_pm: int = 3, seed: int = 0, names=None, *, rtol: float = CHECK_RTOL,
              progress=None) -> tuple:
    """Cross-check every catalog PM (or ``names``) at ``poses_per_pm`` regular poses.

    The Pinocchio models are built once per PM and reused at each pose.  A PM that
    cannot be loaded or has too few regular poses gives one failed report with
    its ``error``.

    Parameters
    ----------
    poses_per_pm : int
    seed : int
    names : sequence of str or PMModel, optional
        Default: every PM of the packaged catalog.
    rtol : float
    progress : callable, optional
        Called with each report as it is made.

    Returns
    -------
    tuple of PMCheckReport
    """
    from ..engine import load_assembled_pm
    from ..errors import ScrewkitError
    from ..pm import PMModel, pm_names

    out = []
    for name in (pm_names() if names is None else names):
        label = name.name if isinstance(name, PMModel) else str(name)
        try:
            model = name if isinstance(name, PMModel) else load_assembled_pm(name)
            checker = PMChecker.for_model(model)
            analyses = regular_analyses(model, poses_per_pm, seed)
            reps = [check_analysis(a, checker, rtol=rtol) for a in analyses]
        except ScrewkitError as exc:
            reps = [PMCheckReport(label, {}, (), None, str(exc))]
        for r in reps:
            if progress is not None:
                progress(r)
            out.append(r)
    return tuple(out)
