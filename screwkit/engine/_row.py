"""What one row of the unified Jacobian is, at one pose: :class:`JacobianRow` (private)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..screws._frozen import freeze_fields
from ..legs import point_label

__all__ = ["JacobianRow"]


@dataclass(frozen=True)
class JacobianRow:
    """What one row of the unified Jacobian is, at one pose.

    Attributes
    ----------
    leg : int
        Index of the leg (0-based).
    leg_name : str
    kind : str
        ``"actuation"``, ``"force"``, ``"couple"`` or ``"screw"``.
    member : str
        Geometric kind of the row's wrench (``"none"`` for the zero row of a
        dependent actuator).
    direction : ndarray (3,)
        Unit direction of the force or couple.
    point : ndarray (3,) or None
        A point of the force line (the named point where there is one); None for a couple.
    point_name : str or None
    pitch : float
        0 for a force, ``inf`` for a couple.
    scale : float
        Row = scale x unit member (1 for constraint rows).
    joint : str or None
        The actuated joint of an actuation row.
    label : str
        ``F_a1``, ``F_c2``, ``T_c3``...
    """

    leg: int
    leg_name: str
    kind: str
    member: str
    direction: np.ndarray
    point: np.ndarray | None
    point_name: str | None
    pitch: float
    scale: float
    joint: str | None
    label: str = ""

    def __post_init__(self):
        freeze_fields(self, ("direction", "point"))

    @property
    def torque(self) -> bool:
        """The row's value is a torque (a couple, a rotary actuator's effort: its ``T``)."""
        return self.label.startswith("T")

    def describe(self) -> str:
        """One line, e.g. ``leg 0 (RRPRR) force along (...) through Q (where R1 meets R5)``."""
        d = "(" + ", ".join(f"{x:.6g}" for x in np.where(np.abs(self.direction) < 5e-13, 0.0,
                                                          self.direction)) + ")"
        if self.member == "couple":
            what = f"couple about {d}"
        elif self.member == "none":
            what = "zero row (the actuated joint is dependent on the passive ones)"
        elif self.member == "screw":
            where = "(" + ", ".join(f"{x:.6g}" for x in self.point) + ")" \
                if self.point is not None else "?"
            what = f"screw of pitch {self.pitch:.6g} along {d} through {where}"
        else:
            where = point_label(self.point_name) or (
                "(" + ", ".join(f"{x:.6g}" for x in self.point) + ")" if self.point is not None
                else "?")
            what = f"{self.member} along {d} through {where}"
        head = f"leg {self.leg} ({self.leg_name}) "
        return head + (f"actuation of {self.joint}: {what}" if self.kind == "actuation" else what)


