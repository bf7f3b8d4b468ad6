"""The switches of screwkit's changes to numba's compiler (screwkit/engine/_kernels/_patching.py):
``SCREWKIT_NUMBA_INLINING`` (:mod:`._inlining`), ``SCREWKIT_NUMBA_LINKING``
(:mod:`._linking`) and ``SCREWKIT_NUMBA_FLAGS`` (:mod:`._flags`).  A hostile value is a one-line error of the CLI (exit 2, nothing on
stdout, the variable and the value named); 0/1, no/yes, off/on, false/true in any case and
with spaces around are read as they say."""

import os
import subprocess
import sys

import pytest

from screwkit.engine._kernels import _flags, _inlining, _linking


@pytest.mark.parametrize("name, module", [("SCREWKIT_NUMBA_INLINING", _inlining),
                                          ("SCREWKIT_NUMBA_LINKING", _linking),
                                          ("SCREWKIT_NUMBA_FLAGS", _flags)])
def test_a_hostile_switch_is_a_one_line_error(name, module, tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    env[name] = "maybe"
    r = subprocess.run([sys.executable, "-m", "screwkit", "analyze", "3RRPRR"],
                       capture_output=True, text=True, env=env, timeout=600)
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and name in lines[0] and "'maybe'" in lines[0]
    for value in ("0", "off", "1", " Yes ", "FALSE", "true"):
        os.environ[name] = value
        try:
            assert module.enabled() is (value.strip().lower() in ("1", "yes", "true"))
        finally:
            del os.environ[name]
    assert name not in os.environ and module.enabled() is True
