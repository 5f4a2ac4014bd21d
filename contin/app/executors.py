"""Executors: one interface for running many independent tasks serially, on local processes or on Dask.

A sweep (``contin classify --sweep``, the studies' loops over cases) hands a module-level function
and a list of items to an :class:`Executor` and gets back ``(index, result)`` pairs as the tasks
finish.  Three executors implement it:

- :class:`SerialExecutor` runs every task in this process, one after the other;
- :class:`ProcessExecutor` (the default) runs them on a pool of local worker processes, started with
  the ``spawn`` method, each with one BLAS/OpenMP thread and with Ctrl-C left to this process;
- :class:`DaskExecutor` runs them on a Dask distributed cluster given by its scheduler's address.  It
  needs the optional extra ``pip install 'contin[dask]'``; ``dask`` and ``distributed`` are imported
  only when a scheduler is given.

:func:`make_executor` picks one from the usual options (``workers``, ``scheduler``).  The task
function is the same for every executor, so are the results: an executor changes where a task runs,
never what it computes.

A task that raises is not swallowed: the exception is raised again by :meth:`Executor.map_unordered`
(as its original type, where it can be sent back) once the other tasks are stopped.  A worker process
that dies under a task (killed, out of memory, a crash in compiled code) does not hang the run: the
tasks it was running are run again one at a time, and the one that kills its worker again gets a
:class:`WorkerDied` in place of its result.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import uuid
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from itertools import islice
from types import TracebackType
from typing import Any

# the BLAS and OpenMP thread counts of the worker processes, set to one: the parallelism is over tasks
from ..numerics.threads import THREAD_ENV

__all__ = ["Executor", "SerialExecutor", "ProcessExecutor", "DaskExecutor", "WorkerDied", "ExecutorError",
           "make_executor", "default_workers", "DASK_EXTRA", "DEFAULT_CONNECT_TIMEOUT"]

#: How to install what :class:`DaskExecutor` needs (quoted in its error messages).
DASK_EXTRA = "pip install 'contin[dask]'"
#: Seconds to wait for a Dask scheduler to answer, and for it to have a worker.
DEFAULT_CONNECT_TIMEOUT = 10.0
_DIED = "the worker process died while running this task (killed, out of memory, or a crash in compiled code)"

Task = Callable[[Any], Any]


class ExecutorError(ValueError):
    """An executor that cannot be had: bad options, Dask not installed, a scheduler that cannot be reached.

    The message is one paragraph meant for the user (the command line prints it with exit status 2).
    """


class WorkerDied(Exception):
    """Yielded (not raised) by :meth:`Executor.map_unordered` in place of the result of a task whose
    worker process died while running it, even when it was run again alone.

    Attributes
    ----------
    message : str
        What happened, one line.
    """

    def __init__(self, message: str = _DIED) -> None:
        super().__init__(message)
        self.message = message

    def __reduce__(self) -> tuple[Any, ...]:
        return type(self), (self.message,)


def _one_line(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


def default_workers() -> int:
    """The number of CPUs this process may use (at least 1)."""
    count = getattr(os, "process_cpu_count", None)  # Python >= 3.13
    if count is not None:
        return max(1, count() or 1)
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


# ---------------------------------------------------------------------------------------------------
# the interface
# ---------------------------------------------------------------------------------------------------
class Executor(ABC):
    """Runs a function over items, somewhere; a context manager (:meth:`close` on exit).

    Attributes
    ----------
    name : str
        ``"serial"``, ``"process"`` or ``"dask"``.
    workers : int
        How many tasks run at once (for Dask: the worker threads of the cluster when it was reached).
    in_process : bool
        True when the tasks run in this process (their function need not be picklable, and they see
        this process's objects, not copies).
    """

    name: str = ""
    workers: int = 1
    in_process: bool = False

    @abstractmethod
    def map_unordered(self, fn: Task, items: Iterable[Any], *, initializer: Callable[..., Any] | None = None,
                      initargs: Sequence[Any] = ()) -> Iterator[tuple[int, Any]]:
        """Run ``fn(item)`` for every item; yield ``(index into items, result)`` as the tasks finish.

        Parameters
        ----------
        fn : callable
            A function of one item.  Except for :class:`SerialExecutor` it is sent to other
            processes: a module-level function (or a :func:`functools.partial` of one) of an
            importable module, with picklable items and results.
        items : iterable
            The items (read into a list first).
        initializer : callable, optional
            Run as ``initializer(*initargs)`` once in each worker process before its first task of
            this call (for example to load a model), and once in this process by
            :class:`SerialExecutor`.  An exception it raises is raised by the tasks of that worker.
        initargs : sequence
            Arguments of ``initializer``.

        Yields
        ------
        (int, object)
            The item's index and ``fn(item)``, or a :class:`WorkerDied` when the task's worker process
            died under it twice (the second time alone).

        Raises
        ------
        Exception
            The first exception raised by a task, after the other tasks are stopped.
        KeyboardInterrupt
            On Ctrl-C: the running tasks are stopped, no further task starts.

        Notes
        -----
        Closing the generator early (``break`` inside :func:`contextlib.closing`) stops the tasks
        still running.  At most :attr:`workers` tasks (Dask: a few per worker thread) are in flight.
        """

    def map(self, fn: Task, items: Iterable[Any], *, initializer: Callable[..., Any] | None = None,
            initargs: Sequence[Any] = ()) -> list[Any]:
        """``[fn(item) for item in items]``, computed by :meth:`map_unordered`, in the order of ``items``.

        Raises
        ------
        WorkerDied
            When a task's worker process died under it (raised here, unlike :meth:`map_unordered`).
        Exception
            The first exception raised by a task.
        """
        items = list(items)
        out: list[Any] = [None] * len(items)
        gen = self.map_unordered(fn, items, initializer=initializer, initargs=initargs)
        try:
            for i, result in gen:
                if isinstance(result, WorkerDied):
                    raise result
                out[i] = result
        finally:
            gen.close()
        return out

    def where(self, n_tasks: int) -> str:
        """Where ``n_tasks`` tasks run, for a progress line (``"on 2 worker processes"``)."""
        return "in this process"

    def close(self) -> None:
        """Release the executor's workers or connection; it cannot be used afterwards."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"{type(self).__name__}(workers={self.workers})"


# ---------------------------------------------------------------------------------------------------
# serial
# ---------------------------------------------------------------------------------------------------
class SerialExecutor(Executor):
    """Every task in this process, in the order of the items (``workers`` is 1)."""

    name = "serial"
    workers = 1
    in_process = True

    def map_unordered(self, fn: Task, items: Iterable[Any], *, initializer: Callable[..., Any] | None = None,
                      initargs: Sequence[Any] = ()) -> Iterator[tuple[int, Any]]:
        items = list(items)
        if items and initializer is not None:
            initializer(*initargs)
        for i, item in enumerate(items):
            yield i, fn(item)


# ---------------------------------------------------------------------------------------------------
# local processes
# ---------------------------------------------------------------------------------------------------
_INIT_ERROR: list[BaseException] = []  # in a worker process: what its initializer raised


def _process_init(initializer: Callable[..., Any] | None, initargs: Sequence[Any]) -> None:
    """Initializer of a worker process: one BLAS thread, Ctrl-C left to the parent, then the caller's."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        if hasattr(signal, "pthread_sigmask"):
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    except (ValueError, OSError):
        pass
    for var in THREAD_ENV:
        os.environ[var] = "1"
    if initializer is not None:
        try:
            initializer(*initargs)
        except BaseException as exc:  # raised by every task of this worker, never a traceback from the pool
            _INIT_ERROR.append(exc)


def _process_task(fn: Task, item: Any) -> Any:
    if _INIT_ERROR:
        raise _INIT_ERROR[0]
    return fn(item)


@contextmanager
def _spawning() -> Iterator[None]:
    """Around starting worker processes: they inherit one BLAS thread and a blocked SIGINT.

    The environment variables must be in place before a worker imports numpy, which happens before
    its initializer runs; the blocked SIGINT keeps a Ctrl-C during a worker's start-up from printing
    a traceback there (the initializer then ignores SIGINT; the parent handles it).
    """
    saved = {var: os.environ.get(var) for var in THREAD_ENV}
    os.environ.update(dict.fromkeys(THREAD_ENV, "1"))
    mask = hasattr(signal, "pthread_sigmask") and threading.current_thread() is threading.main_thread()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if mask else None
    try:
        yield
    finally:
        if mask:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)
        for var, value in saved.items():
            if value is None:
                os.environ.pop(var, None)
            else:
                os.environ[var] = value


def _stop(pool: ProcessPoolExecutor) -> None:
    """Stop the workers now (an interrupt or a failed task): pending work is cancelled, running work killed."""
    terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for p in processes:
        if p.is_alive():
            p.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    # the pool's manager thread may have started a worker after the first look: stop those as well
    late = [p for p in (getattr(pool, "_processes", None) or {}).values() if p not in processes]
    for p in late:
        if p.is_alive():
            p.terminate()
    for p in processes + late:
        p.join(timeout=5)


def _same(a: Any, b: Any) -> bool:
    try:
        return bool(a == b)
    except Exception:
        return False


class ProcessExecutor(Executor):
    """Tasks on a pool of ``workers`` local processes (``spawn``; one BLAS thread each).

    The pool is started at the first task and kept for later calls with the same initializer and
    arguments; :meth:`close` ends it.  Ctrl-C is handled by this process, which then stops the workers.

    Parameters
    ----------
    workers : int, optional
        Worker processes (default: :func:`default_workers`).
    """

    name = "process"

    def __init__(self, workers: int | None = None) -> None:
        workers = default_workers() if workers is None else workers
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise ExecutorError(f"workers must be an integer >= 1, got {workers!r}")
        self.workers = workers
        self._pool: ProcessPoolExecutor | None = None
        self._pool_init: tuple[Any, Any] | None = None
        self._busy = False
        self._closed = False

    def where(self, n_tasks: int) -> str:
        n = max(1, min(self.workers, n_tasks))
        return f"on {n} worker process{'es' if n > 1 else ''}"

    def _new_pool(self, size: int, initializer: Callable[..., Any] | None,
                  initargs: Sequence[Any]) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(max_workers=size, mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_process_init, initargs=(initializer, tuple(initargs)))

    def _shared_pool(self, initializer: Callable[..., Any] | None, initargs: Sequence[Any]) -> ProcessPoolExecutor:
        key = (initializer, tuple(initargs))
        if self._pool is not None and not (self._pool_init is not None and _same(self._pool_init, key)):
            self._pool.shutdown(wait=True)
            self._pool = None
        if self._pool is None:
            self._pool = self._new_pool(self.workers, initializer, initargs)
            self._pool_init = key
        return self._pool

    def _discard(self, pool: ProcessPoolExecutor) -> None:
        if pool is self._pool:
            self._pool = self._pool_init = None

    def _round(self, fn: Task, items: list[Any], queue: deque[int], pool: ProcessPoolExecutor,
               limit: int) -> Iterator[tuple[int, Any]]:
        """Run the queue on ``pool`` until it is empty or the pool breaks; returns the suspects.

        At most ``limit`` tasks are in flight, so when a worker dies the suspects are known: they are
        returned (the rest stays in ``queue``).
        """
        inflight: dict[Future, int] = {}
        broken: list[int] = []
        try:
            while queue or inflight:
                while queue and len(inflight) < limit and not broken:
                    i = queue.popleft()
                    try:
                        with _spawning():
                            inflight[pool.submit(_process_task, fn, items[i])] = i
                    except BrokenProcessPool:
                        queue.appendleft(i)
                        broken.append(-1)
                if not inflight:
                    break
                done, _ = wait(inflight, return_when=FIRST_COMPLETED)
                for fut in done:
                    i = inflight.pop(fut)
                    try:
                        result = fut.result()
                    except BrokenProcessPool:
                        broken.append(i)
                        continue
                    yield i, result
        except BaseException:  # a task raised, Ctrl-C, or the caller closed the generator
            _stop(pool)
            self._discard(pool)
            raise
        if broken:
            pool.shutdown(wait=True)
            self._discard(pool)
        return [i for i in broken if i >= 0]

    def map_unordered(self, fn: Task, items: Iterable[Any], *, initializer: Callable[..., Any] | None = None,
                      initargs: Sequence[Any] = ()) -> Iterator[tuple[int, Any]]:
        if self._closed:
            raise RuntimeError("this ProcessExecutor is closed")
        if self._busy:
            raise RuntimeError("a ProcessExecutor runs one map at a time; finish or close the other first")
        items = list(items)
        if not items:
            return
        self._busy = True
        try:
            queue = deque(range(len(items)))
            while queue:
                pool = self._shared_pool(initializer, initargs)
                suspects = deque((yield from self._round(fn, items, queue, pool, self.workers)))
                # one at a time, each on a fresh pool of one process, so that the task that kills its
                # worker is the one named
                while suspects:
                    alone = self._new_pool(1, initializer, initargs)
                    try:
                        died = yield from self._round(fn, items, suspects, alone, 1)
                    finally:
                        alone.shutdown(wait=True)
                    for i in died:
                        yield i, WorkerDied()
        finally:
            self._busy = False

    def close(self) -> None:
        self._closed = True
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = self._pool_init = None


# ---------------------------------------------------------------------------------------------------
# Dask
# ---------------------------------------------------------------------------------------------------
_DASK_LOCK = threading.Lock()
_DASK_READY: dict[str, BaseException | None] = {}  # in a Dask worker process: initializer outcome per call


def _dask_task(fn: Task, item: Any, initializer: Callable[..., Any] | None, initargs: Sequence[Any],
               token: str) -> Any:
    """A task on a Dask worker: the call's initializer first, once per worker process (cached)."""
    if initializer is not None:
        with _DASK_LOCK:
            if token not in _DASK_READY:
                try:
                    initializer(*initargs)
                    _DASK_READY[token] = None
                except Exception as exc:
                    _DASK_READY[token] = exc
        error = _DASK_READY[token]
        if error is not None:
            raise error
    return fn(item)


class DaskExecutor(Executor):
    """Tasks on a Dask distributed cluster, through ``distributed.Client(address)``.

    The workers must have contin installed (the same version, in an environment like this one); the
    task function and the initializer are sent to them by reference.  The initializer runs on each
    worker process before its first task of a call (held in a cache per worker process).  A worker
    that dies is restarted by its nanny and its task run elsewhere; a task that kills
    ``distributed.scheduler.allowed-failures + 1`` workers (default 4) gets a :class:`WorkerDied`.
    Start the workers with ``--nthreads 1`` when the model is not meant to share a process between
    threads (as for the process pool: one task per process).

    Parameters
    ----------
    address : str
        The scheduler, e.g. ``tcp://127.0.0.1:8786``.
    timeout : float, optional
        Seconds to wait for the scheduler to answer and to have at least one worker (default:
        :data:`DEFAULT_CONNECT_TIMEOUT`).

    Raises
    ------
    ExecutorError
        When ``distributed`` is not installed, the scheduler cannot be reached within ``timeout``, or
        it has no worker.
    """

    name = "dask"

    def __init__(self, address: str, timeout: float | None = None) -> None:
        timeout = DEFAULT_CONNECT_TIMEOUT if timeout is None else float(timeout)
        try:
            import distributed
        except ImportError as exc:
            raise ExecutorError(f"running on a Dask scheduler ({address}) needs the packages dask and distributed, "
                                f"which are not installed ({_one_line(exc)}); install the optional extra: "
                                f"{DASK_EXTRA}") from None
        from distributed.comm.addressing import resolve_address

        self.address = address
        self._closed = False
        try:  # a malformed address would leave a half-made Client behind, which hangs when collected
            resolve_address(address)
        except Exception as exc:
            raise ExecutorError(f"{address!r} is not the address of a Dask scheduler ({_one_line(exc)}); give the "
                                f"address 'dask scheduler' prints, e.g. tcp://127.0.0.1:8786") from None
        try:
            self._client = distributed.Client(address, timeout=timeout, set_as_default=False)
        except Exception as exc:
            raise ExecutorError(f"cannot reach the Dask scheduler at {address!r} within {timeout:g} s "
                                f"({_one_line(exc)}); start one with 'dask scheduler' and give the address it "
                                f"prints, e.g. tcp://127.0.0.1:8786") from None
        try:
            self._client.wait_for_workers(1, timeout=timeout)
        except Exception:
            self._client.close()
            raise ExecutorError(f"the Dask scheduler at {address!r} has no worker after {timeout:g} s; start "
                                f"some with 'dask worker {address} --nthreads 1'") from None
        self.workers = max(1, sum(self._client.nthreads().values()))

    def where(self, n_tasks: int) -> str:
        return f"on the Dask cluster at {self.address} ({self.workers} worker thread{'s' if self.workers > 1 else ''})"

    def map_unordered(self, fn: Task, items: Iterable[Any], *, initializer: Callable[..., Any] | None = None,
                      initargs: Sequence[Any] = ()) -> Iterator[tuple[int, Any]]:
        from distributed import as_completed
        from distributed.scheduler import KilledWorker

        if self._closed:
            raise RuntimeError("this DaskExecutor is closed")
        items = list(items)
        if not items:
            return
        client = self._client
        token = uuid.uuid4().hex  # the initializer runs again on every worker for each call
        initargs = tuple(initargs)
        window = max(16, 4 * self.workers)  # in flight: enough to keep every worker busy
        indices = iter(range(len(items)))
        futures: dict[Any, int] = {}

        def submit(i: int) -> Any:
            fut = client.submit(_dask_task, fn, items[i], initializer, initargs, token, pure=False)
            futures[fut] = i
            return fut

        done = as_completed([submit(i) for i in islice(indices, window)], loop=client.loop)
        try:
            for fut in done:
                i = futures.pop(fut)
                try:
                    result = fut.result()
                except KilledWorker as exc:
                    result = WorkerDied(f"{_DIED}; Dask: {' '.join(str(exc).split())}")
                nxt = next(indices, None)
                if nxt is not None:
                    done.add(submit(nxt))
                yield i, result
        except BaseException:  # a task raised, Ctrl-C, or the caller closed the generator
            if futures:
                try:
                    client.cancel(list(futures))
                except Exception:
                    pass
            raise

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self._client.close()


# ---------------------------------------------------------------------------------------------------
def make_executor(workers: int | None = None, scheduler: str | None = None, *,
                  timeout: float | None = None) -> Executor:
    """The executor for the usual options.

    Parameters
    ----------
    workers : int, optional
        Local worker processes: 1 runs in this process (:class:`SerialExecutor`), more a
        :class:`ProcessExecutor`; default: one per CPU available (:func:`default_workers`; serial on
        one CPU).  Not with ``scheduler``.
    scheduler : str, optional
        A Dask scheduler's address (``tcp://HOST:8786``): a :class:`DaskExecutor`.
    timeout : float, optional
        Seconds to wait for the Dask scheduler (default: :data:`DEFAULT_CONNECT_TIMEOUT`).

    Returns
    -------
    Executor
        To be closed (use it as a context manager).

    Raises
    ------
    ExecutorError
        ``workers`` below 1 or given with ``scheduler``; Dask not installed; the scheduler not reached.
    """
    if scheduler is not None:
        if workers is not None:
            raise ExecutorError(f"give either a number of local workers ({workers}) or a Dask scheduler "
                                f"({scheduler}), not both: the cluster's workers run the tasks")
        if not str(scheduler).strip():
            raise ExecutorError("the Dask scheduler address is empty; give it as tcp://HOST:PORT")
        return DaskExecutor(str(scheduler).strip(), timeout=timeout)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ExecutorError(f"workers must be an integer >= 1, got {workers!r}")
    n = default_workers() if workers is None else workers
    return SerialExecutor() if n == 1 else ProcessExecutor(n)
