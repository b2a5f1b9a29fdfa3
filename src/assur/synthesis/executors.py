"""Where a population is evaluated: in-process, on local worker processes, or on a Dask cluster.

Every executor splits the population into the same fixed chunks (``Evaluator.chunk`` designs, in
order) and evaluates each chunk with the same evaluator, so the numbers — and hence an optimiser's
whole run for a given seed — are identical whatever the executor. ``map_starts`` runs whole
independent optimisation starts as tasks (the large multi-start sweeps).
"""
from __future__ import annotations

import os

from ..errors import SpecError, SynthesisError, require
from .evaluate import Evaluation, Evaluator

_WORKER_EVALUATOR = None


def _chunks(X, size):
    return [X[i:i + size] for i in range(0, len(X), size)] or [X]


class InProcess:
    """Evaluate in the calling process (the default)."""
    name = "in-process"
    workers = 1

    def evaluate(self, evaluator: Evaluator, X, detail: bool = False) -> Evaluation:
        return evaluator(X, detail)

    def map_starts(self, func, args_list, progress=None):
        """``[func(*args) for args in args_list]``, in order; ``progress(done, total)`` after each result."""
        out = []
        for a in args_list:
            out.append(func(*a))
            if progress is not None:
                progress(len(out), len(args_list))
        return out

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _init_worker(evaluator):
    global _WORKER_EVALUATOR
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    _WORKER_EVALUATOR = evaluator


def _evaluate_in_worker(X, detail):
    return _WORKER_EVALUATOR(X, detail)


def _evaluate_with(evaluator, X, detail):
    return evaluator(X, detail)


class LocalProcesses(InProcess):
    """A pool of ``workers`` local processes (``concurrent.futures``); the evaluator is sent once."""
    name = "local processes"

    def __init__(self, workers: int):
        if workers < 1:
            raise SpecError([("workers", f"must be at least 1: {workers}")])
        self.workers = int(workers)
        self._pool = None
        self._for = None

    def _pool_for(self, evaluator):
        import multiprocessing as mp
        from concurrent.futures import ProcessPoolExecutor
        if self._pool is None or self._for is not evaluator:
            self.close()
            ctx = mp.get_context("spawn")
            self._pool = ProcessPoolExecutor(self.workers, mp_context=ctx, initializer=_init_worker,
                                             initargs=(evaluator,))
            self._for = evaluator
        return self._pool

    def evaluate(self, evaluator, X, detail: bool = False):
        pool = self._pool_for(evaluator)
        chunks = _chunks(X, evaluator.chunk)
        return Evaluation.concatenate(list(pool.map(_evaluate_in_worker, chunks, [detail] * len(chunks))))

    def map_starts(self, func, args_list, progress=None):
        """Whole starts as tasks, the results in order (``progress(done, total)`` as each comes in); returns once
        every result is in, without waiting for the worker processes to exit (a second under load: a run's time
        limit does not wait for it; they end in the background)."""
        from concurrent.futures import ProcessPoolExecutor, as_completed
        import multiprocessing as mp
        pool = ProcessPoolExecutor(self.workers, mp_context=mp.get_context("spawn"))
        try:
            futures = [pool.submit(func, *a) for a in args_list]
            if progress is not None:
                for done, _ in enumerate(as_completed(futures), 1):
                    progress(done, len(futures))
            return [f.result() for f in futures]
        finally:
            pool.shutdown(wait=False, cancel_futures=True)

    def close(self):
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
            self._for = None


#: how to install dask.distributed
DASK_INSTALL = "pip install 'dask[distributed]' (or pip install 'assur[synth]')"


class DaskCluster(InProcess):
    """A dask.distributed cluster: ``address`` of a running scheduler, or a ``distributed.Client``.
    The evaluator is scattered to every worker once; chunks are mapped as tasks."""
    name = "dask"

    def __init__(self, address=None, *, client=None):
        Client = require("distributed", "the Dask executor", DASK_INSTALL).Client
        self._own = client is None
        self.client = client if client is not None else _connect(Client, address)
        self._scattered = None
        self._for = None
        info = self.client.scheduler_info()
        self.workers = max(1, sum(w.get("nthreads", 1) for w in info.get("workers", {}).values()))

    def evaluate(self, evaluator, X, detail: bool = False):
        if self._for is not evaluator:
            self._scattered = self.client.scatter(evaluator, broadcast=True)
            self._for = evaluator
        chunks = _chunks(X, evaluator.chunk)
        futures = self.client.map(_evaluate_with, [self._scattered] * len(chunks), chunks, [detail] * len(chunks),
                                  pure=False)
        return Evaluation.concatenate(self.client.gather(futures))

    def map_starts(self, func, args_list, progress=None):
        futures = self.client.map(func, *zip(*args_list), pure=False)
        if progress is not None:
            from distributed import as_completed
            for done, _ in enumerate(as_completed(futures), 1):
                progress(done, len(futures))
        return self.client.gather(futures)

    def close(self):
        if self._own and self.client is not None:
            self.client.close()
            self.client = None


#: how long a Dask client waits for its scheduler to answer
CONNECT_TIMEOUT = "20s"


def _connect(Client, address):
    """A ``Client`` of the scheduler at ``address``; SpecError for what is not an address, SynthesisError when no
    scheduler answers there within :data:`CONNECT_TIMEOUT`."""
    try:
        return Client(address, timeout=CONNECT_TIMEOUT)
    except (ValueError, TypeError) as exc:
        raise SpecError([("dask", f"not the address of a Dask scheduler (tcp://host:port): {address!r} ({exc})")]) \
            from None
    except (OSError, TimeoutError) as exc:
        raise SynthesisError(f"no Dask scheduler answers at {address}: {exc}") from None


def make_executor(workers: int | None = None, dask: str | None = None):
    """The executor for ``--workers N`` / ``--dask ADDRESS`` (in-process if neither)."""
    if dask is not None and not str(dask).strip():
        raise SpecError([("dask", "the address of the Dask scheduler is empty (tcp://host:port)")])
    if workers and dask:
        raise SpecError([("workers, dask", "give either workers or a Dask address, not both")])
    if dask:
        return DaskCluster(dask)
    if workers and workers > 1:
        return LocalProcesses(workers)
    return InProcess()


__all__ = ["DaskCluster", "InProcess", "LocalProcesses", "make_executor"]
