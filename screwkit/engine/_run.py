"""The engine's driver: N poses in chunks, optionally on threads (private).

Poses are processed in chunks of :data:`CHUNK` (the working arrays of a chunk
stay in the processor's cache, and the memory of a run stays linear in N
with a small constant); with ``workers > 1`` chunks run on a thread pool (numpy
releases the interpreter lock inside its loops).  Each chunk is solved,
then its rows, conditioning and statics are formed; only compact arrays are kept.
"""

from __future__ import annotations

import os
from functools import partial
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from ._chains import chains_of, forward
from ._pipeline import (Conditioning, _labels, condition, default_compliance,
                        equilibrium_residual, model_rows,
                        statics_values, templates_of, workload_about_origin)
from ._path import balanced_chunk, solve_path
from ._solve import Closures, solve_closures

__all__ = ["CHUNK", "Computed", "compute"]

#: Poses per chunk.
CHUNK = 8192


@dataclass(frozen=True, eq=False)
class Computed:
    """Compact arrays of N poses (poses first): the closures; and, when rows were asked
    for, ``J (N, m, 6)``, ``scale (N, m)``, the conditioning, the validity of the rows and
    of each leg's structure, and, with a workload, the values ``F_r`` and the equilibrium
    residuals."""

    closures: Closures
    info: tuple
    n_actuated: int
    J: np.ndarray = None
    scale: np.ndarray = None
    conditioning: Conditioning = None
    rows_ok: np.ndarray = None
    structure_ok: np.ndarray = None
    values: np.ndarray = None
    equilibrium: np.ndarray = None
    diagnostics: dict = None


def _chunks(N, size):
    return [slice(s, min(s + size, N)) for s in range(0, N, size)]


def row_points(model, closures: Closures, chunk: int = CHUNK) -> np.ndarray:
    """A point of each row's line at every pose of ``closures``, ``(N, m, 3)`` (recomputed)."""
    templates = templates_of(model)
    N = closures.residual.shape[0]
    out = None
    for sl in _chunks(N, chunk):
        r = model_rows(model, closures.frames(sl), templates)
        if out is None:
            out = np.empty((N,) + r.points.shape[1:])
        out[sl] = r.points
    return out


def _rows_part(model, fr, templates, fx, F, T, compliance) -> dict:
    """The rows, conditioning and (with a workload) statics of one chunk's frames."""
    r = model_rows(model, fr, templates)
    cond, Jn, d = condition(r.J, r.n_actuated, r.centre, r.length)
    part = {"J": r.J, "scale": r.scale, "rows_ok": r.ok, "structure_ok": r.structure_ok}
    part.update({f"cond.{f}": getattr(cond, f) for f in Conditioning.__dataclass_fields__})
    if F is not None:
        n = len(next(iter(fx.values())))
        o = fr.o.T
        W = workload_about_origin(np.broadcast_to(F, (n, 3)), np.broadcast_to(T, (n, 3)), o)
        comp = compliance if compliance is not None else default_compliance(r.info,
                                                                              cond.length)
        values = statics_values(Jn, d, cond.singular_values, cond, W, comp)
        eq = equilibrium_residual(r.J, values, W, cond.centre, cond.length)
        part.update(values=values, equilibrium=eq)
    return part


def chunk_after_path(model, fx, X, path_res, rows=True, F=None, T=None, compliance=None):
    """Frames' residual and (``rows``) rows and statics of one chunk of a solved path.

    A pose the solver gave up (``path_res`` inf: e.g. an unreachable side of a
    representation singularity) stays unreachable whatever its frames' residual."""
    fr = forward(chains_of(model), fx, X)
    res = np.where(np.isfinite(path_res), fr.residual, np.inf)
    part = _rows_part(model, fr, templates_of(model), fx, F, T, compliance) if rows else None
    return res, part


def _chunk_task(model, rows, F, T, compliance, item):
    fx, X, path_res = item
    return chunk_after_path(model, fx, X, path_res, rows, F, T, compliance)


def compute(model, fixed: dict, *, X0=None, side=None, path=False, anchor_every=None,
            rows=True, F=None, T=None, chunk=CHUNK, workers=None, progress=None,
            compliance=None, mapper=None) -> Computed:
    """Solve and (``rows``) form the Jacobian rows, conditioning and statics of N poses.

    The outputs are allocated once and filled chunk by chunk (no concatenation).
    ``progress(done, total)``: ``total = N``, or ``2 N`` for a path with rows (its closures
    are solved first, then the rows and statics of every chunk).  ``mapper(fn, items)``
    (a path only): computes ``[fn(x) for x in items]`` elsewhere, e.g. on a Dask cluster;
    the path's closures are solved here, its chunks' rows and statics by the mapper."""
    ch = chains_of(model)
    N = len(next(iter(fixed.values())))
    templates = templates_of(model) if rows else None
    diag = {}
    steps = 2 * N if path and rows else N          # a path: the closures, then the rows
    if path:
        c = solve_path(model, fixed, X0, anchor_every=anchor_every, workers=workers,
                       progress=(lambda d, n: progress(d, steps)) if progress else None)
        X, its, how, sing, path_res = c.X, c.iterations, c.how, c.singular_beta, c.residual
        diag = dict(c.diagnostics)
    else:
        X = np.empty((ch.n_unknowns, N))
        its, how, sing = np.empty(N, np.int32), np.empty(N, np.int8), np.empty(N, bool)
    res = np.empty(N)
    out = {}
    chunk = max(1, int(chunk))
    nw = workers if workers is not None else (min(2, os.cpu_count() or 1) if N >= 4 * chunk
                                              else 1)
    # the default chunk is balanced over the threads; a chunk the caller chose is kept
    size = balanced_chunk(N, chunk, nw if mapper is None else 1) if chunk == CHUNK else chunk
    slices = _chunks(N, size)

    def put(key, sl, value):
        if key not in out:
            out[key] = np.empty((N,) + value.shape[1:], value.dtype)
        out[key][sl] = value

    def work(sl):
        fx = {k: v[sl] for k, v in fixed.items()}
        if path:
            r_sl, part = chunk_after_path(model, fx, X[:, sl], path_res[sl], rows, F, T,
                                          compliance)
            res[sl] = r_sl
            return part
        cl = solve_closures(model, fx, None if X0 is None else X0[:, sl],
                            side=None if side is None else side[sl])
        X[:, sl], its[sl], how[sl], sing[sl] = cl.X, cl.iterations, cl.how, cl.singular_beta
        res[sl] = cl.residual
        return _rows_part(model, cl.frames, templates, fx, F, T, compliance) if rows else None

    def store(sl, part):
        if part is not None:
            for key, value in part.items():
                put(key, sl, value)

    if mapper is not None and path:
        # the chunks of a solved path are independent: the same function on the same
        # inputs wherever it runs, so the result equals the serial one bit for bit
        items = [({k: v[sl] for k, v in fixed.items()}, X[:, sl], path_res[sl]) for sl in slices]
        fn = partial(_chunk_task, model, rows, F, T, compliance)
        for sl, (r_sl, part) in zip(slices, mapper(fn, items)):
            res[sl] = r_sl
            store(sl, part)
        if progress:
            progress(steps, steps)
    elif nw > 1 and len(slices) > 1:
        with ThreadPoolExecutor(max_workers=nw) as pool:
            for sl, part in zip(slices, pool.map(work, slices)):
                store(sl, part)
                if progress and (rows or not path):
                    progress(steps - N + sl.stop, steps)
    else:
        for sl in slices:
            store(sl, work(sl))
            if progress and (rows or not path):
                progress(steps - N + sl.stop, steps)
    closures = Closures(ch, X, {k: np.asarray(v, float) for k, v in fixed.items()}, res, its,
                        how, sing)
    if not rows:
        return Computed(closures, (), len(ch.active), diagnostics=diag)
    cond = Conditioning(*(out[f"cond.{f}"] for f in Conditioning.__dataclass_fields__))
    return Computed(closures, _labels(templates), len(ch.active), out["J"], out["scale"], cond,
                    out["rows_ok"], out["structure_ok"], out.get("values"),
                    out.get("equilibrium"), diag)
