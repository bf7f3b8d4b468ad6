"""Singularity loci of a map: where ``det J`` changes sign between neighbouring cells.

For every pair of neighbouring cells along a grid parameter whose ``det J`` signs differ
(both reachable, ``J`` square), the crossing is refined by bisection on that parameter,
the other ones held at the cells' values, until the bracket is at most :data:`REFINE` of
the cell size (20 halvings); all crossings are bisected at once, one engine analysis of
every midpoint per halving.  Each crossing is then classified from the conditioning at
its refined point against the two cells':

* ``constraint``: the constraint rows alone lose rank there (the condition number of
  ``J_c`` grows by more than :data:`GROWTH` over the cells' and past the near-singular
  level); the PM gains a freedom;
* ``actuation``: ``J_c`` keeps its conditioning but ``J`` loses rank (the actuators no
  longer control the platform);
* ``discontinuity``: the sign changes but ``J`` stays well-conditioned (a jump of the
  solution to another branch between the cells, or of a row's basis): not a singularity;
* ``unreachable``: a midpoint cannot be assembled (the sign changes across a gap of the
  workspace).

Only the first two are singular loci (``singular_locus`` in the JSON).
"""

from __future__ import annotations

import numpy as np

from ..engine import LENGTH_PARAMS, analyze
from ..engine._quality import NEAR_SINGULAR_COND, det_signs

__all__ = ["REFINE", "GROWTH", "LOCUS_KINDS", "MAX_CROSSINGS", "find_crossings", "refine",
           "locus_variables", "locus_list"]

#: Bracket width reached by the bisection, in cell sizes.
REFINE = 1e-6
_HALVINGS = int(np.ceil(np.log2(1.0 / REFINE)))
#: Growth of a condition number from the cells to the crossing that marks it singular.
GROWTH = 100.0
LOCUS_KINDS = ("actuation", "constraint", "discontinuity", "unreachable")
#: At most this many crossings are refined (the others are counted in a note).
MAX_CROSSINGS = 200_000


def _api(name, v, degrees):
    v = np.asarray(v, float)
    return np.radians(v) if (degrees and name not in LENGTH_PARAMS) else v


def find_crossings(ds):
    """The neighbouring cells with opposite ``det J`` signs.

    Returns
    -------
    along : ndarray (K,) of int
        The grid dimension of each crossing.
    lo, hi : ndarray (K, ndim) of int
        The two cells (grid indices).
    """
    dims = ds["det_sign"].dims
    if dims == ("sample",):
        return np.zeros(0, int), np.zeros((0, 1), int), np.zeros((0, 1), int)
    s = ds["det_sign"].values.astype(int)
    reach = ds["reachable"].values
    along, lo = [], []
    for k in range(s.ndim):
        # each cell and its next neighbour along k (views: no copies of the map's arrays)
        first = tuple(slice(None, -1) if d == k else slice(None) for d in range(s.ndim))
        second = tuple(slice(1, None) if d == k else slice(None) for d in range(s.ndim))
        idx = np.argwhere((s[first] * s[second] == -1) & reach[first] & reach[second])
        along.append(np.full(len(idx), k))
        lo.append(idx)
    along = np.concatenate(along) if along else np.zeros(0, int)
    lo = np.concatenate(lo).reshape(-1, s.ndim) if lo else np.zeros((0, s.ndim), int)
    hi = lo.copy()
    hi[np.arange(len(lo)), along] += 1
    return along, lo, hi


def refine(model, ds, threads=None):
    """Bisect every crossing of a map (see the module docstring).

    Returns
    -------
    dict of ndarray (K,)
        ``along``, ``kind`` (codes of :data:`LOCUS_KINDS`), ``condition_number``,
        ``constraint_condition_number``, ``width`` (final bracket, cell sizes) and one array
        per independent parameter (the crossing's pose, in the map's units);
        ``truncated``: crossings left out beyond :data:`MAX_CROSSINGS`.
    """
    along, lo, hi = find_crossings(ds)
    truncated = max(0, len(along) - MAX_CROSSINGS)
    along, lo, hi = along[:MAX_CROSSINGS], lo[:MAX_CROSSINGS], hi[:MAX_CROSSINGS]
    K = len(along)
    dims = ds["det_sign"].dims
    degrees = ds.attrs.get("units_angle") == "deg"
    indep = str(ds.attrs["independent"]).split(",")
    shown = {}                                     # the cells' values, in the map's units
    for p in indep:
        shown[p] = ds[p].values[lo[:, dims.index(p)]] if p in dims else \
            np.full(K, float(ds[p].values))
    base = {p: _api(p, v, degrees) for p, v in shown.items()}
    # each crossing's bracket along its parameter, in the API's units (angles in radians)
    axes = [_api(d, ds[d].values, degrees) for d in dims]
    t0, t1 = np.empty(K), np.empty(K)
    for k, ax in enumerate(axes):
        on = along == k
        t0[on], t1[on] = ax[lo[on, k]], ax[hi[on, k]]
    h = t1 - t0
    sign_lo = ds["det_sign"].values[tuple(lo.T)].astype(int) if K else np.zeros(0, int)
    gone = np.zeros(K, bool)
    moving = {p: along == dims.index(p) if p in dims else np.zeros(K, bool) for p in indep}

    def poses_at(t):
        return {p: np.where(moving[p], t, base[p]) for p in indep}

    a, b = t0.copy(), t1.copy()
    for _ in range(_HALVINGS if K else 0):
        mid = 0.5 * (a + b)
        res = analyze(model, poses_at(mid), raise_on_singular=False, workers=threads)
        reach = res.solution.reachable_mask
        s = det_signs(res, reach, analyze)               # the kernels' (0: unreachable)
        gone |= ~reach
        same = (s == sign_lo) & reach & ~gone
        move = reach & ~gone
        a = np.where(move & same, mid, a)
        b = np.where(move & ~same, mid, b)
    t = 0.5 * (a + b)
    out = {"along": along.astype(np.int8), "width": np.abs(b - a) / np.where(h != 0, np.abs(h),
                                                                          1.0)}
    if K:
        res = analyze(model, poses_at(t), raise_on_singular=False, workers=threads)
        c = res.jacobian.conditioning
        cond, ccond = c.condition_number, c.constraint_condition_number
        gone |= ~res.solution.reachable_mask
    else:
        cond = ccond = np.zeros(0)
    cc = ds["condition_number"].values
    ccc = ds["constraint_condition_number"].values
    cl, ch = cc[tuple(lo.T)], cc[tuple(hi.T)]
    ccl, cch = ccc[tuple(lo.T)], ccc[tuple(hi.T)]
    n_act = sum(1 for v in ds.data_vars.values() if v.attrs.get("kind") == "actuation")
    con = (n_act < 6) & (ccond > np.maximum(NEAR_SINGULAR_COND, GROWTH * np.minimum(ccl, cch)))
    act = cond > np.maximum(NEAR_SINGULAR_COND, GROWTH * np.minimum(cl, ch))
    kind = np.where(gone, 3, np.where(con, 1, np.where(act, 0, 2))).astype(np.int8)
    out.update(kind=kind, condition_number=np.where(gone, np.nan, cond),
               constraint_condition_number=np.where(gone, np.nan, ccond), truncated=truncated)
    for p in indep:
        v = np.degrees(t) if (degrees and p not in LENGTH_PARAMS) else t
        out[p] = np.where(moving[p], v, shown[p]) if K else np.zeros(0)
    return out


def locus_variables(ds, loc) -> dict:
    """The refined crossings as Dataset variables along ``crossing``."""
    from ._dataset import variable
    dims = ds["det_sign"].dims
    indep = str(ds.attrs["independent"]).split(",")
    lu, au = ds.attrs["units_length"], ds.attrs["units_angle"]
    out = {f"locus_{p}": variable(("crossing",), loc[p], {
        "units": lu if p in LENGTH_PARAMS else au, "long_name": f"{p} at a det J sign change"})
        for p in indep}
    out["locus_kind"] = variable(("crossing",), loc["kind"], {
        "units": "1", "long_name": "kind of the det J sign change",
        "flag_values": np.arange(len(LOCUS_KINDS), dtype=np.int8),
        "flag_meanings": " ".join(LOCUS_KINDS)})
    out["locus_along"] = variable(("crossing",), loc["along"], {
        "units": "1", "long_name": "grid parameter bisected",
        "flag_values": np.arange(len(dims), dtype=np.int8), "flag_meanings": " ".join(dims)})
    out["locus_condition_number"] = variable(("crossing",), loc["condition_number"], {
        "units": "1", "long_name": "normalised condition number of J at the crossing"})
    out["locus_constraint_condition_number"] = variable(
        ("crossing",), loc["constraint_condition_number"],
        {"units": "1", "long_name": "normalised condition number of J_c at the crossing"})
    out["locus_width"] = variable(("crossing",), loc["width"], {
        "units": "1", "long_name": "final bisection bracket, in cell sizes"})
    return out


def locus_list(ds, singular_only: bool = True) -> list:
    """The refined crossings of a map (JSON-ready): ``pose`` (every independent parameter,
    the map's units), ``pose_units`` (the unit of each), ``kind``, ``along``, the condition numbers, ``width``.

    ``singular_only=True``: the singular locus (``actuation`` and ``constraint``
    crossings); ``False``: the other sign changes (``discontinuity``, ``unreachable``)."""
    if "locus_kind" not in ds:
        return []
    indep = str(ds.attrs["independent"]).split(",")
    along = str(ds["locus_along"].attrs["flag_meanings"]).split()
    out = []
    for k in range(ds.sizes.get("crossing", 0)):
        kind = LOCUS_KINDS[int(ds["locus_kind"].values[k])]
        if singular_only != (kind in ("actuation", "constraint")):
            continue
        out.append({"pose": {p: float(ds[f"locus_{p}"].values[k]) for p in indep},
                    "pose_units": {p: str(ds[f"locus_{p}"].attrs["units"]) for p in indep},
                    "kind": kind, "along": along[int(ds["locus_along"].values[k])],
                    "condition_number": float(ds["locus_condition_number"].values[k]),
                    "constraint_condition_number":
                        float(ds["locus_constraint_condition_number"].values[k]),
                    "width": float(ds["locus_width"].values[k])})
    return out
