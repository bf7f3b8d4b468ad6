"""Throughput of the batched engine, beside a hand-written closed form in the same run.

Prints, for each case, poses per second (best of ``--repeat`` runs; the machines are
noisy, so the reference is timed in the same process, right before):

* ``closed form 3RRPRR``: the paper's corrected formulas (gamma = alpha, eq. 11c; X_o, Y_o
  of eq. 11e with the Z_o sign of Y_o fixed; rows of eqs. 13d/14a-e about o; F_r = -J^-T W,
  eq. 9), vectorised with numpy, written here independently of screwkit;
* ``engine 3RRPRR random``: ``screwkit.analyze`` on 100,000 random poses (alpha, beta in
  +-10 deg, Zo in 60-100 cm), each solved from home (no warm start): closures, rows,
  conditioning and statics;
* the same for 2SPS+2SPR, 3RPS and 4SPS+SPR (random poses around their default poses);
* ``engine 3RRPRR path``: a 100,000-sample smooth path (``path=True``: warm starts from
  the neighbours);
* ``one warm pose``: ``screwkit.analyze`` at one pose with the previous pose as guess;
* ``memory``: peak resident memory of the 3RRPRR random case at ``--big`` poses.

Targets (issue "One engine"): >= 100,000 random poses/s for the 3RRPRR (within ~6.5x of
the closed form), >= 200,000/s along a path, one warm pose <= 1 ms, peak memory <= 1 GB
at N = 1,000,000.

Run: ``python benchmarks/bench_engine.py [--n 100000] [--repeat 3] [--big 1000000]``.
"""

from __future__ import annotations

import argparse
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


def _best(fn, repeat):
    times = []
    out = None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


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
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--big", type=int, default=0, help="also measure memory at this N")
    ap.add_argument("--memory-child", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
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
    t_cf, ref = _best(lambda: closed_form_3rrprr(alpha, beta, Zo), args.repeat)
    t_en, res = _best(lambda: screwkit.analyze(pm, {"alpha": alpha, "beta": beta, "Zo": Zo}),
                      args.repeat)
    ok = res.ok
    dev = np.max(np.abs(res.statics.active[ok] - ref[ok, :3])) / np.max(np.abs(ref[ok, :3]))
    print(f"closed form 3RRPRR:       {n / t_cf:12,.0f} poses/s")
    print(f"engine 3RRPRR random:     {n / t_en:12,.0f} poses/s  ({t_en / t_cf:.1f}x the closed "
          f"form; {int(ok.sum())}/{n} ok; largest |F_a| deviation from it {dev:.1e} relative)")
    for name in ("2SPS+2SPR", "3RPS", "4SPS+SPR"):
        m = screwkit.load_pm(name)
        pose = _random_pose(m, n, rng)
        screwkit.analyze(m, {k: v[:10] for k, v in pose.items()})
        t, r = _best(lambda: screwkit.analyze(m, pose), args.repeat)
        print(f"engine {name + ' random:':18s} {n / t:12,.0f} poses/s  ({int(np.sum(r.ok))}/{n} ok)")
    s = np.linspace(0, 1, n)
    path = {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
            "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
    t, r = _best(lambda: screwkit.analyze(pm, path, path=True), args.repeat)
    print(f"engine 3RRPRR path:       {n / t:12,.0f} poses/s  ({int(np.sum(r.ok))}/{n} ok)")
    one = {"alpha": np.radians(5.0), "beta": np.radians(-3.0), "Zo": 80.0}
    prev = screwkit.analyze(pm, one)
    near = {"alpha": np.radians(5.1), "beta": np.radians(-3.0), "Zo": 80.2}
    k = 200
    t, _ = _best(lambda: [screwkit.analyze(pm, near, guess=prev.solution) for _ in range(k)],
                 args.repeat)
    print(f"one warm pose:            {t / k * 1e3:12.3f} ms")
    if args.big:
        out = subprocess.run([sys.executable, __file__, "--memory-child", str(args.big)],
                             capture_output=True, text=True, check=True)
        print(f"memory:                   {out.stdout.strip()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
