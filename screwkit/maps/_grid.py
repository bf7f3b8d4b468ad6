"""The cells of a map: a grid of independent pose parameters, or random samples in a box.

A :class:`Grid` is what :func:`screwkit.maps.map_pm` evaluates: 1 to 3 independent pose
parameters on a regular grid (``{"alpha": (-10, 10, 41), "Zo": [60, 70, 80]}``: a
``(start, stop, count)`` triple or explicit values), the other independent parameters
fixed (``fix``, else the model's default pose), or ``samples`` random poses uniform in a box
(``{"alpha": (-10, 10), ...}``: low and high).  Angles are in radians unless
``degrees=True``; lengths in the model's unit.  The cells are flattened in C order (the
last grid parameter varies fastest), which is also the order of the pose axis that the
engine sees.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..engine import LENGTH_PARAMS, PARAMS
from ..errors import InputError

__all__ = ["Grid", "make_grid", "MAX_CELLS", "MAX_GRID_DIMS", "parse_range"]

#: Largest number of cells of one map (about 0.5 kB of results per cell).
MAX_CELLS = 10_000_000
#: At most this many grid parameters.
MAX_GRID_DIMS = 3


@dataclass(frozen=True, eq=False)
class Grid:
    """The cells of a map (see the module docstring).

    Attributes
    ----------
    dims : tuple of str
        The grid parameters (``("sample",)`` for random samples).
    coords : dict str -> ndarray
        The values of each grid parameter, in the units given (``degrees``): ``(count,)``
        per grid parameter, or ``(N,)`` per sampled parameter along ``sample``.
    fixed : dict str -> float
        The other independent parameters, in the units given.
    defaults : tuple of str
        The independent parameters taken from the model's default pose.
    degrees : bool
        Angles of ``coords`` and ``fixed`` in degrees.
    samples : bool
        Random samples in a box (no neighbours: no singular loci).
    seed : int or None
    box : dict str -> (low, high), optional
        The sampling box of random samples (in the units given).
    """

    dims: tuple
    coords: dict
    fixed: dict
    defaults: tuple
    degrees: bool
    samples: bool = False
    seed: int | None = None
    box: dict | None = None

    @property
    def shape(self) -> tuple:
        if self.samples:
            return (len(next(iter(self.coords.values()))),)
        return tuple(len(self.coords[d]) for d in self.dims)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    @property
    def params(self) -> tuple:
        """The varied parameters (grid or sampled)."""
        return tuple(self.coords)

    def _to_api(self, name, v):
        v = np.asarray(v, float)
        return np.radians(v) if (self.degrees and name not in LENGTH_PARAMS) else v

    def poses(self, sl: slice = slice(None)) -> dict:
        """The independent parameters of the cells ``sl`` of the flattened grid, radians and
        model lengths, ``(n,)`` each (the engine's input)."""
        idx = np.arange(*sl.indices(self.size))
        out = {}
        if self.samples:
            for k, v in self.coords.items():
                out[k] = self._to_api(k, v[idx])
        else:
            sub = np.unravel_index(idx, self.shape)
            for k, ix in zip(self.dims, sub):
                out[k] = self._to_api(k, self.coords[k][ix])
        for k, v in self.fixed.items():
            out[k] = np.full(idx.size, float(self._to_api(k, v)))
        return out

    def pose_of(self, flat: int) -> dict:
        """The independent parameters of one cell in the units given (degrees for angles
        when ``degrees``)."""
        p = self.poses(slice(flat, flat + 1))
        return {k: float(np.degrees(v[0]) if (self.degrees and k not in LENGTH_PARAMS)
                         else v[0]) for k, v in p.items()}


def parse_range(text: str, what: str = "--grid", *, pose: bool = True,
                max_count: int | None = None):
    """``"NAME=START:STOP:COUNT"`` -> ``(NAME, (start, stop, count))``; ``"NAME=LOW:HIGH"``
    -> ``(NAME, (low, high))`` (a sampling box).  With ``pose`` (a pose parameter given at
    the command line, angles in degrees) an angle beyond +-3600 deg is refused here with
    that limit; otherwise (a model dimension) numbers are bounded by the general
    magnitude limit.  ``max_count``: the largest COUNT (default the cells of a map)."""
    from ..legs._guards import (MAX_ANGLE_DEG, MAX_MAGNITUDE, MAX_NAME, parse_int,
                                parse_number, shorten)
    name, sep, rng = str(text).partition("=")
    name = name.strip()
    if not sep or not name:
        raise InputError(f"{what} {shorten(text)} must look like NAME=START:STOP:COUNT")
    if len(name) > MAX_NAME or not name.isidentifier():
        raise InputError(f"{what} {shorten(name)}: not a pose parameter name")
    parts = rng.split(":")
    if len(parts) not in (2, 3):
        raise InputError(f"{what} {name}: {shorten(rng)} must be START:STOP:COUNT (or LOW:HIGH "
                         "for --samples)")
    angle = pose and name in PARAMS and name not in LENGTH_PARAMS
    nums = [parse_number(p, f"{what} {name} {w}", bound=None if angle else MAX_MAGNITUDE)
            for p, w in zip(parts[:2], ("START", "STOP"))]
    for x, w in zip(nums, ("START", "STOP")):
        if angle and not abs(x) <= MAX_ANGLE_DEG:
            raise InputError(f"{what} {name} {w}: {x:g} deg is beyond the limit "
                             f"+-{MAX_ANGLE_DEG:g} deg")
    if len(parts) == 3:
        nums.append(parse_int(parts[2], f"{what} {name} COUNT", 1,
                              MAX_CELLS if max_count is None else max_count))
    return name, tuple(nums)


def _values(name, spec, model, degrees):
    from ..legs._guards import real, real_array
    if isinstance(spec, tuple) and len(spec) == 3 and isinstance(spec[2], (int, np.integer)) \
            and not isinstance(spec[2], bool):
        a, b, n = spec
        what = f"{model.name}: grid {name}"
        a, b = (real(x, f"{what} {w}") for x, w in ((a, "start"), (b, "stop")))
        if not 1 <= n <= MAX_CELLS:
            raise InputError(f"{what}: the count must be 1 to {MAX_CELLS}, got {n}")
        if n > 1 and a == b:
            raise InputError(f"{what}: {n} values from {a:g} to {b:g} repeat one value (give a "
                             "count of 1, or a stop other than the start)")
        _within(model, name, np.array([a, b]), degrees, f"grid {name}")
        return np.linspace(a, b, int(n))
    if isinstance(spec, tuple) and len(spec) == 3:
        # a 3-tuple is (start, stop, count): a count that is not an integer is a mistake, not
        # three values ((-5, 5, 3.0) read as the values -5, 5, 3, unsorted); a list is values
        raise InputError(f"{model.name}: grid {name} {spec!r:.60}: a tuple is (start, stop, "
                         "count) with an integer count; give values as a list or an array")
    v = real_array(spec, f"{model.name}: grid {name}", max_size=MAX_CELLS)
    if v.ndim != 1 or v.size == 0:
        raise InputError(f"{model.name}: grid {name}: the values must be a non-empty 1-D "
                         "array of finite numbers")
    if v.size > 1 and np.unique(v).size != v.size:
        raise InputError(f"{model.name}: grid {name}: the values repeat (a map's axis takes "
                         "each value once)")
    _within(model, name, v, degrees, f"grid {name}")
    return v


def _within(model, name, values, degrees, what) -> None:
    """Pose values within the engine's limits (angles +-3600 deg, lengths 1e12 model sizes),
    checked where the grid is made: a map of out-of-range cells is refused at once."""
    from ..legs._guards import MAX_ANGLE_DEG, MAX_LENGTH_FACTOR
    m = float(np.max(np.abs(values))) if np.size(values) else 0.0
    if name in LENGTH_PARAMS:
        lim = MAX_LENGTH_FACTOR * float(model.normalisation.length)
        unit = ""
    else:
        lim = MAX_ANGLE_DEG if degrees else float(np.radians(MAX_ANGLE_DEG))
        unit = " deg" if degrees else " rad"
    if not m <= lim:
        raise InputError(f"{model.name}: {what}: {m:g}{unit} is beyond the limit "
                         f"+-{lim:g}{unit}")


def _shown_degrees(rad: float) -> float:
    """``rad`` in degrees, written short (-3 rather than -3.0000000000000004) when the short
    value converts back to the same radians bit for bit (the cells are unchanged)."""
    deg = float(np.degrees(rad))
    short = round(deg, 10)
    return short if float(np.radians(short)) == rad else deg


def _check_name(model, name, what):
    if name not in PARAMS:
        raise InputError(f"{model.name}: {what} {name!r} is not a pose parameter (one of "
                         f"{', '.join(PARAMS)})")
    if name not in model.independent:
        raise InputError(f"{model.name}: {what} {name} is a dependent pose parameter; the "
                         f"independent ones are {', '.join(model.independent)}")


def make_grid(model, grid, fix=None, *, samples=None, seed=0, degrees=False) -> Grid:
    """Validate a map's cells (see the module docstring) and return a :class:`Grid`.

    Parameters
    ----------
    model : PMModel
    grid : mapping str -> (start, stop, count) or array_like, or (with ``samples``)
        str -> (low, high)
    fix : mapping str -> float, optional
    samples : int, optional
        Random poses, uniform in the box ``grid``.
    seed : int
        Seed of the random samples (reproducible maps).
    degrees : bool

    Raises
    ------
    InputError
        Unknown or dependent parameters, a parameter both varied and fixed, more than
        three grid parameters, more than :data:`MAX_CELLS` cells.
    """
    if not isinstance(grid, dict) or not grid:
        raise InputError(f"{model.name}: a map needs at least one grid parameter, e.g. "
                         "{'alpha': (-10, 10, 41)}")
    fix = dict(fix or {})
    for k in grid:
        _check_name(model, k, "grid parameter")
    for k, v in fix.items():
        _check_name(model, k, "fixed parameter")
        if k in grid:
            raise InputError(f"{model.name}: {k} is both a grid parameter and fixed")
        from ..legs._guards import real
        v = real(v, f"{model.name}: fixed parameter {k}")
        _within(model, k, np.array([v]), degrees, f"fixed parameter {k}")
        fix[k] = v
    defaults = tuple(p for p in model.independent if p not in grid and p not in fix)
    for p in defaults:
        d = float(model.default_pose[p])
        fix[p] = _shown_degrees(d) if (degrees and p not in LENGTH_PARAMS) else d
    fix = {p: float(fix[p]) for p in model.independent if p in fix}
    if samples is not None:
        from ..legs._guards import MAX_SEED
        if isinstance(samples, (bool, np.bool_)) or not isinstance(samples, (int, np.integer)) \
                or not 1 <= samples <= MAX_CELLS:
            raise InputError(f"{model.name}: samples must be an integer from 1 to {MAX_CELLS}, "
                             f"got {samples!r:.40}")
        if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or \
                not 0 <= seed <= MAX_SEED:
            raise InputError(f"{model.name}: seed must be an integer from 0 to {MAX_SEED}, got "
                             f"{seed!r:.40}")
        rng = np.random.default_rng(int(seed))
        coords, box = {}, {}
        for k, side in grid.items():
            try:
                lo, hi = (float(x) for x in side)
            except (TypeError, ValueError):
                raise InputError(f"{model.name}: sampling box {k}: give (low, high), got "
                                 f"{side!r}") from None
            if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
                raise InputError(f"{model.name}: sampling box {k}: need finite low <= high")
            _within(model, k, np.array([lo, hi]), degrees, f"sampling box {k}")
            coords[k] = rng.uniform(lo, hi, int(samples))
            box[k] = (lo, hi)
        return Grid(("sample",), coords, fix, defaults, bool(degrees), True, int(seed), box)
    if len(grid) > MAX_GRID_DIMS:
        raise InputError(f"{model.name}: a map has 1 to {MAX_GRID_DIMS} grid parameters, got "
                         f"{len(grid)} (fix the others, or use samples)")
    dims = tuple(grid)                      # the caller's order: the first is the x axis
    coords = {k: _values(k, grid[k], model, degrees) for k in dims}
    size = int(np.prod([len(v) for v in coords.values()], dtype=float))
    if size > MAX_CELLS:
        raise InputError(f"{model.name}: the grid has {size} cells, more than {MAX_CELLS}")
    return Grid(dims, coords, fix, defaults, bool(degrees))
