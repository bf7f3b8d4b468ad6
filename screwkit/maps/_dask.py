"""Dask clusters for maps and sizing: a local cluster on loopback, or a running scheduler.

``dask[distributed]`` is an optional dependency (``pip install 'screwkit[dask]'``),
imported only here and only when a cluster is asked for.

* ``cluster=N`` (the CLI's ``--workers N``): a ``LocalCluster`` of N worker
  *processes* with one thread each, listening on 127.0.0.1 only, started for the call
  and closed after it;
* ``cluster="tcp://HOST:PORT"`` (``--scheduler``): a client of a running scheduler
  (``dask scheduler`` on one machine, ``dask worker tcp://HOST:PORT`` on each node); the
  cluster is left running;
* ``cluster=<distributed.Client>``: used as it is, left open.

Each worker receives the model and the grid once (``scatter``, broadcast) and then one
block of cells per task; screwkit must be installed on every worker.
"""

from __future__ import annotations

import contextlib

from ..errors import InputError

__all__ = ["client_for", "MAX_LOCAL_WORKERS"]

#: Largest local cluster started by ``cluster=N``.
MAX_LOCAL_WORKERS = 64


def _distributed():
    try:
        import distributed
    except ImportError:
        raise InputError("a Dask cluster needs dask[distributed] "
                         "(pip install 'screwkit[dask]')") from None
    return distributed


@contextlib.contextmanager
def client_for(cluster):
    """A ``distributed.Client`` for ``cluster`` (see the module docstring), closed on exit
    when it was opened here."""
    dist = _distributed()
    if isinstance(cluster, dist.Client):
        yield cluster
        return
    if isinstance(cluster, bool):
        raise InputError(f"cluster must be a number of workers, an address or a Client, got "
                         f"{cluster!r}")
    if isinstance(cluster, int):
        if not 1 <= cluster <= MAX_LOCAL_WORKERS:
            raise InputError(f"a local Dask cluster has 1 to {MAX_LOCAL_WORKERS} workers, got "
                             f"{cluster}")
        import dask
        with dask.config.set({"distributed.worker.daemon": False,
                              "distributed.logging.distributed": "error"}):
            lc = dist.LocalCluster(n_workers=cluster, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=None,
                                   silence_logs=50)
            try:
                with dist.Client(lc) as client:
                    yield client
            finally:
                lc.close()
        return
    if isinstance(cluster, str):
        if not cluster.startswith(("tcp://", "tls://", "inproc://", "ucx://")):
            raise InputError(f"a Dask scheduler address looks like tcp://HOST:PORT, got "
                             f"{cluster!r}")
        try:
            client = dist.Client(cluster, timeout=30)
        except OSError as exc:
            raise InputError(f"cannot reach the Dask scheduler {cluster}: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    raise InputError(f"cluster must be a number of workers, an address tcp://HOST:PORT or a "
                     f"distributed.Client, got {type(cluster).__name__}")
