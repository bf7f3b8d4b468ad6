"""numba's compile flags compared option by option (screwkit/engine/_kernels/_flags.py).

The change must leave every comparison and hash of numba's configs what numba's own
methods make of them (so that the same implementations are found in numba's caches, and
the kernels' code does not change): checked on random ``Flags``, each option left unset,
set to its default or set to another value, against the methods the change replaced."""

import numpy as np
import pytest

from screwkit.engine._kernels import _flags


def _values(option):
    """``(default, other)``: the values of ``option`` its setter takes, its default and
    another."""
    from numba.core.cpu_options import FastMathOptions, InlineOptions, ParallelOptions
    d = option.default
    if isinstance(d, bool):
        return d, not d
    if isinstance(d, str):
        return d, ("numpy" if d != "numpy" else "python")
    if isinstance(d, InlineOptions):
        return "never", "always"
    if isinstance(d, FastMathOptions):
        return set(), {"nnan"}
    if isinstance(d, ParallelOptions):
        return False, True
    pytest.skip(f"an option of a type this test does not know: {type(d).__name__}")


def _random_flags(rng, names):
    from numba.core.compiler import Flags
    f = Flags()
    for name in names:
        pick = rng.integers(3)          # unset, set to its default, set to another value
        if pick:
            setattr(f, name, _values(Flags.options[name])[pick - 1])
    return f


def test_flags_compare_and_hash_as_numbas_own_methods():
    from numba.core.compiler import Flags
    from numba.core.targetconfig import TargetConfig
    assert _flags.install() and _flags.installed()
    equal, hashed = TargetConfig.__eq__.__wrapped__, TargetConfig.__hash__.__wrapped__
    assert equal is not TargetConfig.__eq__
    rng = np.random.default_rng(7)
    names = list(Flags.options)
    seen = {True: 0, False: 0}
    for _ in range(3000):
        few = [names[i] for i in rng.choice(len(names), size=3, replace=False)]
        a, b = _random_flags(rng, few), _random_flags(rng, few)
        want = equal(a, b)
        assert (a == b) is want and (b == a) is want and (a != b) is (not want)
        assert hash(a) == hashed(a) == hash(b)
        seen[want] += 1
        # a copy compares equal, and so finds what its original was the key of
        c = Flags(a)
        assert c == a and {a: 1}[c] == 1
    assert seen[True] > 300 and seen[False] > 300      # both outcomes exercised
    assert (Flags() == object()) is False and Flags().__eq__(3) is NotImplemented
