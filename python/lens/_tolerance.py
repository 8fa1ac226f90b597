"""Monte Carlo tolerancing from Python, in-process or over any
``concurrent.futures`` executor (docs/tolerancing.md, docs/python.md)."""

from __future__ import annotations

import concurrent.futures
import os
import time
from typing import Any, Optional

from ._lens import LensError, _tolerance_share, _tolerance_summary


def tolerance(
    spec: "str | os.PathLike[str]",
    trials: int = 1000,
    seed: int = 1,
    executor: Optional[concurrent.futures.Executor] = None,
    chunks: Optional[int] = None,
    threads: Optional[int] = None,
) -> dict[str, Any]:
    """The sensitivity table and Monte Carlo statistics of the tolerance
    file ``spec``: the dict ``lens tolerance --json`` prints.

    With ``executor=None`` the trials run in this process on every core
    (rayon; ``threads`` limits it). Given a ``concurrent.futures`` executor
    (a Dask cluster's ``client.get_executor()``, a ``ProcessPoolExecutor``
    made with the ``spawn`` or ``forkserver`` context), the trials are cut
    into ``chunks`` shares (default 4 per worker the executor reports, or
    8) mapped over it; trial k draws from (seed, k) alone, so the result is
    the same to the bit as in-process. Workers read ``spec`` and its
    prescription by path: on a cluster, keep them on a shared file system.
    A process pool that forks is refused: a forked rayon pool hangs.
    """
    path = os.path.abspath(os.fspath(spec))
    if trials < 1:
        raise LensError(f"trials={trials}: give 1 or more")
    t0 = time.perf_counter()
    if executor is None:
        shares = [_tolerance_share(path, seed, trials, 1, 1, threads)]
    else:
        _refuse_fork(executor)
        n = chunks or 4 * int(getattr(executor, "_max_workers", 2) or 2)
        n = max(1, min(n, trials))
        futures = [executor.submit(_tolerance_share, path, seed, trials, i, n, threads) for i in range(1, n + 1)]
        shares = [f.result() for f in futures]
    return _tolerance_summary(path, shares, time.perf_counter() - t0)


def _refuse_fork(executor: concurrent.futures.Executor) -> None:
    """Refuses a process pool whose workers fork this process."""
    if isinstance(executor, concurrent.futures.ProcessPoolExecutor):
        ctx = getattr(executor, "_mp_context", None)
        method = ctx.get_start_method() if ctx is not None else None
        if method == "fork":
            raise LensError(
                "a ProcessPoolExecutor that forks: a forked rayon thread pool hangs; make it with "
                "mp_context=multiprocessing.get_context('spawn') (or 'forkserver')"
            )
