"""An experiment's independent rows as Dask tasks: one call for serial and distributed.

:func:`row_client` gives the client an experiment's rows run on — none (serial, in this
process), a local cluster of one single-threaded worker process per core, or an existing
cluster by its scheduler address — and :func:`map_rows` runs a row function over the jobs
on it, handing every result to the driver's callback in completion order.  The driver is
the only writer of checkpoints: workers only compute.  Inside a Dask worker (a sweep's
point) the rows run serially, so clusters never nest.

Large shared inputs (the condensed pad) are not sent with the tasks: the driver builds
them once into their content-hash disk cache and each worker process loads them on first
use and keeps them (a per-process memo in the row function's module).
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from functools import partial
from typing import Any

import numpy as np

from .. import config
from ..blas_threads import one_blas_thread

log = logging.getLogger(__name__)

__all__ = [
    "check_workers",
    "in_dask_worker",
    "local_cluster",
    "local_memory_limit",
    "map_rows",
    "pin_numba_threads_env",
    "row_client",
    "run_checkpointed",
    "run_rows",
]


def _one_blas_thread(fn: Callable[[Any], Any], job: Any, settings: dict | None = None) -> Any:
    """``fn(job)`` with one BLAS/OpenMP thread (threadpoolctl) and one Numba thread, wherever
    it runs, under the driver's ``settings`` (:func:`workbench.config.changed`: the tolerances and
    defaults it set — a worker is another process, which would otherwise compute with its own).

    A row's numbers must not depend on where it ran: multithreaded BLAS sums in another
    order, and the thesis-code protocol's wrench-grid downsampling turns that last-bit
    noise into a different training set — measured on fem-fitting --quick, per-profile
    errors moved by up to 17 % (the mean by 2 %) between a serial run with the machine's
    BLAS threads and two single-threaded workers; with one thread in both they agree to
    1e-4 (the quartic's iterative solver)."""
    import numba

    pin_numba_threads_env()
    before = numba.get_num_threads()
    numba.set_num_threads(1)  # prange reductions sum in another order on more threads too
    try:
        with one_blas_thread(), config.override(**(settings or {})):
            return fn(job)
    finally:
        numba.set_num_threads(before)


def pin_numba_threads_env() -> None:
    """Set ``NUMBA_NUM_THREADS`` in this process's environment to the pool size Numba already
    has, so that compiling a kernel here (which re-reads the environment) cannot raise.

    A Dask worker imports Numba before the nanny's ``env`` (``NUMBA_NUM_THREADS=1``, see
    :func:`local_cluster`) is applied: its config says 2 threads on this machine, the pool starts
    with 2, and the first kernel compiled in the worker — one not in Numba's disk cache yet, e.g.
    in a fresh checkout — re-reads 1 and raises "Cannot set NUMBA_NUM_THREADS to a different
    value once the threads have been launched" (measured: every fem-fitting reference task, and
    sensitivity and minimal-work, failed so in a clean clone).  Tasks still use one thread
    (:func:`_one_blas_thread`)."""
    import numba

    os.environ["NUMBA_NUM_THREADS"] = str(numba.config.NUMBA_NUM_THREADS)


def in_dask_worker() -> bool:
    """True inside a Dask worker's task."""
    try:
        from distributed import get_worker

        get_worker()
        return True
    except (ImportError, ValueError):
        return False


def check_workers(workers: Any, scheduler: Any) -> None:
    """``ValueError`` unless ``workers`` is an int >= 0 and ``scheduler`` a string — '' or an
    address whose TCP port, if it has one, is in 1-65535 (:func:`scheduler_host_port`) and where
    something listens (:func:`probe_scheduler`) — and not both an address and a ``workers``
    other than 0 (the address would override them)."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise ValueError(
            f"workers must be 0 (a local cluster when there are many rows), 1 (serial) or the "
            f"number of worker processes; got {workers!r}"
        )
    if not isinstance(scheduler, str):
        raise ValueError(
            f"scheduler must be a Dask scheduler address like tcp://host:8786 or ''; got {scheduler!r}"
        )
    if scheduler.strip():
        scheduler_host_port(scheduler, "scheduler")
        if workers != 0:
            raise ValueError(
                f"workers={workers} with scheduler={scheduler!r}: the rows run on that cluster and "
                "workers would be ignored; give one of them (workers=0 with a scheduler)"
            )
        # before any work: nothing listening there fails now, not after the run has started
        probe_scheduler(scheduler, config.RUN.scheduler_probe_s)


def scheduler_host_port(address: str, what: str = "scheduler") -> tuple[str, int] | None:
    """(host, port) of a TCP scheduler address (``tcp://host:port``, ``tls://...``, a bare
    ``host:port``; an IPv6 host in brackets), or None for another protocol or no port (Dask
    judges those).  ``ValueError`` naming ``what`` for a port that is not a number in 1-65535."""
    proto, sep, rest = address.strip().partition("://")
    if not sep:
        proto, rest = "tcp", address.strip()
    if proto not in ("tcp", "tls"):
        return None
    host, colon, port_text = rest.rstrip("/").rpartition(":")
    if not colon or host.count(":") and not host.startswith("["):  # no port, or a bare IPv6 host
        return None
    if not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise ValueError(
            f"{what} {address!r}: port {port_text!r} is not a TCP port (1-65535); give the address "
            "`dask scheduler` printed, e.g. tcp://host:8786"
        )
    return host.strip("[]") or "127.0.0.1", int(port_text)


def probe_scheduler(address: str, timeout: float, what: str = "scheduler") -> None:
    """``ValueError`` (naming ``what``) at once when nothing listens at ``address``'s host and
    port (connection refused, host unknown or unreachable), instead of the Dask client's full
    wait; a probe that times out returns (the client's own wait then decides)."""
    import socket

    host_port = scheduler_host_port(address, what)
    if host_port is None:
        return
    host, port = host_port
    try:
        with socket.create_connection((host, port), timeout=timeout):
            return
    except TimeoutError:
        log.info("no answer from %s:%d within %g s; waiting for the Dask client", host, port, timeout)
        return
    except socket.gaierror as exc:
        raise ValueError(
            f"{what} {address!r}: host {host!r} is unknown ({exc.strerror or exc}); give the "
            "scheduler's host name or IP address, e.g. tcp://10.0.0.5:8786"
        ) from None
    except OSError as exc:  # refused, unreachable
        raise ValueError(
            f"no Dask scheduler at {address!r}: {host}:{port} refused the connection "
            f"({exc.strerror or exc}); start one with `dask scheduler --port {port}` there, or give "
            "the address a running scheduler printed"
        ) from None


@contextmanager
def row_client(
    n_rows: int, workers: int = 0, scheduler: str = "", threads: int = 1, min_rows: int | None = None
) -> Iterator[Any]:
    """The ``distributed.Client`` to run ``n_rows`` rows on, or None to run them serially.

    workers : 0 = a local cluster of one worker per core when ``n_rows`` reaches
    ``min_rows`` (default ``config.RUN.cluster_min_rows``, read now; an experiment
    with a few rows of minutes each passes its own) and the machine has more than one
    core, else serial; 1 = serial; N = a local cluster of N worker processes.
    scheduler : an existing cluster's address (overrides ``workers``).  threads :
    threads per local worker (Numba's and OpenMP's threads are capped to it).
    """
    check_workers(workers, scheduler)
    if n_rows == 0 or in_dask_worker():  # nothing to run, or already a task: no cluster
        yield None
        return
    from distributed import Client

    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    cores = os.cpu_count() or 1
    n = workers if workers > 1 else (cores if workers == 0 and cores > 1 else 1)
    least = config.RUN.cluster_min_rows if min_rows is None else min_rows
    if n == 1 or (workers == 0 and n_rows < least):
        yield None
        return
    logging.getLogger("distributed").setLevel(max(logging.WARNING, logging.getLogger().level))
    with local_cluster(n, threads) as cluster, Client(cluster) as client:
        log.info("rows on a local Dask cluster of %d workers", n)
        yield client


def local_memory_limit(n_workers: int) -> int:
    """The ``memory_limit`` [bytes] of each worker of a :func:`local_cluster` of ``n_workers``:
    this machine's memory (or its cgroup's limit) shared equally — Dask's ``"auto"`` for a
    local cluster, computed here so a sweep knows it before it starts the cluster."""
    from distributed.worker_memory import parse_memory_limit

    return parse_memory_limit("auto", 1, max(1, int(n_workers)), logger=log)


def local_cluster(n_workers: int, threads: int = 1, memory_limit: int | None = None) -> Any:
    """A ``distributed.LocalCluster`` of ``n_workers`` processes with ``threads`` threads each,
    their Numba and OpenMP threads capped to ``threads`` (spinning OpenMP threads of one worker
    starve the others), their progress bars off (the driver shows one), the scheduler's
    queueing from ``config.RUN.cluster_worker_saturation``, and each worker's memory
    limit ``memory_limit`` [bytes] (default :func:`local_memory_limit`; its nanny restarts it
    above ``distributed.worker.memory.terminate`` of that)."""
    import dask
    from distributed import LocalCluster

    n = str(threads)
    # The nanny's pre-spawn environment is set before each worker process starts, so the thread
    # pools read it on import — but Dask sets it with os.environ.update in *this* process, where
    # it stays: only what the driver may share goes there.  Dask's default MALLOC_TRIM_THRESHOLD_
    # is removed: setting it at all turns off glibc's dynamic mmap threshold, so every large
    # temporary is mmap'ed and page-faulted afresh, which slowed fem-fitting's full-mesh
    # reference solve so much that two workers were barely faster than one (docs/decisions.md).  Numba's
    # thread count cannot go there (a driver whose Numba pool already runs on more threads
    # raises when it re-reads NUMBA_NUM_THREADS): it is the worker's own environment, and each
    # task caps Numba's threads anyway (_one_blas_thread).
    dask_settings = {
        "distributed.nanny.pre-spawn-environ": {
            "MALLOC_TRIM_THRESHOLD_": None,
            **dict.fromkeys(("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"), n),
        },
        # the scheduler (in this process) reads its queueing when it is created, here too
        "distributed.scheduler.worker-saturation": config.RUN.cluster_worker_saturation,
    }
    env = {"NUMBA_NUM_THREADS": n, "TQDM_DISABLE": "1"}  # set inside each worker process only
    with dask.config.set(dask_settings):  # each nanny reads its environment when it is created, here
        return LocalCluster(
            n_workers=n_workers,
            threads_per_worker=threads,
            processes=True,
            dashboard_address=None,
            env=env,
            memory_limit=local_memory_limit(n_workers) if memory_limit is None else int(memory_limit),
        )


def map_rows(
    fn: Callable[[Any], Any],
    jobs: Iterable[Any],
    on_result: Callable[[Any, Any], None],
    *,
    client: Any = None,
    progress: Any = None,
    retries: int = 2,
    meanwhile: Callable[[], Any] | None = None,
    stats: dict | None = None,
) -> Any:
    """Run ``fn(job)`` for every job — serially when ``client`` is None, else as Dask tasks —
    and call ``on_result(job, result)`` in this process as each finishes (completion order).

    fn must be importable by the workers (a module-level function or a ``functools.partial``
    of one); progress : an object with ``update(n)`` (e.g. a tqdm bar) advanced by
    ``len(result)`` when the result is a list, else by 1.  A task that raises stops the run
    with that exception (the rows written so far stay checkpointed).

    meanwhile : the driver's own work that needs none of the results (figures, examples),
    run here while the workers compute — after the tasks are submitted, or before the
    serial loop — so the driver's core is not idle; its return value is returned
    (None without it).  Results that finish meanwhile are handed over after it.

    stats : a dict filled with where the time went (:func:`_stream_stats`): per task the
    compute seconds, and on Dask each worker's busy seconds from the scheduler's task stream —
    so a run can tell idle or starting workers from slow tasks."""
    jobs = list(jobs)

    def step(job: Any, res: Any) -> None:
        on_result(job, res)
        if progress is not None:
            progress.update(len(res) if isinstance(res, list) else 1)

    if client is None:
        return _map_serial(fn, jobs, step, meanwhile, stats)
    return _map_dask(fn, jobs, step, client, retries, meanwhile, stats)


def _map_serial(
    fn: Callable[[Any], Any],
    jobs: list,
    step: Callable[[Any, Any], None],
    meanwhile: Callable[[], Any] | None,
    stats: dict | None,
) -> Any:
    """:func:`map_rows` in this process: ``meanwhile`` first, then every job in order."""
    t0 = time.perf_counter()
    extra = meanwhile() if meanwhile is not None else None
    busy = []
    for job in jobs:
        t = time.perf_counter()
        res = _one_blas_thread(fn, job)
        busy.append(time.perf_counter() - t)
        step(job, res)
    if stats is not None:
        stats.update(_stream_stats({"serial": busy}, time.perf_counter() - t0))
    return extra


def _map_dask(
    fn: Callable[[Any], Any],
    jobs: list,
    step: Callable[[Any, Any], None],
    client: Any,
    retries: int,
    meanwhile: Callable[[], Any] | None,
    stats: dict | None,
) -> Any:
    """:func:`map_rows` as Dask tasks on ``client``: submitted, ``meanwhile`` run here, then the
    results handed to ``step`` as they complete (the rest cancelled if one raises)."""
    from contextlib import nullcontext

    from distributed import as_completed, get_task_stream

    t0 = time.perf_counter()
    with get_task_stream(client) if stats is not None else nullcontext() as ts:
        settings = config.changed()  # what configure() set here, for the workers' processes
        task = partial(_one_blas_thread, fn, settings=settings)
        futures = client.map(task, jobs, pure=False, retries=retries)
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            # the driver is a third process beside the workers: its own share runs on one BLAS and
            # one Numba thread too, or their pools spin on the workers' cores
            extra = _one_blas_thread(lambda _: meanwhile(), None) if meanwhile is not None else None
            # results arrive with the completions (a batch per event-loop turn): a fut.result() per
            # task crossed to the client's loop thread and back each time, a cost paid per row
            ac, lost = as_completed(futures, with_results=True), WorkerLoss(client)
            while not ac.is_empty():
                if ac.has_ready():
                    fut, res = next(ac)  # raises the task's exception, as iterating would
                    step(jobs[index[fut.key]], res)
                else:
                    lost.check(ac.count())
                    time.sleep(0.05)  # as_completed's own wait polls every 0.1 s too
        finally:
            client.cancel(futures)
    if stats is not None:
        stats.update(_stream_stats(_compute_seconds(ts.data), time.perf_counter() - t0))
    return extra


class WorkerLoss:
    """A driver's watch for a Dask cluster left without workers while tasks wait on it: the
    nannies restart a worker that dies, but when they die too (the machine out of memory) the
    tasks wait forever.  :meth:`check` raises once the cluster has had no worker for
    ``config.RUN.cluster_no_worker_s`` (read at each check)."""

    PROBE_S = 1.0  # seconds between two asks of the scheduler (one round trip each)

    def __init__(self, client: Any) -> None:
        self.client = client
        self.since: float | None = None  # when the cluster was first seen without workers
        self.next_probe = 0.0

    def check(self, pending: int) -> None:
        """Ask the scheduler (at most every :attr:`PROBE_S`) whether a worker is left; raise
        RuntimeError when none has been for the configured time, ``pending`` tasks waiting."""
        now = time.monotonic()
        if now < self.next_probe:
            return
        self.next_probe = now + self.PROBE_S
        if self.client.nthreads():
            self.since = None
            return
        self.since = now if self.since is None else self.since
        wait = config.RUN.cluster_no_worker_s
        if now - self.since >= wait:
            raise RuntimeError(
                f"the Dask cluster has had no worker for {now - self.since:.0f} s while {pending} "
                "task(s) wait: its workers died or were closed (out of memory? see the worker logs). "
                "What was written so far stays (a checkpointed run resumes from it); on a cluster that "
                "scales down to zero, wait longer with config.configure(cluster_no_worker_s=...) "
                f"(now {wait:g} s)"
            )


def _compute_seconds(stream: list[dict]) -> dict[str, list[float]]:
    """worker -> the compute seconds of each of its tasks in a Dask task stream."""
    per: dict[str, list[float]] = {}
    for task in stream:
        for ss in task.get("startstops", ()):
            if ss.get("action") == "compute":
                per.setdefault(task["worker"], []).append(ss["stop"] - ss["start"])
    return per


def _stream_stats(per_worker: dict[str, list[float]], wall_s: float) -> dict:
    """``{"wall_s", "busy_s", "utilisation", "workers": {name: {"tasks", "busy_s"}},
    "task_s": {median, p95, max}}`` of one :func:`map_rows` call: busy = the tasks' compute
    seconds; utilisation = busy / (wall × workers) — below 1 the workers idled or started up
    (or the tasks shared the cores with the driver)."""
    all_s = np.array([x for v in per_worker.values() for x in v], dtype=float)
    busy = float(all_s.sum())
    n = max(1, len(per_worker))
    return {
        "wall_s": wall_s,
        "busy_s": busy,
        "utilisation": busy / (wall_s * n) if wall_s > 0 else float("nan"),
        "workers": {
            name.rsplit(":", 1)[-1] if name != "serial" else name: {"tasks": len(v), "busy_s": float(sum(v))}
            for name, v in per_worker.items()
        },
        "task_s": {
            "median": float(np.median(all_s)) if all_s.size else 0.0,
            "p95": float(np.percentile(all_s, 95)) if all_s.size else 0.0,
            "max": float(all_s.max()) if all_s.size else 0.0,
        },
    }


# its keyword API is called by every experiment's driver (other files): kept as it is
def run_rows(  # noqa: PLR0913 — public keyword API (above)
    fn: Callable[[Any], Any],
    jobs: Iterable[Any],
    on_result: Callable[[Any, Any], None],
    config: dict,
    *,
    n_rows: int | None = None,
    min_rows: int | None = None,
    progress: Any = None,
    meanwhile: Callable[[], Any] | None = None,
    stats: dict | None = None,
) -> tuple[Any, str]:
    """An experiment's rows: :func:`map_rows` on the :func:`row_client` of its ``workers`` and
    ``scheduler`` settings (``config``) for ``n_rows`` rows (default one per job; the auto rule
    counts rows, which a job may hold several of) and ``min_rows``.  Returns ``meanwhile``'s
    value and where the rows ran: "serial" or "dask (N workers)"; ``stats`` as in :func:`map_rows`."""
    jobs = list(jobs)
    n = len(jobs) if n_rows is None else n_rows
    with row_client(n, config["workers"], config["scheduler"], min_rows=min_rows) as client:
        extra = map_rows(
            fn, jobs, on_result, client=client, progress=progress, meanwhile=meanwhile, stats=stats
        )
        where = "serial" if client is None else f"dask ({len(client.scheduler_info()['workers'])} workers)"
    return extra, where


def run_checkpointed(
    fn: Callable[[Any], Any],
    tasks: list,
    key: Callable[[Any], str],
    out: Any,
    config: dict,
    *,
    desc: str,
    unit: str = "row",
    code: str | None = None,
) -> tuple[Any, int, str]:
    """Every task of ``tasks`` whose ``key(task)`` is not yet in ``out``/rows.jsonl run by
    :func:`run_rows` (``fn(task)`` on the experiment's workers, a tqdm bar named ``desc``),
    each result checkpointed under its key as it arrives.  The checkpoint's key is ``config``
    without where the rows run (``out``, ``workers``, ``scheduler``), so a killed run resumes
    with no row lost or run twice; ``code`` keys the rows instead of the whole package's hash
    (:class:`~workbench.runner.results.Checkpoint`).
    Returns ``(checkpoint, rows resumed, where they ran)``."""
    from pathlib import Path

    from tqdm import tqdm

    from .results import Checkpoint

    where = ("out", "workers", "scheduler")  # change no number
    ckpt = Checkpoint(
        Path(out) / "rows.jsonl", {k: v for k, v in config.items() if k not in where}, code=code
    )
    n_resumed = len(ckpt.rows)
    todo = [t for t in tasks if key(t) not in ckpt]
    with tqdm(total=len(todo), desc=desc, unit=unit) as bar:
        _, ran_on = run_rows(fn, todo, lambda t, row: ckpt.add(key(t), row), config, progress=bar)
    return ckpt, n_resumed, ran_on
