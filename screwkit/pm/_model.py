"""The model of a parallel manipulator: geometry, home legs and pose parametrisation.

:class:`PMModel` is a constant description of an assembled PM (built by
:func:`screwkit.pm.load_pm`); the solvers of :mod:`screwkit.engine` take it as
input and never change it.  The platform pose is given by the six parameters
:data:`PARAMS` (lengths :data:`LENGTH_PARAMS`, angles in radians), of which a PM
has ``dof`` independent ones.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..legs import Placement, build_leg
from ..screws import Normalisation, rotation_matrix
from ._limits import NO_LIMITS, Limits
from ._units import UNDECLARED, Units

__all__ = ["PMModel", "PARAMS", "LENGTH_PARAMS"]

#: The six pose parameters of the platform, in this order.
PARAMS = ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")
LENGTH_PARAMS = frozenset(("Xo", "Yo", "Zo"))


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
        The ``pms:`` entry the model was built from (:meth:`with_dimensions` evaluates it
        again with other dimensions); None for a model built otherwise.
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
    definition: object = dataclasses.field(default=None, repr=False)

    def __repr__(self) -> str:
        return (f"PMModel({self.name!r}, legs={'+'.join(self.legs)}, dof={self.stated_dof}, "
                f"independent={self.independent}, order={self.order!r})")

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
        R = np.asarray(rotation, float)
        p = np.asarray(translation, float).reshape(3)
        R0, p0 = self.frame
        frame = (R @ R0, R @ p0 + p)
        legs = tuple(lg.moved(R, p) for lg in self.home_legs)
        norm = Normalisation(R @ self.normalisation.centre + p, self.normalisation.length)
        load = None if self.workload is None else self.workload.moved(R)
        return dataclasses.replace(self, home_legs=legs, frame=frame, normalisation=norm,
                                   workload=load)
