"""Arrays filled once without numpy's huge-page advice (``engine/_memory.fresh_array``), and
the recycled memory of the analysis kernel's outputs (``engine/_memory.Recycler``)."""

import gc
import mmap
import pickle

import numpy as np
import pytest

import screwkit
from screwkit.engine import _memory
from screwkit.engine._memory import ADVISED_BYTES, RECYCLED_BYTES, RECYCLER, Recycler, fresh_array

from random_poses import random_pose


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


def test_memory_comes_back_when_its_last_view_goes_and_serves_the_same_size():
    r = Recycler(limit=64 * RECYCLED_BYTES)
    n = RECYCLED_BYTES // 8 + 3                    # not a whole number of pages
    a = r.empty(n)
    assert a.shape == (n,) and a.dtype == np.float64 and a.flags.writeable
    where = a.ctypes.data
    v = a[5:9].reshape(2, 2)
    del a
    gc.collect()
    assert r.kept_bytes == 0                       # a view still holds it
    del v
    gc.collect()
    size = -(-n * 8 // mmap.PAGESIZE) * mmap.PAGESIZE
    assert r.kept_bytes == size
    b = r.empty(n)                                 # the same size: the same memory
    assert b.ctypes.data == where and r.kept_bytes == 0
    c = r.empty(2 * n)                             # another size: fresh memory
    assert c.ctypes.data != where and c.shape == (2 * n,)
    i = r.empty(n, np.int64)                       # the same bytes, another type
    assert i.dtype == np.int64 and i.ctypes.data != where
    small = r.empty(10)
    assert small.base is None                      # numpy's own
    del b, c, i
    gc.collect()
    r.clear()
    assert r.kept_bytes == 0


def test_at_most_the_limit_is_kept_the_oldest_released_first():
    page = mmap.PAGESIZE
    unit = -(-RECYCLED_BYTES // page) * page
    r = Recycler(limit=4 * unit)
    big = r.empty(5 * unit // 8)                   # over the limit: never kept
    del big
    gc.collect()
    assert r.kept_bytes == 0
    a, b = r.empty(unit // 8), r.empty(2 * unit // 8)
    wa, wb = a.ctypes.data, b.ctypes.data
    del a
    gc.collect()
    del b
    gc.collect()
    assert r.kept_bytes == 3 * unit
    c = r.empty(unit // 8 + page // 8)             # a size not kept: the oldest goes, to fit
    assert r.kept_bytes == 2 * unit and c.ctypes.data not in (wa, wb)
    d = r.empty(2 * unit // 8)
    assert d.ctypes.data == wb and r.kept_bytes == 0


def _arrays(res, prefix="", depth=0):
    """Every array a result (and the results it holds) shows, by name."""
    out = {}
    for name in dir(res):
        if name.startswith("_"):
            continue
        try:
            v = getattr(res, name)
        except Exception:                          # (one-pose properties of a batch)
            continue
        if isinstance(v, np.ndarray):
            out[prefix + name] = v.copy()
        elif depth < 1 and type(v).__module__.startswith("screwkit") and not callable(v):
            out.update(_arrays(v, f"{prefix}{name}.", depth + 1))
    return out


@pytest.mark.parametrize("name, kw", [
    ("3RRPRR", {}), ("3RRPRR", {"path": True}), ("2SPS+2SPR", {}), ("3RPS", {}),
    ("6SPS", {}), ("4SPS+SPR", {}), ("2UPR+SPR", {})])
def test_a_result_does_not_depend_on_what_the_recycled_memory_held(name, kw):
    """An analysis whose outputs take memory an earlier one handed back, first filled with
    NaNs and -1s, shows the same values as that earlier one, which had fresh memory: every
    output the results show is written by the analysis."""
    pm = screwkit.load_pm(name)
    n = 3000                                       # outputs of a few MB: recycled
    if kw.get("path"):
        s = np.linspace(0.0, 1.0, n)
        poses = {p: v + 0.05 * np.sin(2 * np.pi * s + k) * (abs(v) if p in ("Xo", "Yo", "Zo")
                                                              else 1.0)
                 for k, (p, v) in enumerate(pm.default_pose.items()) if p in pm.independent}
    else:
        poses = random_pose(pm, n, seed=7)
    RECYCLER.clear()
    first = screwkit.analyze(pm, poses, **kw)
    want = _arrays(first)
    assert want and first.residual.nbytes >= 8 * n
    del first
    gc.collect()
    kept = list(RECYCLER._kept)
    assert kept, "the first analysis handed no memory back"
    for _, raw in kept:
        np.frombuffer(raw, np.uint8)[...] = 0xFF    # NaN as a float, -1 as an integer
    again = screwkit.analyze(pm, poses, **kw)
    assert RECYCLER.kept_bytes < sum(s for s, _ in kept)   # it took the memory back
    got = _arrays(again)
    assert set(got) == set(want)
    for key, v in want.items():
        if v.dtype.kind in "fc":
            assert np.array_equal(got[key], v, equal_nan=True), (name, key)
        else:
            assert np.array_equal(got[key], v), (name, key)
