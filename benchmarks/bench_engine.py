"""Throughput of the engine's kernels, beside two closed forms in the same run.

Prints every target of the issue "The compiled core", each beside two references timed in
the same process, alternated with it round by round (the machines are noisy: read the
ratios): each figure is the best of its rounds, each ratio the median over the rounds of
the engine's time over the reference's in the same round.  The issue's figures were taken
on a light machine, where the fused closed form ran 7.6M poses/s on 2 threads; each target
is also printed as the ratio to the fused closed form's time it makes there (2,000,000
samples/s: 3.8x), which holds under load where the absolute figures do not:

* ``numpy closed form``: the paper's corrected formulas of the 3RRPRR (gamma = alpha, eq.
  11c; X_o, Y_o of eq. 11e with the Z_o sign of Y_o fixed; rows of eqs. 13d/14a-e about o;
  F_r = -J^-T W, eq. 9), vectorised with numpy, written here independently of screwkit;
* ``fused numba closed form``: the same formulas as one numba kernel per pose (closed-form
  pose, rows, a 6x6 Gaussian elimination), ``prange`` over the poses on 2 threads, written
  here (not screwkit's kernels);
* ``engine 3RRPRR random``: ``screwkit.analyze`` on 100,000 random poses (alpha, beta in
  +-10 deg, Zo in 60-100 cm), each solved from home (no warm start): closures, rows,
  conditioning and statics; target >= 1,000,000 poses/s on 2 threads;
* the same for 2SPS+2SPR, 3RPS, 4SPS+SPR and the 6-SPS (random poses around their default
  poses); target >= 500,000 poses/s each;
* ``engine 3RRPRR path``: a 100,000-sample smooth path (``path=True``); target >= 2,000,000
  samples/s;
* ``one warm pose``: ``screwkit.analyze`` at one pose with the previous pose as guess, for
  the 3RRPRR and the 6-SPS; target <= 100 us;
* ``map 1e6 cells serial``: ``screwkit.map`` over 100 x 100 x 100 cells, one process;
  target <= 3 s (``--map``);
* ``memory``: peak resident memory of 1,000,000 random 3RRPRR poses (``--big``); target
  <= 1 GB;
* ``cold commands``: ``screwkit analyze 3RRPRR`` and ``screwkit leg RRPRR`` as fresh
  processes with the kernels' cache warm, beside ``python -c "import numpy"`` and
  ``python -c "import numpy, numba"``, interleaved run by run (medians of 5 or more),
  the modules' bytecode in place as an installed package has it; targets 0.6 s and 0.35 s
  (``--cold``);
* ``first run``: ``screwkit analyze 3RRPRR`` with an empty kernel cache (the compilation
  included; wall and CPU time); target <= 60 s (``--first``).

Run: ``python benchmarks/bench_engine.py [--n 100000] [--repeat 5] [--big 1000000] [--map]
[--cold] [--first]`` (``--repeat``: the rounds; each time in a round is the best of two
calls).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time

import numpy as np

B3 = np.sqrt(3.0)
L3, l3 = 120.0, 60.0
E3, e3 = L3 / B3, l3 / B3
A3 = np.array([E3 / 2 * np.array([B3, -1, 0]), [0, E3, 0], E3 / 2 * np.array([-B3, -1, 0])])
MA3 = np.array([e3 / 2 * np.array([B3, -1, 0]), [0, e3, 0], e3 / 2 * np.array([-B3, -1, 0])])
R1 = A3 / np.linalg.norm(A3, axis=1, keepdims=True)
F_LOAD = np.array([-20.0, -30.0, -60.0])
T_LOAD = np.array([-30.0, -30.0, 100.0])


def _rx(t):
    c, s = np.cos(t), np.sin(t)
    R = np.zeros(t.shape + (3, 3))
    R[..., 0, 0] = 1
    R[..., 1, 1] = R[..., 2, 2] = c
    R[..., 2, 1], R[..., 1, 2] = s, -s
    return R


def _ry(t):
    c, s = np.cos(t), np.sin(t)
    R = np.zeros(t.shape + (3, 3))
    R[..., 1, 1] = 1
    R[..., 0, 0] = R[..., 2, 2] = c
    R[..., 0, 2], R[..., 2, 0] = s, -s
    return R


def closed_form_3rrprr(alpha, beta, Zo):
    """Active and constraint forces of the 3RRPRR at N poses from the paper's formulas."""
    sa, ca, sb, cb = np.sin(alpha), np.cos(alpha), np.sin(beta), np.cos(beta)
    den = -sa ** 2 + ca ** 2 * cb
    Xo = (Zo * ca + e3 * sa) * sb / den
    Yo = (-Zo * sa * ca * (1 + cb) + e3 * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
    R = _rx(alpha) @ _ry(beta) @ _rx(alpha)                     # intrinsic XYX, gamma = alpha
    o = np.stack([Xo, Yo, Zo], axis=1)
    a = np.einsum("nij,kj->nki", R, MA3) + o[:, None]
    d = a - A3
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    act = np.concatenate([d, np.cross(a - o[:, None], d)], axis=2)
    c = np.cross(R1, d)
    c /= np.linalg.norm(c, axis=2, keepdims=True)
    z = R[:, :, 2]
    q = a - (a[:, :, 2] / z[:, 2:3])[:, :, None] * z[:, None, :]
    con = np.concatenate([c, np.cross(q - o[:, None], c)], axis=2)
    J = np.concatenate([act, con], axis=1)
    W = np.broadcast_to(np.r_[F_LOAD, T_LOAD], (len(alpha), 6))
    return -np.linalg.solve(np.transpose(J, (0, 2, 1)), W[..., None])[..., 0]


def fused_closed_form(alpha, beta, Zo, threads=2):
    """The 3RRPRR closed form as one numba kernel per pose (prange): ``F_r (N, 6)``."""
    import numba
    kern = _fused_kernel()
    numba.set_num_threads(threads)
    out = np.empty((len(alpha), 6))
    kern(alpha, beta, Zo, A3, MA3, R1, np.r_[F_LOAD, T_LOAD], out)
    return out


_FUSED = []


def _fused_kernel():
    if _FUSED:
        return _FUSED[0]
    from numba import njit, prange

    @njit(parallel=True, cache=False, error_model="numpy")
    def kern(alpha, beta, Zo, A, MA, R1, W, out):
        for p in prange(alpha.shape[0]):
            J = np.empty((6, 6))        # hoisted out of the pose loop by numba's parfor
            b = np.empty(6)
            sa, ca = np.sin(alpha[p]), np.cos(alpha[p])
            sb, cb = np.sin(beta[p]), np.cos(beta[p])
            den = -sa * sa + ca * ca * cb
            o0 = (Zo[p] * ca + e3 * sa) * sb / den
            o1 = (-Zo[p] * sa * ca * (1 + cb) + e3 * (cb - ca * ca + sa * sa * cb) / 2) / den
            o2 = Zo[p]
            # R = Rx(a) Ry(b) Rx(a), written out
            r00, r01, r02 = cb, sb * sa, sb * ca
            r10, r11, r12 = sa * sb, ca * ca - sa * cb * sa, -ca * sa - sa * cb * ca
            r20, r21, r22 = -ca * sb, sa * ca + ca * cb * sa, -sa * sa + ca * cb * ca
            for i in range(3):
                m0, m1, m2 = MA[i, 0], MA[i, 1], MA[i, 2]
                a0 = r00 * m0 + r01 * m1 + r02 * m2 + o0
                a1 = r10 * m0 + r11 * m1 + r12 * m2 + o1
                a2 = r20 * m0 + r21 * m1 + r22 * m2 + o2
                d0, d1, d2 = a0 - A[i, 0], a1 - A[i, 1], a2 - A[i, 2]
                nd = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                d0, d1, d2 = d0 / nd, d1 / nd, d2 / nd
                x0, x1, x2 = a0 - o0, a1 - o1, a2 - o2
                J[i, 0], J[i, 1], J[i, 2] = d0, d1, d2
                J[i, 3], J[i, 4], J[i, 5] = x1 * d2 - x2 * d1, x2 * d0 - x0 * d2, x0 * d1 - x1 * d0
                c0 = R1[i, 1] * d2 - R1[i, 2] * d1
                c1 = R1[i, 2] * d0 - R1[i, 0] * d2
                c2 = R1[i, 0] * d1 - R1[i, 1] * d0
                nc = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
                c0, c1, c2 = c0 / nc, c1 / nc, c2 / nc
                k = a2 / r22
                q0, q1, q2 = a0 - k * r02 - o0, a1 - k * r12 - o1, a2 - k * r22 - o2
                J[3 + i, 0], J[3 + i, 1], J[3 + i, 2] = c0, c1, c2
                J[3 + i, 3] = q1 * c2 - q2 * c1
                J[3 + i, 4] = q2 * c0 - q0 * c2
                J[3 + i, 5] = q0 * c1 - q1 * c0
            # J^T F = -W: Gaussian elimination with partial pivoting on M = J^T, in place
            for r in range(6):
                b[r] = -W[r]
            for k in range(6):
                piv = k
                for r in range(k + 1, 6):
                    if abs(J[k, r]) > abs(J[k, piv]):
                        piv = r
                if piv != k:
                    for c in range(6):
                        J[c, k], J[c, piv] = J[c, piv], J[c, k]
                    b[k], b[piv] = b[piv], b[k]
                for r in range(k + 1, 6):
                    f = J[k, r] / J[k, k]
                    for c in range(k, 6):
                        J[c, r] -= f * J[c, k]
                    b[r] -= f * b[k]
            for r in range(5, -1, -1):
                s = b[r]
                for c in range(r + 1, 6):
                    s -= J[c, r] * out[p, c]
                out[p, r] = s / J[r, r]
    _FUSED.append(kern)
    return kern


#: The fused closed form's rate on the light machine of the issue's figures (poses/s, 2
#: threads): a target rate R is the ratio FUSED_LIGHT / R to its time.
FUSED_LIGHT = 7.6e6


def _best(fn, repeat):
    times = []
    out = None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def _alternated(fn, refs, rounds):
    """``fn`` timed in ``rounds`` rounds, each the references ``refs`` (callables) then
    ``fn``, every time in a round the best of two calls: ``(best time of fn, [median over
    the rounds of fn's time over each reference's], its last result)``."""
    own, ratios, out = [], [[] for _ in refs], None
    for _ in range(rounds):
        ref_times = [_best(r, 2)[0] for r in refs]
        t, out = _best(fn, 2)
        own.append(t)
        for k, tr in enumerate(ref_times):
            ratios[k].append(t / tr)
    return min(own), [float(np.median(r)) for r in ratios], out


def _random_pose(model, n, rng, span_deg=8.0, span_len=0.08):
    c = model.default_pose
    z = abs(c.get("Zo", 0.0)) or 1.0
    return {p: c[p] + (rng.uniform(-span_len, span_len, n) * z if p in ("Xo", "Yo", "Zo")
                       else np.radians(rng.uniform(-span_deg, span_deg, n)))
            for p in model.independent}


def main(argv=None):
    import screwkit

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--big", type=int, default=0, help="also measure memory at this N")
    ap.add_argument("--map", action="store_true", help="also time a 1e6-cell map")
    ap.add_argument("--cold", action="store_true", help="also time cold commands")
    ap.add_argument("--first", action="store_true", help="also time a first run (compile)")
    ap.add_argument("--memory-child", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if not 1 <= args.repeat <= 100:
        ap.error(f"--repeat must be 1 to 100 rounds, got {args.repeat}")
    if not 10 <= args.n <= 10_000_000:
        ap.error(f"--n must be 10 to 10,000,000 poses, got {args.n}")
    rng = np.random.default_rng(0)
    pm = screwkit.load_pm("3RRPRR")
    if args.memory_child:
        n = args.memory_child
        pose = {"alpha": rng.uniform(-10, 10, n), "beta": rng.uniform(-10, 10, n),
                "Zo": rng.uniform(60, 100, n)}
        res = screwkit.analyze(pm, pose, degrees=True)
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(f"{n} poses, {int(np.sum(res.ok))} ok, peak memory {peak:.0f} MB")
        return 0
    n = args.n
    alpha, beta = np.radians(rng.uniform(-10, 10, n)), np.radians(rng.uniform(-10, 10, n))
    Zo = rng.uniform(60, 100, n)
    screwkit.analyze(pm, {"alpha": alpha[:10], "beta": beta[:10], "Zo": Zo[:10]})   # warm up
    fused_closed_form(alpha[:10], beta[:10], Zo[:10])                                # compile
    numpy_cf = lambda: closed_form_3rrprr(alpha, beta, Zo)          # noqa: E731
    fused = lambda: fused_closed_form(alpha, beta, Zo)              # noqa: E731
    refs = (numpy_cf, fused)
    t_cf, ref = _best(numpy_cf, args.repeat)
    t_fu, ref2 = _best(fused, args.repeat)
    t_en, (r_cf, r_fu), res = _alternated(
        lambda: screwkit.analyze(pm, {"alpha": alpha, "beta": beta, "Zo": Zo}), refs,
        args.repeat)
    ok = res.ok
    dev = np.max(np.abs(res.statics.active[ok] - ref[ok, :3])) / np.max(np.abs(ref[ok, :3]))
    dev2 = np.max(np.abs(ref2 - ref)) / np.max(np.abs(ref))

    def line(what, t, ratios, target, note=""):
        print(f"{what:34s} {n / t:12,.0f} /s  ({ratios[0]:4.2f}x the numpy closed form's "
              f"time, {ratios[1]:4.2f}x the fused one's; target >= {target:,.0f}: "
              f"{FUSED_LIGHT / target:.1f}x the fused one's{note})")

    print(f"numpy closed form 3RRPRR:          {n / t_cf:12,.0f} poses/s")
    print(f"fused numba closed form 3RRPRR:    {n / t_fu:12,.0f} poses/s  (2 threads; agrees "
          f"with numpy to {dev2:.1e}; {FUSED_LIGHT:,.0f} in the issue)")
    print(f"(each engine figure: the best of {args.repeat} rounds; its ratios: medians over "
          f"the rounds, each alternating the two closed forms and the engine)")
    line("engine 3RRPRR random", t_en, (r_cf, r_fu), 1_000_000)
    print(f"{'':34s} ({int(ok.sum())}/{n} ok; largest |F_a| deviation from the closed form "
          f"{dev:.1e} relative)")
    for name in ("2SPS+2SPR", "3RPS", "4SPS+SPR", "6SPS"):
        m = screwkit.load_pm(name)
        pose = _random_pose(m, n, rng)
        screwkit.analyze(m, {k: v[:10] for k, v in pose.items()}, force=F_LOAD, torque=T_LOAD)
        t, ratios, r = _alternated(
            lambda: screwkit.analyze(m, pose, force=F_LOAD, torque=T_LOAD), refs, args.repeat)
        line(f"engine {name} random", t, ratios, 500_000, f"; {int(np.sum(r.ok))}/{n} ok")
    s = np.linspace(0, 1, n)
    path = {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
            "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
    t, ratios, r = _alternated(lambda: screwkit.analyze(pm, path, path=True), refs,
                               args.repeat)
    c0 = time.process_time()
    screwkit.analyze(pm, path, path=True)
    cpu = (time.process_time() - c0) / n * 1e6
    line("engine 3RRPRR path", t, ratios, 2_000_000, f"; {int(np.sum(r.ok))}/{n} ok; "
         f"{cpu:.1f} us of CPU a sample, all threads")
    for name, one, near in (
            ("3RRPRR", {"alpha": np.radians(5.0), "beta": np.radians(-3.0), "Zo": 80.0},
             {"alpha": np.radians(5.1), "beta": np.radians(-3.0), "Zo": 80.2}),
            ("6SPS", None, None)):
        m = screwkit.load_pm(name)
        if one is None:
            one = dict(m.default_pose)
            near = {p: v + (0.002 if p in ("alpha", "beta", "gamma") else 0.1)
                    for p, v in one.items()}
        prev = screwkit.analyze(m, one, force=F_LOAD, torque=T_LOAD)
        k = 500
        call = lambda: fused_closed_form(alpha[:1], beta[:1], Zo[:1], threads=1)  # noqa: E731
        t, (ratio,), _ = _alternated(
            lambda: [screwkit.analyze(m, near, guess=prev.solution, force=F_LOAD,
                                      torque=T_LOAD) for _ in range(k)], (call,), args.repeat)
        print(f"one warm pose {name:20s} {t / k * 1e6:12.1f} us  (target <= 100 us; "
              f"{ratio / k:.2f}x the time of the fused closed form's call of one pose)")
    if args.map:
        t0, c0 = time.perf_counter(), time.process_time()
        screwkit.map(pm, {"alpha": (-15.0, 15.0, 100), "beta": (-15.0, 15.0, 100),
                          "Zo": (60.0, 100.0, 100)}, degrees=True)
        # CPU time of all threads beside the wall time: steadier on a shared machine
        print(f"map 1e6 cells serial:              {time.perf_counter() - t0:12.2f} s   "
              f"(target <= 3 s; {time.process_time() - c0:.1f} s of CPU, all threads)")
    if args.big:
        out = subprocess.run([sys.executable, __file__, "--memory-child", str(args.big)],
                             capture_output=True, text=True, check=True)
        print(f"memory:                            {out.stdout.strip()}  (target <= 1 GB)")
    if args.cold:
        # the references (a fresh Python importing numpy, and numpy and numba) interleaved
        # with the commands, run after run: each figure is a median over the same minutes
        runs = ((["-c", "import numpy"], None, "python -c 'import numpy'"),
                (["-c", "import numpy, numba"], None, "python -c 'import numpy, numba'"),
                (["-m", "screwkit", "analyze", "3RRPRR"], 0.6, "screwkit analyze 3RRPRR"),
                (["-m", "screwkit", "leg", "RRPRR"], 0.35, "screwkit leg RRPRR"))
        # warm the caches and the disk; the bytecode is written here even where
        # PYTHONDONTWRITEBYTECODE is set (as on the development machines): an installed
        # package has it (pip compiles it), and without it every start compiles the
        # package's modules again (some 0.15 s)
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        for cmd, _, _ in runs:
            subprocess.run([sys.executable] + cmd, capture_output=True, check=True, env=env)
        times = [[] for _ in runs]
        for _ in range(max(5, args.repeat)):
            for k, (cmd, _, _) in enumerate(runs):
                t0 = time.perf_counter()
                subprocess.run([sys.executable] + cmd, capture_output=True, check=True)
                times[k].append(time.perf_counter() - t0)
        for (cmd, target, name), ts in zip(runs, times):
            what = f"target <= {target} s" if target else "reference"
            print(f"cold {name:31s} {sorted(ts)[len(ts) // 2]:9.2f} s   (median of {len(ts)}; "
                  f"{what})")
    if args.first:
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            env = dict(os.environ, NUMBA_CACHE_DIR=tmp)
            cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "screwkit", "analyze", "3RRPRR"], env=env,
                           capture_output=True, check=True)
            cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
            print(f"first run (empty kernel cache):    {time.perf_counter() - t0:12.1f} s   "
                  f"({cpu:.0f} s of CPU; target <= 60 s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
