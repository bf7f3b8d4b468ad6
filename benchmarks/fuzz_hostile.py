"""The hostile command lines of ``tests/hostile.py``, family by family, many more than the
suite runs: prints per family the inputs, exits 0 and 2, exits 3 (internal errors) and
hangs, and the first failure of a family if there is one.

    python benchmarks/fuzz_hostile.py [EXAMPLES_PER_FAMILY] [SEED]

Each command line runs in-process with a time limit (``tests/hostile.py``: LIMIT); the
rule checked is issue 20's (exit 0 with finite or flagged output, or exit 2 with one line
on stderr).  The examples are drawn by hypothesis from a fixed seed (reproducible).
"""

from __future__ import annotations

import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
os.environ.setdefault("MPLBACKEND", "Agg")


def main(n: int = 150, seed: int = 0) -> int:
    from hypothesis import HealthCheck, given, seed as hseed, settings

    from hostile import COUNTS, FAMILIES, run

    failures = {}
    t0 = time.perf_counter()
    for name, strategy in FAMILIES.items():
        seen = []

        @hseed(seed)
        @settings(max_examples=n, deadline=None, database=None,
                  suppress_health_check=list(HealthCheck))
        @given(strategy)
        def family(argv):
            seen.append(argv)
            try:
                run(name, argv)
            except AssertionError as exc:            # count it, keep going
                failures.setdefault(name, (argv, str(exc)[:400]))

        t = time.perf_counter()
        family()
        c = COUNTS.get(name, {})
        print(f"{name:<11} inputs {c.get('inputs', 0):5d}  exit 0 {c.get('exit 0', 0):5d}  "
              f"exit 2 {c.get('exit 2', 0):5d}  exit 3 {c.get('exit 3', 0):3d}  hangs "
              f"{c.get('hangs', 0):3d}  ({time.perf_counter() - t:.0f} s)", flush=True)
    tot = {k: sum(c.get(k, 0) for c in COUNTS.values())
           for k in ("inputs", "exit 0", "exit 2", "exit 3", "hangs")}
    print(f"{'all':<11} inputs {tot['inputs']:5d}  exit 0 {tot['exit 0']:5d}  exit 2 "
          f"{tot['exit 2']:5d}  exit 3 {tot['exit 3']:3d}  hangs {tot['hangs']:3d}  "
          f"({time.perf_counter() - t0:.0f} s)")
    for name, (argv, msg) in failures.items():
        print(f"FAILED {name}: {argv}\n  {msg}")
    return 1 if failures else 0


if __name__ == "__main__":
    args = [int(x) for x in sys.argv[1:3]]
    sys.exit(main(*args))
