"""Time plots of a path's statics, laid out like the paper's Fig. 5.

:func:`plot_fig5` takes plain arrays (the pose parameters, leg extensions,
active forces, constraint forces and torques sampled along a path) and draws
the panels of Fig. 5 of Hu, Lu, Zhang, Yu:

(a) the independent pose parameters versus ``t`` (angles in degrees on the left
    axis, lengths on a twin right axis);
(b) the leg extensions ``r_i``;
(c) the active forces ``F_ai``;
(d) the constraint forces ``F_ci`` and the constraint torques ``T_ri`` (twin axis).

Samples flagged as singular or unreachable are cut out of the curves and shaded
grey on every panel.  matplotlib is optional (``pip install "screwkit[plot]"``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._figure import new_figure, save_figure

__all__ = ["plot_fig5", "DEFAULT_UNITS", "POSE_LABELS"]

#: Units printed on the axes unless overridden (``units=`` of :func:`plot_fig5`).
DEFAULT_UNITS = {"t": "", "angle": "deg", "length": "cm", "force": "kN", "torque": "kN·cm",
                 "active": None}

#: Mathtext names of the pose parameters.
POSE_LABELS = {"Xo": "$X_o$", "Yo": "$Y_o$", "Zo": "$Z_o$", "alpha": r"$\alpha$",
               "beta": r"$\beta$", "gamma": r"$\gamma$"}

_ANGLES = ("alpha", "beta", "gamma")


def _column_block(x, n_rows, name, allow_none=False):
    if x is None:
        if allow_none:
            return None
        raise InputError(f"{name} is required")
    try:
        a = np.array(x, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers") from None
    if a.ndim == 1:
        a = a.reshape(-1, 1)
    if a.ndim != 2 or a.shape[0] != n_rows:
        raise InputError(f"{name} must have shape (N, k) with N = {n_rows} samples, got "
                         f"{np.shape(x)}")
    if a.shape[1] == 0:
        return None if allow_none else a
    return a


def _labels_for(labels, key, k, default):
    got = (labels or {}).get(key)
    if got is None:
        return [default.format(i + 1) for i in range(k)]
    got = list(got)
    if len(got) != k:
        raise InputError(f"labels[{key!r}] has {len(got)} names for {k} columns")
    return [str(g) for g in got]


def _runs(mask):
    """(start, stop) index pairs of the runs of True in ``mask``."""
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    d = np.diff(m.astype(int))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def _shade(ax, t, flags):
    if flags is None or not flags.any():
        return
    dt = np.diff(t)
    for i0, i1 in _runs(flags):
        left = t[i0] - (0.5 * dt[i0 - 1] if i0 > 0 else 0.0)
        right = t[i1] + (0.5 * dt[i1] if i1 < len(dt) else 0.0)
        if right <= left:  # a single isolated sample at an end: give it some width
            w = 0.5 * (dt.min() if dt.size else 1.0)
            left, right = t[i0] - w, t[i1] + w
        ax.axvspan(left, right, color="0.82", alpha=0.7, lw=0, zorder=0)


def _legend_on_top(ax, top, handles, **kw):
    """Legend on ``top`` (a twin of ``ax``, drawn above it) placed by ``loc="best"``
    avoiding the curves of both axes: invisible copies of ``ax``'s curves are
    added to ``top`` in its y coordinates (after freezing both y ranges)."""
    if top is not ax:
        lo1, hi1 = ax.get_ylim()
        lo2, hi2 = top.get_ylim()
        ax.set_ylim(lo1, hi1)
        top.set_ylim(lo2, hi2)
        for line in ax.get_lines():
            x, y = line.get_xdata(), np.asarray(line.get_ydata(), float)
            top.plot(x, lo2 + (y - lo1) / (hi1 - lo1) * (hi2 - lo2), alpha=0.0,
                     label="_nolegend_")
    top.legend(handles=handles, loc="best", framealpha=0.9, **kw)


def _unit(u):
    return f" [{u}]" if u else ""


def plot_fig5(t, pose, extensions, active, constraint_forces=None, constraint_torques=None,
              *, labels=None, units=None, flags=None, out=None, title=None, dpi: int = 150,
              pose_angles_in: str = "deg"):
    """Draw the panels of the paper's Fig. 5 for one PM along one path.

    Parameters
    ----------
    t : array_like (N,)
        Sample parameter (time), increasing.
    pose : dict str -> array_like (N,)
        Independent pose parameters by name (``alpha``, ``beta``, ``gamma``,
        ``Xo``, ``Yo``, ``Zo`` or any other name, taken as a length).  Angles in
        degrees unless ``pose_angles_in="rad"``.
    extensions : array_like (N, n)
        Leg extensions ``r_i``.
    active : array_like (N, n)
        Active (actuator) forces ``F_ai``.
    constraint_forces : array_like (N, k), optional
        Constraint forces ``F_ci``.
    constraint_torques : array_like (N, k), optional
        Constraint torques ``T_ri``.
    labels : dict, optional
        Legend names per panel: keys ``"extensions"``, ``"active"``,
        ``"constraint_forces"``, ``"constraint_torques"`` (lists, mathtext
        allowed; default ``r_1``, ``F_a1``, ``F_c1``, ``T_r1`` ...) and
        ``"pose"`` (dict name -> label).
    units : dict, optional
        Overrides of :data:`DEFAULT_UNITS` (keys ``t``, ``angle``, ``length``,
        ``force``, ``torque``).
    flags : array_like (N,) of bool, optional
        True at samples that are singular or unreachable: removed from the
        curves and shaded grey.
    out : str or Path, optional
        Save the figure (PNG).
    title : str, optional
        Figure title.
    dpi : int
    pose_angles_in : {"deg", "rad"}
        Unit of the angle arrays in ``pose`` (they are always shown in degrees).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a)-(c), and (d) when constraint forces or torques are given.
    """
    try:
        t = np.array(t, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError("t must be an array of numbers") from None
    N = t.size
    if N == 0:
        raise InputError("t has no samples")
    if not np.all(np.isfinite(t)):
        raise InputError("t contains NaN or infinite values")
    if N > 1 and np.any(np.diff(t) <= 0):
        raise InputError("t must increase strictly")
    if pose_angles_in not in ("deg", "rad"):
        raise InputError(f"pose_angles_in must be 'deg' or 'rad', not {pose_angles_in!r}")
    if not isinstance(pose, dict):
        raise InputError("pose must be a dict name -> (N,) array")
    P = {}
    for k, v in pose.items():
        a = _column_block(v, N, f"pose[{k!r}]")
        if a.shape[1] != 1:
            raise InputError(f"pose[{k!r}] must have shape (N,), got {np.shape(v)}")
        a = a[:, 0]
        if k in _ANGLES and pose_angles_in == "rad":
            a = np.degrees(a)
        P[str(k)] = a
    R = _column_block(extensions, N, "extensions")
    Fa = _column_block(active, N, "active")
    Fc = _column_block(constraint_forces, N, "constraint_forces", allow_none=True)
    Tr = _column_block(constraint_torques, N, "constraint_torques", allow_none=True)
    if flags is not None:
        flags = np.asarray(flags).reshape(-1)
        if flags.shape != (N,):
            raise InputError(f"flags must have shape ({N},), got {np.shape(flags)}")
        flags = flags.astype(bool)
    U = dict(DEFAULT_UNITS)
    unknown = set(units or {}) - set(U)
    if unknown:
        raise InputError(f"unknown unit keys {sorted(unknown)}; known: {sorted(U)}")
    U.update(units or {})
    if U["active"] is None:               # the actuators' efforts: forces unless rotary
        U["active"] = U["force"]
    pose_names = {**POSE_LABELS, **((labels or {}).get("pose") or {})}

    def masked(a):
        a = np.array(a, dtype=float)
        a[~np.isfinite(a)] = np.nan
        if flags is not None:
            a[flags] = np.nan
        return a

    has_d = Fc is not None or Tr is not None
    shape = (2, 2) if has_d else (1, 3)
    fig, _ = new_figure((11.0, 7.6) if has_d else (14.0, 4.4), layout="constrained")
    axes = fig.subplots(*shape, sharex=True, squeeze=False).ravel()
    t_lab = f"t{_unit(U['t'])}"

    # (a) pose parameters
    ax = axes[0]
    ang = [k for k in P if k in _ANGLES]
    lin = [k for k in P if k not in _ANGLES]
    handles = []
    colors = iter(f"C{i}" for i in range(10 * max(1, len(P))))
    if ang:
        for k in ang:
            (h,) = ax.plot(t, masked(P[k]), color=next(colors), lw=1.8, label=pose_names.get(k, k))
            handles.append(h)
        ax.set_ylabel(f"angle{_unit(U['angle'])}")
    ax_len = ax.twinx() if (ang and lin) else ax
    for k in lin:
        (h,) = ax_len.plot(t, masked(P[k]), color=next(colors), lw=1.8, ls="--",
                           label=pose_names.get(k, k) + (" (right axis)" if ang else ""))
        handles.append(h)
    if lin:
        ax_len.set_ylabel(f"length{_unit(U['length'])}")
    if not P:
        ax.text(0.5, 0.5, "no pose parameters given", ha="center", va="center",
                transform=ax.transAxes, color="0.4")
    ax.set_title("(a) independent pose parameters", fontsize=10, loc="left")
    if handles:  # on the topmost (twin) axes, so that no curve is drawn over it
        _legend_on_top(ax, ax_len, handles, fontsize=8)

    # (b) extensions, (c) active forces
    panels = [(axes[1], R, "extensions", "$r_{{{}}}$", "(b) leg extensions $r_i$",
               f"$r_i${_unit(U['length'])}"),
              (axes[2], Fa, "active", "$F_{{a{}}}$", "(c) active forces $F_{ai}$",
               f"$F_{{ai}}${_unit(U['active'])}")]
    for ax, data, key, deflab, ttl, ylab in panels:
        names = _labels_for(labels, key, data.shape[1], deflab)
        for i in range(data.shape[1]):
            ax.plot(t, masked(data[:, i]), lw=1.8, color=f"C{i % 10}", label=names[i])
        ax.set_title(ttl, fontsize=10, loc="left")
        ax.set_ylabel(ylab)
        ax.legend(fontsize=8, loc="best", ncol=2 if data.shape[1] > 4 else 1)
    axes[2].axhline(0.0, color="0.5", lw=0.6, zorder=1)

    # (d) constraint forces and torques
    if has_d:
        ax = axes[3]
        handles = []
        if Fc is not None:
            names = _labels_for(labels, "constraint_forces", Fc.shape[1], "$F_{{c{}}}$")
            for i in range(Fc.shape[1]):
                (h,) = ax.plot(t, masked(Fc[:, i]), lw=1.8, color=f"C{i % 10}", label=names[i])
                handles.append(h)
            ax.set_ylabel(f"$F_{{ci}}${_unit(U['force'])}")
            ax.axhline(0.0, color="0.5", lw=0.6, zorder=1)
        ax_t = ax.twinx() if (Fc is not None and Tr is not None) else ax
        if Tr is not None:
            names = _labels_for(labels, "constraint_torques", Tr.shape[1], "$T_{{r{}}}$")
            off = Fc.shape[1] if Fc is not None else 0
            for i in range(Tr.shape[1]):
                (h,) = ax_t.plot(t, masked(Tr[:, i]), lw=1.8, ls="--", color=f"C{(i + off) % 10}",
                                 label=names[i] + (" (right axis)" if ax_t is not ax else ""))
                handles.append(h)
            ax_t.set_ylabel(f"$T_{{ri}}${_unit(U['torque'])}")
            if ax_t is ax:
                ax.axhline(0.0, color="0.5", lw=0.6, zorder=1)
        what = " and ".join(w for w, x in (("forces $F_{ci}$", Fc), ("torques $T_{ri}$", Tr))
                            if x is not None)
        ax.set_title(f"(d) constraint {what}", fontsize=10, loc="left")
        _legend_on_top(ax, ax_t, handles, fontsize=8, ncol=2 if len(handles) > 4 else 1)

    nrow = shape[0]
    for i, ax in enumerate(axes):
        _shade(ax, t, flags)
        ax.grid(True, lw=0.4, alpha=0.6)
        ax.set_xlim(t[0], t[-1]) if N > 1 else None
        if i // shape[1] == nrow - 1:
            ax.set_xlabel(t_lab)
        else:
            ax.tick_params(labelbottom=True)
    sup = title or ""
    if flags is not None and flags.any():
        note = f"grey: {int(flags.sum())} of {N} samples singular or unreachable (not plotted)"
        sup = f"{sup}\n{note}" if sup else note
    if sup:
        fig.suptitle(sup, fontsize=10)
    save_figure(fig, out, dpi)
    return fig
