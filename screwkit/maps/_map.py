"""``screwkit.map``: a PM over a grid of poses (workspace, conditioning, forces, loci).

Every cell is a pose of the batched engine (:func:`screwkit.engine.analyze`), solved from
the home predictor exactly as ``screwkit.analyze`` solves that pose alone, so a cell equals
the analysis at its pose.

Examples
--------
>>> import screwkit
>>> ds = screwkit.map("3RRPRR", {"alpha": (-10, 10, 5), "Zo": (70, 90, 3)},
...                   fix={"beta": -3}, degrees=True)
>>> ds["F_a1"].dims, ds["F_a1"].attrs["units"], int(ds["ok"].sum())
(('alpha', 'Zo'), 'kN', 15)
"""

from __future__ import annotations

from ..errors import InputError

__all__ = ["map_pm", "map_dataset", "resolve_model", "workload", "NO_WORKLOAD"]

#: The workload source of a map made without one: no force variables, the rest is there.
NO_WORKLOAD = ("none: the model declares no workload and none was given (no forces; give "
               "force=/torque=, at the command line --force/--torque)")


def resolve_model(pm, overrides=None):
    """A model from a :class:`~screwkit.pm.PMModel`, a catalog name or a YAML path."""
    from ..engine import load_assembled_pm
    return load_assembled_pm(pm, overrides)


def workload(model, force=None, torque=None):
    """``[F, T, source]``: the workload as two validated 3-vectors and where it comes from
    (the engine's checks and rules: one without the other means the other is zero; neither,
    the model's declared default); an :class:`InputError` when there is none."""
    from ..engine._workloads import no_workload_message, resolve_workload
    load = resolve_workload(model, force, torque)
    if load is None:
        raise InputError(no_workload_message(model))
    return list(load)


def _cluster(cluster, scheduler):
    if cluster is not None and scheduler is not None:
        raise InputError("give either cluster (workers or a Client) or scheduler (an "
                         "address), not both")
    return scheduler if scheduler is not None else cluster


def map_pm(pm, grid, fix=None, *, samples=None, seed: int = 0, degrees: bool = False,
           force=None, torque=None, stiffness=None, locus: bool = True,
           workers=None, cluster=None, scheduler=None, progress=None, block=None,
           overrides=None):
    """A map of a PM: every cell of a grid of independent pose parameters analysed.

    Parameters
    ----------
    pm : PMModel or str
    grid : mapping str -> (start, stop, count) or array_like
        1 to 3 independent pose parameters (radians, model lengths; degrees with
        ``degrees``).  With ``samples``: ``str -> (low, high)``, the box of random poses.
    fix : mapping str -> float, optional
        The other independent parameters (default: the model's default pose).
    samples : int, optional
        ``samples`` random poses uniform in the box ``grid`` (seed ``seed``).
    force, torque : array_like (3,), optional
        Workload at ``o`` (model units; one without the other: the other is zero; neither:
        the model's declared default, else none: the map has no force variables, its
        attribute ``workload_source`` says so, and the reachability, conditioning, indices,
        extensions and loci are all there).
    stiffness : optional
        Row stiffnesses for indeterminate statics (as :func:`screwkit.analyze`).
    locus : bool
        Refine the sign changes of ``det J`` between neighbouring cells
        (:mod:`screwkit.maps._locus`) into the ``crossing`` variables.
    workers : int, optional
        *Threads* of each block's analysis, as in :func:`screwkit.analyze`; with two or more
        (the default where there are two cores), a second Python thread forms each block's
        arrays while the next block is analysed (the same bits as one thread).
    cluster : int or distributed.Client, optional
        *Dask*: N starts a local cluster of N worker processes on loopback for this call; a
        Client is used as it is.  The result equals the serial map bit for bit.
    scheduler : str, optional
        *Dask*: the address ``tcp://HOST:PORT`` of a running scheduler.
    progress : callable(done, total), optional
        Called as blocks finish.
    block : int, optional
        Cells per block (default :data:`~screwkit.maps._compute.BLOCK`).

    Returns
    -------
    xarray.Dataset
        Dimensions: the grid parameters (``sample`` for samples); per cell ``reachable``,
        ``converged``, ``ok``, ``residual``, ``condition_number``,
        ``constraint_condition_number``, ``det_sign``, ``singular``, ``singular_kind``,
        ``level``, ``amplification``, ``equilibrium_residual``, the dependent pose
        parameters, one variable per row of ``J`` (``F_a1`` ... in force or torque units),
        ``T_r<i>`` for linear legs, extensions ``r<i>``, actuated joint values ``q_a<i>``,
        and ``within_limits`` (``min_leg_distance``) when the model declares limits; the
        refined loci along ``crossing`` (``locus_*``).  Units in every ``units`` attribute;
        the model, its units and the workload in the Dataset's attributes.
    """
    from ._dataset import xarray
    from ._grid import make_grid

    xarray()                                        # fail before a long run, not after
    from ..legs._guards import flag
    degrees, locus = flag(degrees, "degrees"), flag(locus, "locus")
    model = resolve_model(pm, overrides)
    from ..engine._workloads import resolve_workload
    load = resolve_workload(model, force, torque)
    F, T, source = load if load is not None else (None, None, NO_WORKLOAD)
    g = make_grid(model, grid, fix, samples=samples, seed=seed, degrees=degrees)
    cl = _cluster(cluster, scheduler)
    ds, meta, _ = map_dataset(model, g, F, T, stiffness=stiffness, workers=workers,
                              cluster=cl, progress=progress, block=block)
    ds.attrs["workload_source"] = source
    if locus and not g.samples and meta.square:
        from ._locus import locus_variables, refine
        loc = refine(model, ds, threads=workers)
        ds = ds.assign(locus_variables(ds, loc))
        ds.attrs["locus_truncated"] = int(loc["truncated"])
    ds.attrs["locus"] = ("refined" if "locus_kind" in ds else
                         "none: random samples have no neighbours" if g.samples else
                         "none: J is not square (det J has no sign)" if not meta.square else
                         "not asked for")
    return ds


def map_dataset(model, grid, F, T, *, stiffness=None, workers=None, cluster=None,
                progress=None, block=None, loads=None, max_level_code: int = 2) -> tuple:
    """``(Dataset, Meta, (reductions, usable_any))``: the map of a model over a made grid
    under ``(F, T)`` (no loci), and with ``loads`` each block's largest efforts under those
    workloads and the cells counted for any of them, as
    :func:`screwkit.maps._compute.compute` returns them (None without)."""
    from ._compute import BLOCK, compute, meta_of
    from ._dataset import build_dataset
    meta = meta_of(model)
    got = compute(model, grid, F, T, stiffness=stiffness, workers=workers, cluster=cluster,
                  progress=progress, block=BLOCK if block is None else block, loads=loads,
                  max_level_code=max_level_code)
    arrays, reductions = got if loads is not None else (got, None)
    ds = build_dataset(model, grid, arrays, meta, F, T, workers=workers, cluster=cluster)
    return ds, meta, (reductions, arrays.get("usable_any"))
