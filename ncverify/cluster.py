"""Checking a library on a Dask cluster (``pip install "ncverify[dask]"``).

The workers run the same per-file function as the local worker processes
(:func:`ncverify.batch.check_path`), so the results are the same as a local run. They open
the programs, and the subprograms those call, by path: the library must be visible to every
worker at the same path (a shared or synchronised folder), and relative paths are read from
the worker's working directory, so give absolute ones to a remote cluster.

    >>> import dask.bag as db
    >>> from ncverify.cluster import check_bag
    >>> outcomes = check_bag(db.from_sequence(paths, npartitions=8)).compute()
    >>> [outcome.to_json() for outcome in outcomes]   # the JSON report's file entries
"""
from __future__ import annotations

from pathlib import Path

from .batch import Dispatch, check_path
from .pool import WorkerFailure
from .settings import Settings

CONNECT_TIMEOUT_S = 10.0


class ClusterError(Exception):
    """No cluster to run on: dask is not installed or the scheduler cannot be reached."""


def check_bag(paths, settings: Settings | None = None):
    """A Dask bag of program paths -> a bag of :class:`~ncverify.batch.FileOutcome`, one
    per path, in the bag's order (``outcome.result`` is the :class:`~ncverify.FileResult`,
    ``outcome.error`` says why a file could not be checked)."""
    settings = settings or Settings()
    return paths.map(lambda path: check_path((Path(path), settings)))


def dask_dispatch(address: str, timeout_s: float = CONNECT_TIMEOUT_S) -> Dispatch:
    """Run tasks on the cluster at ``address``; raises :class:`ClusterError` at once when
    dask is missing and after ``timeout_s`` when the scheduler does not answer."""
    client = connect(address, timeout_s)

    def dispatch(tasks):
        from distributed import as_completed

        try:
            futures = client.map(check_path, tasks, pure=False)
            position = {future.key: index for index, future in enumerate(futures)}
            for future in as_completed(futures):
                try:
                    value = future.result()
                except Exception as error:  # a worker died on this file (KilledWorker) or the task raised
                    value = WorkerFailure(f"the Dask task failed: {type(error).__name__}: {error}")
                yield position[future.key], value
        finally:
            client.close()

    return dispatch


def connect(address: str, timeout_s: float = CONNECT_TIMEOUT_S):
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError('--dask needs dask.distributed: pip install "ncverify[dask]"') from None
    try:
        return Client(address, timeout=timeout_s)
    except (OSError, TimeoutError, ValueError) as error:
        raise ClusterError(f"cannot reach the Dask scheduler at {address} within {timeout_s:g} s: {error}") from None
