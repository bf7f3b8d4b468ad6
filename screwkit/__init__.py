"""screwkit: screw-theory statics of limited-DOF parallel manipulators.

Conventions: twists ``[v; w]`` about the base origin, wrenches ``[f; m]`` with
moments about the base origin, reciprocal product ``f.v + m.w`` (see
``docs/conventions.md``).
"""

from .errors import (CatalogError, GeometryError, InputError, MisuseError, ParseError,
                     ScrewkitError, SingularityError, UnreachablePoseError)
from .screws import FreedomResult, Line, Twist, Wrench, freedoms
from .legs import Joint, Leg, Placement, leg_from_joints, parse_leg, parse_pm
from .api import analyze, define_leg, extend_catalog, leg, load_legs, load_pm, solve, solve_path
from .api import assembly_modes, forward, map, optimize, size  # noqa: A004 (screwkit.map)
from .api import to_pinocchio
from .pm import PMBuilder

__version__ = "0.1.0"

#: Names of the engine, imported on first use (``import screwkit`` stays light).
_ENGINE = ("PMAnalysis", "PoseSolution", "JacobianResult", "JacobianRow", "StaticsResult",
           "unified_jacobian", "statics", "solve_statics", "PAPER_FORCE", "PAPER_TORQUE")

__all__ = [
    # errors
    "ScrewkitError", "ParseError", "CatalogError", "GeometryError", "InputError",
    "SingularityError", "UnreachablePoseError", "MisuseError",
    # screws and legs
    "Line", "Twist", "Wrench", "freedoms", "FreedomResult", "parse_leg", "parse_pm", "Joint", "Leg", "Placement",
    "leg_from_joints", "leg", "define_leg", "load_legs", "extend_catalog",
    # PMs and the engine
    "load_pm", "PMBuilder", "solve", "solve_path", "analyze", *_ENGINE, "dynamics",
    # maps, sizing, forward kinematics
    "map", "size", "optimize", "forward", "assembly_modes",
    # interoperability and the 3D view
    "to_pinocchio", "view",
    "__version__",
]


def __getattr__(name):
    if name == "dynamics":              # the dynamics layer; callable: screwkit.dynamics(pm, ...)
        import importlib
        return importlib.import_module(".dynamics", __name__)
    if name == "view":                  # the interactive 3D view (screwkit.paths.view)
        from .paths import view
        return view
    if name in _ENGINE:
        from . import engine
        return getattr(engine, name)
    raise AttributeError(f"module 'screwkit' has no attribute {name!r}")
