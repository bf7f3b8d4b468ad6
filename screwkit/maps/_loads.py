"""Many workloads over one map: the statics are linear in the workload (private).

The closures, ``J`` and its conditioning of a cell do not depend on the workload, and
``F_r`` (hence ``T_r``) is linear in it: for the workload ``(F, T)`` at ``o``,
``F_r = S [F; T]`` with ``S (m, 6)`` the responses to a unit force at ``o`` along each axis
and a unit torque about each axis (:meth:`~screwkit.engine.PMAnalysis.under`, the engine's
statics on the cell's ``J``).  A sizing over ``K`` workloads thus analyses every cell once
and forms ``K`` matrix-vector products, instead of ``K`` maps.  The trust level of each
cell under each workload (its force amplification) comes from the engine's own rule
(:func:`screwkit.engine._quality.trust`).  Each block of cells is reduced on the spot to
its largest efforts, so the memory stays that of one map whatever ``K``.
"""

from __future__ import annotations

import numpy as np

from ..engine._pipeline import workload_about_origin
from ..engine._quality import trust

__all__ = ["unit_responses", "reduce_block", "merge_reductions"]


def unit_responses(res, linear) -> tuple:
    """``(S (N, m, 6), TS (N, l, 6))``: the values ``F_r`` and ``T_r`` (of the ``l`` linear
    legs, mask ``linear (n,)``) of every pose of ``res`` per unit workload at ``o``: a
    force along X, Y, Z, then a torque about X, Y, Z (NaN where the statics are undefined)."""
    values, t_r = [], []
    for k in range(6):
        F, T = np.zeros(3), np.zeros(3)
        (F if k < 3 else T)[k % 3] = 1.0
        st = res.under(F, T).statics
        values.append(np.asarray(st.F_r, float))
        t_r.append(np.asarray(st.T_r, float)[:, linear])
    return np.stack(values, axis=-1), np.stack(t_r, axis=-1)


def reduce_block(res, out: dict, loads, linear, max_level_code: int, offset: int,
                 codes) -> tuple:
    """The largest efforts of one block of cells under each workload.

    Parameters
    ----------
    res : PMAnalysis
        The block's analysis (a batch).
    out : dict
        Its map arrays (``ok``, ``within_limits``).
    loads : list of (name, force (3,), torque (3,))
    linear : sequence of bool
        Per leg: a linear actuator (its ``T_r`` is sized).
    max_level_code : int
        The worst level code counted.
    offset : int
        Flat index of the block's first cell.
    codes : callable
        Level names -> the map's level codes.

    Returns
    -------
    reduction : dict
        ``max_abs``, ``value`` ``(K, Q)`` (``Q``: the rows of ``J``, then ``T_r`` of the
        linear legs; ``-inf`` and NaN where no cell counts), ``index`` (flat cell, -1),
        ``level`` (code, -1), and ``usable (K,)`` the cells counted per workload.
    usable_any : ndarray (N,) of bool
        The cells counted for at least one workload.
    """
    linear = np.asarray(linear, bool)
    S, TS = unit_responses(res, linear)
    jac = res.jacobian
    o = jac.origin
    reach = np.asarray(res.solution.reachable_mask, bool)
    base = np.asarray(out["ok"], bool).copy()
    if "within_limits" in out:
        base &= out["within_limits"]
    N = len(base)
    K, Q = len(loads), S.shape[1] + TS.shape[1]
    red = {"max_abs": np.full((K, Q), -np.inf), "value": np.full((K, Q), np.nan),
           "index": np.full((K, Q), -1, np.int64), "level": np.full((K, Q), -1, np.int8),
           "usable": np.zeros(K, np.int64)}
    usable_any = np.zeros(N, bool)
    cols = np.arange(Q)
    for k, (_, F, T) in enumerate(loads):
        w = np.concatenate([F, T])
        q = np.concatenate([S @ w, TS @ w], axis=1)                    # (N, Q)
        W = workload_about_origin(np.broadcast_to(F, (N, 3)), np.broadcast_to(T, (N, 3)), o)
        _, lev_names = trust(jac, q[:, :S.shape[1]], W, o, reach)
        lev = codes(lev_names)
        use = base & (lev <= max_level_code)
        red["usable"][k] = int(use.sum())
        usable_any |= use
        a = np.where(use[:, None], np.abs(q), -np.inf)
        a = np.where(np.isnan(a), -np.inf, a)
        i = np.argmax(a, axis=0) if N else np.zeros(Q, int)
        best = a[i, cols] if N else np.full(Q, -np.inf)
        has = np.isfinite(best)
        red["max_abs"][k, has] = best[has]
        red["value"][k, has] = q[i[has], cols[has]]
        red["index"][k, has] = offset + i[has]
        red["level"][k, has] = lev[i[has]]
    return red, usable_any


def merge_reductions(parts) -> dict:
    """The block reductions (in block order) merged: the largest ``max_abs`` of each
    workload and quantity, the earlier block on a tie (as ``argmax`` over the whole map)."""
    parts = list(parts)
    best = {k: v.copy() for k, v in parts[0].items()}
    for p in parts[1:]:
        better = p["max_abs"] > best["max_abs"]
        for key in ("max_abs", "value", "index", "level"):
            best[key][better] = p[key][better]
        best["usable"] = best["usable"] + p["usable"]
    return best
