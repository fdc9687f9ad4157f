"""Local worker processes: tasks run on a pool, results yielded as they finish (a sweep's hunts, an own-loop run's
hunts, a study's episodes).

A worker that dies loses only the tasks it was running. A death breaks the whole pool: the tasks then running go
to a new pool, and after ``MAX_WORKER_DEATHS`` deaths the run stops (:class:`~mpc_hunt.errors.WorkersDied`).
Workers ignore Ctrl-C while idle and exit at once while they run a task (not by KeyboardInterrupt, which a solver
such as IPOPT takes as a request to end its solve); on Linux they die with the process that started them.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
from collections import deque
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Generator, Iterable, Iterator

from mpc_hunt.errors import WorkersDied

MAX_WORKER_DEATHS = 3
PR_SET_PDEATHSIG = 1  # prctl(2): the signal a process gets when its parent dies
_END = object()  # the end of a task iterator


def run_local(todo: Iterable, work: Callable[[Any], Any], workers: int | None = None) -> Generator[Any, None, None]:
    """``work(task)`` for each task of ``todo`` on local worker processes, yielded as each finishes; stops cleanly
    when the caller stops iterating. ``work`` is a module-level function (so that it pickles); ``todo`` is read as
    workers are free (at most two tasks a worker wait at once)."""
    workers = workers or os.cpu_count() or 1
    pending, retry = iter(todo), deque[Any]()
    for _ in range(MAX_WORKER_DEATHS + 1):
        if not (yield from _run_pool(pending, retry, workers, work)):
            return
    raise WorkersDied(f"local worker processes died {MAX_WORKER_DEATHS + 1} times (killed? out of memory?)")


def _run_pool(pending: Iterator, retry: deque, workers: int, work: Callable[[Any], Any]) -> Generator[Any, None, bool]:
    """Run the tasks of ``retry`` then ``pending`` on one pool, yielding results; True if a worker died (its
    unfinished tasks go back to ``retry``)."""
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_start_worker, initargs=(os.getpid(),))
    running: dict[Future, Any] = {}
    broken = False
    try:
        while not broken:
            while len(running) < 2 * workers:
                task = retry.popleft() if retry else next(pending, _END)
                if task is _END:
                    break
                running[pool.submit(_interruptible, work, task)] = task
            if not running:
                break
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            broken = any(isinstance(f.exception(), BrokenProcessPool) for f in finished)
            if broken:  # every running task is lost with the pool; some may have finished first
                finished, _ = wait(running)
            for future in finished:
                task = running.pop(future)
                if isinstance(future.exception(), BrokenProcessPool):
                    retry.appendleft(task)
                else:
                    yield future.result()
        return broken
    finally:
        for future in running:
            future.cancel()
        pool.shutdown(wait=True, cancel_futures=True)


def _start_worker(parent_pid: int) -> None:
    """A worker ignores Ctrl-C while idle and, on Linux, dies with the process that started it: a run killed
    outright (SIGKILL, out of memory) leaves no worker waiting for work that will never come."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
        if os.getppid() != parent_pid:  # the parent died before the request was made
            os._exit(1)


def _interruptible(work: Callable[[Any], Any], task) -> Any:
    """``work(task)`` in a worker, which ignores Ctrl-C except while it runs a task: then it exits at once."""
    signal.signal(signal.SIGINT, _exit_now)
    try:
        return work(task)
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def _exit_now(signum, frame):
    os._exit(128 + signum)
