"""screwkit: screw-theory statics of limited-DOF parallel manipulators.

Conventions: twists ``[v; w]`` about the base origin, wrenches ``[f; m]`` with
moments about the base origin, reciprocal product ``f.v + m.w`` (see
``docs/conventions.md``).
"""

from .errors import (CatalogError, GeometryError, InputError, ParseError, ScrewkitError,
                     SingularityError, UnreachablePoseError)
from .screws import Line, Twist, Wrench
from .legs import parse_leg, parse_pm
from .api import analyze, define_leg, extend_catalog, leg, load_legs, load_pm, solve, solve_path

__version__ = "0.1.0"

__all__ = [
    "ScrewkitError", "ParseError", "CatalogError", "GeometryError", "InputError",
    "SingularityError", "UnreachablePoseError",
    "Line", "Twist", "Wrench", "parse_leg", "parse_pm", "leg", "define_leg", "load_legs",
    "extend_catalog", "load_pm", "solve", "solve_path", "analyze", "__version__",
]
