"""Fig. 5-style time plots of a PM's inverse dynamics: the dynamic curves beside the static ones.

:func:`plot_dynamics` takes plain arrays sampled along a motion:

(a) the independent pose parameters (angles on the left axis, lengths on a twin axis);
(b) the active forces ``F_ai``: static (external workload alone, dashed) and dynamic
    (with gravity, inertia and friction, solid), leg i in its colour;
(c) the constraint forces (and couples on a twin axis, their dynamic curves with dots),
    static dashed, dynamic solid;
(d) the mechanical energy (kinetic plus potential) and the actuators' power.

Flagged samples are cut out of the curves and shaded grey.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._figure import POSE_COLORS, leg_color, new_figure, save_figure

__all__ = ["plot_dynamics"]

_ANGLES = ("alpha", "beta", "gamma")
_NAMES = {"Xo": "$X_o$", "Yo": "$Y_o$", "Zo": "$Z_o$", "alpha": r"$\alpha$", "beta": r"$\beta$",
          "gamma": r"$\gamma$"}


#: The markers of a leg's constraint rows in panel (c), in row order.
_ROW_MARKERS = ("o", "s", "^", "D", "v", "P")


def _math(label):
    head, _, sub = label.partition("_")
    return f"${head}_{{{sub.replace('.', ',')}}}$" if sub else label


def _cols(x, N, name):
    a = np.array(x, float)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] != N:
        raise InputError(f"{name} must have shape (N, k) with N = {N}, got {np.shape(x)}")
    return a


def _shade(ax, t, flags):
    if flags is None or not flags.any():
        return
    edges = np.flatnonzero(np.diff(np.concatenate([[0], flags.astype(int), [0]])))
    for s, e in zip(edges[::2], edges[1::2]):
        lo, hi = t[max(s - 1, 0)], t[min(e, len(t) - 1)]
        ax.axvspan(lo, hi, color="0.85", zorder=0, lw=0)


_LOCS = ("upper left", "upper right", "lower left", "lower right", "center left",
         "center right", "upper center", "lower center")


def _place_legends(fig, pending):
    """Each panel's legend where it covers the fewest points of all the panel's curves (its
    twin axes' too, which ``loc="best"`` does not see), measured on the laid-out figure."""
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    for ax, handles, kw in pending:
        pts = [h.axes.transData.transform(np.column_stack(h.get_data()).astype(float))
               for h in handles]
        pts = np.concatenate(pts) if pts else np.zeros((0, 2))
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        best = None
        for loc in _LOCS:
            leg = ax.legend(handles=handles, loc=loc, **kw)
            bb = leg.get_window_extent(renderer).padded(10)      # a margin in pixels
            n = int(np.sum((pts[:, 0] >= bb.x0) & (pts[:, 0] <= bb.x1)
                           & (pts[:, 1] >= bb.y0) & (pts[:, 1] <= bb.y1)))
            if best is None or n < best[0]:
                best = (n, loc)
            if n == 0:
                break
        ax.legend(handles=handles, loc=best[1], **kw)

def plot_dynamics(t, pose, active_static, active_dynamic, constraint_static=None,
                  constraint_dynamic=None, constraint_labels=(), constraint_kinds=(),
                  energy=None, power=None, *, constraint_legs=None, units=None, flags=None,
                  out=None, title=None, dpi: int = 150, active_legs=None, active_rotary=None):
    """Draw the static and dynamic efforts of a PM along a motion (module docstring).

    Parameters
    ----------
    t : array_like (N,)
        Time (s).
    pose : dict str -> array_like (N,)
        Independent pose parameters (angles in degrees, lengths).
    active_static, active_dynamic : array_like (N, n)
    constraint_static, constraint_dynamic : array_like (N, k), optional
    constraint_labels, constraint_kinds : sequence of str
        Per constraint column: its label (``F_c1``, ``T_c2``) and kind (``couple`` goes on
        the torque axis).
    energy, power : array_like (N,), optional
        Kinetic plus potential energy and the actuators' power.
    constraint_legs : sequence of int, optional
        The leg (0-based) of each constraint column (its colour); default from the label.
    active_legs : sequence of int, optional
        The leg (0-based) of each active column (default: column i is leg i; a PM with a
        passive leg has no active column for it).
    active_rotary : sequence of bool, optional
        Per active column: a rotary actuator (its effort a torque, on the torque unit);
        default: every actuator linear.
    units : dict, optional
        ``length``, ``force``, ``torque``, ``energy`` (printed on the axes).
    flags : array_like (N,) of bool, optional
        Samples to cut out and shade.
    out : str or Path, optional
        Save the figure (PNG).

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = np.asarray(t, float).reshape(-1)
    N = t.size
    if N == 0 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InputError("t must be finite and strictly increasing, with at least one sample")
    U = {"length": "", "force": "", "torque": "", "energy": ""}
    U.update(units or {})
    fl = None if flags is None else np.asarray(flags, bool).reshape(N)

    def masked(a):
        a = np.array(a, float)
        a[~np.isfinite(a)] = np.nan
        if fl is not None:
            a[fl] = np.nan
        return a

    Fs, Fd = _cols(active_static, N, "active_static"), _cols(active_dynamic, N, "active_dynamic")
    fig, _ = new_figure((12.0, 8.2), layout="constrained")
    axes = [fig.add_subplot(2, 2, k + 1) for k in range(4)]
    for ax in axes[1:]:
        ax.sharex(axes[0])
    # (a) pose
    ax = axes[0]
    ang = [k for k in pose if k in _ANGLES]
    lin = [k for k in pose if k not in _ANGLES]
    hs = []
    for k in ang:
        hs += ax.plot(t, masked(pose[k]), color=POSE_COLORS.get(k, "k"), label=_NAMES.get(k, k))
    if ang:
        ax.set_ylabel("angle [deg]")
    ax2 = ax.twinx() if ang and lin else ax
    for k in lin:
        hs += ax2.plot(t, masked(pose[k]), color=POSE_COLORS.get(k, "k"), ls="--" if ang else "-",
                       label=_NAMES.get(k, k) + (" (right)" if ang else ""))
    if lin:
        ax2.set_ylabel(f"length [{U['length']}]")
    pending = [(ax2, hs, dict(fontsize=8))]
    ax.set_title("(a) independent pose parameters", loc="left", fontsize=10)
    # (b) active forces
    ax = axes[1]
    act_legs = list(active_legs) if active_legs is not None else list(range(Fs.shape[1]))
    rotary = list(active_rotary) if active_rotary is not None else [False] * len(act_legs)
    for k, i in enumerate(act_legs):
        c = leg_color(i)
        sym = "T" if k < len(rotary) and rotary[k] else "F"     # (a rotary actuator: torque)
        ax.plot(t, masked(Fs[:, k]), color=c, ls="--", lw=1.2,
                label=f"${sym}_{{a{i + 1}}}$ static")
        ax.plot(t, masked(Fd[:, k]), color=c, lw=2.0, label=f"${sym}_{{a{i + 1}}}$ dynamic")
    rot = set(bool(x) for x in (active_rotary if active_rotary is not None else [False]))
    what = {frozenset({False}): ("force", U["force"]), frozenset({True}): ("torque", U["torque"])
            }.get(frozenset(rot), ("effort", f"{U['force']} or {U['torque']}"))
    ax.set_ylabel(f"active {what[0]} [{what[1]}]")
    pending.append((ax, ax.get_lines(), dict(fontsize=7, ncol=2)))
    ax.set_title(f"(b) active {what[0]}s: static (dashed), dynamic (solid)", loc="left",
                 fontsize=10)
    # (c) constraint forces and couples
    ax = axes[2]
    if constraint_static is not None and len(constraint_labels):
        Cs = _cols(constraint_static, N, "constraint_static")
        Cd = _cols(constraint_dynamic, N, "constraint_dynamic")
        legs = (list(constraint_legs) if constraint_legs is not None else
                [int("".join(ch for ch in lab.split("_")[1][1:].split(".")[0]) or 1) - 1
                 for lab in constraint_labels])
        couple = [k == "couple" for k in constraint_kinds]
        twin = any(couple) and not all(couple)
        axc = ax.twinx() if twin else ax
        hs = []
        seen: dict = {}
        for j, lab in enumerate(constraint_labels):
            a = axc if couple[j] else ax
            c = leg_color(legs[j])
            side = " (right)" if twin and couple[j] else ""
            # (a leg's rows share its colour: each its own marker, so that they read apart)
            nth = seen[legs[j]] = seen.get(legs[j], -1) + 1
            mark = _ROW_MARKERS[nth % len(_ROW_MARKERS)]
            hs += a.plot(t, masked(Cs[:, j]), color=c, ls="--", lw=1.2, marker=mark,
                         markevery=max(1, N // 12), ms=3, mfc="none",
                         label=f"{_math(lab)} static{side}")
            hs += a.plot(t, masked(Cd[:, j]), color=c, lw=2.0,
                         label=f"{_math(lab)} dynamic{side}",
                         marker=mark, markevery=max(1, N // 12), ms=3.5)
        if not all(couple):
            ax.set_ylabel(f"constraint force [{U['force']}]")
        if any(couple):
            axc.set_ylabel(f"constraint couple [{U['torque']}]")
        pending.append((axc, hs, dict(fontsize=7, ncol=2)))
    else:
        ax.text(0.5, 0.5, "no constraint wrenches", ha="center", va="center",
                transform=ax.transAxes, color="0.4")
    ax.set_title("(c) constraint wrenches: static (dashed), dynamic (solid)", loc="left",
                 fontsize=10)
    # (d) energy and power
    ax = axes[3]
    hs = []
    if energy is not None:
        e = masked(np.asarray(energy, float).reshape(N))
        hs += ax.plot(t, e - np.nanmin(e) if np.isfinite(e).any() else e, color="k",
                      label="kinetic + potential energy (from its minimum)")
        ax.set_ylabel(f"energy [{U['energy']}]")
    if power is not None:
        axp = ax.twinx()
        hs += axp.plot(t, masked(np.asarray(power, float).reshape(N)), color="#b2182b", ls="--",
                       label="actuators' power (right)")
        axp.set_ylabel(f"power [{U['energy']}/s]")
        axp.ticklabel_format(axis="y", useOffset=False)     # (values, not an offset)
    if hs:
        pending.append((axp if power is not None else ax, hs, dict(fontsize=8)))
    ax.set_title("(d) energy E and actuators' power P = dE/dt + power against load and friction",
                 loc="left", fontsize=9)
    for ax in axes:
        _shade(ax, t, fl)
        ax.grid(True, lw=0.3, alpha=0.5)
    for ax in axes[2:]:
        ax.set_xlabel("t [s]")
    if title:
        fig.suptitle(title, fontsize=10)
    _place_legends(fig, pending)
    save_figure(fig, out, dpi=dpi)
    return fig
