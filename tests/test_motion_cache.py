"""The finite motion kept on disk (``screwkit.engine._motion_cache``): a kept verdict is the
one computed now, bit for bit; any change to the model or to the classification constants
gives another file; a bad file is recomputed; the declared-motion check still runs on a
kept verdict; ``SCREWKIT_MOTION_CACHE=0`` keeps nothing.

The independent reference is :func:`screwkit.engine._motion._compute` run on the model in
this process (the classification itself is tested against hand derivations in
tests/test_finite_motion.py)."""

import dataclasses
import json

import numpy as np
import pytest

import screwkit
from screwkit.engine import _motion, _motion_cache
from screwkit.errors import CatalogError
from screwkit.pm import load_pm


@pytest.fixture
def disk(tmp_path, monkeypatch):
    """An empty folder of kept verdicts; the in-process caches emptied around the test."""
    monkeypatch.setattr(_motion_cache, "_folder", lambda: str(tmp_path / "motion"))
    monkeypatch.setenv("SCREWKIT_MOTION_CACHE", "1")
    _motion._BY_CONTENT.clear()
    yield tmp_path / "motion"
    _motion._BY_CONTENT.clear()


def _fresh(model):
    """The model's finite motion, the in-process caches bypassed (a copy of the model)."""
    _motion._BY_CONTENT.clear()
    return _motion.finite_motion(dataclasses.replace(model))


def _identical(a, b):
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        assert type(x) is type(y), f.name
        if isinstance(y, np.ndarray):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), f.name
        else:
            assert x == y, f.name


def test_a_kept_verdict_is_the_computed_one_bit_for_bit(disk):
    for name in ("3RRPRR", "3UPU/spherical", "4UPU"):     # no array, a centre, an axis
        model = load_pm(name)
        first = _fresh(model)                       # computed and kept
        assert len(list(disk.glob("*.json"))) >= 1
        computed = _motion._compute(model)
        _identical(first, computed)
        kept = _fresh(model)                        # read back from the file
        _identical(kept, computed)


def test_another_model_or_constant_is_another_file(disk, monkeypatch):
    model = load_pm("3RRPRR")
    constants = (_motion.AMPLITUDE_DEG, _motion.AMPLITUDE_LENGTH, _motion.STEP, 1e-7, 1e-5)
    d0 = _motion_cache.model_digest(model, constants)
    assert d0 == _motion_cache.model_digest(dataclasses.replace(model), constants)
    longer = load_pm("3RRPRR", {"L": 130.0})
    assert _motion_cache.model_digest(longer, constants) != d0
    moved = dataclasses.replace(model, home_pose={**model.home_pose,
                                                  "Zo": model.home_pose["Zo"] + 1e-9})
    assert _motion_cache.model_digest(moved, constants) != d0
    assert _motion_cache.model_digest(model, constants[:-1] + (2e-5,)) != d0
    _fresh(model)
    monkeypatch.setattr(_motion, "STEP", 2e-3)       # a constant changed at the call
    _fresh(model)
    assert len(list(disk.glob("*.json"))) == 2


def test_a_bad_file_is_recomputed(disk):
    model = load_pm("3RRPRR")
    good = _fresh(model)
    (path,) = disk.glob("*.json")
    for text in ("{not json", json.dumps({"digest": "another", "motion": {}}),
                 json.dumps({"digest": path.stem, "motion": {"label": "3T"}})):
        path.write_text(text)
        _identical(_fresh(model), good)
    _identical(_fresh(model), good)                 # and kept again


def test_the_declared_motion_is_checked_on_a_kept_verdict(disk, tmp_path):
    from test_finite_motion import DECLARED
    path = tmp_path / "wrong.yaml"
    path.write_text(DECLARED.replace("MOTION", "3T"))
    for _ in range(2):                              # computed, then kept
        _motion._BY_CONTENT.clear()
        with pytest.raises(CatalogError, match="declares motion 3T.*computed from home is 1T2R"):
            screwkit.load_pm(str(path))
    assert len(list(disk.glob("*.json"))) == 1


def test_switched_off_nothing_is_kept(disk, monkeypatch):
    monkeypatch.setenv("SCREWKIT_MOTION_CACHE", "0")
    _fresh(load_pm("3RRPRR"))
    assert not disk.exists() or not list(disk.glob("*.json"))
