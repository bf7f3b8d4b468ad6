"""Screw-theory layer: lines, twists, wrenches, reciprocal screw systems, Euler angles.

The lowest layer above :mod:`screwkit.errors`; it knows nothing about legs or
parallel manipulators.

* primitives (:class:`Line`, :class:`Twist`, :class:`Wrench` and the batched
  helpers on ``(..., 6)`` arrays);
* reciprocal screw systems (:func:`reciprocal_system`, :class:`Normalisation`,
  span tests) and the dual, the classified freedoms of a wrench system
  (:func:`freedoms`);
* numerical tolerances (:data:`RANK_RTOL`, :data:`GEOMETRY_RTOL`);
* Euler-angle parametrisations (:func:`rotation_matrix`, :func:`angular_jacobian`).
"""

from ._tolerance import GEOMETRY_RTOL, RANK_RTOL, characteristic_length
from ._vector import cross
from ._primitives import (as_rotation, as_vector3, reciprocal_product, screw_axis_point,
                          screw_pitch, transform_twists, transform_wrenches, unit)
from ._line import Line
from ._screw import (Twist, Wrench, couple_wrench, force_wrench, helical_twist, prismatic_twist,
                     revolute_twist)
from ._reciprocal import (Normalisation, ReciprocalSystem, compare_spans, independent_subset,
                          reciprocal_system, same_span, span_contains, twist_rank)
from ._freedoms import MAX_WRENCHES, Freedom, FreedomResult, classify_freedoms, freedoms
from ._euler import (ORDERS, EulerAngles, angular_jacobian, axis_rotation, check_order,
                     euler_angles, euler_matrices, is_singular, rotation_matrix)

__all__ = [
    "cross",
    # primitives
    "Line", "Twist", "Wrench", "as_rotation", "as_vector3", "unit", "revolute_twist",
    "prismatic_twist", "helical_twist", "force_wrench", "couple_wrench", "reciprocal_product",
    "transform_twists", "transform_wrenches", "screw_pitch", "screw_axis_point",
    # reciprocal screw systems
    "Normalisation", "ReciprocalSystem", "reciprocal_system", "independent_subset", "same_span",
    "span_contains", "compare_spans", "twist_rank",
    # freedoms (twists reciprocal to constraint wrenches)
    "Freedom", "FreedomResult", "freedoms", "classify_freedoms", "MAX_WRENCHES",
    # tolerances
    "RANK_RTOL", "GEOMETRY_RTOL", "characteristic_length",
    # Euler angles
    "ORDERS", "EulerAngles", "check_order", "rotation_matrix", "euler_angles", "is_singular",
    "angular_jacobian", "axis_rotation", "euler_matrices",
]
