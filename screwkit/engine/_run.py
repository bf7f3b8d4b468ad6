"""The engine's driver: N poses through the kernels, in launches (private).

Poses are handed to the analysis kernel in launches of up to :data:`CHUNK` poses (a
progress callback is called after each); a launch runs its poses in ``prange`` on up to
``workers`` threads.  Each pose is computed alone, whatever the launch or the thread, so
the results do not change by a bit with either.  The outputs are allocated once for the N
poses and filled in place; only compact arrays are kept.
"""

from __future__ import annotations

import dataclasses
from functools import partial
from typing import NamedTuple

import numpy as np

from ._chains import PARAMS, chains_of
from ._kernels import compile_analysis
from ._kernels._layout import ACCEPTED
from ._launch import output_buffers, run_poses
from ._outputs import owned
from ._path_launch import LevelLaunches
from ._pipeline import Conditioning
from ._templates import labels_of, templates_of
from ._path import solve_path
from ._reversal import actuator_lines, legs_of, resolve
from ._solve import Closures, predictor_of

__all__ = ["CHUNK", "Computed", "compute", "load_block_kernel", "row_points"]

#: Poses per launch (progress is reported after each).
CHUNK = 131072
#: The column of each pose parameter in ``P6``.
_COLUMN = {p: k for k, p in enumerate(PARAMS)}


class Computed(NamedTuple):
    """Compact arrays of N poses (poses first): the closures; and, when rows were asked
    for, ``J (N, m, 6)``, ``scale (N, m)``, the conditioning, the validity of the rows and
    of each leg's structure, and, with a workload, the values ``F_r``, the equilibrium
    residuals, the force amplifications and the signs of ``det J``.  (An immutable named
    tuple, read by field: as a frozen dataclass of its 16 fields it took some 3 us to
    build, one pose's analysis a twenty-fifth.)"""

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
    amplification: np.ndarray = None
    det_sign: np.ndarray = None
    twists: np.ndarray = None
    lines: np.ndarray = None
    platform: np.ndarray = None
    reversed_mask: np.ndarray = None


def load_block_kernel(model) -> None:
    """Load the parallel analysis kernel in this process (on a first run, compile it: once,
    with its note on stderr), by a launch of two poses at home on two threads.  Worker
    processes that analyse their batches on one thread in blocks (a Dask map's, which run
    the parallel kernel on one thread) then load it from the cache rather than each
    compiling it at once."""
    ch = chains_of(model)
    fixed = {p: np.full(2, float(ch.home[p])) for p in ch.fixed}
    run_poses(ch.flat, predictor_of(ch), ch.full_params(fixed, 2), rows=False, workers=2,
              per_thread=1)


def _chunks(N, size):
    return [slice(s, min(s + size, N)) for s in range(0, N, size)]


def row_points(model, closures: Closures, chunk: int = CHUNK) -> np.ndarray:
    """A point of each row's line at every pose of ``closures``, ``(N, m, 3)`` (the named
    point; the point nearest the leg's centroid for a force without one; NaN for couples
    and for rows that are not forces)."""
    from ._kernels import kernels
    ch = closures.chains
    flat = ch.flat
    J = run_poses(flat, flat.Z, closures.params(), X=closures.X.T, statics=False)["J"]
    out = np.full(J.shape[:2] + (3,), np.nan)
    kernels().row_points_range(flat.M, flat.Z[0], flat.Z[1], closures.params(),
                               np.ascontiguousarray(closures.X.T), J, out, 0, J.shape[0])
    return out


_KEYS = ("J", "scale", "rows_ok", "structure_ok", "centre", "length", "singular_values", "rank",
         "condition_number", "constraint_rank", "constraint_condition_number", "values",
         "equilibrium", "amplification", "det_sign", "twists", "lines", "platform",
         "reversed_mask")


def _per_pose(compliance, N, idx):
    """The compliances of the poses ``idx`` of N (one row for all poses: as it is)."""
    if compliance is None or np.ndim(compliance) < 2 or np.shape(compliance)[0] != N:
        return compliance
    return np.asarray(compliance)[idx]


class PathRows:
    """The rows, conditioning and statics of a path's samples, formed in the launches that
    solve the path's levels (:func:`~screwkit.engine._path.solve_path`,
    :class:`~screwkit.engine._path_launch.LevelLaunches`): the frames of each sample's final
    unknowns are then at hand, one forward pass a sample fewer than a launch from the
    solved unknowns, and the same bits (the kernels form a pose's rows from the frames of
    its final unknowns either way).  The samples solved elsewhere (the anchors) or again
    after their level (the retries taken), and those Newton did not close from their
    level's start, are not *kept*: :meth:`finish` forms theirs from their final unknowns.
    Each level's launch writes its samples' outputs into their rows of the path's output
    buffers: nothing copied after a launch, and every output byte touched once."""

    def __init__(self, ch, N, F, T, compliance, twists, lines):
        self.ch, self.N, self.F, self.T = ch, N, F, T
        self.compliance, self.twists, self.lines = compliance, twists, lines
        self.buffers = output_buffers(ch.flat, N, statics=F is not None, twists=twists,
                                      lines=lines, excess=True)
        self.launches = None

    def begin(self, N, Z) -> LevelLaunches:
        """The path's :class:`~screwkit.engine._path_launch.LevelLaunches` (``N`` samples)."""
        self.launches = LevelLaunches(self.ch.flat, Z, self.buffers, N, F=self.F,
                                      T=self.T, compliance=self.compliance,
                                      twists=self.twists, lines=self.lines)
        return self.launches

    def kept(self) -> int:
        """The samples whose rows their level's launch formed, and that stay."""
        return 0 if self.launches is None else int(np.count_nonzero(self.launches.kept))

    def finish(self, fixed, X, workers) -> dict:
        """The outputs of every sample (``X (N, n_unknowns)`` the path's unknowns): the
        samples not kept formed now, in launches of up to :data:`CHUNK`; the residuals and
        the arrays of :data:`_KEYS` the launches filled, by name."""
        stale = np.flatnonzero(self.launches.kept == 0)
        for sl in _chunks(stale.size, CHUNK):
            idx = stale[sl]
            run_poses(self.ch.flat, predictor_of(self.ch),
                      self.ch.full_params({k: v[idx] for k, v in fixed.items()}, idx.size),
                      X=X[idx], F=self.F, T=self.T,
                      compliance=_per_pose(self.compliance, self.N, idx),
                      statics=self.F is not None, twists=self.twists, lines=self.lines,
                      workers=workers, out=(self.buffers, idx))
        # (the booleans converted now, once all rows are in)
        return {k: v for k, v in self.buffers.arrays().items()
                if k in _KEYS + ("residual",) and v.shape[0]}


def chunk_after_path(model, fx, X, path_res, rows=True, F=None, T=None, compliance=None,
                     twists=False):
    """Residuals and (``rows``) rows and statics of one chunk of a solved path, ``X
    (n_unknowns, N)``.  A pose the solver gave up (``path_res`` inf: e.g. an unreachable
    side of a representation singularity) stays unreachable whatever its frames' residual."""
    ch = chains_of(model)
    N = X.shape[1]
    out = run_poses(ch.flat, ch.flat.Z, ch.full_params(fx, N), X=X.T, F=F, T=T,
                    compliance=compliance, rows=rows, statics=F is not None, twists=twists,
                    workers=1)
    res = np.where(np.isfinite(path_res), out["residual"], np.inf)
    return res, ({k: out[k] for k in _KEYS} if rows else None)


def _chunk_task(model, rows, F, T, compliance, item):
    fx, X, path_res = item
    return chunk_after_path(model, fx, X, path_res, rows, F, T, compliance)


def _one_launch(ch, templates, fixed, N, X0, side, rows, F, T, compliance, workers,
                progress, twists, lines=False, G6=None, orient=False, frozen=False) -> Computed:
    """:func:`compute` of poses that fit one launch (not a path): the kernel's outputs, no
    chunks' copies (``frozen``: one pose's read-only, :meth:`._outputs.OnePose.views`)."""
    flat = ch.flat
    if N == 1:                          # one pose: the row of P6 without a numpy call a value
        row = [0.0] * 6
        for p, v in fixed.items():
            row[_COLUMN[p]] = v[0]
        P6 = np.array([row])
    else:
        P6 = ch.full_params(fixed, N)
    o = run_poses(flat, predictor_of(ch), P6,
                  X0=None if X0 is None else X0.T, G6=G6, side=side, F=F, T=T,
                  compliance=compliance, rows=rows, statics=F is not None, twists=twists,
                  lines=lines, orient=orient, workers=workers, frozen=frozen)
    if progress:
        progress(N, N)
    closures = Closures(ch, o["X"].T, fixed, o["residual"], o["iterations"], o["how"],
                        o["singular_beta"])
    if not rows:
        return Computed(closures, (), flat.n_act, diagnostics={},
                        reversed_mask=o["reversed_mask"])
    out = {key: o[key] for key in _KEYS if o[key].shape[0]}
    cond = Conditioning(out["centre"], out["length"], out["singular_values"], out["rank"],
                        out["condition_number"], out["constraint_rank"],
                        out["constraint_condition_number"])
    return Computed(closures, labels_of(templates), flat.n_act, out["J"], out["scale"], cond,
                    out["rows_ok"], out["structure_ok"], out.get("values"),
                    out.get("equilibrium"), {}, out.get("amplification"),
                    out.get("det_sign"), out.get("twists"), out.get("lines"),
                    out.get("platform"), out.get("reversed_mask"))


def compute(model, fixed: dict, *, X0=None, G6=None, side=None, path=False,
            anchor_every=None, rows=True, F=None, T=None, chunk=CHUNK, workers=None,
            progress=None, compliance=None, mapper=None, twists=False,
            lines=False, orient=False) -> Computed:
    """Solve and (``rows``) form the Jacobian rows, conditioning and statics of N poses.

    ``progress(done, total)``: ``total = N``, or ``2 N`` for a path with rows (its closures
    are solved first, then the rows and statics).  ``mapper(fn, items)`` (a path only):
    computes ``[fn(x) for x in items]`` elsewhere, e.g. on a Dask cluster; the path's
    closures are solved here, the rows and statics of its chunks by the mapper.  ``lines``
    (with ``rows``, not with a mapper): also the lines of the transmission indices' joints
    and the platform of every pose (:func:`~screwkit.engine._launch.run_poses`); ``orient``
    (not a path): ``det_sign`` times the legs' orientation (``diagnostics["det_oriented"]``
    says where it is).  ``G6 (N, 6)`` (with ``X0``, not a path): the parameters of the
    poses the warm starts solve, by which the kernels move each start
    (:func:`~screwkit.engine._launch.run_poses`).

    A pose whose solution runs a leg's linear actuator to a negative length
    (:mod:`._reversal`) is solved again (its reversed legs from home, else by continuation
    from home), and is unreachable (``closures.reversed``; ``diagnostics["reversed_legs"]
    (N, n)`` saying which legs) where that finds no other assembly."""
    comp = _compute(model, fixed, X0=X0, G6=G6, side=side, path=path,
                    anchor_every=anchor_every, rows=rows, F=F, T=T, chunk=chunk,
                    workers=workers, progress=progress, compliance=compliance,
                    mapper=mapper, twists=twists, lines=lines, orient=orient)
    return _unreversed(model, comp, side, rows, F, T, compliance, workers, twists, lines)


def _unreversed(model, comp: Computed, side, rows, F, T, compliance, workers, twists,
                lines) -> Computed:
    """``comp`` with its poses whose solution reverses a leg's actuator (:mod:`._reversal`)
    solved again (:func:`._reversal.resolve`; their outputs put in their rows, ``how`` 1),
    and those still reversed unreachable (``closures.reversed``), their legs in
    ``diagnostics["reversed_legs"]``."""
    c = comp.closures
    mask = comp.reversed_mask
    if mask is None:                    # (a route whose launches did not return them)
        mask = actuator_lines(model).mask(c.X)
    if len(mask) == 1:
        if not mask[0]:
            return comp                 # (one pose: the common case without numpy's calls)
    elif not mask.any():
        return comp
    bad = np.flatnonzero((mask != 0) & (np.asarray(c.residual) <= ACCEPTED))
    if not bad.size:
        return comp
    rev = legs_of(mask[bad], model.n_legs)          # (the legs of those poses only)
    ch = c.chains
    fx = {k: v[bad] for k, v in c.fixed.items()}
    sub_side = None if side is None else np.asarray(side)[bad]
    X, its, done = resolve(model, fx, c.X[:, bad], sub_side, workers)
    idx = bad[done]
    if idx.size:
        comp = owned(comp)              # (one pose's results' arrays were read-only)
        templates = templates_of(model) if rows else None
        sub = _one_launch(ch, templates, {k: v[done] for k, v in fx.items()}, idx.size,
                          X[:, done], None if sub_side is None else sub_side[done], rows, F,
                          T, _per_pose(compliance, len(c.residual), idx), workers, None,
                          twists, lines, None,
                          bool((comp.diagnostics or {}).get("det_oriented")))
        sc = sub.closures
        c.X[:, idx] = sc.X
        for name in ("residual", "singular_beta"):
            getattr(c, name)[idx] = getattr(sc, name)
        c.iterations[idx] = its[done] + sc.iterations
        c.how[idx] = 1
        for name, value in zip(Computed._fields[3:], sub[3:]):
            whole = getattr(comp, name)
            if isinstance(value, np.ndarray) and whole is not None and len(whole):
                whole[idx] = value
        if comp.conditioning is not None:
            for f in dataclasses.fields(comp.conditioning):
                getattr(comp.conditioning, f.name)[idx] = getattr(sub.conditioning, f.name)
    still = bad[~done]
    if not still.size:
        return comp
    diag = dict(comp.diagnostics or {})
    flagged = np.zeros((len(c.residual), rev.shape[1]), bool)
    flagged[still] = rev[~done]
    diag["reversed_legs"] = flagged
    return comp._replace(closures=dataclasses.replace(c, reversed=flagged.any(axis=1)),
                         diagnostics=diag)


def _compute(model, fixed: dict, *, X0, G6, side, path, anchor_every, rows, F, T, chunk,
             workers, progress, compliance, mapper, twists, lines, orient) -> Computed:
    """:func:`compute` by its routes (one launch, chunks, a path), as the kernels solve."""
    compile_analysis()                  # (a first run: the kernels compiled on two processes)
    ch = chains_of(model)
    flat = ch.flat
    N = len(next(iter(fixed.values())))
    fixed = {k: np.asarray(v, float) for k, v in fixed.items()}
    templates = templates_of(model) if rows else None
    orient = bool(orient and rows and F is not None and not path)
    if not path and N <= chunk:
        c = _one_launch(ch, templates, fixed, N, X0, side, rows, F, T, compliance,
                        workers, progress, twists, lines, G6, orient, True)
        if orient:
            c.diagnostics["det_oriented"] = True
        return c
    diag = {"det_oriented": True} if orient else {}
    steps = 2 * N if path and rows else N          # a path: the closures, then the rows
    chunk = max(1, int(chunk))
    slices = _chunks(N, chunk)
    out = {}
    statics = F is not None
    fused = path and rows and mapper is None
    if path:
        levels = PathRows(ch, N, F, T, compliance, twists, lines) if fused else None
        # with the rows formed in the levels' launches, a sample kept is two steps done
        # (its closures and its rows)
        done = (lambda d: d + levels.kept()) if fused else (lambda d: d)
        c = solve_path(model, fixed, X0, anchor_every=anchor_every, workers=workers,
                       progress=(lambda d, n: progress(done(d), steps)) if progress else None,
                       levels=levels)
        X = np.ascontiguousarray(c.X.T)            # (the path's rows as they are: no copy)
        # (the closure's arrays are its own copies, not the launches' recycled buffers)
        its, how, sing = c.iterations, c.how, c.singular_beta
        diag = dict(c.diagnostics)
        path_res = c.residual
        res = np.empty(N)
    Z = predictor_of(ch)

    def put(key, sl, value):
        if sl.start == 0 and sl.stop == N:          # one launch: its arrays as they are
            out[key] = value
            return
        if key not in out:
            out[key] = np.empty((N,) + value.shape[1:], value.dtype)
        out[key][sl] = value

    if fused:
        # the rows came with the levels' solves; the stale samples' now
        o = levels.finish(fixed, X, workers)
        res = o["residual"]                     # (the buffers' own: written in place)
        res[~np.isfinite(path_res)] = np.inf
        for key in _KEYS:
            if key in o:
                out[key] = o[key]
        if progress:
            progress(steps, steps)
    elif mapper is not None and path:
        # the chunks of a solved path are independent: the same kernels on the same inputs
        # wherever they run, so the result equals the serial one bit for bit
        items = [({k: v[sl] for k, v in fixed.items()}, X[sl].T, path_res[sl]) for sl in slices]
        fn = partial(_chunk_task, model, rows, F, T, compliance)
        for sl, (r_sl, part) in zip(slices, mapper(fn, items)):
            res[sl] = r_sl
            for key, value in (part or {}).items():
                if value.shape[0]:
                    put(key, sl, value)
        if progress:
            progress(steps, steps)
    else:
        # poses in chunks, or a path's residuals at its solved unknowns (no rows: with rows,
        # a path takes one of the branches above); the chunks of poses write their rows of
        # one set of output buffers in place (fresh memory touched once, nothing copied)
        buffers = None if path else output_buffers(flat, N, rows=rows, statics=statics,
                                                   twists=twists, lines=lines)
        for sl in slices:
            n = sl.stop - sl.start
            P6 = ch.full_params({k: v[sl] for k, v in fixed.items()}, n)
            comp = compliance if compliance is None or np.ndim(compliance) < 2 or \
                np.shape(compliance)[0] != N else compliance[sl]
            o = run_poses(flat, Z, P6, X0=None if X0 is None else X0[:, sl].T,
                          G6=None if G6 is None or path else G6[sl], X=X[sl] if path else None,
                          side=None if side is None else side[sl], F=F, T=T, compliance=comp,
                          rows=rows, statics=statics, twists=twists, lines=lines,
                          orient=orient, workers=workers,
                          out=None if path else (buffers, sl.start))
            if path:
                res[sl] = np.where(np.isfinite(path_res[sl]), o["residual"], np.inf)
            elif progress:
                progress(sl.stop, steps)
        if buffers is not None:
            o = buffers.arrays()
            X, res = o["X"], o["residual"]
            its, how, sing = o["iterations"], o["how"], o["singular_beta"]
            out = {key: o[key] for key in _KEYS if o[key].shape[0]} if rows else \
                {"reversed_mask": o["reversed_mask"]}
    closures = Closures(ch, X.T, fixed, res, its, how, sing)
    if not rows:
        return Computed(closures, (), flat.n_act, diagnostics=diag,
                        reversed_mask=out.get("reversed_mask"))
    cond = Conditioning(out["centre"], out["length"], out["singular_values"], out["rank"],
                        out["condition_number"], out["constraint_rank"],
                        out["constraint_condition_number"])
    return Computed(closures, labels_of(templates), flat.n_act, out["J"], out["scale"], cond,
                    out["rows_ok"], out["structure_ok"], out.get("values"),
                    out.get("equilibrium"), diag, out.get("amplification"),
                    out.get("det_sign"), out.get("twists"), out.get("lines"),
                    out.get("platform"), out.get("reversed_mask"))
