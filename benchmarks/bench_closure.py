"""The cost of the closure solve's parts, per pose, on one thread: the floor of the kernels.

Times the engine's own compiled functions (no copy of their maths) called in a loop by a
small numba function compiled here, on 20,000 random poses of a catalog PM (the 3RRPRR:
alpha, beta in +-10 deg, Zo in 60-100 cm, as ``bench_engine.py``; the others around their
default poses):

* ``forward pass``: the platform, every leg's product of exponentials and closure error at
  the solved unknowns (``_kin.forward``);
* ``forward pass, blocks of BLOCK``: the same pass on blocks of ``BLOCK`` poses, the pose axis
  innermost (``_kin.forward_block``, the function the one-pose pass runs on a block of one),
  the copy of each block's unknowns into the block layout included;
* ``Newton step``: the platform's columns and one Gauss-Newton step (``_newton``: the
  joints' normalised twists, each leg's Gram matrix, its Cholesky solve with the platform's
  columns, the Schur complement, the reduced system);
* ``Gauss-Newton from the predictor``: the home predictor's start and the iteration to
  ``STOP`` (the mean number of steps beside it);
* ``solve, warm start at the solution``: the batch driver's closure solve
  (``_driver.run_blocks``, the loop of the parallel kernel: blocks of ``BLOCK`` poses; solve
  only) from the exact solution, the case of a path's samples (no step);
* ``solve from the predictor``: the same from the home predictor, a random pose's closures;
* ``rows, conditioning, statics``: the launch of the analysis kernel from warm starts at the
  solution, less the same launch without rows (on one thread: the serial kernel, one pose
  at a time);
* ``analysis``: ``screwkit.analyze`` on one thread (closures, rows, conditioning, statics;
  a batch on one thread runs the parallel kernel's blocks on that thread: ``_launch``).

Times are CPU times, best of 7: of this thread (``time.thread_time``), so that other
processes on a shared machine inflate them less than wall-clock times, except the last two
lines, of the process (``time.process_time``: a launch on one thread may run on one of
numba's threads); the ratios between the lines are the figures to read.  Run: ``python benchmarks/bench_closure.py [PM ...]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np


def _bench_kernel():
    from numba import njit

    from screwkit.engine._kernels._closures import predict
    from screwkit.engine._kernels._jit import one_lane
    from screwkit.engine._kernels._driver import run_blocks
    from screwkit.engine._kernels._kin import forward, forward_block
    from screwkit.engine._kernels._layout import BLOCK
    from screwkit.engine._kernels._newton import (W_FA, W_FE, W_FL, W_FP, W_FROZ, W_P6,
                                                  W_PT, W_PZ, W_S, W_XB, gauss_newton,
                                                  home_vector, make_work, newton_step,
                                                  platform_columns)
    from screwkit.engine._kernels._pack import model, params
    from screwkit.engine._kernels._layout import SY_SIZE
    from screwkit.engine._kernels._path_loop import level_of, path_state

    @njit
    def parts(Mf, Mi, Md, Zf, Zi, Zd, P6, Xs, what):
        M, Z = model(Mf, Mi, Md), params(Zf, Zi, Zd)
        W = make_work(M[0].shape[0], M[0].shape[1], Xs.shape[1])
        unk, xs, fix, p6home = Z[0], Z[1], Z[4], Z[6]
        X = np.zeros(Xs.shape[1])
        steps = 0
        for p in range(P6.shape[0]):
            if what == 2:
                home_vector(unk, xs, p6home, W[W_XB])
                predict(Z[7], fix, Z[8], Z[9], Z[10][0], one_lane(P6[p]), W[W_XB], one_lane(X),
                        W[W_PZ], 1, 1)
                steps += gauss_newton(M, unk, xs, P6[p], X, 1e-12, 30, W)[1]
                continue
            X[:] = Xs[p]
            forward(M, unk, xs, P6[p], X, W[W_FA], W[W_FL], W[W_FE], W[W_FP], 0, W[W_S],
                    W[W_P6])
            if what == 1:
                platform_columns(M, one_lane(W[W_FP][0]), unk, one_lane(W[W_PT]), 1, 1)
                newton_step(M, W, 0, unk.shape[0], W[W_FROZ])
        return steps

    @njit
    def blocks(Mf, Mi, Md, Zf, Zi, Zd, P6, Xs):
        B = BLOCK                  # the lane stride is a constant (_kin.chain)
        M, Z = model(Mf, Mi, Md), params(Zf, Zi, Zd)
        n, m, nx, N = M[0].shape[0], M[0].shape[1], Xs.shape[1], Xs.shape[0]
        unk, xs = Z[0], Z[1]
        FA, FL = np.zeros((2, n, m, 6, B)), np.zeros((2, n, 12, B))
        FE, FP = np.zeros((2, n, 6, B)), np.zeros((2, 27, B))
        Xb, P6b, res, CS = np.zeros((nx, B)), np.zeros((6, B)), np.zeros(B), np.zeros((2, B))
        S = np.zeros((6, 3, 3))
        worst = 0.0
        for p0 in range(0, N, B):
            nb = min(B, N - p0)
            for k in range(nx):
                for l in range(nb):
                    Xb[k, l] = Xs[p0 + l, k]
            for k in range(6):
                for l in range(nb):
                    P6b[k, l] = P6[p0 + l, k]
            forward_block(M, unk, xs, P6b, Xb, FA, FL, FE, FP, 0, S, nb, BLOCK, res, CS)
            for l in range(nb):
                worst = max(worst, res[l])
        return worst

    @njit
    def driver(Mf, Mi, Md, Zf, Zi, Zd, I, O, flags):
        # one piece of all the poses, claimed from a counter of this call (one thread);
        # no path (an empty path state: the level of a launch that is not a path's)
        taken = np.zeros(1, np.int64)
        H, V, P6, res, comp = path_state(np.empty(0), np.empty(0, np.int64))
        N = I[0].shape[0]
        L = level_of(H, V, P6, res, comp, np.zeros(SY_SIZE, np.int64), N)
        run_blocks(model(Mf, Mi, Md), params(Zf, Zi, Zd), I, O, flags, N, 1, taken, L)

    return parts, blocks, driver


def _best(fn, repeat=7, clock=time.thread_time):
    times = []
    for _ in range(repeat):
        t0 = clock()
        out = fn()
        times.append(clock() - t0)
    return min(times), out


def random_poses(name: str, n: int):
    """``(pm, pose)``: ``n`` random poses of the catalog PM ``name`` (the 3RRPRR: alpha, beta in
    +-10 deg, Zo in 60-100 cm, as ``bench_engine.py``; the others around their default
    poses), seed 0."""
    import screwkit

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from bench_engine import _random_pose

    rng = np.random.default_rng(0)
    pm = screwkit.load_pm(name)
    if name == "3RRPRR":
        return pm, {"alpha": np.radians(rng.uniform(-10, 10, n)),
                    "beta": np.radians(rng.uniform(-10, 10, n)), "Zo": rng.uniform(60, 100, n)}
    return pm, _random_pose(pm, n, rng)


def measure(name: str, n: int = 20_000) -> None:
    import screwkit
    from screwkit.engine._chains import chains_of
    from screwkit.engine._kernels._layout import LINE_WIDTH
    from screwkit.engine._solve import predictor_of, solve_closures

    pm, pose = random_poses(name, n)
    from bench_engine import F_LOAD, T_LOAD
    ch = chains_of(pm)
    Mp, Zp = ch.flat.pack(predictor_of(ch))
    args = Mp.args + Zp.args
    P6 = np.ascontiguousarray(ch.full_params(pose, n))
    Xs = np.ascontiguousarray(solve_closures(pm, pose).X.T)
    parts, blocks, driver = _bench_kernel()
    us = 1e6 / n
    rows = []
    t_fwd, _ = _best(lambda: parts(*args, P6, Xs, 0))
    rows.append(("forward pass", t_fwd * us, ""))
    from screwkit.engine._kernels._layout import BLOCK, STENCIL_WIDTH
    t, _ = _best(lambda: blocks(*args, P6, Xs))
    rows.append((f"forward pass, blocks of {BLOCK}", t * us, f"{t_fwd / t:.2f}x"))
    t_step, _ = _best(lambda: parts(*args, P6, Xs, 1))
    rows.append(("Newton step", (t_step - t_fwd) * us, ""))
    t_gn, steps = _best(lambda: parts(*args, P6, Xs, 2))
    rows.append(("Gauss-Newton from the predictor", t_gn * us,
                 f"{steps / n:.2f} steps a pose"))
    nx, mr, na = Xs.shape[1], ch.flat.mr, ch.flat.n_act
    for label, X0 in (("solve, warm start at the solution", Xs), ("solve from the predictor",
                                                                  np.zeros((0, nx)))):
        z = (np.zeros(0), np.zeros(0, np.int64))
        I = (P6, X0, z[0], np.zeros(3), np.zeros(3), np.zeros((0, mr)), np.zeros(mr, np.int64),
             z[1], np.zeros((0, STENCIL_WIDTH)))
        O = (np.zeros((n, nx)), np.zeros(n), np.zeros(n, np.int64), np.zeros(n, np.int64),
             np.zeros(n, np.int64), np.zeros((0, mr, 6)), np.zeros((0, mr)), z[1],
             np.zeros((0, ch.flat.n), np.int64), np.zeros((0, 3)), z[0],
             np.zeros((0, min(mr, 6))), z[1], z[0], z[1], z[0], np.zeros((0, mr)), z[0], z[0],
             z[0], np.zeros((0, na, 6)), np.zeros((0, ch.flat.n, LINE_WIDTH)),
             np.zeros((0, 27)), z[0], np.zeros(n, np.int64))
        flags = np.array([1, 0, 0, 1, 0, 0, 0], np.int64)
        t, _ = _best(lambda: driver(*args, I, O, flags))
        rows.append((label, t * us, f"{O[2].mean():.2f} steps a pose"))
    from screwkit.engine._launch import run_poses as launch
    Z = predictor_of(ch)
    # (the process's CPU time: a launch on one thread may run on one of numba's threads)
    t_solve, _ = _best(lambda: launch(ch.flat, Z, P6, X0=Xs, rows=False, workers=1,
                                      blocks=False), clock=time.process_time)
    t_all, _ = _best(lambda: launch(ch.flat, Z, P6, X0=Xs, F=F_LOAD, T=T_LOAD, workers=1,
                                    blocks=False), clock=time.process_time)
    rows.append(("rows, conditioning, statics", (t_all - t_solve) * us,
                 "(the launch from a warm start, less its solve)"))
    fixed = {p: pose[p] for p in ch.fixed}
    screwkit.analyze(pm, {p: v[:10] for p, v in fixed.items()}, force=F_LOAD, torque=T_LOAD,
                     workers=1)
    t, _ = _best(lambda: screwkit.analyze(pm, fixed, force=F_LOAD, torque=T_LOAD, workers=1),
                 3, clock=time.process_time)
    rows.append(("analysis (screwkit.analyze)", t * us, ""))
    print(f"{name}, {n} random poses, CPU time per pose on one thread:")
    for label, v, note in rows:
        print(f"  {label:36s} {v:7.2f} us  {note}")


if __name__ == "__main__":
    for pm_name in sys.argv[1:] or ["3RRPRR", "6SPS"]:
        measure(pm_name)
