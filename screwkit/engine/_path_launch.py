"""A path's levels solved in launches of the analysis kernel (private): the inputs' buffers
and the path's state that the compiled level loop (``_kernels._path_loop``) reads and
writes, and Python between its launches (:func:`screwkit.engine._path.solve_path`)."""

from __future__ import annotations

import numpy as np

from ._kernels import kernels
from ._kernels._layout import (LH_BUDGET, LH_FILL, LH_N, LH_RETRY, LH_SIZE, LH_TEAM, LV_IDX,
                               LV_ROWS)
from ._launch import BLOCKS_ALONE, BLOCKS_LOADING, _launch, _plan, run_poses
from ._memory import recycled_empty

__all__ = ["LevelLaunches"]


class LevelLaunches:
    """A path's levels solved in launches of the parallel kernel, the level loop compiled
    (``_kernels._path_loop``): the inputs' buffers (room for a level of every sample: its
    given parameters, starts, rows of the outputs and stencils), and the path's state, which
    Python reads and writes between the launches through views: ``res (N,)`` the residuals,
    ``solved, iterations, how, singular, kept (N,)`` (int64; ``kept``: the sample's rows,
    formed in its level's launch, stay).  :meth:`run` solves levels until every sample is
    solved, a level has samples to solve again, or the budget is reached.

    ``buffers``: the path's outputs (:func:`output_buffers` of ``N`` poses with the
    ``excess``), written by the levels' launches in their samples' rows; ``N`` the samples,
    whose given parameters the caller writes into :attr:`P6`; ``compliance`` one row for
    all or one a sample."""

    def __init__(self, flat, Z, buffers, N, *, F=None, T=None, compliance=None,
                 rows=True, twists=False, lines=False):
        statics = F is not None
        kind = (bool(rows), bool(rows and statics), bool(twists), bool(lines), True)
        if buffers.kind != kind or buffers.N != N:
            raise ValueError(f"output buffers of {buffers.N} poses {buffers.kind} do not take "
                             f"a path of {N} samples {kind}")
        comp = None if compliance is None else np.atleast_2d(np.asarray(compliance, float))
        own = comp is not None and comp.shape[0] == N and N > 1
        ncomp = N if own else (0 if comp is None else comp.shape[0])
        plan = _plan(flat, N, N, 0, ncomp, True, bool(rows), statics, True, bool(twists),
                     bool(lines), N, N, True)
        self.flat, self.Z, self.buffers, self.N = flat, Z, buffers, N
        self.F, self.T, self.compliance, self.kind = F, T, comp, kind
        # (recycled memory, as the outputs: every value the kernels read is written first)
        self.If = recycled_empty(plan.in_nf)
        (_, _, _), _, _, (f0, f1, _), (t0, t1, _), (c0, c1, csh) = plan.in_f
        self.If[f0:f1] = 0.0 if F is None else F
        self.If[t0:t1] = 0.0 if T is None else T
        if comp is not None and not own:
            self.If[c0:c1].reshape(csh)[...] = comp
        self.Ii, self.Id, self.flags = plan.in_i.copy(), plan.in_d, plan.flags
        r0 = plan.in_rows
        s0, s1, ssh = plan.in_stencil
        #: the level left to Python's retries: its samples and their stencils
        self.level_rows, self.level_stencils = self.Ii[r0:r0 + N], self.If[s0:s1].reshape(ssh)
        self.Lf = recycled_empty(7 * N + (comp.size if own else 0))
        #: the samples' given parameters ``(N, 6)``, which the caller writes
        self.P6 = self.Lf[:6 * N].reshape(N, 6)
        self.res = self.Lf[6 * N:7 * N]
        self.res[...] = np.inf
        if own:
            self.Lf[7 * N:] = comp.ravel()
        self.Li = recycled_empty(LH_SIZE + LV_ROWS * N, np.int64)
        self.Li[:LH_SIZE] = 0
        self.Li[LH_N] = N
        # the levels on a team of threads that wait for each other only where each range of
        # a launch has a thread of its own (numba's workqueue layer; a work-stealing layer
        # could run two ranges on one thread, one waiting for the other)
        self.Li[LH_TEAM] = kernels().numba.config.THREADING_LAYER == "workqueue"
        V = self.Li[LH_SIZE:].reshape(LV_ROWS, N)
        V[:LV_IDX] = 0                          # (the loop's scratch: written before read)
        self.solved, self.iterations, self.how, self.singular, self.kept = V[:LV_IDX]

    def solve_at(self, idx, workers=None) -> tuple:
        """The samples ``idx`` solved from home (the predictor), their rows formed as the
        levels' launches form theirs, into their rows of the outputs.  Returns their
        ``(X (nx, K), residual, iterations, how, singular)`` (copies)."""
        comp = self.compliance
        if comp is not None and comp.shape[0] == self.N and self.N > 1:
            comp = comp[idx]
        rows, statics, twists, lines, _ = self.kind
        o = run_poses(self.flat, self.Z, self.P6[idx], F=self.F, T=self.T, compliance=comp,
                      rows=rows, statics=statics, twists=twists, lines=lines,
                      workers=workers, out=(self.buffers, idx))
        return (o["X"][idx].T, o["residual"][idx], o["iterations"][idx], o["how"][idx],
                o["singular_beta"][idx].astype(bool))

    @property
    def filling(self) -> bool:
        """Whether the levels have come to the fill (``_kernels._path_loop``)."""
        return bool(self.Li[LH_FILL])

    def run(self, budget: int, workers=None) -> int:
        """Solve levels until every sample is solved, or to the end of the level that
        reaches ``budget`` samples, or of a level with samples to solve again: returns their
        level's size ``G`` (0 otherwise), its samples ``level_rows[:G]``, not marked solved
        (their results are in the state), their stencils ``level_stencils[:G]``."""
        k = kernels()
        self.Li[LH_BUDGET] = max(1, int(budget))
        self.Li[LH_RETRY] = 0
        Mp, Zp = self.flat.pack(self.Z)
        b = self.buffers
        N = self.N
        # on threads and in blocks as a launch of the path's samples would be
        _launch(k.run_range, k.run_parallel, Mp.args + Zp.args + (
            self.If, self.Ii, self.Id, b.f, b.i, b.d, self.flags), N, workers, note=True,
            pieces=True, path=(self.Lf, self.Li), blocks=N >= BLOCKS_ALONE and (
                bool(k.run_parallel.overloads) or N >= BLOCKS_LOADING))
        return int(self.Li[LH_RETRY])
