"""High-level Python API (the CLI is a thin shell over these functions)."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, Callable, Union

from .legs import Leg, Placement, generic_leg

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    import xarray

    from .engine import AssemblyModes, ForwardResult, PMAnalysis, PoseSolution
    from .design import OptimizationResult
    from .maps import Sizing
    from .pm import Catalog, LegSpec, PMBuilder, PMModel

    #: A PM: a model, a catalog name, a YAML path, ``"path.yaml#NAME"``, a mapping, a builder.
    PMLike = Union[PMModel, str, os.PathLike, Mapping[str, Any], PMBuilder]
    #: Pose parameters: numbers (one pose), 1-D arrays of one length N, or a pandas
    #: DataFrame with one column per parameter (any mapping of column names to columns).
    PoseLike = Mapping[str, ArrayLike]

__all__ = ["leg", "load_pm", "solve", "solve_path", "analyze", "define_leg", "load_legs",
           "extend_catalog", "map", "size", "optimize", "forward", "assembly_modes",
           "to_pinocchio"]


def leg(name: str, placement: Placement | None = None, *, seed: int = 0,
        catalog: Catalog | None = None) -> Leg:
    """A placed leg: a catalog variant by name (``"UPU/couple"``, ``"RRPRR"``) or, for a
    string not in the catalog, the bare string with a generic geometry.

    Parameters
    ----------
    name : str
        Catalog name or leg string (an ``_`` marks the actuated joint).
    placement : Placement, optional
        End points and frames; default :func:`screwkit.legs.default_placement`
        or the catalog entry's own placement.
    seed : int
        Seed of the generic geometry of a bare string.
    catalog : Catalog, optional
        Default: the packaged ``legs_catalog.yaml``.
    """
    from .legs._rules import check_leg_request
    from .pm import Catalog, default_catalog

    seed = check_leg_request(name, placement, seed)
    if catalog is not None and not isinstance(catalog, Catalog):
        from .errors import InputError
        raise InputError(f"catalog must be a screwkit Catalog, got {type(catalog).__name__}")
    cat = catalog if catalog is not None else default_catalog()
    spec = cat.find_leg(name)
    if spec is not None:
        return spec.build(placement)
    return generic_leg(name, placement, seed)


# ---------------------------------------------------------------------------
# user-defined leg types
# ---------------------------------------------------------------------------

def define_leg(name: str, string: str, joints: Sequence[Mapping[str, Any]],
               structure: Sequence[Mapping[str, Any]] = (), expect: Mapping[str, Any] | None = None,
               summary: str = "", *,
               placement: Placement | Mapping[str, ArrayLike] | None = None) -> LegSpec:
    """A user-defined leg type, validated exactly like a ``legs_catalog.yaml`` entry.

    Parameters
    ----------
    name : str
        Unique name; variants as ``STRING/variant`` (``"RPS/mine"``).
    string : str
        Leg string, ``_`` before the actuated joint (``"R_PS"``).
    joints : list of dict
        One placement rule per letter (``axis``/``axes``/``at``, see :mod:`screwkit.legs._rules`).
    structure : list of dict
        Checks that must hold wherever the leg is built
        (``{perpendicular: [R1, leg]}`` ...).
    expect : dict, optional
        Expected constraint wrenches: ``forces``, ``couples``, ``screws`` (counts),
        ``words``, ``force_lines`` (``[{through: P, parallel: REF}]``), ``couples_along``.
    summary : str
    placement : Placement or mapping, optional
        Default end points (``{"A": [..], "a": [..]}``); default
        :func:`screwkit.legs.default_placement`.

    Returns
    -------
    screwkit.pm.LegSpec
        Use it with ``spec.build()``, or add it to a catalog with :func:`extend_catalog`
        and then ``screwkit.leg(name, catalog=...)``.

    Raises
    ------
    CatalogError
        Naming the leg and the field at fault.
    """
    from dataclasses import replace

    from .pm import leg_spec_from_mapping

    d: dict[str, Any] = {"name": name, "string": string, "joints": joints,
         "structure": list(structure or ()), "summary": summary}
    if expect is not None:
        d["expect"] = expect
    pl_obj = placement if isinstance(placement, Placement) else None
    if placement is not None and pl_obj is None:
        d["placement"] = placement
    spec = leg_spec_from_mapping(d, source="define_leg")
    return replace(spec, placement=pl_obj) if pl_obj is not None else spec


def load_legs(path: str | os.PathLike) -> tuple[LegSpec, ...]:
    """The leg types (:class:`~screwkit.pm.LegSpec`, in file order) of a YAML file (``str``
    or path-like) with a ``legs:`` list (the catalog's schema).

    Raises
    ------
    CatalogError
        Unreadable file, invalid YAML, no ``legs`` list, or a malformed entry
        (the message names the file, the entry and the field).
    """
    from .pm import load_catalog
    from .errors import CatalogError

    cat = load_catalog(path)
    if not cat.legs:
        raise CatalogError("no leg types: expected a non-empty 'legs:' list", None, "legs",
                           str(path))
    return tuple(cat.legs.values())


def extend_catalog(legs: LegSpec | Iterable[LegSpec] | Catalog, catalog: Catalog | None = None,
                   *, replace: bool = False) -> Catalog:
    """A catalog with extra leg types, for ``screwkit.leg(name, catalog=...)``.

    Parameters
    ----------
    legs : LegSpec, iterable of LegSpec, or Catalog
        From :func:`define_leg` or :func:`load_legs`.
    catalog : Catalog, optional
        The catalog to extend (default: the packaged one); it is not modified.
    replace : bool
        Allow a new leg to replace an existing leg of the same name (otherwise
        a :class:`~screwkit.errors.CatalogError`).

    Returns
    -------
    screwkit.pm.Catalog
    """
    from .pm import catalog_with_legs

    return catalog_with_legs(legs, catalog, replace=replace)


def load_pm(pm: str | os.PathLike | Mapping[str, Any] | PMBuilder,
            overrides: Mapping[str, float] | None = None, *, catalog: Catalog | None = None,
            name: str | None = None) -> PMModel:
    """A parallel manipulator model: a catalog name (``"3RRPRR"``), a YAML path,
    ``"path.yaml#NAME"``, one PM's mapping as a model file holds it under ``pms:`` (its
    name ``name``), or a :class:`PMBuilder`; ``overrides`` changes dimensions.

    The model is built by :func:`screwkit.pm.load_pm` (the same checks for a file and a
    mapping), then its default pose is solved (:func:`screwkit.engine.check_default_pose`).

    Returns
    -------
    screwkit.pm.PMModel
        The model data (a constant description); solve it at a pose with
        :func:`solve`, analyse it with :func:`analyze`.

    Raises
    ------
    CatalogError
        Unknown PM, a malformed definition, or a default pose that cannot be
        assembled (``the default pose cannot be assembled: ...``).
    InputError
        Bad overrides.
    """
    from .engine import check_default_pose
    from .pm import load_pm as _load

    text = os.fspath(pm) if isinstance(pm, os.PathLike) else pm     # a pathlib.Path too
    over = dict(overrides) if isinstance(overrides, Mapping) else overrides    # (else: said)
    return check_default_pose(_load(text, over, catalog, name=name))


def _model(pm: PMLike, overrides: Mapping[str, float] | None = None,
           catalog: Catalog | None = None) -> PMModel:
    from .pm import PMModel

    if isinstance(pm, PMModel):           # (its dimensions changed: never the overrides dropped)
        from .engine import load_assembled_pm
        return load_assembled_pm(pm, overrides)
    return load_pm(pm, overrides, catalog=catalog)


def solve(pm: PMLike, independent: PoseLike | None = None,
          guess: PoseSolution | Mapping[str, float] | None = None, degrees: bool = False,
          **kwargs: Any) -> PoseSolution:
    """Unified inverse displacement of a PM at one pose or N poses.

    Parameters
    ----------
    pm : PMModel or str
        A loaded model, or a name or path for :func:`load_pm`.
    independent : dict or DataFrame
        Values of ``pm.independent``: numbers (one pose) or 1-D arrays of one length N
        (N poses; numbers broadcast); missing ones are taken from the default pose, with
        a note.  Angles in radians unless ``degrees``.
    guess : PoseSolution or dict, optional
        Warm start (e.g. the previous pose along a path); default home.
    degrees : bool
    **kwargs
        ``path=True`` (the poses are successive samples of a path: warm starts from the
        neighbours), ``chunk``, ``workers``: see :func:`screwkit.engine.solve`.

    Returns
    -------
    screwkit.engine.PoseSolution

    Raises
    ------
    InputError
        Unknown, dependent or non-finite parameters.
    UnreachablePoseError
        One pose whose loop closures cannot be satisfied (``residual`` attribute); N poses
        are flagged instead (``status``, ``residual``).

    Examples
    --------
    >>> import screwkit
    >>> pm = screwkit.load_pm("3RRPRR")
    >>> sol = screwkit.solve(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
    >>> bool(sol.success), sol.legs[0].name
    (True, 'RRPRR')
    """
    from .engine import solve as _solve

    return _solve(_model(pm, kwargs.pop("overrides", None)), independent, guess, degrees,
                  **kwargs)


def solve_path(pm: PMLike, poses: Sequence[Mapping[str, float]],
               guess: PoseSolution | Mapping[str, float] | None = None,
               degrees: bool = False) -> tuple[PoseSolution, ...]:
    """:func:`solve` at each of a sequence of independent-parameter dicts, as successive
    samples of a path (``path=True``: each warm-started from its solved neighbours;
    ``guess`` warm-starts the first).  Returns a tuple of ``screwkit.engine.PoseSolution``.

    Raises
    ------
    InputError
        No samples, a sample that is not a mapping, an unknown or a missing parameter.
    UnreachablePoseError
        Naming the first sample that cannot be assembled.
    """
    from .engine import solve_path as _solve_path

    return _solve_path(_model(pm), poses, guess, degrees)


def analyze(pm: PMLike, pose: PoseLike | None = None, **kwargs: Any) -> PMAnalysis:
    """Analyse a PM at one pose or N poses: closures, unified Jacobian, conditioning, statics.

    ``pose`` holds numbers (one pose: a result without a pose axis, errors raised) or
    arrays of shape ``(N,)`` / a pandas DataFrame (N poses: every array of the result starts
    with N, flagged poses are kept: ``res.ok``, ``res.singular``, ``res.unreachable``);
    ``res[i]`` is the one-pose analysis of pose ``i``.  Keywords: ``force``, ``torque``,
    ``degrees``, ``guess``, ``overrides``, ``raise_on_singular``, ``path``, ``chunk``,
    ``workers``, ``progress`` (see :func:`screwkit.engine.analyze`).

    Examples
    --------
    >>> import screwkit
    >>> res = screwkit.analyze("2SPS+2SPR")
    >>> res.mobility.dof
    4
    """
    global _ANALYZE_PM
    if _ANALYZE_PM is None:             # the engine imported on the first analysis, once
        from .engine import analyze_pm
        _ANALYZE_PM = analyze_pm
    return _ANALYZE_PM(pm, pose, **kwargs)


_ANALYZE_PM: Any = None


# ---------------------------------------------------------------------------
# maps, sizing, forward kinematics
# ---------------------------------------------------------------------------

def map(pm: PMLike, grid: Mapping[str, Any], fix: Mapping[str, float] | None = None,  # noqa: A001
        **kwargs: Any) -> xarray.Dataset:                # (screwkit.map, like xarray's map)
    """A PM over a grid of independent pose parameters: an :class:`xarray.Dataset` with
    reachability, conditioning, the sign of ``det J``, singularity kind and level, every row's
    force, ``T_r``, extensions, actuated joint values, limits and the refined singular loci
    (see :func:`screwkit.maps.map_pm` for the keywords: ``samples``, ``degrees``, ``force``,
    ``torque``, ``workers`` (threads), ``cluster`` / ``scheduler`` (Dask), ``progress``).

    Examples
    --------
    >>> import screwkit
    >>> ds = screwkit.map("3RRPRR", {"alpha": (-5, 5, 3)}, fix={"beta": 0, "Zo": 80},
    ...                   degrees=True)
    >>> ds["F_a1"].shape, bool(ds["ok"].all())
    ((3,), True)
    """
    from .engine._inputs import forwarded
    from .maps import map_pm

    return forwarded("screwkit.map", map_pm, pm, grid, fix, **kwargs)


def size(pm: PMLike, grid: Mapping[str, Any], fix: Mapping[str, float] | None = None,
         **kwargs: Any) -> Sizing:
    """The largest force of every actuator and constraint row (and ``T_r``) over a map and a
    list of workloads, with the pose where it occurs: :func:`screwkit.maps.size`."""
    from .engine._inputs import forwarded
    from .maps import size as _size

    return forwarded("screwkit.size", _size, pm, grid, fix, **kwargs)


def optimize(pm: PMLike, vary: Mapping[str, Any], grid: Mapping[str, Any],
             fix: Mapping[str, float] | None = None, **kwargs: Any) -> OptimizationResult:
    """Dimensional synthesis: the dimensions ``vary`` (``{"l": (30, 120)}``, model lengths) of
    a PM that are best over a task (the cells and workloads of :func:`size`), the whole task
    usable: :func:`screwkit.design.optimize` (objectives, constraints, search options)."""
    from .design import optimize as _optimize
    from .engine._inputs import forwarded

    return forwarded("screwkit.optimize", _optimize, pm, vary, grid, fix, **kwargs)


def forward(pm: PMLike, actuators: ArrayLike | Mapping[str, float],
            guess: PoseSolution | Mapping[str, float] | None = None, *, degrees: bool = False,
            overrides: Mapping[str, float] | None = None) -> ForwardResult:
    """Forward kinematics: the platform pose(s) where the actuated joints take ``actuators``
    (displacements from home, an array ``(n,)`` / ``(N, n)`` or a mapping ``q1..`` /
    ``r1..`` of leg extensions), by Newton on the loop closures from home (or ``guess``) with
    continuation: :func:`screwkit.engine.forward_kinematics`.

    Examples
    --------
    >>> import screwkit
    >>> pm = screwkit.load_pm("3RRPRR")
    >>> sol = screwkit.solve(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
    >>> fk = screwkit.forward(pm, sol.actuator_values)
    >>> p = fk.pose(0, degrees=True)
    >>> bool(fk.success[0]), round(p["alpha"], 9), round(p["Zo"], 9)
    (True, 5.0, 80.0)
    """
    from .engine import forward_kinematics

    return forward_kinematics(_model(pm, overrides), actuators, guess, degrees=degrees)


def assembly_modes(pm: PMLike, actuators: ArrayLike | Mapping[str, float], *, seeds: int = 1000,
                   seed: int = 0, degrees: bool = False, overrides: Mapping[str, float]
                   | None = None, progress: Callable | None = None) -> AssemblyModes:
    """The distinct real forward-kinematics solutions from ``seeds`` starts, each with its
    ``det J`` sign (``progress(done, total)``): :func:`screwkit.engine.assembly_modes`."""
    from .engine import assembly_modes as _modes
    return _modes(_model(pm, overrides), actuators, seeds=seeds, seed=seed, degrees=degrees,
                  progress=progress)


def to_pinocchio(pm: PMLike, overrides: Mapping[str, float] | None = None, *,
                 point_contacts: bool = False) -> Any:
    """The Pinocchio model of a PM and its loop-closure constraint models.

    Every leg is a branch of one ``pinocchio.Model`` (native joints, values 0 at the home
    pose); leg 1 carries the platform and each other leg is tied to it by a
    ``pinocchio.RigidConstraintModel`` (see
    :func:`screwkit.interop.build_closed_loop_model`).  Needs Pinocchio (``pin``).

    Returns
    -------
    screwkit.interop.ClosedLoopModel
        ``.model`` (``pinocchio.Model``), ``.constraints`` (tuple of
        ``pinocchio.RigidConstraintModel``), ``.q(joint_values)`` (the Pinocchio
        configuration of screwkit's per-leg joint values).

    Examples
    --------
    >>> import screwkit
    >>> pin_model = screwkit.to_pinocchio("3RRPRR")
    >>> pin_model.model.nq, len(pin_model.constraints)
    (15, 2)
    """
    from .interop import to_pinocchio as _to_pinocchio

    return _to_pinocchio(_model(pm, overrides), point_contacts=point_contacts)
