"""The engine's outputs on 2,000 random poses of every catalog PM, saved or compared.

For a change that should keep the results (a faster kernel, another start of the
closures), run it once with the code before and once after, then compare::

    PYTHONPATH=<before> python benchmarks/compare_outputs.py save before.npz
    PYTHONPATH=<after>  python benchmarks/compare_outputs.py save after.npz [workers]
    python benchmarks/compare_outputs.py compare before.npz after.npz

``workers`` (default 1: the serial kernel, one pose at a time) 2 runs the batches on two
threads (the parallel kernel: the closures in blocks); ``1b`` the parallel kernel on one
thread (what a batch on one thread runs).

Saved per PM: the closures ``X``, the normalised rows ``J``, the singular values, the
condition numbers and the statics' values under the benchmark's load (random poses around
each model's default pose, as ``bench_engine.py``), and the transmission and constraint
indices of the same poses (``INDEX_KEYS``, an analysis through :func:`screwkit.analyze`).
``compare`` prints, per PM and output, the largest difference relative to the largest
magnitude of that output over the poses (poses flagged unsolved in either run are counted
apart).
"""

from __future__ import annotations

import sys

import numpy as np

KEYS = ("X", "residual", "iterations", "J", "singular_values", "condition_number",
        "constraint_condition_number", "values", "equilibrium", "rank", "constraint_rank",
        "how")
#: The transmission and constraint indices (:attr:`screwkit.engine.PMAnalysis.indices`),
#: from an analysis of the same poses through the public API (its indices kernel).
INDEX_KEYS = ("iti_legs", "oti_legs", "cti_rows", "input_arm", "output_arm", "constraint_arm",
              "amplification")


def save(path: str, n: int = 2000, workers: int = 1, blocks: bool = False) -> None:
    import screwkit
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import run_poses
    from screwkit.engine._solve import predictor_of
    from screwkit.pm._loader import pm_names

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from bench_engine import F_LOAD, T_LOAD, _random_pose

    out = {}
    for name in pm_names():
        pm = screwkit.load_pm(name)
        pose = _random_pose(pm, n, np.random.default_rng(0))
        ch = chains_of(pm)
        r = run_poses(ch.flat, predictor_of(ch), ch.full_params(pose, n), F=F_LOAD, T=T_LOAD,
                      workers=workers, blocks=blocks)
        for k in KEYS:
            if k in r:
                out[f"{name}/{k}"] = np.asarray(r[k])
        res = screwkit.analyze(pm, pose, force=F_LOAD, torque=T_LOAD, lines=True,
                               raise_on_singular=False, workers=workers)
        ix = res.indices
        for k in INDEX_KEYS:
            out[f"{name}/{k}"] = np.asarray(getattr(ix, k), float)
    np.savez(path, **out)


def compare(a: str, b: str) -> None:
    A, B = np.load(a), np.load(b)
    worst = 0.0
    for name in sorted({k.rsplit("/", 1)[0] for k in A.files}):
        ok = (A[f"{name}/how"] < 2) & (B[f"{name}/how"] < 2)
        line = []
        for k in KEYS + INDEX_KEYS:
            key = f"{name}/{k}"
            if key not in A.files or key not in B.files or k == "how":
                continue
            x, y = A[key][ok].astype(float), B[key][ok].astype(float)
            fin = np.isfinite(x) & np.isfinite(y)
            same_nan = np.array_equal(np.isfinite(x), np.isfinite(y))
            scale = np.max(np.abs(x[fin]), initial=0.0) or 1.0
            d = np.max(np.abs(x[fin] - y[fin]), initial=0.0) / scale
            if k != "residual":
                worst = max(worst, d)
            line.append(f"{k} {d:.1e}" + ("" if same_nan else " (NaN differ)"))
        print(f"{name:14s} unsolved {int((~ok).sum())}: " + ", ".join(line))
    print(f"largest relative difference (residual apart): {worst:.2e}")


if __name__ == "__main__":
    if sys.argv[1] == "save":
        w = sys.argv[3] if len(sys.argv) > 3 else "1"
        save(sys.argv[2], workers=int(w.rstrip("b")), blocks=w.endswith("b") or w != "1")
    else:
        compare(sys.argv[2], sys.argv[3])
