"""Leg layer: leg strings, placed equivalent chains, catalog rules, and the analysis of a leg.

* parsing of leg and PM strings (:func:`parse_leg`, :func:`parse_pm`);
* the placed equivalent chain of a leg (:class:`Joint`, :class:`Leg`, built from
  explicit joints by :func:`leg_from_joints`) and its
  end points and frames (:class:`Placement`);
* the placement rules of the catalog (:class:`LegRules`, :func:`build_leg`,
  :func:`generic_leg`) and their structure checks (:func:`structure_residuals`,
  :func:`structure_vector`);
* the three observation rules (:func:`decompose`, :func:`explain_force`, ...)
  and the screw-theoretic analysis of a leg (:func:`analyze_leg`,
  :meth:`Leg.analyze`).
"""

from ._parsing import JOINT_DOF, JOINT_LETTERS, EquivalentJoint, LegString, parse_leg
from ._pm_string import PASSIVE_SUFFIX, PMString, PMTerm, parse_pm
from ._chain import Joint, Leg
from ._explicit import leg_from_joints
from ._placement import Placement, default_placement
from ._rules import JointRule, LegRules, build_leg, generic_leg
from ._structure import structure_residuals, structure_vector
from ._observation import (ConstraintWrench, RuleNote, candidate_points, explain_couple,
                           explain_force, named_points, point_label)
from ._decompose import decompose, reciprocity_residual
from ._analysis import ActuationWrench, LegAnalysis, actuation_wrench, analyze_leg

__all__ = [
    # leg and PM strings
    "JOINT_LETTERS", "JOINT_DOF", "EquivalentJoint", "LegString", "PMTerm", "PMString",
    "parse_leg", "parse_pm", "PASSIVE_SUFFIX",
    # placed chains
    "Joint", "Leg", "leg_from_joints", "Placement", "default_placement",
    # catalog rules
    "JointRule", "LegRules", "build_leg", "generic_leg", "structure_residuals",
    "structure_vector",
    # observation rules and leg analysis
    "RuleNote", "ConstraintWrench", "decompose", "explain_force", "explain_couple",
    "named_points", "candidate_points", "reciprocity_residual", "point_label",
    "LegAnalysis", "ActuationWrench", "analyze_leg", "actuation_wrench",
]
