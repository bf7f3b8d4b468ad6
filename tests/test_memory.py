"""Arrays filled once without numpy's huge-page advice (``engine/_memory.fresh_array``)."""

import mmap
import pickle

import numpy as np
import pytest

import screwkit
from screwkit.engine import _memory
from screwkit.engine._memory import ADVISED_BYTES, fresh_array


@pytest.mark.parametrize("order", ["C", "F"])
def test_a_large_array_has_its_own_mapping_and_behaves_as_numpys(order):
    shape = (ADVISED_BYTES // 8 // 3 + 7, 3)               # just over the threshold
    a = fresh_array(shape, np.float64, order=order)
    assert isinstance(a.base, mmap.mmap)
    assert a.shape == shape and a.dtype == np.float64 and a.flags.writeable
    assert a.flags.f_contiguous if order == "F" else a.flags.c_contiguous
    ref = np.arange(np.prod(shape), dtype=float).reshape(shape)
    a[...] = ref
    assert np.array_equal(a, ref)
    assert np.array_equal(pickle.loads(pickle.dumps(a)), ref)


def test_a_small_array_is_numpys_own():
    a = fresh_array((10, 4), np.int8, order="F")
    assert a.base is None and a.flags.f_contiguous and a.dtype == np.int8
    b = fresh_array(5, bool)
    assert b.shape == (5,) and b.dtype == bool


def test_a_map_filled_into_mapped_arrays_equals_one_filled_into_numpys(monkeypatch, tmp_path):
    """Every array of a map above a threshold of one byte (all of them mapped) equals the
    same map's arrays in numpy's own memory, and so does the map written to netCDF and read
    back."""
    pytest.importorskip("xarray")
    grid = {"alpha": (-10.0, 10.0, 5), "beta": (-10.0, 10.0, 4), "Zo": (60.0, 90.0, 3)}
    load = dict(force=(0.0, 0.0, -1.0), torque=(0.0, 0.0, 0.0))
    plain = screwkit.map("3RRPRR", grid, degrees=True, **load)
    monkeypatch.setattr(_memory, "ADVISED_BYTES", 1)
    mapped = screwkit.map("3RRPRR", grid, degrees=True, **load)
    assert set(plain.data_vars) == set(mapped.data_vars)
    for name in plain.data_vars:
        assert np.array_equal(plain[name].values, mapped[name].values, equal_nan=True), name
    import xarray as xr
    back = xr.open_dataset(screwkit.maps.write(mapped, tmp_path / "m.nc")).load()
    for name in ("F_a1", "condition_number", "level", "iti"):
        assert np.array_equal(back[name].values, plain[name].values, equal_nan=True), name
