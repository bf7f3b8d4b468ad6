"""PM layer: the leg catalog, parallel-manipulator models and their mobility.

* the catalog of leg types and PM definitions (:func:`default_catalog`,
  :func:`load_catalog`, :class:`LegSpec`, :class:`Catalog`);
* the model of a PM (:func:`load_pm` -> :class:`PMModel`): geometry, home legs
  and pose parametrisation (:data:`PARAMS`), a constant description that the
  solvers of :mod:`screwkit.engine` take as input (this layer never imports the
  engine; :func:`screwkit.load_pm` also checks that the default pose assembles);
* the units a model declares (:class:`Units`);
* the mobility of an assembled PM (:func:`mobility`) and the classification of its finite
  motion from sampled poses (:func:`classify_finite_motion`);
* the safe expressions of the dimensions and paths (:func:`parse_expression`).
"""

from ._expressions import (CONSTANTS, FUNCTIONS, MAX_LENGTH, Expression, evaluate,
                           parse_expression)
from ._catalog import (Catalog, LegSpec, catalog_path, default_catalog, leg_spec_from_mapping,
                       load_catalog)
from ._units import FORCE_UNITS, LENGTH_UNITS, UNDECLARED, Units, units_from_mapping
from ._model import LENGTH_PARAMS, PARAMS, PMModel
from ._limits import NO_LIMITS, Limits
from ._inertia import (NO_BODY, BarPair, Body, DynamicsParameters, LegDynamics, LegStiffness,
                       check_inertia, cylinder_body)
from ._physical import STANDARD_GRAVITY, dynamics_for, dynamics_from_mapping
from ._workload import Workload, workload_from_mapping
from ._loader import load_pm, pm_names
from ._variants import Definition, definition_yaml, with_dimensions
from ._builder import PMBuilder, leg_type_of
from ._extend import catalog_with_legs
from ._schema import model_schema, schema_path, schema_text
from ._model_check import Problem, check_model_file
from ._finite import (FINITE_RTOL, FiniteMotion, classify_finite_motion, register_finite_motion,
                      registered_finite_motion, rotation_vectors, set_finite_motion_solver)
from ._mobility import (Mobility, declared_motion, describe_twist_space, linkage_graph, mobility,
                        mobility_of_legs, motion_type)
from ..legs import structure_vector    # re-exported: it was screwkit.pm.structure_vector

__all__ = [
    # catalog
    "LegSpec", "Catalog", "load_catalog", "default_catalog", "catalog_path",
    "leg_spec_from_mapping",
    # models
    "PMModel", "PARAMS", "LENGTH_PARAMS", "load_pm", "pm_names", "structure_vector",
    "Definition", "with_dimensions", "definition_yaml", "PMBuilder", "leg_type_of",
    "catalog_with_legs",
    # the model-file schema and checks
    "model_schema", "schema_text", "schema_path", "check_model_file", "Problem",
    # limits
    "Limits", "NO_LIMITS",
    # masses, inertias, friction, stiffness (the dynamics: block)
    "Body", "BarPair", "NO_BODY", "LegDynamics", "LegStiffness", "DynamicsParameters", "cylinder_body",
    "check_inertia", "dynamics_from_mapping", "dynamics_for", "STANDARD_GRAVITY",
    # workloads
    "Workload", "workload_from_mapping",
    # units
    "Units", "UNDECLARED", "LENGTH_UNITS", "FORCE_UNITS", "units_from_mapping",
    # mobility
    "Mobility", "mobility", "mobility_of_legs", "motion_type", "declared_motion", "linkage_graph",
    "describe_twist_space",
    # the finite motion type (computed by screwkit.engine.finite_motion, classified here)
    "FiniteMotion", "classify_finite_motion", "rotation_vectors", "FINITE_RTOL",
    "register_finite_motion", "registered_finite_motion", "set_finite_motion_solver",
    # expressions
    "Expression", "parse_expression", "evaluate", "FUNCTIONS", "CONSTANTS", "MAX_LENGTH",
]
