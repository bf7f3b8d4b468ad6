"""One screwkit leg as a chain of Pinocchio joint blocks: the map between screwkit's joint values
(one per equivalent 1-DOF joint) and Pinocchio's ``q``/``v``, and the S angles of a rotation.

See :mod:`screwkit.interop._pinocchio_model` for the joint correspondence.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, InputError
from ..legs import Leg
from ..screws import cross

__all__ = ["JointBlock", "LegChain", "sphere_angles", "as_pose"]


def as_pose(pose, what: str = "pose"):
    """``(R, p)`` as a checked (3x3 proper rotation, 3-vector) pair of float arrays."""
    try:
        R, p = pose
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a pair (R (3, 3), p (3,))") from None
    R = np.asarray(R, float)
    p = np.asarray(p, float)
    if R.shape != (3, 3) or p.shape != (3,) or not (np.all(np.isfinite(R)) and np.all(np.isfinite(p))):
        raise InputError(f"{what}: expected a finite rotation (3, 3) and position (3,), "
                         f"got shapes {R.shape} and {p.shape}")
    if not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise InputError(f"{what}: the rotation is not a proper rotation matrix")
    return R, p


def _rot(u, t):
    import pinocchio as pin
    return pin.exp3(np.asarray(u, float) * float(t))


@dataclass(frozen=True)
class JointBlock:
    """One Pinocchio joint and the screwkit equivalent joints it stands for.

    Attributes
    ----------
    kind : str
        ``"spherical"``, ``"universal"``, ``"revolute"``, ``"prismatic"``, ``"helical"``, or
        for a parallelogram ``Pa`` its three hinges in the model: ``"bar"`` (the first bar
        about the near link's first hinge), ``"bar_far"`` (the far link about the bar's
        end) and ``"bar_twin"`` (the second bar, a branch of the near link closed on the far
        link by a point contact).
    joint_id : int
        Pinocchio joint index.
    sk : tuple of int
        Indices of the screwkit equivalent joints (3 for S, 2 for U, 1 otherwise).
    idx_q, nq, idx_v, nv : int
        Slices of the Pinocchio configuration and velocity vectors.
    axes : ndarray (k, 3)
        Home axes of the equivalent joints (world = joint frame at home).
    scale : float
        Pinocchio's joint value per unit screwkit value: 1, or for a ``Pa`` (whose screwkit
        value is the arc length ``|b| theta``) ``1 / |b|`` for the two bars and ``-1 / |b|``
        for the far link (which so keeps its orientation).
    origin : ndarray (3,) or None
        The joint frame's home point when it is not the equivalent joint's point (the far
        hinge and the second bar of a ``Pa``).
    """

    kind: str
    joint_id: int
    sk: tuple
    idx_q: int
    nq: int
    idx_v: int
    nv: int
    axes: np.ndarray
    scale: float = 1.0
    origin: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class LegChain:
    """One leg inside a Pinocchio model.

    Attributes
    ----------
    leg : Leg
        Home geometry.
    blocks : tuple of JointBlock
        In chain order.
    end_joint : int
        Pinocchio index of the last joint (the link carrying the platform).
    frame_id : int
        Operational frame at the platform's home pose, on ``end_joint``.
    end_frame_id : int
        Operational frame at the home point of the last joint (the S centre
        for an S-ended leg).
    platform_home : tuple (R (3, 3), p (3,))
    truncated : bool
        The leg's last S is not in the model (a point contact at its centre
        replaces it, see :func:`build_closed_loop_model`): ``frame_id`` and
        ``end_frame_id`` are then a frame at the S centre on the link before the S,
        with the world orientation at home, and the S's joints have no column.
    passive : bool
        A passive leg (no actuator): every joint is passive, :meth:`actuated_columns` is
        empty.
    loops : tuple
        The parallelogram loops inside the leg: ``(joint1, point1, joint2, point2)`` per
        ``Pa``, the end of its second bar and the same point of its far link (translations
        in each joint's frame), tied by a ``CONTACT_3D`` in a closed-loop model.
    """

    leg: Leg
    blocks: tuple
    end_joint: int
    frame_id: int
    end_frame_id: int
    platform_home: tuple
    truncated: bool = False
    passive: bool = False
    loops: tuple = ()

    @property
    def m(self) -> int:
        """Number of screwkit equivalent joints."""
        return len(self.leg.joints)

    @property
    def ends_with_sphere(self) -> bool:
        """The leg's last joint is an S (whether or not the model keeps it)."""
        return self.truncated or self.blocks[-1].kind == "spherical"

    @property
    def sphere_centre(self) -> np.ndarray:
        """Home centre of the leg's last S (ValueError if the leg does not end in S)."""
        if not self.ends_with_sphere:
            raise ValueError(f"leg {self.leg.name} does not end in S")
        return np.asarray(self.leg.joints[-1].point, float)

    def v_columns(self) -> tuple:
        """Pinocchio velocity columns of each screwkit joint: an int (one to one) or, for
        the three joints of an S, the tuple of the S's three columns (spans match);
        None for the joints of a dropped S (``truncated``)."""
        out = [None] * self.m
        for b in self.blocks:
            if b.kind in ("bar_far", "bar_twin"):    # a Pa's value is its first bar's turn
                continue
            cols = tuple(range(b.idx_v, b.idx_v + b.nv))
            for k, i in enumerate(b.sk):
                out[i] = cols if b.kind == "spherical" else cols[k]
        return tuple(out)

    def actuated_columns(self) -> tuple:
        """Pinocchio velocity columns carrying the actuated joint (3 for an actuated S; none
        for a passive leg)."""
        if self.passive:
            return ()
        c = self.v_columns()[self.leg.actuated_index]
        return c if isinstance(c, tuple) else (c,)

    def rates(self, q, v) -> np.ndarray:
        """Screwkit joint rates (m,) of the Pinocchio velocity ``v`` (nv,) at joint values
        ``q`` (the inverse of :meth:`velocity_map` on this chain; 0 on dropped joints)."""
        out = np.zeros(self.m)
        for b in self.blocks:
            vb = np.asarray(v[b.idx_v:b.idx_v + b.nv], float)
            if b.kind in ("bar_far", "bar_twin"):
                continue
            if b.kind == "bar":
                out[b.sk[0]] = vb[0] / b.scale
            elif b.kind == "spherical":
                M = self.velocity_map(q, len(v))[b.idx_v:b.idx_v + 3][:, list(b.sk)]
                out[list(b.sk)] = np.linalg.solve(M, vb)
            else:
                out[list(b.sk)] = vb
        return out

    def fill_q(self, q, out) -> None:
        """Write the Pinocchio configuration of screwkit joint values ``q`` (m,) into ``out``."""
        import pinocchio as pin
        for b in self.blocks:
            vals = q[list(b.sk)]
            if b.kind == "spherical":
                # screwkit: Rot(u1, q1) Rot(u2, q2) Rot(u3, q3) about the centre, home axes
                # expressed in the parent frame (= world orientation at home).
                R = _rot(b.axes[0], vals[0]) @ _rot(b.axes[1], vals[1]) @ _rot(b.axes[2], vals[2])
                out[b.idx_q:b.idx_q + 4] = pin.Quaternion(R).normalized().coeffs()
            else:
                out[b.idx_q:b.idx_q + b.nq] = b.scale * vals

    def read_q(self, qpin, hint=None) -> np.ndarray:
        """Screwkit joint values (m,) of a Pinocchio configuration (S angles nearest ``hint``)."""
        import pinocchio as pin
        q = np.zeros(self.m)
        h = np.zeros(self.m) if hint is None else np.asarray(hint, float)
        for b in self.blocks:
            if b.kind == "spherical":
                quat = pin.Quaternion(np.asarray(qpin[b.idx_q:b.idx_q + 4], float))
                q[list(b.sk)] = sphere_angles(quat.normalized().toRotationMatrix(), b.axes,
                                              h[list(b.sk)])
            elif b.kind == "bar":
                q[b.sk[0]] = qpin[b.idx_q] / b.scale
            elif b.kind in ("bar_far", "bar_twin"):
                continue
            else:
                q[list(b.sk)] = qpin[b.idx_q:b.idx_q + b.nq]
        return q

    def velocity_map(self, q, nv: int) -> np.ndarray:
        """Matrix ``M`` (nv, m) with ``v_pin = M qdot`` at screwkit joint values ``q``.

        ``scale`` on one-DOF blocks (1, or the bars of a ``Pa``: ``+-1 / |b|``), and on an S
        the angular velocity in the joint frame: ``R^T (u1 q1' + R1 u2 q2' + R1 R2 u3 q3')`` with
        ``R = R1 R2 R3``.
        """
        M = np.zeros((nv, self.m))
        for b in self.blocks:
            if b.kind == "spherical":
                i1, i2, i3 = b.sk
                R1, R2, R3 = (_rot(b.axes[k], q[i]) for k, i in enumerate(b.sk))
                R = R1 @ R2 @ R3
                sl = slice(b.idx_v, b.idx_v + 3)
                M[sl, i1] = R.T @ b.axes[0]
                M[sl, i2] = R.T @ (R1 @ b.axes[1])
                M[sl, i3] = R.T @ (R1 @ R2 @ b.axes[2])
            else:
                for k, i in enumerate(b.sk):
                    M[b.idx_v + k, i] = b.scale
        return M


def sphere_angles(R, axes, hint=None) -> np.ndarray:
    """Angles ``(a, b, c)`` with ``R = Rot(u1, a) Rot(u2, b) Rot(u3, c)`` (Davenport angles
    about arbitrary axes, u1 and u3 not parallel to u2).

    Parameters
    ----------
    R : ndarray (3, 3)
    axes : ndarray (3, 3)
        Unit axes ``u1, u2, u3`` as rows.
    hint : ndarray (3,), optional
        Of the two solutions (and of their 2 pi shifts) the one nearest ``hint`` (default 0).

    Returns
    -------
    ndarray (3,)
    """
    u1, u2, u3 = (np.asarray(a, float) for a in axes)
    h = np.zeros(3) if hint is None else np.asarray(hint, float)

    def near(x, ref):
        return x + 2 * np.pi * np.round((ref - x) / (2 * np.pi))

    def angle_about(u, x, y):
        # signed angle about u taking x to y (projections onto the plane normal to u)
        x = x - (x @ u) * u
        y = y - (y @ u) * u
        return float(np.arctan2(u @ cross(x, y), x @ y))

    d23, d12 = u2 @ u3, u1 @ u2
    A = u1 @ u3 - d23 * d12
    B = u1 @ cross(u2, u3)
    rho = float(np.hypot(A, B))
    if rho < 1e-12:
        raise GeometryError("spherical joint axes are degenerate (u2 parallel to u1 or u3)")
    phi = float(np.arctan2(B, A))
    t = float(np.clip((u1 @ R @ u3 - d23 * d12) / rho, -1.0, 1.0))
    best = None
    for b in (phi + np.arccos(t), phi - np.arccos(t)):
        b = near(b, h[1])
        v = _rot(u2, b) @ u3
        x = R @ u3
        if np.linalg.norm(cross(u1, v)) < 1e-9:      # gimbal lock: a and c share an axis
            a = h[0]
        else:
            a = near(angle_about(u1, v, x), h[0])
        M = (_rot(u1, a) @ _rot(u2, b)).T @ R
        w = cross(u3, u1 if np.linalg.norm(cross(u3, u1)) > 0.1 else u2)
        c = near(angle_about(u3, w, M @ w), h[2])
        sol = np.array([a, b, c])
        err = np.abs(_rot(u1, a) @ _rot(u2, b) @ _rot(u3, c) - R).max()
        key = (err > 1e-9, float(np.linalg.norm(sol - h)))
        if best is None or key < best[0]:
            best = (key, sol)
    return best[1]
