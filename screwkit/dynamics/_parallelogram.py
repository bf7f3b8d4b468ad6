"""The parallelograms ``Pa`` of a leg in the dynamics: their own kinematics and their bars.

A Pa is one equivalent joint whose value ``s`` is the arc length of its bars' ends
(``theta = s / |b|`` the bars' turn about the hinges ``h`` relative to the near link); the
far link translates along a circle: its unit twist is the translation ``xi = [d; 0]`` with
``d = h x b_hat`` turning with the bars (:mod:`screwkit.engine._poe`).  Two consequences
for the dynamics (poses first throughout):

* **its own twist rate.**  ``d`` turns with the near link (the screw product ``V_(j-1) x
  xi``, as every joint twist) *and* with the Pa's own angle: ``d(d)/dt = ... + (h x d)
  theta_dot``.  The acceleration of the far link so gets the bias ``[(h x d) s_dot^2 / |b|;
  0] = [-b_hat s_dot^2 / |b|; 0]``, the centripetal acceleration of the circular
  translation (:func:`pa_state`'s ``curv``, added by :func:`~._legs.bias_terms`);
* **its bars.**  Each bar turns about its own hinge line on the near link, through the
  point ``P = p + o d_0`` carried by that link: its twist is ``V_bar = V_(j-1) + X s_dot``
  with ``X = [P x h; h] / |b|`` (a revolute twist per unit arc), its acceleration ``A_bar =
  A_(j-1) + (V_(j-1) x X) s_dot + X s_ddot``.  Its Newton-Euler wrench ``W`` enters the
  joint efforts by virtual power, ``dV_bar / dq_dot_i . W``: ``xi_i . W`` for the joints
  before the Pa and ``X . W`` for the Pa itself (what the bars need from the Pa's value;
  the bars' internal forces in the loop are not needed).

At ``s_dot = 0`` the bias vanishes and a bar's end point moves with ``d s_dot``, the far
link's velocity: ``X`` and ``xi`` agree on the far hinge (``h x b / |b| = d``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._spatial import body_wrench, cross3, cross_motion

__all__ = ["PaSetup", "PaState", "setup_parallelograms", "pa_state", "bar_efforts",
           "bar_mass_product"]


@dataclass(frozen=True, eq=False)
class PaSetup:
    """The constant data of a leg's parallelograms (world frame at home).

    ``slots (k,)`` the Pa joints, ``hinges (k, 3)`` their unit hinges, ``lengths (k,)`` the
    bars' length ``|b|``; the massive bars: ``bar_pa (nb,)`` (index into the Pas), hinge
    points ``bar_points (nb, 3)``, ``bar_mass (nb,)``, ``bar_com (nb, 3)``,
    ``bar_inertia (nb, 3, 3)``."""

    slots: np.ndarray
    hinges: np.ndarray
    lengths: np.ndarray
    bar_pa: np.ndarray
    bar_points: np.ndarray
    bar_mass: np.ndarray
    bar_com: np.ndarray
    bar_inertia: np.ndarray

    @property
    def massless(self) -> bool:
        return self.bar_pa.size == 0


@dataclass(frozen=True, eq=False)
class PaState:
    """A leg's parallelograms at N poses: ``curv (N, m, 3)`` (``(h x d) / |b|`` at each Pa
    slot, zero elsewhere) and per massive bar its Pa ``slot``, its twist per unit arc
    ``X (N, 6)``, centre ``c (N, 3)`` and inertia ``I (N, 3, 3)`` (current)."""

    curv: np.ndarray
    bars: tuple


def setup_parallelograms(leg, ld, R0, p0) -> PaSetup | None:
    """The :class:`PaSetup` of a leg at home (world frame) with its dynamics ``ld`` (bars
    in the base frame, moved by ``x -> R0 x + p0``); None for a leg without a Pa."""
    slots = [k for k, j in enumerate(leg.joints) if j.spec.parallelogram]
    if not slots:
        return None
    hinges = np.array([leg.joints[k].hinge for k in slots], float)
    lengths = np.array([np.linalg.norm(leg.joints[k].bar) for k in slots], float)
    rows = []
    for pair in ld.bars:
        j = leg.joints[pair.slot]
        for o, body in zip(pair.offsets, pair.bodies):
            if not body.massless:
                bw = body.moved(R0, p0)
                rows.append((slots.index(pair.slot), np.asarray(j.point) + o * j.direction,
                             bw.mass, bw.com, bw.inertia))
    return PaSetup(np.array(slots, int), hinges, lengths,
                   np.array([x[0] for x in rows], int),
                   np.array([x[1] for x in rows], float).reshape(-1, 3),
                   np.array([x[2] for x in rows], float),
                   np.array([x[3] for x in rows], float).reshape(-1, 3),
                   np.array([x[4] for x in rows], float).reshape(-1, 3, 3))


def _rotations(axis, angle):
    """Rodrigues ``Rot(axis, angle) (N, 3, 3)`` of a unit axis (3,) and angles (N,)."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]],
                  [-axis[1], axis[0], 0.0]])
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def pa_state(pa: PaSetup | None, tw, q, Rs, ts) -> PaState | None:
    """A leg's parallelograms at the poses: ``tw (N, m, 6)`` the joint twists, ``q (N, m)``
    the joint values, ``Rs, ts`` the displacement of the link after each joint."""
    if pa is None:
        return None
    N, m = tw.shape[:2]
    curv = np.zeros((N, m, 3))
    bars = []
    for k, j in enumerate(pa.slots):
        R_near = Rs[:, j]                    # a Pa does not turn its far link
        h = R_near @ pa.hinges[k]
        curv[:, j] = cross3(h, tw[:, j, :3]) / pa.lengths[k]
        t_near = ts[:, j - 1] if j > 0 else np.zeros((N, 3))
        mine = np.flatnonzero(pa.bar_pa == k)
        if not mine.size:
            continue
        R_bar = R_near @ _rotations(pa.hinges[k], q[:, j] / pa.lengths[k])
        for b in mine:
            P = R_near @ pa.bar_points[b] + t_near
            X = np.concatenate([cross3(P, h), h], axis=-1) / pa.lengths[k]
            c = P + R_bar @ (pa.bar_com[b] - pa.bar_points[b])
            I = R_bar @ pa.bar_inertia[b] @ R_bar.transpose(0, 2, 1)
            bars.append((int(j), X, c, I, float(pa.bar_mass[b])))
    return PaState(curv, tuple(bars))


def bar_efforts(state: PaState | None, tw, qd, qdd, Vc, Ac, g, ID):
    """Add the bars' efforts to ``ID (N, m)`` (in place); returns their kinetic and
    potential energies ``(N,)``.  ``Vc, Ac (N, m, 6)``: the twist and acceleration of the
    link after each joint."""
    N = tw.shape[0]
    kin, pot = np.zeros(N), np.zeros(N)
    if state is None:
        return kin, pot
    for j, X, c, I, mass in state.bars:
        Vn = Vc[:, j - 1] if j > 0 else np.zeros((N, 6))
        An = Ac[:, j - 1] if j > 0 else np.zeros((N, 6))
        sd, sdd = qd[:, j, None], qdd[:, j, None]
        W, ke, _ = body_wrench(mass, c, I, Vn + X * sd, An + cross_motion(Vn, X) * sd
                               + X * sdd, g)
        ID[:, :j] += np.einsum("nja,na->nj", tw[:, :j], W)
        ID[:, j] += np.einsum("na,na->n", X, W)
        kin += ke
        pot -= mass * (c @ g)
    return kin, pot


def bar_mass_product(state: PaState | None, tw, X_acc, A, out):
    """Add the bars' part of ``M x`` to ``out (N, m, K)`` (in place): ``X_acc (N, m, K)``
    joint accelerations alone, ``A (N, m, K, 6)`` the links' accelerations they give."""
    if state is None:
        return
    N, m, K = X_acc.shape
    zero = np.zeros(3)
    for j, X, c, I, mass in state.bars:
        An = A[:, j - 1] if j > 0 else np.zeros((N, K, 6))
        Ab = An + X[:, None, :] * X_acc[:, j, :, None]
        W, _, _ = body_wrench(mass, c[:, None], I[:, None], np.zeros((N, K, 6)), Ab, zero)
        out[:, :j] += np.einsum("nja,nka->njk", tw[:, :j], W)
        out[:, j] += np.einsum("na,nka->nk", X, W)
