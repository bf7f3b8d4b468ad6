"""Time the batch validation of Table I (``screwkit validate``).

Usage::

    python benchmarks/bench_validate.py [--draws N] [--seed S] [--repeat R]

Prints the total time, the time per string, the split between the generic
analysis, the synthesis and the verification, and the number of synthesized
legs verified per second.
"""

from __future__ import annotations

import argparse
import time


def main(argv=None) -> int:
    from screwkit.pm import default_catalog
    from screwkit.synthesis import _validation as validation
    from screwkit.synthesis import DEFAULT_DRAWS, validate_table1

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=DEFAULT_DRAWS)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=3, help="runs; the best is reported")
    args = ap.parse_args(argv)

    default_catalog()            # read the YAML once, outside the timings
    validate_string_warm = validation.validate_string("UPU", draws=1)
    assert validate_string_warm.ok

    # wrap the stages to split the time (the wrappers cost a few microseconds per call)
    spent = {"synthesis": 0.0, "verification": 0.0}
    real_synth, real_verify = validation.synthesize, validation.verify

    def timed(name, fn):
        def inner(*a, **k):
            t = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                spent[name] += time.perf_counter() - t
        return inner

    best = None
    for _ in range(max(1, args.repeat)):
        spent.update(synthesis=0.0, verification=0.0)
        validation.synthesize = timed("synthesis", real_synth)
        validation.verify = timed("verification", real_verify)
        try:
            t0 = time.perf_counter()
            rep = validate_table1(draws=args.draws, seed=args.seed, check_catalog=False)
            t_table = time.perf_counter() - t0
            t0 = time.perf_counter()
            cat = validation.validate_catalog(known={v.string.marked: v for v in rep.legs},
                                              draws=args.draws, seed=args.seed)
            t_cat = time.perf_counter() - t0
        finally:
            validation.synthesize, validation.verify = real_synth, real_verify
        if best is None or t_table < best[0]:
            best = (t_table, t_cat, dict(spent), rep, cat)
    t_table, t_cat, sp, rep, cat = best
    n = len(rep.legs)
    nlegs = rep.counts["synthesized_legs"]
    other = t_table - sp["synthesis"] - sp["verification"]
    print(f"Table I validation: {n} strings, {args.draws} draws per target, seed {args.seed} "
          f"(best of {max(1, args.repeat)})")
    print(f"  total            {t_table:8.3f} s   ({1e3 * t_table / n:.1f} ms per string)")
    print(f"  synthesis        {sp['synthesis']:8.3f} s")
    print(f"  verification     {sp['verification']:8.3f} s   ({nlegs} synthesized legs, "
          f"{1e3 * sp['verification'] / max(nlegs, 1):.2f} ms per leg)")
    print(f"  generic analysis {other:8.3f} s   (two random geometries per string + bookkeeping)")
    print(f"  catalog legs     {t_cat:8.3f} s   ({len(cat)} legs)")
    print(f"  disagreements    {sum(len(v.problems) for v in rep.legs) + sum(len(c.problems) for c in cat)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
