"""Issue 20's property: random hostile values of every option and model key give exit
status 0 with finite (or flagged) output, or exit status 2 with one line on stderr: never
exit 3, a traceback, a warning before the error, or an unbounded run.

One hypothesis test per family of ``tests/hostile.py`` (analyze, stiffness, map and size,
trajectory, fk, export, the model keys, freedom, draw, the other commands' counts, seeds,
addresses and outputs), derandomised and kept small so the suite
stays fast; ``benchmarks/fuzz_hostile.py`` runs the same families longer and prints the
counts (inputs, exit 0, exit 2, exit 3, hangs).
"""

from __future__ import annotations

import os

import pytest
from hypothesis import HealthCheck, given, settings

from hostile import COUNTS, FAMILIES, run

pytest.importorskip("xarray")

#: Examples per family in the suite (the benchmark runs many more); ten times as many with
#: SCREWKIT_TEST_SLOW=1.
EXAMPLES = {"analyze": 6, "stiffness": 6, "map/size": 5, "trajectory": 5, "fk": 4,
            "export": 4, "model keys": 5, "freedom": 6, "draw": 3, "other commands": 4}
if os.environ.get("SCREWKIT_TEST_SLOW") == "1":
    EXAMPLES = {k: 10 * v for k, v in EXAMPLES.items()}


def _settings(n):
    return settings(max_examples=n, deadline=None, derandomize=True, database=None,
                    suppress_health_check=list(HealthCheck))


def _family_test(name):
    @_settings(EXAMPLES[name])
    @given(FAMILIES[name])
    def test(argv):
        run(name, argv)
    test.__name__ = f"test_hostile_{name.replace('/', '_').replace(' ', '_')}"
    return test


for _name in FAMILIES:
    globals()[f"test_hostile_{_name.replace('/', '_').replace(' ', '_')}"] = _family_test(_name)


def test_counts_are_kept():
    """The harness counts every input; no exit 3 and no hang among them."""
    if not COUNTS:
        pytest.skip("run with the family tests above")
    for fam, c in COUNTS.items():
        assert c["exit 3"] == 0 and c["hangs"] == 0, (fam, c)
        assert c["inputs"] == sum(v for k, v in c.items() if k.startswith("exit")) + c["hangs"]
