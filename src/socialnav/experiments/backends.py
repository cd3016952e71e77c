"""Where a suite's episodes run: this machine's process pool, a Dask cluster or a Ray cluster.

Each backend maps a picklable function over the episodes and yields results as they finish (in
any order), so the caller can store every finished episode at once. The engines' own task APIs
do the scheduling: ``joblib`` (loky processes) for ``local``, ``distributed.Client.submit`` with
``as_completed`` for ``dask``, ``ray.remote`` tasks with ``ray.wait`` for ``ray``.

- ``address=None`` starts a cluster on this machine with ``n_jobs`` single-threaded worker
  processes and stops it at the end; an address joins a running cluster (Dask: the scheduler's
  ``tcp://host:8786``; Ray: ``auto`` or ``host:6379``) and leaves it running. Workers must have
  socialnav installed, and episode files are written by the workers under the results folder, so
  on several machines that folder must be on a shared file system.
- Dask and Ray are the optional extra ``cluster`` (``pip install 'socialnav[cluster]'``); asking
  for one that is not installed raises a :class:`ConfigurationError` that says so.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from socialnav.core.errors import ConfigurationError

BACKENDS = ("local", "dask", "ray")


def _workers(n_jobs: int) -> int:
    return max(1, os.cpu_count() or 1) if n_jobs < 1 else n_jobs


def check_backend(backend: str, address: str | None = None) -> None:
    """Raise a :class:`ConfigurationError` for an unknown or uninstalled backend."""
    if backend not in BACKENDS:
        raise ConfigurationError(f"unknown backend {backend!r}; use {', '.join(BACKENDS)}")
    if backend == "local" and address:
        raise ConfigurationError("--address joins a Dask or Ray cluster; use --backend dask|ray")
    module = {"dask": "distributed", "ray": "ray"}.get(backend)
    if module is None:
        return
    try:
        __import__(module)
    except ImportError:
        raise ConfigurationError(
            f"backend {backend!r} needs the cluster extra: pip install 'socialnav[cluster]'"
        ) from None


def map_unordered(
    fn: Callable[..., Any],
    items: Sequence[Any],
    *,
    backend: str = "local",
    n_jobs: int = -1,
    address: str | None = None,
    args: tuple[Any, ...] = (),
) -> Iterator[Any]:
    """Yield ``fn(item, *args)`` for every item as each finishes, on ``backend``."""
    check_backend(backend, address)
    if not items:
        return iter(())
    if backend == "dask":
        return _dask(fn, items, n_jobs, address, args)
    if backend == "ray":
        return _ray(fn, items, n_jobs, address, args)
    return _local(fn, items, n_jobs, args)


def _local(
    fn: Callable[..., Any], items: Sequence[Any], n_jobs: int, args: tuple[Any, ...]
) -> Iterator[Any]:
    from joblib import Parallel, delayed

    runner = Parallel(n_jobs=n_jobs, return_as="generator_unordered", backend="loky")
    yield from runner(delayed(fn)(item, *args) for item in items)


def _dask(
    fn: Callable[..., Any],
    items: Sequence[Any],
    n_jobs: int,
    address: str | None,
    args: tuple[Any, ...],
) -> Iterator[Any]:
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    if address is None:
        cluster = LocalCluster(  # type: ignore[no-untyped-call]
            n_workers=_workers(n_jobs),
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )
    client = Client(cluster if cluster is not None else address)  # type: ignore[no-untyped-call]
    try:
        # pure=False: two equal specs are two episodes, never one cached result
        futures = [client.submit(fn, item, *args, pure=False) for item in items]
        for future in as_completed(futures):  # type: ignore[no-untyped-call]
            yield future.result()
            future.release()
    finally:
        client.close()  # type: ignore[no-untyped-call]
        if cluster is not None:
            cluster.close()


def _ray(
    fn: Callable[..., Any],
    items: Sequence[Any],
    n_jobs: int,
    address: str | None,
    args: tuple[Any, ...],
) -> Iterator[Any]:
    import ray

    started = False
    if not ray.is_initialized():
        if address is None:
            ray.init(
                num_cpus=_workers(n_jobs),
                include_dashboard=False,
                log_to_driver=False,
                configure_logging=False,
            )
        else:
            ray.init(address=address, log_to_driver=False, configure_logging=False)
        started = True
    try:
        task = ray.remote(num_cpus=1)(fn)
        pending = [task.remote(item, *args) for item in items]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield ray.get(done[0])
    finally:
        if started:
            ray.shutdown()
