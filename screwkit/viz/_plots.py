"""Time plots of a path's statics, laid out like the paper's Fig. 5.

:func:`plot_fig5` takes plain arrays (the pose parameters, leg extensions,
active forces, constraint forces and torques sampled along a path) and draws
the panels of Fig. 5 of Hu, Lu, Zhang, Yu:

(a) the independent pose parameters versus ``t`` (angles in degrees on the left
    axis, lengths on a twin right axis);
(b) the leg extensions ``r_i``;
(c) the active forces ``F_ai``;
(d) the constraint forces ``F_ci`` and the constraint torques ``T_ri`` (twin axis);
(e) optionally, the normalised condition number on a log axis.

Leg i has one colour and marker in every panel (and in the PM drawings).  Samples
flagged as singular or unreachable are cut out of the curves and shaded grey on every
panel; force axes near a singularity take a symmetric log scale.  matplotlib is optional
(``pip install "screwkit[plot]"``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._figure import POSE_COLORS, new_figure, save_figure
from ._panels import (apply_scale, band_legend, choose_scale, coincident_names,
                      condition_panel, curve_styles, shade, spiky)

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


def _unit(u):
    return f" [{u}]" if u else ""


def _leg_list(legs, key, k):
    got = (legs or {}).get(key)
    if got is None:
        return list(range(k))
    try:
        got = [int(x) for x in got]
    except (TypeError, ValueError):
        raise InputError(f"legs[{key!r}] must be leg indices (0-based integers)") from None
    if len(got) != k or any(x < 0 for x in got):
        raise InputError(f"legs[{key!r}] has {len(got)} leg indices for {k} columns "
                         "(0-based, >= 0)")
    return got


def _undetermined(determined, key, k, N):
    """Per column: True where statics does not determine it at some sample."""
    got = (determined or {}).get(key)
    if got is None:
        return np.zeros(k, bool)
    d = np.asarray(got, bool)
    if d.shape not in ((k,), (N, k)):
        raise InputError(f"determined[{key!r}] must have shape ({k},) or ({N}, {k}), got "
                         f"{d.shape}")
    return ~(d.all(axis=0) if d.ndim == 2 else d)


def plot_fig5(t, pose, extensions, active, constraint_forces=None, constraint_torques=None,
              *, labels=None, units=None, flags=None, out=None, title=None, dpi: int = 150,
              pose_angles_in: str = "deg", legs=None, determined=None, condition_number=None,
              condition_levels=None, force_scale: str = "auto", note=None,
              determined_note: str = "not determined by statics (least-norm values)"):
    """Draw the panels of the paper's Fig. 5 for one PM along one path.

    Every curve of leg i (its ``r_i``, ``F_ai``, constraint forces and torques) has the
    leg's colour and marker (:func:`~screwkit.viz.leg_color`, the colour of the leg in
    :func:`~screwkit.viz.draw_pm`); torques are dashed with open markers.  A curve equal
    to an earlier one of its panel is labelled ``(= ...)`` and drawn thinner on top of it.

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
        Constraint torques ``T_ri`` (and constraint couples ``T_ci``).
    labels : dict, optional
        Legend names per panel: keys ``"extensions"``, ``"active"``,
        ``"constraint_forces"``, ``"constraint_torques"`` (lists, mathtext
        allowed; default ``r_1``, ``F_a1``, ``F_c1``, ``T_r1`` ...) and
        ``"pose"`` (dict name -> label).
    units : dict, optional
        Overrides of :data:`DEFAULT_UNITS` (keys ``t``, ``angle``, ``length``,
        ``force``, ``torque``, ``active``).
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
    legs : dict, optional
        The leg (0-based) of each column, by key as in ``labels`` (default: column i is
        leg i), e.g. ``{"constraint_forces": [1, 2]}`` when only legs 2 and 3 carry one.
    determined : dict, optional
        By key: bool ``(k,)`` or ``(N, k)``, False where statics does not determine the
        value (an indeterminate PM): the column's name gets a ``*`` and the legend says
        ``determined_note``.
    condition_number : array_like (N,), optional
        The normalised condition number: adds panel (e) on a log axis.
    condition_levels : dict str -> float, optional
        Levels drawn in panel (e), e.g. ``{"ill-conditioned": 1e2, "singular": 1e8}``.
    force_scale : {"auto", "linear", "symlog"}
        Scale of the force and torque axes of (c) and (d): ``auto`` takes a symmetric
        log scale (linear near 0, ``linthresh`` from the data) where the largest value
        exceeds 5 times the median one, as near a singularity.
    note : str, optional
        A line added under the title (e.g. why some curves are left out).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a)-(c), (d) when constraint forces or torques are given, (e) when the
        condition number is given.
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
    if force_scale not in ("auto", "linear", "symlog"):
        raise InputError(f"force_scale must be 'auto', 'linear' or 'symlog', not "
                         f"{force_scale!r}")
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
    cond = None
    if condition_number is not None:
        cond = _column_block(condition_number, N, "condition_number")
        if cond.shape[1] != 1:
            raise InputError(f"condition_number must have shape ({N},)")
        cond = cond[:, 0]
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
    blocks = {"extensions": R, "active": Fa, "constraint_forces": Fc, "constraint_torques": Tr}
    leg_of = {k: _leg_list(legs, k, b.shape[1]) for k, b in blocks.items() if b is not None}
    undet = {k: _undetermined(determined, k, b.shape[1], N) for k, b in blocks.items()
             if b is not None}

    def masked(a):
        a = np.array(a, dtype=float)
        a[~np.isfinite(a)] = np.nan
        if flags is not None:
            a[flags] = np.nan
        return a

    def names_of(key, data, default):
        names = _labels_for(labels, key, data.shape[1], default)
        names = [n + ("*" if u else "") for n, u in zip(names, undet[key])]
        return coincident_names(masked(data), names)

    sp = spiky(cond)
    has_d = Fc is not None or Tr is not None
    ncol = 2 if has_d else 3
    nrow = (2 if has_d else 1) + (cond is not None)
    size = (11.0, 7.6 if has_d else 4.4)
    if cond is not None:
        size = (size[0], size[1] + (2.6 if has_d else 2.4))
    fig, _ = new_figure(size if has_d else (14.0, size[1]), layout="constrained")
    ratios = [1.0] * (nrow - (cond is not None)) + ([0.62] if cond is not None else [])
    gs = fig.add_gridspec(nrow, ncol, height_ratios=ratios)
    axes = []
    for k in range(4 if has_d else 3):
        axes.append(fig.add_subplot(gs[k // ncol, k % ncol],
                                    sharex=axes[0] if axes else None))
    t_lab = f"t{_unit(U['t'])}"

    # (a) pose parameters
    ax = axes[0]
    ang = [k for k in P if k in _ANGLES]
    lin = [k for k in P if k not in _ANGLES]
    handles = []
    spare = iter(f"C{i}" for i in range(10 * max(1, len(P))))
    pose_cols = ang + lin
    pnames = coincident_names(masked(np.column_stack([P[k] for k in pose_cols])) if P else
                              np.zeros((N, 0)), [pose_names.get(k, k) for k in pose_cols])
    for j, k in enumerate(pose_cols):
        if k not in ang:
            continue
        (h,) = ax.plot(t, masked(P[k]), color=POSE_COLORS.get(k) or next(spare),
                       lw=max(1.0, 2.2 - 0.4 * j), zorder=2 + 0.1 * j, label=pnames[j])
        handles.append(h)
    if ang:
        ax.set_ylabel(f"angle{_unit(U['angle'])}")
    ax_len = ax.twinx() if (ang and lin) else ax
    for j, k in enumerate(pose_cols):
        if k in ang:
            continue
        (h,) = ax_len.plot(t, masked(P[k]), color=POSE_COLORS.get(k) or next(spare),
                           lw=max(1.0, 2.2 - 0.4 * j), ls="--", zorder=2 + 0.1 * j,
                           label=pnames[j] + (" (right axis)" if ang else ""))
        handles.append(h)
    if lin:
        ax_len.set_ylabel(f"length{_unit(U['length'])}")
    if not P:
        ax.text(0.5, 0.5, "no pose parameters given", ha="center", va="center",
                transform=ax.transAxes, color="0.4")
    ax.set_title("(a) independent pose parameters", fontsize=10, loc="left")
    if handles:  # on the topmost (twin) axes, so that no curve is drawn over it
        band_legend([ax] + ([ax_len] if ax_len is not ax else []), handles)

    # (b) extensions, (c) active forces
    panels = [(axes[1], R, "extensions", "$r_{{{}}}$", "(b) leg extensions $r_i$",
               f"$r_i${_unit(U['length'])}", None),
              (axes[2], Fa, "active", "$F_{{a{}}}$", "(c) active forces $F_{ai}$",
               f"$F_{{ai}}${_unit(U['active'])}", U["active"])]
    for ax, data, key, deflab, ttl, ylab, unit in panels:
        names = names_of(key, data, deflab)
        handles = [ax.plot(t, masked(data[:, i]), label=names[i], **st)[0]
                   for i, st in enumerate(curve_styles(leg_of[key], "force", N))]
        if unit is not None:
            ttl += apply_scale(ax, *choose_scale([masked(data)], force_scale, sp), unit)
        ax.set_title(ttl, fontsize=10, loc="left")
        ax.set_ylabel(ylab)
        band_legend([ax], handles, title="* " + determined_note if undet[key].any() else None)
    axes[2].axhline(0.0, color="0.5", lw=0.6, zorder=1)

    # (d) constraint forces and torques
    if has_d:
        _panel_d(axes[3], t, N, Fc, Tr, masked, names_of, leg_of, undet, U, (force_scale, sp),
                 determined_note)

    if cond is not None:
        ax_e = fig.add_subplot(gs[nrow - 1, :], sharex=axes[0])
        condition_panel(ax_e, t, cond, condition_levels, flags,
                        letter="e" if has_d else "d")
        axes.append(ax_e)
    for ax in axes:
        shade(ax, t, flags)
        ax.grid(True, lw=0.4, alpha=0.6)
        ax.set_xlim(t[0], t[-1]) if N > 1 else None
        ax.set_xlabel(t_lab)
        ax.tick_params(labelbottom=True)
    lines = [title or ""]
    if note:
        lines.append(note)
    if flags is not None and flags.any():
        lines.append(f"grey: {int(flags.sum())} of {N} samples singular or unreachable "
                     "(not plotted)")
    sup = "\n".join(x for x in lines if x)
    if sup:
        fig.suptitle(sup, fontsize=10)
    save_figure(fig, out, dpi)
    return fig


def _torque_kinds(names) -> list:
    """``(symbol, word)`` of the moments among the curve ``names`` of panel (d): the
    constraint couples ``T_ci`` (names starting ``$T_{c``) and the torques ``T_ri`` (the
    others)."""
    couples = [n.startswith("$T_{c") for n in names]
    out = [("$T_{ci}$", "couples")] if any(couples) else []
    return out + ([("$T_{ri}$", "torques")] if not all(couples) else [])


def _panel_d(ax, t, N, Fc, Tr, masked, names_of, leg_of, undet, U, scale, det_note):
    """Panel (d): constraint forces (left axis) and couples and torques (right axis,
    dashed), the legend in a band kept free at the top of the panel."""
    handles, ttl = [], ""
    if Fc is not None:
        names = names_of("constraint_forces", Fc, "$F_{{c{}}}$")
        for i, st in enumerate(curve_styles(leg_of["constraint_forces"], "force", N)):
            (h,) = ax.plot(t, masked(Fc[:, i]), label=names[i], **st)
            handles.append(h)
        ax.set_ylabel(f"$F_{{ci}}${_unit(U['force'])}")
        ax.axhline(0.0, color="0.5", lw=0.6, zorder=1)
        ttl += apply_scale(ax, *choose_scale([masked(Fc)], *scale), U["force"])
    ax_t = ax.twinx() if (Fc is not None and Tr is not None) else ax
    tkinds = []
    if Tr is not None:
        names = names_of("constraint_torques", Tr, "$T_{{r{}}}$")
        tkinds = _torque_kinds(names)
        first = Fc.shape[1] if Fc is not None else 0
        for i, st in enumerate(curve_styles(leg_of["constraint_torques"], "torque", N,
                                            first=first)):
            (h,) = ax_t.plot(t, masked(Tr[:, i]), **st,
                             label=names[i] + (" (right axis)" if ax_t is not ax else ""))
            handles.append(h)
        ax_t.set_ylabel(", ".join(sym for sym, _ in tkinds) + _unit(U["torque"]))
        if ax_t is ax:
            ax.axhline(0.0, color="0.5", lw=0.6, zorder=1)
        ttl += apply_scale(ax_t, *choose_scale([masked(Tr)], *scale), U["torque"])
    parts = ["forces $F_{ci}$"] * (Fc is not None) + [f"{w} {sym}" for sym, w in tkinds]
    what = " and ".join([", ".join(parts[:-1]), parts[-1]] if len(parts) > 1 else parts)
    ax.set_title(f"(d) constraint {what}{ttl}", fontsize=10, loc="left")
    marked = any(undet[k].any() for k in ("constraint_forces", "constraint_torques")
                 if k in undet)
    band_legend([ax] + ([ax_t] if ax_t is not ax else []), handles,
                title="* " + det_note if marked else None)
