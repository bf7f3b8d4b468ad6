"""Row points and placed legs of a pose or a sub-batch of a Jacobian result (private)."""

from __future__ import annotations

from typing import Callable

import numpy as np


def _rows_of_pose(points: Callable[[slice], np.ndarray], pose: slice, rows: slice) -> np.ndarray:
    """``points(pose)[rows]``: the lazily formed row points of one pose of a batch."""
    return points(pose)[rows]


def _rows_of_subset(points: Callable, idx: np.ndarray, poses) -> np.ndarray:
    """The row points of the poses ``poses`` of a sub-batch ``idx`` of a batch."""
    return points(idx[poses])


def _legs_of_subset(legs: Callable[[int], tuple], idx: np.ndarray, pose: int) -> tuple:
    """The placed legs of pose ``pose`` of a sub-batch ``idx`` of a batch."""
    return legs(int(idx[pose]))


def _legs_of_pose(legs: Callable[[int], tuple], pose: int, _index: int) -> tuple:
    """``legs(pose)``: the placed legs of pose ``pose`` of a batch, for its one-pose result."""
    return legs(pose)
