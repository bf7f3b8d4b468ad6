"""Every cell of a map is a pose of the batched engine: blocks of cells, serial or on Dask.

The cells are cut into blocks of :data:`BLOCK` poses (one engine launch each);
each block is one call of :func:`screwkit.engine.analyze` (threads inside it, as analyze's
``workers``), and :func:`arrays_of` keeps only the compact per-cell arrays of the map.  With
a Dask cluster the same function runs on the workers, one block per task, so a distributed
map equals the serial one bit for bit (the same code on the same inputs); results are
stored as the blocks finish.  On two threads or more, a second Python thread forms each
block's arrays while the next block is analysed (:func:`_pipelined`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..engine import CONVERGED, analyze
from ..engine._memory import fresh_array
from ..engine._report import row_quantity

__all__ = ["BLOCK", "LEVEL_CODES", "CONDITIONING_CODES", "KIND_CODES", "INDEX_NAMES", "Meta",
           "meta_of", "arrays_of", "compute"]

#: Cells per block (one engine launch).  Blocks of 16,384 3RRPRR cells rather than 65,536:
#: the launch's outputs (about 1.4 kB a cell with the indices' lines) then stay under
#: glibc's largest dynamic mmap threshold (32 MB), so each block reuses the memory the
#: last one freed instead of mapping, faulting in and zeroing fresh pages; measured on
#: 250,000 cells: 7% less CPU in all, a third less outside the kernels.  The cells'
#: values do not depend on the blocks.
BLOCK = 4 * 4096
#: ``level`` codes of a map (the engine's levels, then unreachable).
LEVEL_CODES = ("ok", "ill-conditioned", "near-singular", "singular", "unreachable")
#: ``conditioning`` codes of a map: the engine's one classification
#: (:func:`screwkit.engine.classify`), then unreachable.
CONDITIONING_CODES = ("regular", "near-singular", "singular", "unreachable")
#: ``singular_kind`` codes.
KIND_CODES = ("regular", "actuation", "constraint", "unreachable")
#: The per-cell indices of :attr:`screwkit.engine.PMAnalysis.indices` a map keeps.
INDEX_NAMES = ("iti", "oti", "lti", "cti", "sigma_min")


@dataclass(frozen=True)
class Meta:
    """What the rows and legs of a model's maps are (the same at every cell).

    Attributes
    ----------
    labels : tuple of str
        The rows of ``J`` (``F_a1`` ... ``F_c1``, ``T_c2``).
    quantities : tuple of str
        ``force`` or ``torque`` per row.
    kinds : tuple of str
        ``actuation`` or the constraint member (``force``, ``couple``, ``screw``) per row.
    legs : tuple of int
        The leg (0-based) of each row.
    n_actuated : int
    linear : tuple of bool
        Per leg: a linear actuator (``T_r`` is defined for it).
    dependent : tuple of str
    home_det_sign : int
    square : bool
        ``J`` is 6 x 6 (``det J`` has a sign).
    """

    labels: tuple
    quantities: tuple
    kinds: tuple
    legs: tuple
    n_actuated: int
    linear: tuple
    dependent: tuple
    home_det_sign: int
    square: bool


def meta_of(model) -> Meta:
    """The :class:`Meta` of a model (one analysis at its default pose)."""
    from ..engine._quality import home_det_sign
    res = analyze(model, {p: np.array([v]) for p, v in model.default_pose.items()},
                  raise_on_singular=False)
    jac = res.jacobian
    info = jac.info
    return Meta(tuple(r.label for r in info), tuple(row_quantity(r) for r in info),
                tuple(r.kind for r in info), tuple(r.leg for r in info), jac.n_actuated,
                tuple(lg.actuated_joint.kind == "P" for lg in model.home_legs),
                tuple(model.dependent), home_det_sign(model, analyze), jac.square)


def _analysis(model, poses, force, torque, stiffness, threads):
    """The engine's analysis of a block: one launch (its outputs as they are, not copied
    together from chunks), keeping the joints and platform the indices read (no second
    pass over the cells)."""
    N = len(next(iter(poses.values())))
    return analyze(model, poses, force=force, torque=torque, raise_on_singular=False,
                   workers=threads, stiffness=stiffness, lines=True,
                   chunk=min(max(N, 1), 1 << 20))


def _arrays_loads(model, res, loads, max_level_code, offset) -> tuple:
    """``(arrays, reductions)``: :func:`arrays_of` of a block's analysis ``res`` (its first
    cell ``offset``) and, from the same analysis, the block's largest efforts under each of
    ``loads`` (:func:`screwkit.maps._loads.reduce_block`); the cells counted for any
    workload are the per-cell array ``usable_any``."""
    from ._loads import reduce_block
    out = arrays_of(model, res)
    red, usable_any = reduce_block(res, out, loads, _linear(model), max_level_code, offset,
                                   _level_codes)
    out["usable_any"] = usable_any
    return out, red


def _level_codes(names):
    lev = _codes(names)
    lev[names == "unreachable"] = LEVEL_CODES.index("unreachable")
    return lev


def arrays_of(model, res) -> dict:
    """The map's per-cell arrays of an analysis of N cells (radians, model lengths):
    ``(N,)`` per cell, or ``(N, m)`` / ``(N, n)`` per row / leg (see :func:`compute`)."""
    sol, jac = res.solution, res.jacobian
    ix = res.indices            # first: its frames give the platform the rest reads
    st = res.statics if res.has_workload else None          # no workload: no forces
    reach = sol.reachable_mask
    c = jac.conditioning
    q = res.quality
    lev = _codes(q.level)
    lev[~reach] = LEVEL_CODES.index("unreachable")
    kind = np.zeros(len(reach), np.int8)
    ka = jac.kind_array
    kind[(ka == "actuation") & reach] = 1
    kind[(ka == "constraint") & reach] = 2
    kind[~reach] = 3                    # (no pose: no kind of singularity to say)
    nan_unreach = lambda x: np.where(reach, x, np.nan)            # noqa: E731
    out = {
        "residual": np.asarray(sol.closures.residual, float),
        "reachable": reach,                 # (stored by a copy into the map's arrays)
        "converged": sol.closures.residual <= CONVERGED,
        "ok": np.asarray(res.ok, bool),
        "condition_number": nan_unreach(c.condition_number),
        "constraint_condition_number": nan_unreach(c.constraint_condition_number),
        "det_sign": np.where(reach, q.det_sign, 0).astype(np.int8),
        "singular": np.asarray(res.singular, bool),
        "singular_kind": kind,
        "level": lev.astype(np.int8),
        "conditioning": _class_codes(q.conditioning),
        "amplification": nan_unreach(q.amplification),
        "equilibrium_residual": (np.full(len(reach), np.nan) if st is None else
                                 np.asarray(st.equilibrium_residual, float)),
        "values": None if st is None else np.asarray(st.F_r, float),
        "T_r": None if st is None else _linear_only(model, st.T_r),
        "extensions": np.asarray(sol._extensions, float),
        "actuators": np.asarray(sol.actuator_values, float),       # (N, actuated legs)
    }
    out = {k: v for k, v in out.items() if v is not None}
    for name in INDEX_NAMES:
        out[name] = np.asarray(getattr(ix, name), float)
    if model.dynamics is not None and model.dynamics.has_stiffness:
        # the model declares its legs' stiffness: the Cartesian stiffness of every cell
        from ..dynamics import stiffness_fields
        for name, (v, _, _) in stiffness_fields(res).items():
            out[f"stiff.{name}"] = np.asarray(v)
    for p in model.dependent:
        out[f"dep.{p}"] = np.asarray(sol._params[p], float)
    from ..engine._limits import limits_check     # (the analysis' own: one pose says it too)
    chk = limits_check(res)
    if chk is not None:
        out["within_limits"] = chk["within"]
        if model.limits.min_leg_distance is not None:
            out["min_leg_distance"] = chk["min_leg_distance"]
    return out


def _linear_only(model, T_r):
    """``T_r (N, n)`` of the legs with a linear actuator, NaN for the others (as it is when
    every leg is linear: the map's arrays copy it)."""
    linear = np.array(_linear(model))
    return T_r if linear.all() else np.where(linear[None, :], T_r, np.nan)


def _class_codes(classes):
    out = np.zeros(classes.shape, np.int8)
    for k, name in enumerate(CONDITIONING_CODES):
        out[classes == name] = k
    return out


def _codes(levels):
    out = np.zeros(levels.shape, np.int8)
    for k, name in enumerate(LEVEL_CODES[:4]):
        out[levels == name] = k
    return out


def _linear(model):
    return [lg.actuated_joint.kind == "P" for lg in model.home_legs]


def _blocks(N, size):
    return [slice(s, min(s + size, N)) for s in range(0, N, size)]


def _block(model, grid, sl, force, torque, stiffness, threads, loads, max_level_code):
    res = _analysis(model, grid.poses(sl), force, torque, stiffness, threads)
    return _block_arrays(model, res, sl, loads, max_level_code)


def _block_arrays(model, res, sl, loads, max_level_code):
    """The arrays of the block ``sl`` from its analysis ``res``: :func:`arrays_of`, or with
    ``loads`` :func:`_arrays_loads`."""
    return arrays_of(model, res) if loads is None else \
        _arrays_loads(model, res, loads, max_level_code, sl.start)


def _pipelined(model, grid, slices, force, torque, stiffness, workers, loads, max_level_code,
               write, advance):
    """The blocks in order, each analysed here (the kernels on ``workers`` threads) while a
    second Python thread turns the analyses into the map's arrays and writes them (``write(sl,
    part)``; numpy, and the kernels it launches run on that thread:
    :func:`screwkit.engine._launch.on_this_thread`); ``advance(sl)`` here once a block is
    written.  The kernels run without the GIL and the analysis's threads take pieces of its
    poses as they are free, so the numpy work of one block fills the CPU time the analysis
    of the next leaves.  Each block's arrays are those of :func:`_block` (the same functions
    on the same analysis): the same bits.  At most three analyses are held at once."""
    from concurrent.futures import ThreadPoolExecutor

    from ..engine import analyze
    from ..engine._launch import on_this_thread
    from ..engine._quality import det_signs

    def arrays(res, sl):
        with on_this_thread():
            write(sl, _block_arrays(model, res, sl, loads, max_level_code))

    pending = []
    with ThreadPoolExecutor(1, thread_name_prefix="screwkit-map") as helper:
        try:
            for sl in slices:
                res = _analysis(model, grid.poses(sl), force, torque, stiffness, workers)
                # (the assembly-mode signs here, on the analysis' threads: the arrays'
                # thread, which reads them, has the indices and the arrays to form)
                det_signs(res, res.solution.reachable_mask, analyze)
                pending.append((sl, helper.submit(arrays, res, sl)))
                del res
                while len(pending) > 2:
                    done, fut = pending.pop(0)
                    fut.result()
                    advance(done)
            for done, fut in pending:
                fut.result()
                advance(done)
        finally:
            for _, fut in pending:
                fut.cancel()


def _remote_block(model, grid, sl, force, torque, stiffness, loads=None, max_level_code=0):
    """One block on a Dask worker (one thread: the worker's processes give the parallelism)."""
    return _block(model, grid, sl, force, torque, stiffness, 1, loads, max_level_code)


def compute(model, grid, force, torque, *, stiffness=None, workers=None, cluster=None,
            progress=None, block: int = BLOCK, loads=None, max_level_code: int = 2):
    """The arrays of every cell of ``grid`` (flattened, C order), filled block by block.

    With ``loads`` (a list of ``(name, force, torque)``), returns ``(arrays, reductions)``:
    also each block's largest efforts under every one of ``loads`` counting the cells of
    level code at most ``max_level_code`` (:func:`screwkit.maps._loads.reduce_block`), in
    block order.

    Parameters
    ----------
    workers : int, optional
        Threads of each block's analysis (as :func:`screwkit.engine.analyze`).
    cluster : int, str or distributed.Client, optional
        Dask: ``N`` starts a local cluster of N worker processes on loopback; an address
        ``tcp://HOST:PORT`` connects to a running scheduler; a ``Client`` is used as it is.
    progress : callable(done, total), optional
    block : int
        Cells per block (rounded up to a multiple of 4096).
    """
    from ..errors import InputError
    N = grid.size
    if isinstance(block, bool) or int(block) < 1:
        raise InputError(f"block must be a positive number of cells, got {block!r}")
    size = -(-int(block) // 4096) * 4096
    slices = _blocks(N, size)
    out = {}
    reductions = [None] * len(slices)

    def write(sl, part):
        if loads is not None:
            part, reductions[slices.index(sl)] = part
        for k, v in part.items():
            if k not in out:
                # per-row and per-leg arrays column by column (Fortran order): each column
                # is then one Dataset variable without a copy; filled once, block by block
                # (fresh_array: without numpy's huge-page advice)
                out[k] = fresh_array((N,) + v.shape[1:], v.dtype, order="F")
            out[k][sl] = v

    def advance(sl):
        if progress:
            done[0] += sl.stop - sl.start
            progress(done[0], N)

    def store(sl, part):
        write(sl, part)
        advance(sl)

    done = [0]
    result = (lambda: (out, reductions)) if loads is not None else (lambda: out)
    if cluster is None:
        from ..engine._launch import threads
        if len(slices) < 2 or threads(min(N, size), workers) < 2:
            for sl in slices:
                store(sl, _block(model, grid, sl, force, torque, stiffness, workers, loads,
                                 max_level_code))
        else:
            _pipelined(model, grid, slices, force, torque, stiffness, workers, loads,
                       max_level_code, write, advance)
        return result()
    from ._dask import client_for
    # the workers analyse each block on one thread in blocks (the parallel kernel): on a
    # first run it is compiled here, once, not by every worker process at the same time
    from ..engine._run import load_block_kernel
    load_block_kernel(model)
    with client_for(cluster) as client:
        from distributed import as_completed
        m, g = client.scatter([model, grid], broadcast=True)
        futures = {client.submit(_remote_block, m, g, sl, force, torque, stiffness, loads,
                                 max_level_code, pure=False): sl for sl in slices}
        for fut in as_completed(futures):
            store(futures[fut], fut.result())
            fut.release()
    return result()
