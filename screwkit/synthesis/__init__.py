"""Synthesis layer: type synthesis of legs by the observation rules, and its validation.

* :func:`synthesize` places the joints of a leg string in the hand-derived
  target layouts (:data:`LAYOUTS`, :func:`make_layout`) and proves the
  impossible ones (:func:`counting_rank`, :func:`rule_reason`);
* :func:`validate_string`, :func:`validate_catalog` and :func:`validate_table1`
  verify every synthesized leg with the reciprocal-screw solver (:func:`verify`)
  and reproduce the paper's Table I (read from the catalog, :mod:`screwkit.pm`);
* :func:`motion_pattern`, :func:`build_pool` (the catalog's leg types and those
  :func:`generated_legs` enumerates for the pattern), :func:`compositions_for` and
  :func:`pm_definition` form the candidate PMs of a motion pattern (the type synthesis
  of PMs; :mod:`screwkit.design` verifies them with the engine).
"""

from ._linalg import NULL_RTOL, cross, null_basis, perpendicular_unit, random_unit, unit
from ._layouts import LAYOUTS, Layout, Locus, compositions, layouts_for, make_layout
from ._joints import (Letter, admissible_directions, choice_words, joint_twist, letters_of,
                      options_for, place_letter)
from ._proofs import counting_rank, counting_reason, rank_bound, rule_reason
from ._synthesis import JointChoice, Synthesis, synthesize, synthesize_composition
from ._verify import Verification, verify
from ._reports import (CatalogCheck, DrawResult, LegValidation, TargetResult, ValidationReport,
                       catalog_rows, chain_text, composition_label, report_rows)
from ._validation import DEFAULT_DRAWS, validate_catalog, validate_string, validate_table1
from ._motions import MOTIONS, MotionPattern, motion_pattern
from ._leg_types import GeneratedLeg, SYNTHESIS_PLACEMENT, generated_legs, pattern_twists
from ._pool import (EXTRA_LEGS_YAML, LegKind, LegPool, build_pool, extra_legs, leg_pool,
                    synthesis_catalog)
from ._candidates import (CENTRAL_GEOMETRIES, GEOMETRIES, PAIR_GEOMETRIES, PASSIVE_GEOMETRIES,
                          Candidate, catalog_compositions, central_compositions,
                          compositions_for, geometries_for, literature_name, model_yaml,
                          pair_compositions, passive_compositions, pm_definition)

__all__ = [
    # synthesis
    "Locus", "Layout", "JointChoice", "Synthesis", "LAYOUTS", "NULL_RTOL", "compositions",
    "counting_rank", "layouts_for", "make_layout", "synthesize", "synthesize_composition",
    # joints in a layout
    "Letter", "admissible_directions", "place_letter", "joint_twist", "letters_of", "options_for",
    "choice_words",
    # proofs
    "rule_reason", "rank_bound", "counting_reason",
    # 3-vector helpers, null spaces
    "cross", "unit", "random_unit", "perpendicular_unit", "null_basis",
    # validation
    "Verification", "verify", "DrawResult", "TargetResult", "LegValidation", "CatalogCheck",
    "ValidationReport", "validate_string", "validate_catalog", "validate_table1",
    "composition_label", "chain_text", "report_rows", "catalog_rows", "DEFAULT_DRAWS",
    # motion patterns and candidate PMs (verified by screwkit.design)
    "MOTIONS", "MotionPattern", "motion_pattern", "EXTRA_LEGS_YAML", "GEOMETRIES", "Candidate",
    "PASSIVE_GEOMETRIES", "LegKind", "compositions_for", "extra_legs", "geometries_for",
    "leg_pool", "model_yaml", "passive_compositions", "pm_definition", "synthesis_catalog",
    "literature_name", "LegPool", "build_pool", "catalog_compositions", "central_compositions",
    "CENTRAL_GEOMETRIES", "PAIR_GEOMETRIES", "pair_compositions",
    # legs generated for a motion pattern
    "GeneratedLeg", "SYNTHESIS_PLACEMENT", "generated_legs", "pattern_twists",
]
