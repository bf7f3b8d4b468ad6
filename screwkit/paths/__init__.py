"""Paths layer: path input (CSV, expressions in ``t``) and the statics of a PM along a path.

* :class:`PathSpec` and its readers (:func:`path_from_expressions`,
  :func:`path_from_csv`, the CLI's :func:`add_path_arguments` /
  :func:`path_from_args`);
* :func:`run_trajectory` -> :class:`TrajectoryResult`: pose, extensions, active
  and constraint forces, condition number at every sample (with
  :meth:`TrajectoryResult.plot` drawing the panels of the paper's Fig. 5 with
  :mod:`screwkit.viz`);
* :func:`view`: the interactive 3D view of a PM over a grid of poses (a slider per
  independent parameter) or along a path (a time slider), drawn by :mod:`screwkit.scene`.
"""

from ._pathspec import (ANGLE_PARAMETERS, POSE_PARAMETERS, PathSpec, add_path_arguments,
                        parse_assignment, path_from_args, path_from_csv, path_from_expressions)
from ._trajectory import STATUSES, TrajectoryResult, run_trajectory
from ._plotting import plot_trajectory
from ._view import view

__all__ = [
    "PathSpec", "POSE_PARAMETERS", "ANGLE_PARAMETERS", "path_from_csv", "path_from_expressions",
    "parse_assignment", "add_path_arguments", "path_from_args",
    "TrajectoryResult", "run_trajectory", "STATUSES", "plot_trajectory", "view",
]
