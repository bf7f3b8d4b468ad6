"""The model of a parallel manipulator: geometry, home legs and pose parametrisation.

:class:`PMModel` is a constant description of an assembled PM (built by
:func:`screwkit.pm.load_pm`); the solvers of :mod:`screwkit.engine` take it as
input and never change it.  The platform pose is given by the six parameters
:data:`PARAMS` (lengths :data:`LENGTH_PARAMS`, angles in radians), of which a PM
has ``dof`` independent ones.
"""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..screws._frozen import read_only
from ..legs import Placement, build_leg
from ..legs._guards import MAX_MAGNITUDE
from ..screws import Normalisation, as_rotation, as_vector3, rotation_matrix
from ._limits import NO_LIMITS, Limits
from ._units import UNDECLARED, Units
from ..errors import MisuseError

__all__ = ["PMModel", "PARAMS", "LENGTH_PARAMS"]

#: The six pose parameters of the platform, in this order.
PARAMS = ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")
LENGTH_PARAMS = frozenset(("Xo", "Yo", "Zo"))


class ConstantDict(dict):
    """A ``dict`` that cannot be changed (a model's poses and dimensions): reading, copying
    (``dict(d)``, ``d.copy()``), JSON and pickling work as for a dict."""

    def _constant(self, *args, **kwargs):
        raise MisuseError("a model's poses and dimensions are constants: copy them (dict(...)) "
                        "to change them, and give the copy (load_pm overrides, "
                        "PMModel.with_dimensions)")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = _constant
    __ior__ = _constant

    def copy(self) -> dict:
        return dict(self)

    def __reduce__(self):
        return (ConstantDict, (dict(self),))


@dataclass(frozen=True, eq=False)
class PMModel:
    """An assembled PM: geometry, home legs, pose parametrisation.

    A constant description of the mechanism (it holds no solver state):
    the inverse displacement at a pose is :func:`screwkit.solve` /
    :func:`screwkit.engine.solve_pose`, the analysis :func:`screwkit.analyze`.

    Attributes
    ----------
    name : str
    legs : tuple of str
        Catalog leg name at each vertex.
    leg_rules : tuple of LegRules
        The rules of each leg (with the PM's per-vertex axis overrides).
    home_legs : tuple of Leg
        Legs built by their rules at the home pose (joint values 0).
    home_pose : dict
        Full pose at home (radians).
    independent, dependent : tuple of str
    order : str
        Euler order (scipy convention; ``"XYX"`` is intrinsic).
    dimensions : dict
    base_points : ndarray (n, 3)
        ``A_i`` in the base frame.
    platform_points : ndarray (n, 3)
        ``a_i`` in the platform frame.
    centre : ndarray (3,)
        The base-fixed point ``C`` of the leg rules (base frame).
    stated_dof : int
    motion : str
        The motion type the definition states (``"1T2R"``), or "".
    default_pose : dict
        The default values of the *independent* pose parameters only (the
        definition's ``pose:``; angles in radians, lengths in model units).
        The solvers take missing independent parameters from it; the full pose
        there is ``screwkit.solve(pm, pm.default_pose).params``.
    frame : tuple (R0 (3, 3), p0 (3,))
        World <- base frame (identity unless :meth:`moved`).
    notes : tuple of str
    units : Units
        The length and force units the definition declares (``units:``; the catalog's
        are cm and kN); torques are force x length.
    constraint_references : tuple of tuple
        Per leg, the reference directions its catalog entry declares for the basis and
        signs of its constraint wrenches (``constraint_basis``; empty: the default rule of
        :mod:`screwkit.engine._rows`).
    limits : Limits
        The joint, stroke and leg-distance limits the definition declares (``limits:``,
        :mod:`screwkit.pm._limits`); maps mark the poses outside them.
    dynamics : DynamicsParameters or None
        Masses, inertias, friction, gravity and stiffness (the definition's ``dynamics:``,
        :mod:`screwkit.pm._physical`), used by :mod:`screwkit.dynamics`; None if not given.
    passive : tuple of int
        0-based indices of the passive legs: legs without an actuator, which add their
        constraint rows to ``J`` and no actuation row (the Tricept's central UP column).
        Empty when every leg is actuated.
    workload : Workload or None
        The default workload at ``o`` the definition declares (``workload:``, in the
        model's units and world axes, :mod:`screwkit.pm._workload`), or None: then the
        statics need one given.
    definition : Definition or None
        How the model was defined: the ``pms:`` entry as read with its catalog and overrides
        (:meth:`with_dimensions` evaluates it again with other dimensions), and the same entry
        self-contained (``Definition.mapping``: leg types not of the packaged catalog written
        inline, dimension overrides applied; :meth:`to_mapping`, :meth:`to_yaml`). None for a
        model built otherwise.
    """

    name: str
    string: str
    legs: tuple
    leg_rules: tuple
    home_legs: tuple
    home_pose: dict
    independent: tuple
    dependent: tuple
    order: str
    dimensions: dict
    base_points: np.ndarray
    platform_points: np.ndarray
    centre: np.ndarray
    stated_dof: int
    motion: str
    default_pose: dict
    frame: tuple
    normalisation: Normalisation
    summary: str = ""
    note: str = ""
    notes: tuple = ()
    source: str = ""
    constraint_references: tuple = ()
    units: Units = UNDECLARED
    limits: Limits = NO_LIMITS
    dynamics: object = None
    passive: tuple = ()
    workload: object = None
    definition: object = field(default=None, repr=False)

    def __post_init__(self) -> None:
        # a constant description: its mappings read-only (a written default pose moved every
        # later analysis while the definition said otherwise).  (Its arrays stay as they are:
        # the kernels' model arrays are typed writable, a read-only one compiles them again.)
        for name in ("home_pose", "dimensions", "default_pose"):
            value = getattr(self, name)
            if isinstance(value, dict) and not isinstance(value, ConstantDict):
                object.__setattr__(self, name, ConstantDict(value))
        # its arrays read-only views (the flattening copies them for the kernels)
        for name in ("base_points", "platform_points", "centre"):
            object.__setattr__(self, name, read_only(getattr(self, name)))
        object.__setattr__(self, "frame", tuple(read_only(x) for x in self.frame))

    def __repr__(self) -> str:
        return (f"PMModel({self.name!r}, legs={'+'.join(self.legs)}, dof={self.stated_dof}, "
                f"independent={self.independent}, order={self.order!r})")

    # -- the definition -----------------------------------------------------
    def to_mapping(self) -> dict:
        """The model's definition, as a model file holds it under ``pms:`` (a new copy):
        ``screwkit.load_pm(pm.to_mapping(), name=pm.name)`` builds the same model
        (:meth:`same_as`)."""
        if self.definition is None:
            from ..errors import InputError
            raise InputError(f"{self.name}: this model keeps no definition to write")
        return copy.deepcopy(self.definition.mapping)

    def to_yaml(self, path=None) -> str | None:
        """The model as a model file (``pms: {NAME: definition}``): the text, or written to
        ``path`` (then None).  Reading the file gives the same model (:meth:`same_as`)."""
        import yaml
        text = yaml.safe_dump({"pms": {self.name: self.to_mapping()}}, sort_keys=False,
                              default_flow_style=None, allow_unicode=True, width=100)
        if path is None:
            return text
        from pathlib import Path
        try:
            Path(path).write_text(text, encoding="utf-8")
        except OSError as exc:
            from ..errors import InputError
            raise InputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
        return None

    def same_as(self, other) -> bool:
        """True when ``other`` is the same model, number for number: the same name,
        definition, pose parametrisation, units, passive legs and, bit for bit, the same
        vertices, home pose and home legs (every joint's axis and point)."""
        if not isinstance(other, PMModel):
            return False
        a, b = self, other
        same = (a.name == b.name and a.string == b.string and a.legs == b.legs
                and _mapping(a) == _mapping(b) and a.independent == b.independent
                and a.order == b.order and a.stated_dof == b.stated_dof
                and a.units == b.units and a.passive == b.passive and a.motion == b.motion
                and a.home_pose == b.home_pose and a.default_pose == b.default_pose
                and a.dimensions == b.dimensions and len(a.home_legs) == len(b.home_legs))
        arrays = [(a.base_points, b.base_points), (a.platform_points, b.platform_points),
                  (a.centre, b.centre)]
        for la, lb in zip(a.home_legs, b.home_legs):
            same = same and la.string.marked == lb.string.marked
            arrays += [(la.A, lb.A), (la.a, lb.a)]
            arrays += [(x, y) for ja, jb in zip(la.joints, lb.joints)
                       for x, y in ((ja.direction, jb.direction), (ja.point, jb.point))]
        return bool(same and all(np.array_equal(x, y) for x, y in arrays))

    # -- geometry ---------------------------------------------------------
    def pose_matrix(self, pose: dict):
        """World <- platform rotation (3, 3) and the platform centre ``o`` (3,)."""
        R0, p0 = self.frame
        R = rotation_matrix(self.order, pose["alpha"], pose["beta"], pose["gamma"])
        return R0 @ R, R0 @ np.array([pose["Xo"], pose["Yo"], pose["Zo"]], float) + p0

    @property
    def platform_home(self):
        """``T_end_home`` of every leg: the platform pose at home, (R (3, 3), p (3,))."""
        return self.pose_matrix(self.home_pose)

    @property
    def world_base_points(self) -> np.ndarray:
        R0, p0 = self.frame
        return (R0 @ self.base_points.T).T + p0

    @property
    def n_legs(self) -> int:
        return len(self.legs)

    @property
    def active(self) -> tuple:
        """0-based indices of the actuated legs (every leg but the :attr:`passive` ones), in
        leg order: the order of the actuation rows of ``J`` and of the actuator values."""
        return tuple(i for i in range(len(self.legs)) if i not in self.passive)

    def placement(self, i: int, pose: dict) -> Placement:
        """The :class:`Placement` of leg ``i`` (0-based) at ``pose`` (radians)."""
        R0, p0 = self.frame
        R, o = self.pose_matrix(pose)
        return Placement(self.world_base_points[i], R @ self.platform_points[i] + o, p0, o, R0, R,
                         R0 @ self.centre + p0)

    def rebuild_legs(self, pose: dict, check_structure: bool = False) -> tuple:
        """Every leg built afresh by its catalog rules at ``pose`` (for checks)."""
        return tuple(build_leg(r, self.placement(i, pose), check_structure)
                     for i, r in enumerate(self.leg_rules))

    def with_dimensions(self, values: dict) -> "PMModel":
        """The same PM with the dimensions ``values`` (``{"l": 80}``, model units), the others
        as they are: its definition evaluated again, no file read or parsed
        (:func:`screwkit.pm.with_dimensions`); equal to ``load_pm(name, {...})``."""
        if self.definition is None:
            from ..errors import InputError
            raise InputError(f"model {self.name}: no definition to rebuild it from (load it "
                             "with screwkit.load_pm)")
        return self.definition.rebuild(self, values)

    def moved(self, rotation, translation) -> "PMModel":
        """The same PM with its base frame placed at ``x -> R x + p`` in the world.

        Pose parameters stay relative to the base frame; every world quantity
        (legs, ``o``) moves with it.
        """
        R = as_rotation(rotation)
        p = as_vector3(translation, "translation", MAX_MAGNITUDE)
        R0, p0 = self.frame
        frame = (R @ R0, R @ p0 + p)
        legs = tuple(lg.moved(R, p) for lg in self.home_legs)
        norm = Normalisation(R @ self.normalisation.centre + p, self.normalisation.length)
        load = None if self.workload is None else self.workload.moved(R)
        return dataclasses.replace(self, home_legs=legs, frame=frame, normalisation=norm,
                                   workload=load)


def _mapping(model):
    """The self-contained definition of ``model`` (None if it keeps none)."""
    return None if model.definition is None else model.definition.mapping

