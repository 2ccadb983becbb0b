"""Where the members of a study run: local worker processes (the default: every core, nothing
to set up) or a Dask distributed cluster (docs/ensembles.md, "Engines").

Both are used the same way: :meth:`submit` a member, iterate :meth:`completed` over the
futures as they finish. A worker process lives for the whole study, so the kernels it loads
(or compiles, on a cold cache) serve every member it runs. On Dask, a worker that dies hands
its members to the others (the scheduler's own rule; a member that kills workers three times
is reported as failed); locally, a pool whose worker died is restarted with the members not
yet finished.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, as_completed, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from conslaw.ensemble.member import (
    MemberOutcome,
    MemberTask,
    prepare_member,
    run_member,
    run_members,
)
from conslaw.errors import ConfigError, shown


class WorkerLostError(Exception):
    """The worker running a member died (out of memory, killed); the member may be run again."""


#: ``prctl`` option: the signal this process gets when the thread that started it ends.
_PR_SET_PDEATHSIG = 1
#: Seconds between a local worker's looks at whether its study's process is still there.
PARENT_POLL_SECONDS = 1.0


def _ignore_interrupts() -> None:
    """The start of a local worker. Ctrl-C is for the study (it stops submitting and keeps what
    is done); a worker finishes its member. A worker ends as soon as the study's process is
    gone, even killed outright (``kill -9``), instead of living on as an orphan holding its
    memory and the caller's stdout (:func:`_end_with_the_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _end_with_the_parent()


def _end_with_the_parent() -> None:
    """Make this worker end when the process that started it ends: on Linux the kernel sends it
    SIGKILL then (``prctl(PR_SET_PDEATHSIG)``: also in the middle of a compiled kernel that
    holds the GIL); everywhere, a daemon thread waits on the parent's sentinel (and, where
    there is no sentinel, polls the parent's pid) and ends the process once the parent is gone.
    """
    parent = multiprocessing.parent_process()
    parent_pid = os.getppid()
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent_pid:  # gone before prctl took effect
            os._exit(1)

    def watch() -> None:
        if parent is not None and parent.sentinel is not None:
            multiprocessing.connection.wait([parent.sentinel])
        else:
            while os.getppid() == parent_pid:
                time.sleep(PARENT_POLL_SECONDS)
        os._exit(1)  # nothing to finish: the study that wanted the result is gone

    threading.Thread(target=watch, name="conslaw-parent-watch", daemon=True).start()


class LocalEngine:
    """Local worker processes (``spawn``: a fresh interpreter each, no inherited JIT state).

    Parameters
    ----------
    workers : int, optional
        Processes (default: the cores this process may use). At most one per core and one per
        member are started (more only wait their turn, each holding a whole interpreter with
        its kernels); :attr:`note` says so when ``workers`` asked for more.
    members : int, optional
        The members to run, if known.
    """

    name = "local"

    def __init__(self, workers: int | None = None, members: int | None = None) -> None:
        if workers is not None and (
            isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
        ):
            raise ConfigError(f"--workers: expected an integer >= 1, got {shown(workers)}")
        affinity = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
        cores = affinity or os.cpu_count() or 1
        cap = min(cores, max(members, 1)) if members is not None else cores
        self.workers = min(workers or cores, cap)
        #: Why fewer workers than asked start (None: as many as asked).
        self.note: str | None = None
        if workers is not None and workers > self.workers:
            each = f"one per core this process may use ({cores})"
            if members is not None:
                each += f" and one per member ({members})"
            self.note = f"--workers {shown(workers)}: starting {self.workers}, at most {each}"
        self._pool: ProcessPoolExecutor | None = None

    def start(self) -> None:
        """Start the worker processes."""
        context = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(
            self.workers, mp_context=context, initializer=_ignore_interrupts
        )

    def capacity(self) -> int:
        """Members that can run at once: the worker processes."""
        return self.workers

    def boot(self, task: MemberTask) -> None:
        """Start every worker process now, each loading the kernels ``task`` needs
        (:func:`~conslaw.ensemble.member.prepare_member`), while this process goes on."""
        assert self._pool is not None, "start() first"
        for _ in range(self.workers):
            self._pool.submit(prepare_member, task)

    def submit(self, task: MemberTask) -> Future[MemberOutcome]:
        """Run ``task`` on a worker."""
        return self._submit(run_member, task)

    def submit_batch(self, tasks: list[MemberTask]) -> Future[list[MemberOutcome]]:
        """Run ``tasks`` one after the other on one worker (one call for several short
        members)."""
        return self._submit(run_members, tasks)

    def _submit(self, function: Any, argument: Any) -> Future[Any]:
        """``function(argument)`` on a worker; a pool already broken (a worker died since the
        last call) gives a future failed with its error, as if the worker died on this one."""
        assert self._pool is not None, "start() first"
        try:
            return self._pool.submit(function, argument)
        except BrokenProcessPool as error:
            failed: Future[Any] = Future()
            failed.set_exception(error)
            return failed

    def completed(self, futures: Iterable[Future[Any]]) -> Iterator[Any]:
        """The futures as they finish."""
        return as_completed(list(futures))

    def wait_any(self, futures: Iterable[Future[Any]]) -> set[Any]:
        """Wait until at least one of ``futures`` is done; the done ones."""
        return set(wait(list(futures), return_when=FIRST_COMPLETED).done)

    def outcome(self, future: Future[Any]) -> Any:
        """A finished future's outcome (a list of them for a batch); :class:`WorkerLostError`
        if its worker died."""
        try:
            return future.result()
        except BrokenProcessPool:
            raise WorkerLostError("a worker process died") from None

    def restart(self) -> None:
        """A new pool after a worker died (the old one refuses new work)."""
        self.stop(wait=False)
        self.start()

    def stop(self, wait: bool = True) -> None:
        """Cancel what has not started; with ``wait``, wait for the processes to end (without,
        they end in the background)."""
        if self._pool is not None:
            self._pool.shutdown(wait=wait, cancel_futures=True)
            self._pool = None

    def abandon(self) -> None:
        """End the worker processes now (a second interrupt)."""
        if self._pool is not None:
            # ProcessPoolExecutor has no public way to end its processes at once.
            for process in list(getattr(self._pool, "_processes", {}).values()):
                process.terminate()
            self.stop(wait=False)


class DaskEngine:
    """A Dask distributed cluster: a scheduler address (``tcp://host:8786``), a
    ``distributed.Client``, or a cluster object (``LocalCluster``, a dask-jobqueue or
    Kubernetes cluster).

    Parameters
    ----------
    scheduler : str or Client or cluster
    """

    name = "dask"

    def __init__(self, scheduler: Any) -> None:
        self.scheduler = scheduler
        self._client: Any = None
        self._own_client = False
        self.workers = 0

    def start(self) -> None:
        """Connect to the scheduler (a ConfigError naming it if that fails)."""
        try:
            from distributed import Client
        except ImportError:
            raise ConfigError(
                "--scheduler needs Dask distributed: pip install 'dask[distributed]'"
            ) from None
        if isinstance(self.scheduler, Client):
            self._client = self.scheduler
        else:
            try:
                self._client = Client(self.scheduler, timeout="10s")
            except (OSError, TimeoutError, ValueError) as error:
                raise ConfigError(
                    f"--scheduler {self.scheduler}: cannot reach the Dask scheduler ({error})"
                ) from None
            self._own_client = True
        self.workers = len(self._client.scheduler_info().get("workers", {}))

    def capacity(self) -> int:
        """Members that can run at once: the threads of the workers connected now (an adaptive
        cluster grows and shrinks during a study)."""
        workers = self._client.scheduler_info().get("workers", {})
        self.workers = len(workers)
        return sum(int(worker.get("nthreads", 1)) for worker in workers.values())

    def boot(self, task: MemberTask) -> None:
        """Nothing: a cluster's workers are running already; each loads the kernels at its
        first member."""

    def submit(self, task: MemberTask) -> Any:
        """Run ``task`` on a worker (one Dask task per member, not cached by value)."""
        return self._client.submit(run_member, task, pure=False)

    def submit_batch(self, tasks: list[MemberTask]) -> Any:
        """Run ``tasks`` one after the other as one Dask task."""
        return self._client.submit(run_members, tasks, pure=False)

    def completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        """The futures as they finish."""
        from distributed import as_completed as dask_completed

        return iter(dask_completed(list(futures)))

    def wait_any(self, futures: Iterable[Any]) -> set[Any]:
        """Wait until at least one of ``futures`` is done; the done ones."""
        from distributed import wait as dask_wait

        return set(dask_wait(list(futures), return_when="FIRST_COMPLETED").done)

    def outcome(self, future: Any) -> Any:
        """A finished future's outcome (a list of them for a batch); :class:`WorkerLostError`
        if its workers kept dying (the scheduler gave up on it)."""
        from distributed import KilledWorker

        try:
            return future.result()
        except KilledWorker as error:
            raise WorkerLostError(f"its workers died while running it ({error})") from None

    def restart(self) -> None:
        """Nothing to do: the scheduler moves a dead worker's tasks itself."""

    def stop(self, wait: bool = True) -> None:
        """Disconnect (a client made here is closed)."""
        if self._client is not None and self._own_client:
            self._client.close()
        self._client = None

    def abandon(self) -> None:
        """Disconnect at once."""
        self.stop(wait=False)


def engine_for(
    scheduler: Any = None, workers: int | None = None, members: int | None = None
) -> LocalEngine | DaskEngine:
    """:class:`DaskEngine` for a scheduler, else :class:`LocalEngine` with ``workers`` (for
    ``members`` members, if known)."""
    if scheduler is not None:
        if workers is not None:
            raise ConfigError("--workers is for the local engine; a Dask cluster has its own")
        return DaskEngine(scheduler)
    return LocalEngine(workers, members)
