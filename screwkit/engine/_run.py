"""The engine's driver: N poses in chunks, optionally on threads (private).

Poses are processed in chunks of :data:`CHUNK` (the working arrays of a chunk
stay in the processor's cache, and the memory of a run stays linear in N
with a small constant); with ``workers > 1`` chunks run on a thread pool (numpy
releases the interpreter lock inside its loops).  Each chunk is solved,
then its rows, conditioning and statics are formed; only compact arrays are kept.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from ._chains import chains_of, forward
from ._pipeline import (Conditioning, condition, model_rows, statics_values, templates_of,
                        workload_about_origin, _labels)
from ._solve import Closures, solve_closures, solve_path

__all__ = ["CHUNK", "Computed", "compute"]

#: Poses per chunk.
CHUNK = 4096


@dataclass(frozen=True, eq=False)
class Computed:
    """Compact arrays of N poses (poses first): the closures; and, when rows were asked
    for, ``J (N, m, 6)``, ``scale``, ``points (N, m, 3)``, the conditioning, ``values``
    (statics, when a workload was given) and ``W``."""

    closures: Closures
    info: tuple
    n_actuated: int
    J: np.ndarray = None
    scale: np.ndarray = None
    points: np.ndarray = None
    origin: np.ndarray = None
    platform_points: np.ndarray = None
    conditioning: Conditioning = None
    rows_ok: np.ndarray = None
    structure_ok: np.ndarray = None
    values: np.ndarray = None
    W: np.ndarray = None
    diagnostics: dict = None


def _chunks(N, size):
    return [slice(s, min(s + size, N)) for s in range(0, N, size)]


def compute(model, fixed: dict, *, X0=None, side=None, path=False, anchor_every=None,
            rows=True, F=None, T=None, chunk=CHUNK, workers=None, progress=None) -> Computed:
    """Solve and (``rows``) form the Jacobian rows, conditioning and statics of N poses."""
    ch = chains_of(model)
    N = len(next(iter(fixed.values())))
    templates = templates_of(model) if rows else None
    diag = {}
    if path:
        c = solve_path(model, fixed, X0, anchor_every=anchor_every, progress=progress)
        X, res, its, how, sing = c.X, c.residual, c.iterations, c.how, c.singular_beta
        diag = dict(c.diagnostics)
    slices = _chunks(N, max(1, int(chunk)))

    def work(sl):
        fx = {k: v[sl] for k, v in fixed.items()}
        if path:
            fr = forward(ch, fx, X[:, sl])
            part = {"X": X[:, sl], "residual": fr.residual, "iterations": its[sl],
                    "how": how[sl], "sing": sing[sl]}
        else:
            cl = solve_closures(model, fx, None if X0 is None else X0[:, sl],
                                side=None if side is None else side[sl])
            fr = cl.frames
            part = {"X": cl.X, "residual": cl.residual, "iterations": cl.iterations,
                    "how": cl.how, "sing": cl.singular_beta}
        if rows:
            r = model_rows(model, fr, templates)
            cond, Jn, d = condition(r.J, r.n_actuated, r.leg_points)
            o = fr.o.T
            a = np.einsum("ijn,kj->nki", fr.R_p, model.platform_points) + o[:, None]
            part.update(J=r.J, scale=r.scale, points=r.points, origin=o, a=a, cond=cond,
                        rows_ok=r.ok, structure_ok=r.structure_ok)
            if F is not None:
                n = len(sl.indices(N)) if False else (sl.stop - sl.start)
                W = workload_about_origin(np.broadcast_to(F, (n, 3)), np.broadcast_to(T, (n, 3)), o)
                part.update(values=statics_values(Jn, d, cond.singular_values, cond, W), W=W)
        return part

    nw = workers if workers is not None else (min(2, os.cpu_count() or 1) if N >= 4 * chunk
                                              else 1)
    if nw > 1 and len(slices) > 1:
        with ThreadPoolExecutor(max_workers=nw) as pool:
            parts = []
            for k, p in enumerate(pool.map(work, slices)):
                parts.append(p)
                if progress and not path:
                    progress(slices[k].stop, N)
    else:
        parts = []
        for sl in slices:
            parts.append(work(sl))
            if progress and not path:
                progress(sl.stop, N)

    def cat(key, axis=0):
        return np.concatenate([p[key] for p in parts], axis=axis)

    closures = Closures(ch, cat("X", 1), {k: np.asarray(v, float) for k, v in fixed.items()},
                        cat("residual"), cat("iterations"), cat("how"), cat("sing"))
    if not rows:
        return Computed(closures, (), ch.n, diagnostics=diag)
    conds = [p["cond"] for p in parts]
    cond = Conditioning(*(np.concatenate([getattr(c, f) for c in conds])
                          for f in Conditioning.__dataclass_fields__))
    vals = cat("values") if F is not None else None
    W = cat("W") if F is not None else None
    return Computed(closures, _labels(templates), ch.n, cat("J"), cat("scale"), cat("points"),
                    cat("origin"), cat("a"), cond, cat("rows_ok"), cat("structure_ok"), vals, W,
                    diag)
