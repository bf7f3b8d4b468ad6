"""Every output of paths and maps, saved or compared byte for byte between two checkouts.

For a change around the kernels that must keep the results (the path's levels, the map's
blocks), run it once with the code before and once after, then compare::

    PYTHONPATH=<before> python benchmarks/compare_paths_maps.py save before.npz
    PYTHONPATH=<after>  python benchmarks/compare_paths_maps.py save after.npz
    python benchmarks/compare_paths_maps.py compare before.npz after.npz

Saved: for every catalog PM, a smooth 3,000-sample path around its default pose
(``path=True``), with and without a workload: the closures (``X``, residual, iterations,
how, singular_beta), ``J``, ``ok``, ``F_r`` and the transmission indices; and every variable
of three maps (3RRPRR 30 x 30 x 30 cells, 6-SPS and 2SPS+2SPR 20 x 20 x 20 around their
default poses).  ``compare`` names every array whose shape, dtype or bytes differ.
"""

from __future__ import annotations

import sys

import numpy as np

#: The workload of the paths with one (N, N m).
FORCE, TORQUE = np.array([10.0, -20.0, 50.0]), np.array([1.0, 2.0, -3.0])
#: The 3RRPRR map's grid (degrees, cm); the other maps: +-8 deg and +-10% around home.
GRID_3RRPRR = {"alpha": (-15.0, 15.0, 30), "beta": (-15.0, 15.0, 30), "Zo": (60.0, 100.0, 30)}


def _path_of(pm, n=3000):
    """A smooth path of ``n`` samples around the default pose (each parameter its own sine)."""
    s = np.linspace(0, 1, n)
    pose = {}
    for k, (p, v) in enumerate(dict(pm.default_pose).items()):
        amp = 0.08 if p in ("alpha", "beta", "gamma") else 0.05 * max(abs(v), 1.0)
        pose[p] = v + amp * np.sin(2 * np.pi * s * (1 + k) + k)
    return pose


def _grid_of(pm):
    grid = {}
    for p, v in list(pm.default_pose.items())[:3]:
        if p in ("alpha", "beta", "gamma"):
            grid[p] = (np.degrees(v) - 8, np.degrees(v) + 8, 20)
        else:
            grid[p] = (v - 0.1 * max(abs(v), 1), v + 0.1 * max(abs(v), 1), 20)
    return grid


def save(path: str) -> None:
    import screwkit
    from screwkit.pm._loader import pm_names
    out = {}
    for name in pm_names():
        pm = screwkit.load_pm(name)
        pose = _path_of(pm)
        for tag, kw in (("w", dict(force=FORCE, torque=TORQUE)), ("n", {})):
            try:
                r = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **kw)
            except Exception as e:               # (a PM that needs a load: said, skipped)
                print(name, tag, "error", type(e).__name__, e)
                continue
            c = r.solution.closures
            out[f"{name}|{tag}|X"] = c.X
            for a in ("residual", "iterations", "how", "singular_beta"):
                out[f"{name}|{tag}|{a}"] = np.asarray(getattr(c, a))
            out[f"{name}|{tag}|J"] = np.asarray(r.jacobian.J)
            out[f"{name}|{tag}|ok"] = np.asarray(r.ok)
            if r.has_workload:
                out[f"{name}|{tag}|F_r"] = np.asarray(r.statics.F_r)
            for a in ("iti", "oti", "lti", "cti", "sigma_min"):
                out[f"{name}|{tag}|{a}"] = np.asarray(getattr(r.indices, a), float)
    for name in ("3RRPRR", "6SPS", "2SPS+2SPR"):
        pm = screwkit.load_pm(name)
        ds = screwkit.map(pm, GRID_3RRPRR if name == "3RRPRR" else _grid_of(pm), degrees=True)
        for k in ds.data_vars:
            out[f"map|{name}|{k}"] = np.asarray(ds[k].values)
    np.savez(path, **out)
    print(f"saved {len(out)} arrays to {path}")


def compare(a: str, b: str) -> int:
    A, B = np.load(a), np.load(b)
    bad = 0
    for k in sorted(set(A.files) | set(B.files)):
        if k not in A.files or k not in B.files:
            print("missing", k)
            bad += 1
            continue
        x, y = A[k], B[k]
        if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
            print("differs", k, x.shape, y.shape, x.dtype, y.dtype)
            bad += 1
    print(f"{len(A.files)} arrays; {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "save":
        save(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        sys.exit(__doc__)
