"""A design study for the analysis kernel's outputs along a path: how their layout and the
kind of store decide what writing them in the levels' order costs.

A path's samples are solved level by level (``_path.solve_path``): each level writes its
samples' outputs into rows spread over the whole path, and ``path_breakdown.py`` measures
that spread at some 10-16 ms of a 100,000-sample path (its rows from given unknowns, the
inputs gathered beforehand: 54.5 ms in the levels' order against 44.7 in the path's).  This
script times the writes alone (no arithmetic: each value its pose's index plus a constant),
100,000 poses on two threads (each half of the order), the poses in the path's order and
in the levels' order (``path_breakdown.levels_order``), three ways:

* ``24 arrays``: the engine's layout today, one array an output (15 of one value a pose,
  one of 3, three of 6, ``J (N, 6, 6)``, ``X (N, 18)``): a pose's values spread over 24
  arrays, its small ones a cache line each;
* ``records``: the same 88 values a pose as one record of 88 doubles (11 whole cache lines
  where the array starts on a line);
* ``records, non-temporal``: the records written with non-temporal stores (LLVM's
  ``!nontemporal``: the lines go to memory without being read first).

The records written both ways are checked equal.  Prints the best of ``--repeat`` runs of
each (alternated), in milliseconds.  Run: ``python benchmarks/bench_output_writes.py [--n
100000] [--repeat 15]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from llvmlite import ir
from numba import njit, prange, types
from numba.extending import intrinsic

from path_breakdown import levels_order

#: Values a pose writes: 15 single ones, 3, 3 x 6, 36 (J) and 18 (X).
RECORD = 88


@intrinsic
def _store_nontemporal(typingctx, x, i, v):
    """``x.flat[i] = v`` by a non-temporal store (``x`` C-contiguous float64)."""
    if not (isinstance(x, types.Array) and x.dtype == types.float64 and x.layout == "C"):
        return None

    def codegen(context, builder, sig, args):
        ary = context.make_array(sig.args[0])(context, builder, args[0])
        at = builder.gep(ary.data, [context.cast(builder, args[1], sig.args[1], types.intp)])
        value = context.cast(builder, args[2], sig.args[2], types.float64)
        store = builder.store(value, at)
        store.set_metadata("nontemporal",
                           builder.module.add_metadata([ir.Constant(ir.IntType(32), 1)]))
        return context.get_dummy_value()
    return types.void(x, i, v), codegen


@njit(parallel=True)
def write_arrays(idx, S, R3, R6, J, X):
    n = idx.shape[0]
    for t in prange(2):
        for g in range(t * n // 2, (t + 1) * n // 2):
            q = idx[g]
            for a in range(S.shape[0]):
                S[a, q] = g + a
            for k in range(3):
                R3[q, k] = g + k
            for b in range(3):
                for k in range(6):
                    R6[b, q, k] = g + k
            for r in range(6):
                for k in range(6):
                    J[q, r, k] = g + r + k
            for k in range(18):
                X[q, k] = g + k


@njit(parallel=True)
def write_records(idx, R):
    n = idx.shape[0]
    for t in prange(2):
        for g in range(t * n // 2, (t + 1) * n // 2):
            q = idx[g]
            for a in range(RECORD):
                R[q, a] = g + a


@njit(parallel=True)
def write_records_nontemporal(idx, R):
    n = idx.shape[0]
    flat = R.reshape(-1)
    for t in prange(2):
        for g in range(t * n // 2, (t + 1) * n // 2):
            base = idx[g] * RECORD
            for a in range(RECORD):
                _store_nontemporal(flat, base + a, float(g + a))


def _line_aligned(n: int) -> np.ndarray:
    """A zeroed ``(n, RECORD)`` array starting on a 64-byte line."""
    buf = np.zeros(n * RECORD + 8)
    start = (-(buf.ctypes.data // 8)) % 8
    return buf[start:start + n * RECORD].reshape(n, RECORD)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)
    for name, lo, hi in (("n", 64, 10_000_000), ("repeat", 1, 1000)):
        if not lo <= getattr(args, name) <= hi:
            ap.error(f"--{name} must be within {lo}..{hi}")
    n = args.n
    orders = {"path's order": np.arange(n, dtype=np.int64),
              "levels' order": np.ascontiguousarray(levels_order(n, -(-n // 32)), np.int64)}
    arrays = (np.zeros((15, n)), np.zeros((n, 3)), np.zeros((3, n, 6)), np.zeros((n, 6, 6)),
              np.zeros((n, 18)))
    plain, nontemporal = _line_aligned(n), _line_aligned(n)
    ways = {"24 arrays": lambda idx: write_arrays(idx, *arrays),
            "records": lambda idx: write_records(idx, plain),
            "records, non-temporal": lambda idx: write_records_nontemporal(idx, nontemporal)}
    best = {(w, o): np.inf for w in ways for o in orders}
    for w, f in ways.items():                      # (compiled and warm before the rounds)
        for idx in orders.values():
            f(idx)
    for _ in range(args.repeat):
        for o, idx in orders.items():
            for w, f in ways.items():
                t0 = time.perf_counter()
                f(idx)
                best[w, o] = min(best[w, o], time.perf_counter() - t0)
    assert np.array_equal(plain, nontemporal), "the non-temporal records differ"
    print(f"{n} poses' outputs written on two threads, no arithmetic (best of {args.repeat}, "
          "alternated):")
    for w in ways:
        cells = "   ".join(f"{o} {best[w, o] * 1e3:6.2f} ms" for o in orders)
        print(f"  {w:24s} {cells}")


if __name__ == "__main__":
    main()
