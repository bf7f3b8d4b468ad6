"""Dask clusters for maps and sizing: a local cluster on loopback, or a running scheduler.

``dask[distributed]`` is an optional dependency (``pip install 'screwkit[dask]'``),
imported only here and only when a cluster is asked for.

* ``cluster=N`` (the CLI's ``--workers N``): a ``LocalCluster`` of N worker
  *processes* with one thread each, listening on 127.0.0.1 only, started for the call
  and closed after it;
* ``cluster="tcp://HOST:PORT"`` (``--scheduler``): a client of a running scheduler
  (``dask scheduler`` on one machine, ``dask worker tcp://HOST:PORT`` on each node; see
  docs/maps.md for the workers' ``MALLOC_TRIM_THRESHOLD_``); the cluster is left running;
* ``cluster=<distributed.Client>``: used as it is, left open.

Each worker receives the model and the grid once (``scatter``, broadcast) and then one
block of cells per task; screwkit must be installed on every worker.  :func:`run_tasks`
runs any picklable function over a list of items the same way (``screwkit validate
--workers``: one leg string per task).
"""

from __future__ import annotations

import contextlib
import re

from ..errors import InputError

__all__ = ["client_for", "run_tasks", "check_address", "MAX_LOCAL_WORKERS", "LOCAL_CONFIG",
           "SCHEDULER_TIMEOUT"]

#: Largest local cluster started by ``cluster=N``.
MAX_LOCAL_WORKERS = 64
#: Seconds to wait for a remote Dask scheduler before giving up.
SCHEDULER_TIMEOUT = 10.0
#: Dask settings of a local cluster.  ``MALLOC_TRIM_THRESHOLD_`` unset: distributed's
#: nanny sets it (65536) in the workers' environment, which switches off glibc's dynamic
#: mmap threshold, so every large temporary of a batched analysis is mapped and unmapped
#: again; measured: a block of 65,536 3RRPRR cells 2.5 to 4.5 times slower on a worker.
LOCAL_CONFIG = {"distributed.worker.daemon": False,
                "distributed.logging.distributed": "error",
                "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}


_ADDRESS = re.compile(r"(tcp|tls|ucx|ws|wss)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9](?:[A-Za-z0-9.-]"
                      r"{0,251}[A-Za-z0-9])?):([0-9]{1,5})")


def check_address(address, what: str = "scheduler") -> str:
    """A Dask scheduler address ``tcp://HOST:PORT`` (also tls, ucx, ws, wss): a host name,
    an IPv4 or a bracketed IPv6 address, a port from 1 to 65535; an :class:`InputError`
    naming ``what`` otherwise (checked before any connection is tried)."""
    from ..legs._guards import shorten
    if not isinstance(address, str):
        raise InputError(f"{what}: an address tcp://HOST:PORT is text, got "
                         f"{type(address).__name__}")
    m = _ADDRESS.fullmatch(address.strip())
    if m is None or not 1 <= int(m.group(3)) <= 65535:
        raise InputError(f"{what}: {shorten(address)} is not a Dask scheduler address "
                         "tcp://HOST:PORT (port 1 to 65535)")
    return address.strip()


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
        with dask.config.set(LOCAL_CONFIG):
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
        cluster = check_address(cluster)
        try:
            client = dist.Client(cluster, timeout=SCHEDULER_TIMEOUT)
        except Exception as exc:            # noqa: BLE001 - OSError, TimeoutError, a bad host
            msg = " ".join(str(exc).split())[:200] or type(exc).__name__
            raise InputError(f"cannot reach the Dask scheduler {cluster} within "
                             f"{SCHEDULER_TIMEOUT:g} s: {msg}") from None
        try:
            yield client
        finally:
            client.close()
        return
    raise InputError(f"cluster must be a number of workers, an address tcp://HOST:PORT or a "
                     f"distributed.Client, got {type(cluster).__name__}")


def run_tasks(cluster, fn, items, progress=None) -> list:
    """``[fn(x) for x in items]`` computed on a Dask cluster (see :func:`client_for`).

    ``fn`` and the items must be picklable (a module-level function, or a
    :func:`functools.partial` of one); the results come back in the order of ``items``
    whatever the order the tasks finish in, so the list equals the serial one.
    ``progress(done, total)`` is called as tasks finish.
    """
    items = list(items)
    with client_for(cluster) as client:
        from distributed import as_completed
        futures = client.map(fn, items, pure=False)
        where = {f.key: k for k, f in enumerate(futures)}
        out = [None] * len(items)
        done = 0
        for fut in as_completed(futures):
            out[where[fut.key]] = fut.result()
            fut.release()
            done += 1
            if progress is not None:
                progress(done, len(items))
    return out
