"""The Fig. 5 plot of a :class:`~screwkit.paths.TrajectoryResult`: the columns it shows, the
leg of each, the values statics does not determine, and the notes derived from the data."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_trajectory", "zero_torque_note"]

#: |T_ri| at or below this fraction of the largest leg wrench counts as 0.
ZERO_TR_RTOL = 1e-9


def _math(label: str) -> str:
    """``F_c2`` -> ``$F_{c2}$``; ``F_c1.2`` -> ``$F_{c1,2}$``."""
    head, _, sub = label.partition("_")
    return f"${head}_{{{sub.replace('.', ',')}}}$"


def _legs_text(legs) -> str:
    legs = sorted(legs)
    return ("leg " if len(legs) == 1 else "legs ") + ", ".join(str(i + 1) for i in legs)


def zero_torque_note(res, zero_legs) -> str:
    """Why the ``T_ri`` of ``zero_legs`` (0-based) vanish, from the result's data: where
    their constraint forces pass (``res.constraint_points``), which legs carry no
    constraint, and that their couples are perpendicular to the leg (else ``T_ri`` would
    not vanish).  '' when ``zero_legs`` is empty."""
    if not zero_legs:
        return ""
    zero_legs = set(zero_legs)
    n_ok = int(res.ok.sum())
    cols = [j for j, leg in enumerate(res.constraint_legs) if leg in zero_legs]
    bare = zero_legs - {res.constraint_legs[j] for j in cols}
    where = {}
    points = res.constraint_points or (None,) * len(res.constraint_kinds)
    for j in cols:
        if res.constraint_kinds[j] == "couple":
            where.setdefault("couple", set()).add(res.constraint_legs[j])
        else:
            w = points[j] or "other"
            where.setdefault(w, set()).add(res.constraint_legs[j])
    single = len(where) == 1            # one reason for every leg that has a constraint

    def whose(legs):
        return "" if single else f" ({_legs_text(legs)})"

    reasons = []
    for key, legs in where.items():
        if key in ("A_i", "a_i"):
            reasons.append(f"constraint forces through ${key}$" + whose(legs))
        elif key == "couple":
            reasons.append("constraint couples perpendicular to the leg" + whose(legs))
        elif key == "other":
            reasons.append("constraint forces meeting the leg axis" + whose(legs))
        else:
            reasons.append(f"constraint forces through {key}, on the leg axis" + whose(legs))
    if bare:
        reasons.append(f"{_legs_text(bare)}: no constraint")
    every = len(zero_legs) == res.n_legs
    what = "all $T_{ri}$" if every else ", ".join(f"$T_{{r{i + 1}}}$" for i in sorted(zero_legs))
    return f"{what} = 0 at the {n_ok} regular samples ({'; '.join(reasons)}): not plotted"


def plot_trajectory(res, out=None, *, title=None, units=None, dpi: int = 150):
    """The panels of the paper's Fig. 5 for ``res`` (:func:`screwkit.viz.plot_fig5`).

    (a) the independent pose parameters, (b) the extensions ``r_i``, (c) the active
    forces ``F_ai``, (d) the constraint forces ``F_c``, couples ``T_c`` and the ``T_ri``
    (those of a leg that vanish at every regular sample are left out, with a note on why
    that is derived from the data), (e) the normalised condition number with the
    engine's quality levels.  Every leg has one colour in all panels; values statics does
    not determine (an indeterminate PM) are marked ``*``; flagged samples are shaded grey.
    """
    from ..engine import COND_THRESHOLD, ILL_CONDITIONED_COND, NEAR_SINGULAR_COND
    from ..viz import plot_fig5

    mu = res._units()
    rot = res.rotary or (False,) * res.n_legs
    torque_unit = mu.torque.replace(".", "·")
    plot_units = {"length": mu.length, "force": mu.force, "torque": torque_unit,
                  "active": (mu.force if not any(rot) else torque_unit if all(rot) else
                             f"{mu.force} or {torque_unit}")}
    plot_units.update(units or {})
    p = res.params_degrees()
    pose = {k: p[k] for k in res.independent}
    n = res.n_legs
    acts = res.actuated
    det = res.determined if res.determined is not None else \
        np.ones((len(res), len(acts) + len(res.constraint_kinds)), bool)
    det_c = det[:, len(acts):]
    force_cols = [j for j, k in enumerate(res.constraint_kinds) if k != "couple"]
    couple_cols = [j for j, k in enumerate(res.constraint_kinds) if k == "couple"]
    Fc = res.constraint[:, force_cols] if force_cols else None
    torques = [res.constraint[:, j] for j in couple_cols]
    tlabels = [_math(res.constraint_labels[j]) for j in couple_cols]
    tlegs = [res.constraint_legs[j] for j in couple_cols]
    tdet = [det_c[:, j] for j in couple_cols]
    scale = max(float(np.nanmax(np.abs(res.leg_wrenches), initial=0.0)), 1e-300)
    Tr = res.T_r
    zero = [i for i in range(n)
            if np.all(~np.isfinite(Tr[:, i]) | (np.abs(Tr[:, i]) <= ZERO_TR_RTOL * scale))]
    for i in range(n):
        if i in zero or rot[i]:     # T_ri: about a linear leg's own line only
            continue
        torques.append(Tr[:, i])
        tlabels.append(f"$T_{{r{i + 1}}}$")
        tlegs.append(i)
        rows = [j for j, leg in enumerate(res.constraint_legs) if leg == i]
        tdet.append(det_c[:, rows].all(axis=1) if rows else np.ones(len(res), bool))
    note = zero_torque_note(res, zero) if res.ok.any() else ""
    Tc = np.column_stack(torques) if torques else None
    labels = {"extensions": [f"$r_{{{i + 1}}}$" for i in range(n)],
              "active": [f"${'T' if rot[i] else 'F'}_{{a{i + 1}}}$" for i in acts]}
    legs = {"active": list(acts)}
    determined = {"active": det[:, :len(acts)]}
    if Fc is not None:
        labels["constraint_forces"] = [_math(res.constraint_labels[j]) for j in force_cols]
        legs["constraint_forces"] = [res.constraint_legs[j] for j in force_cols]
        determined["constraint_forces"] = det_c[:, force_cols]
    if Tc is not None:
        labels["constraint_torques"] = tlabels
        legs["constraint_torques"] = tlegs
        determined["constraint_torques"] = np.column_stack(tdet)
    u = plot_units
    F, T = res.force, res.torque
    load = (f"F = [{', '.join(f'{x:g}' for x in F)}] {u['force']}, "
            f"T = [{', '.join(f'{x:g}' for x in T)}] {u['torque']} at o")
    # (a title of the user's keeps the workload's line: every figure says its load)
    title = f"{res.pm}: {load}" if title is None else f"{title}\n{load}"
    return plot_fig5(res.t, pose, res.extensions, res.active, Fc, Tc, labels=labels,
                     units=plot_units, flags=np.isin(res.status, ("singular", "unreachable")),
                     out=out, title=title, dpi=dpi,
                     legs=legs, determined=determined, condition_number=res.condition_number,
                     condition_levels={"ill-conditioned": ILL_CONDITIONED_COND,
                                       "near-singular": NEAR_SINGULAR_COND,
                                       "singular": COND_THRESHOLD},
                     note=note or None)
