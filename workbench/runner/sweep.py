"""Parameter sweeps on Dask: every point of a grid of settings is one run of an experiment.

``workbench sweep <experiment> --grid KEY=JSON_LIST ... [--zip KEY=JSON_LIST ...]`` runs the
Cartesian product of the ``--grid`` lists (the ``--zip`` lists are paired element by element
and form one more axis of the product).  Every point's config is built and checked like
``workbench run``'s — defaults, ``--quick``, ``--set``, then the point's values — before any
work, so an unknown key, a wrong type or an empty list stops the sweep at once.

The points run as Dask tasks (``dask.distributed``): on a local cluster of one worker
process per core with one thread each by default, or on an existing cluster given by its
scheduler address.  Each task sets Numba's thread count to its worker's threads, so workers
do not oversubscribe the cores.  The driver is the only writer of the sweep's checkpoint
(``DIR/points.jsonl``, one line per finished point, fsynced) and of its table
(``DIR/table.parquet``, rewritten atomically after every point); each point's experiment
writes its own outputs under ``DIR/points/<key>/``.  A killed driver resumes on re-run with
every point exactly once and nothing recomputed; a task that raises is recorded as
``failed`` with its traceback and the sweep goes on (``retry_failed=True`` runs such points
again); a worker lost mid-task is rescheduled by Dask.

Finished points are never computed twice.  Each task also records its own result, when it
finishes, in ``DIR/points/<key>/sweep_point.json`` (:data:`POINT_FILE`, atomic, keyed by the
point's config and the code), and a task that finds an ok result of its own there returns it
instead of running: Dask resubmits a finished task whose result was held by a worker that
died before the driver collected it, and a driver killed between a task's end and its
checkpoint line finds the result on re-run.  The driver releases each result as soon as it is
recorded (a result still referenced when its worker dies is computed again by Dask — what
made a restarted worker recompute finished points).

Memory.  An experiment module may define ``memory_estimate(config) -> bytes`` (the
peak resident memory of one run; e.g. wall-stiffness's, fitted by
``benchmarks/bench_memory.py``); a sweep compares it, before any point runs, with its workers'
``memory_limit`` — on the local cluster each worker's share of this machine's memory, one of
``min(workers, points to run)`` shares (known before the cluster starts, which is not started
for points all refused); on another cluster the largest ``memory_limit`` its
``scheduler_info`` gives — and refuses a point whose estimate exceeds the memory at which
the nanny restarts a worker (``distributed.worker.memory.terminate`` of the limit): its row says
``refused: needs ~14.2 GiB, worker limit 11.8 GiB (mesh=[144,72])`` and the sweep goes on
with the others.  Refused points are not checkpointed: a re-run on larger workers runs them.
A point whose worker the nanny restarts for memory while it runs alone there is not retried
(it would be killed again): its row is ``killed`` with the worker's limit and the estimate;
a worker that died for another reason is named as such.  The table has the estimate
(``memory_estimate_GiB``) and, where the worker runs one point at a time on Linux, the
point's measured peak (``peak_rss_GiB``) beside every row.

``--plot`` metrics are checked before any work (:func:`_check_plot_metrics`): against this
sweep's finished rows when it has some, else against the columns the experiment declares
(an optional ``summary_columns(config) -> list[str]``), else against the tables of earlier
sweeps of the experiment beside ``DIR`` and its ``results/<experiment>/summary.json`` (a
name that matches there up to its list indices and numeric parts passes); only with none of
these is the metric checked on the first finished point.  Plots use log axes on a geometric
grid and label axes with units (:func:`axis_label`).

The table has one row per point: ``point`` (its key), every varied key (JSON text for a
list or object value), ``status`` (``ok``, ``failed``, ``killed`` or ``refused``), ``error``,
``seconds``, the memory columns, ``seed``, ``git_revision``, ``version.<package>`` and every
scalar number or flag of the experiment's summary as a column named by its path
(``table_4_6.vertical_lifting.q_work.All``).
"""

from __future__ import annotations

import contextlib
import dataclasses
import itertools
import json
import logging
import os
import re
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

from ..atomic_io import atomic_write_bytes
from ..code_key import code_digest
from .results import Checkpoint, _jsonable, code_revision, content_hash, versions, write_parquet

log = logging.getLogger(__name__)

__all__ = [
    "SweepCluster",
    "SweepError",
    "SweepPlan",
    "SweepSpec",
    "execute_sweep",
    "expand_grid",
    "flatten_scalars",
    "line_keys",
    "plan_sweep",
    "plot_sweep",
    "point_key",
    "read_table",
    "run_point",
    "run_sweep",
    "sweep_dir",
]

#: summary keys that are run metadata, not results: kept out of the table's metric columns
#: (``seed`` has a column of its own)
_META = {"config", "versions", "seed", "headline"}

#: an experiment's own keys that place its rows on a Dask cluster; inside a sweep each point
#: runs serially in one task of the sweep's cluster, so a sweep refuses them
#: (its ``--workers`` / ``--scheduler`` size that cluster instead)
CLUSTER_KEYS = ("workers", "scheduler")


class SweepError(ValueError):
    """A sweep's grid or settings are not usable (raised before any work)."""


def expand_grid(grid: dict[str, list], zipped: dict[str, list] | None = None) -> list[dict[str, Any]]:
    """The points of a sweep: the Cartesian product of ``grid``'s lists, with the ``zipped``
    lists (all of one length, paired element by element) as one more axis.

    grid, zipped : key -> non-empty list of values.  Returns a list of {key: value} dicts in
    the product's order (the first key varies slowest).  Raises ``SweepError`` for an empty
    list, a value that is not a list, a key in both, or zipped lists of different lengths.
    """
    zipped = zipped or {}
    if not grid and not zipped:
        raise SweepError("a sweep needs at least one --grid KEY=JSON_LIST or --zip KEY=JSON_LIST")
    both = sorted(set(grid) & set(zipped))
    if both:
        raise SweepError(f"keys {both} are in both --grid and --zip: give each key once")
    for kind, lists in (("--grid", grid), ("--zip", zipped)):
        for key, values in lists.items():
            if not isinstance(values, list):
                raise SweepError(
                    f"{kind} {key}=...: expected a JSON list of values, each as --set {key}= takes it "
                    f"(e.g. {key}=[{json.dumps(values, default=repr)}] for that one value); "
                    f"got {json.dumps(values, default=repr)}"
                )
            if not values:
                raise SweepError(f"{kind} {key}=[]: the list is empty; give at least one value")
    axes: list[list[dict[str, Any]]] = [[{k: v} for v in vals] for k, vals in grid.items()]
    if zipped:
        lengths = {k: len(v) for k, v in zipped.items()}
        if len(set(lengths.values())) > 1:
            raise SweepError(f"--zip lists must have one length (they are paired); got lengths {lengths}")
        n = next(iter(lengths.values()))
        axes.append([{k: zipped[k][i] for k in zipped} for i in range(n)])
    return [
        dict(itertools.chain.from_iterable(d.items() for d in combo)) for combo in itertools.product(*axes)
    ]


def point_key(values: dict[str, Any], config: dict | None = None) -> str:
    """A file-name-safe key of a point: its values (shortened, keys sorted) and a hash of its
    whole ``config`` (less ``out``; of the values alone without one), e.g.
    ``mu=0.3_n_angles=4-1f3a9c2e``.  Equal configs give equal keys, whatever the order the
    keys were given in; the same swept values under other fixed settings (``--set``,
    ``--seed``, ``--quick``) get another key, so their outputs never overwrite each other."""
    text = "_".join(
        f"{k}={json.dumps(v, sort_keys=True, separators=(',', ':'))}" for k, v in sorted(values.items())
    )
    text = re.sub(r"[^A-Za-z0-9=._,+-]+", "", text)[:60]
    whole = values if config is None else {k: v for k, v in config.items() if k != "out"}
    return f"{text}-{content_hash(whole, 8)}"


def sweep_dir(
    experiment: str,
    grid: dict,
    zipped: dict | None = None,
    *,
    quick: bool = False,
    sets: dict | None = None,
    seed: int | None = None,
) -> Path:
    """Default output directory ``results/sweeps/<experiment>-<hash of the sweep>``."""
    return (
        Path("results")
        / "sweeps"
        / (f"{experiment}-{content_hash([grid, zipped or {}, quick, sets or {}, seed], 8)}")
    )


#: lists up to this long enter the table element by element (``w_max_exact.0`` ...); longer
#: ones (per-grasp or per-profile arrays) stay in each point's summary.json only
MAX_LIST_COLUMNS = 16


def flatten_scalars(summary: dict | list, prefix: str = "") -> dict[str, float | int | bool | str | None]:
    """Every scalar (number, flag, string or null) of a nested summary dict, keyed by its
    dotted path — the top-level ``experiment`` name too; the elements of lists of at most
    :data:`MAX_LIST_COLUMNS` entries by their index (``table_3_2.S1.6d_nonplanar.4``); longer
    lists and the run metadata (``config``, ``versions``, ``seed``, ``headline``) are left out.
    A null (an undefined number, e.g. a recall without positives) keeps its column: NaN in
    the table."""
    out: dict[str, Any] = {}
    items = summary.items() if isinstance(summary, dict) else enumerate(summary)
    for key, value in items:
        if not prefix and key in _META:
            continue
        name = f"{prefix}{key}"
        if isinstance(value, dict) or (isinstance(value, list) and 0 < len(value) <= MAX_LIST_COLUMNS):
            out.update(flatten_scalars(value, f"{name}."))
        elif value is None or isinstance(value, (bool, int, float, str)):
            out[name] = value
    return out


#: each task's own record of its finished point, beside the point's outputs (module docstring)
POINT_FILE = "sweep_point.json"
#: Dask event topic of a sweep's tasks: ``{"point", "worker", "pid", "phase": "start" | "end",
#: "memory_limit"}``, so the driver knows which points a worker process was running, and its
#: limit, when its nanny restarted it
POINT_TOPIC = "workbench-sweep-point"
#: the nanny's event when it restarts a worker over its memory budget (distributed.worker_memory):
#: ``{"worker", "pid", "rss"}``
MEMORY_TOPIC = "worker-restart-memory"
GiB = 2**30


def run_point(
    experiment: str,
    config: dict,
    threads: int = 1,
    *,
    module: str | None = None,
    point: str | None = None,
    token: str | None = None,
    settings: dict | None = None,
) -> dict:
    """Run one point (in a Dask worker): ``{"status", "summary", "seconds", "error",
    "peak_rss_bytes", "reused"}``, under the driver's ``settings`` (:func:`workbench.config.changed`:
    the tolerances and defaults it set; a worker is another process).

    An exception is caught and returned as ``status="failed"`` with its traceback, so one
    bad point never stops a sweep; ``threads`` caps Numba's threads in this process.
    module : the experiment's module (default ``EXPERIMENTS[experiment]`` of this process; the
    driver passes its own, so a worker needs no registry of its own).  point, token : the
    point's key and the driver's identity of its config and code: with a token the result is
    written to ``<out>/``:data:`POINT_FILE` when the run ends, and an ok result of the same
    token found there (with the run's ``summary.json``) is returned as is, ``reused=True``,
    without running again.  ``peak_rss_bytes``: this process's peak resident memory while the
    point ran (Linux, a worker running one task at a time; else None)."""
    import importlib

    from .experiment_config import EXPERIMENTS

    path = Path(config["out"]) / POINT_FILE if token else None
    stored = _stored_point(path, token)
    if stored is not None:
        log.info("sweep point %s: finished before (%s), not run again", point, path)
        return {**stored, "reused": True}
    _announce(point, "start")
    try:
        import numba

        from .parallel import pin_numba_threads_env

        pin_numba_threads_env()  # a kernel compiled in this worker would raise otherwise
        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    except Exception as exc:  # a worker without Numba threads still runs, serially
        log.warning("could not set Numba's threads: %s", exc)
    measured = _reset_peak_rss()
    t0 = time.perf_counter()
    try:
        from .. import config as _config

        with _config.override(**(settings or {})):
            summary = importlib.import_module(module or EXPERIMENTS[experiment]).run(dict(config))
        res = {"status": "ok", "summary": _jsonable(summary), "error": None}
    except Exception:
        res = {"status": "failed", "summary": None, "error": traceback.format_exc()}
    res.update(
        seconds=time.perf_counter() - t0, peak_rss_bytes=_peak_rss() if measured else None, reused=False
    )
    if path is not None:
        try:
            atomic_write_bytes(path, (json.dumps({"token": token, **res}) + "\n").encode())
        except OSError as exc:  # the driver records the result anyway; only a resubmission re-runs
            log.warning("sweep point %s: could not write %s (%s)", point, path, exc)
    _announce(point, "end")
    return res


def _stored_point(path: Path | None, token: str | None) -> dict | None:
    """The ok result a task recorded in ``path`` under ``token``, while its ``summary.json``
    is there; None otherwise (no file, another config or code, a failure, a torn file)."""
    if path is None or not path.is_file() or not (path.parent / "summary.json").is_file():
        return None
    try:
        stored = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(stored, dict) or stored.get("token") != token or stored.get("status") != "ok":
        return None
    return {k: stored.get(k) for k in ("status", "summary", "seconds", "error", "peak_rss_bytes")}


def _announce(point: str | None, phase: str) -> None:
    """Log a :data:`POINT_TOPIC` event from this worker (nothing outside a Dask worker)."""
    if point is None:
        return
    try:
        from distributed import get_worker

        worker = get_worker()
        msg = {"point": point, "worker": worker.address, "pid": os.getpid(), "phase": phase}
        msg["memory_limit"] = getattr(getattr(worker, "memory_manager", None), "memory_limit", None)
        worker.log_event(POINT_TOPIC, msg)
    except (ImportError, ValueError):
        pass


def _reset_peak_rss() -> bool:
    """Reset this process's peak resident memory (Linux ``/proc/self/clear_refs``), when it runs
    one task at a time (a reset would cut short the peak of a task beside it); True if reset."""
    try:
        from distributed import get_worker

        if get_worker().state.nthreads != 1:
            return False
    except (ImportError, ValueError):
        pass  # not in a worker: this process runs one point
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def _peak_rss() -> int | None:
    """This process's peak resident memory [bytes] since :func:`_reset_peak_rss` (``VmHWM``)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def memory_estimate(experiment: str, config: dict) -> int | None:
    """The experiment's estimate of one run's peak memory [bytes] (its module's optional
    ``memory_estimate(config)``), or None when it has none.  An estimator that raises or
    returns something other than a positive number is logged and ignored (the point runs
    unchecked), never trusted."""
    import importlib
    import math

    from .experiment_config import EXPERIMENTS

    fn = getattr(importlib.import_module(EXPERIMENTS[experiment]), "memory_estimate", None)
    if fn is None:
        return None
    try:
        est = fn(config)
    except Exception as exc:
        log.warning(
            "%s.memory_estimate failed (%s: %s); its points run without a memory check",
            experiment,
            type(exc).__name__,
            exc,
        )
        return None
    if est is None:
        return None
    if isinstance(est, bool) or not isinstance(est, (int, float)) or not math.isfinite(est) or est <= 0:
        log.warning("%s.memory_estimate returned %r, not a number of bytes > 0; ignored", experiment, est)
        return None
    return int(est)


def worker_memory_limit(client: Any) -> int | None:
    """The largest ``memory_limit`` [bytes] among the client's workers (``scheduler_info``),
    None when none has one.  Workers of unequal limits are logged: a point is refused only
    when it fits none of them."""
    limits = sorted({int(w.get("memory_limit") or 0) for w in client.scheduler_info()["workers"].values()})
    if len(limits) > 1:
        log.info(
            "workers have unequal memory limits %s GiB; points are checked against the largest",
            [round(x / GiB, 2) for x in limits],
        )
    return limits[-1] if limits and limits[-1] > 0 else None


def _terminate_fraction() -> float:
    """The fraction of its memory limit at which a nanny restarts a worker (1 when it never does)."""
    import dask

    frac = dask.config.get("distributed.worker.memory.terminate", 0.95)
    return float(frac) if frac else 1.0


def _values_text(values: dict) -> str:
    """``mesh=[144,72], mu=0.3``: a point's swept values as the command line gives them."""
    return ", ".join(f"{k}={json.dumps(v, separators=(',', ':'))}" for k, v in values.items())


def _refusals(
    configs: dict, todo: list[str], estimates: dict, limit: int | None, fix: Callable[[int], str]
) -> dict[str, str]:
    """key -> the table's message for each point of ``todo`` whose estimate exceeds what a
    worker of ``limit`` bytes holds before its nanny restarts it; ``fix(estimate)`` says what to do."""
    if not limit:
        return {}
    frac = _terminate_fraction()
    out = {}
    for k in todo:
        est = estimates.get(k)
        if est is not None and est > frac * limit:
            out[k] = (
                f"refused: needs ~{est / GiB:.1f} GiB, worker limit {limit / GiB:.1f} GiB "
                f"({_values_text(configs[k][0])}); a worker is restarted above {frac:.0%} of its limit "
                f"— {fix(est)}"
            )
    return out


def _local_fix(cores: int) -> Callable[[int], str]:
    """What to do about a point too large for this machine's local workers: the most workers
    whose share of the memory (:func:`workbench.runner.parallel.local_memory_limit`) holds it."""
    from .parallel import local_memory_limit

    frac = _terminate_fraction()

    def fix(est: int) -> str:
        fits = [n for n in range(1, cores + 1) if frac * local_memory_limit(n) >= est]
        if fits:
            n = max(fits)
            return (
                f"run it with --workers {n} ({local_memory_limit(n) / GiB:.1f} GiB per worker), "
                "then only the refused points run"
            )
        return (
            f"it needs more than this machine's {local_memory_limit(1) / GiB:.1f} GiB: a smaller "
            "setting, or a cluster of larger workers (--scheduler)"
        )

    return fix


def _cluster_fix(est: int) -> str:
    return (
        "start the cluster's workers with more memory (dask worker --memory-limit), or use a "
        "smaller setting; a re-run then runs only the refused points"
    )


def list_key_hint(key: str, values: list, default: Any, flag: str = "--grid") -> str | None:
    """The fix for swept ``values`` that are not lists where ``key``'s default is one (a
    ``--grid 'force_range=[20,35]'`` sweeps the scalars 20 and 35): a list-valued key is swept
    by a list of lists, one inner list per point — the example wraps the values given (one
    point of them), not the default.  None when that is not the mistake."""
    import shlex

    if not isinstance(default, (list, tuple)) or any(isinstance(v, (list, tuple)) for v in values):
        return None
    example = json.dumps([list(values)])
    return (
        f"{key} takes a list, so {flag} sweeps it by a list of lists, one inner list per point: "
        f"e.g. {flag} {shlex.quote(f'{key}={example}')}"
    )


def _point_configs(
    experiment: str,
    points: list[dict],
    out: Path,
    quick: bool,
    sets: dict,
    seed: int | None,
    zipped_keys: tuple[str, ...] = (),
) -> dict[str, tuple[dict, dict]]:
    """key -> (point values, full config), every config checked before any work.  A point's
    values are taken as its config holds them (an int given for a float key is that float),
    so ``mu=[1, 1.0]`` repeats a point and ``mu=1`` resumes a point written as ``mu=1.0``."""
    import importlib

    from .experiment_config import EXPERIMENTS, ConfigValueError, build_config, seed_refusal

    refusal = None if seed is None else seed_refusal(experiment, seed)
    if refusal is not None:  # before any point: no point's config could take it
        raise SweepError(refusal)
    both = sorted(set(sets) & set(points[0]))
    if both:
        raise SweepError(f"{both} are given both as --set and in the grid: give each key in one of them")
    if seed is not None and "seed" in points[0]:
        raise SweepError("seed is swept by the grid and also given by --seed: give it in one of them")
    configs: dict[str, tuple[dict, dict]] = {}
    for given in points:
        try:
            cfg = build_config(experiment, quick, str(out / "points"), seed, {**sets, **given})
        except ConfigValueError as exc:
            if exc.key not in given or exc.flag != "--set":  # a --set or --seed value: as the CLI says it
                raise SweepError(str(exc.code)) from None
            # the value came from the grid: say so, and fix the grid rather than a --set
            k = exc.key
            flag = "--zip" if k in zipped_keys else "--grid"
            default = importlib.import_module(EXPERIMENTS[experiment]).DEFAULT_CONFIG.get(k)
            swept = list(dict.fromkeys(json.dumps(p[k]) for p in points))  # in the order given
            hint = list_key_hint(k, [json.loads(v) for v in swept], default, flag)
            fix = hint or f"each value in the list must look like the default, e.g. {exc.example()}"
            raise SweepError(f"point {given}: {exc.message(f'grid value {k}={exc.text}', fix)}") from None
        except SystemExit as exc:  # an unknown key, or the experiment's own check_config
            msg = str(exc.code)
            # name the point only when one of its values is in question, not a --set one
            raise SweepError(f"point {given}: {msg}" if any(k in msg for k in given) else msg) from None
        values = {k: cfg[k] for k in given}
        key = point_key(values, cfg)
        if key in configs:
            raise SweepError(
                f"the grid repeats a point: {given} is {configs[key][0]} (drop the duplicate value)"
            )
        cfg["out"] = str(out / "points" / key)
        configs[key] = (values, cfg)
    return configs


def _table_rows(rows: list[dict], varied: list[str]) -> list[dict]:
    table = []
    for r in rows:
        row: dict[str, Any] = {"point": r["key"]}
        for k in varied:
            v = r["values"].get(k)
            row[k] = v if isinstance(v, (bool, int, float, str)) or v is None else json.dumps(v)
        row.update(status=r["status"], error=r["error"], seconds=r["seconds"])
        for name, field in (
            ("memory_estimate_GiB", "memory_estimate_bytes"),
            ("peak_rss_GiB", "peak_rss_bytes"),
        ):
            if r.get(field) is not None:  # a column only where the experiment estimates / was measured
                row[name] = r[field] / GiB
        row.update(seed=r["seed"], git_revision=r["git_revision"])
        row.update({f"version.{k}": v for k, v in r["versions"].items()})
        row.update(r["metrics"])
        table.append(row)
    return table


def write_table(path: Path, rows: list[dict], varied: list[str]) -> Path:
    """Write the sweep's rows as one Parquet table, atomically (module docstring)."""
    return write_parquet(Path(path), _table_rows(rows, varied))


def read_table(path: Path) -> Any:
    """The sweep table as a ``pandas.DataFrame``."""
    import pandas as pd

    return pd.read_parquet(path)


def scheduler_host_port(address: str) -> tuple[str, int] | None:
    """:func:`~.parallel.scheduler_host_port` of ``--scheduler``, its error a ``SweepError``."""
    from .parallel import scheduler_host_port as parallel_host_port

    try:
        return parallel_host_port(address, "--scheduler")
    except ValueError as exc:
        raise SweepError(str(exc)) from None


def _probe_scheduler(address: str, timeout: float) -> None:
    """:func:`~.parallel.probe_scheduler` of ``--scheduler``, its error a ``SweepError``."""
    from .parallel import probe_scheduler

    try:
        probe_scheduler(address, timeout, "--scheduler")
    except ValueError as exc:
        raise SweepError(str(exc)) from None


def _client(
    workers: int | None, scheduler: str | None, threads: int, memory_limit: int | None = None
) -> tuple[Any, Any]:
    """(client, cluster or None): a local cluster of ``workers`` processes with ``threads``
    threads and ``memory_limit`` bytes each (default one per core and their share of the
    memory; :func:`workbench.runner.parallel.local_cluster`), or a
    client of the scheduler at ``scheduler`` once it has a worker — ``SweepError`` at once if
    its host:port refuses a connection (:func:`_probe_scheduler`,
    ``config.RUN.scheduler_probe_s``), else if it does not answer, or has no worker,
    within ``config.RUN.scheduler_wait_s`` (both read now)."""
    import os

    from distributed import Client

    from .. import config
    from .parallel import local_cluster

    if scheduler:
        wait = config.RUN.scheduler_wait_s
        _probe_scheduler(scheduler, config.RUN.scheduler_probe_s)
        try:
            client = Client(scheduler, timeout=wait)
        except (ValueError, TypeError) as exc:  # a malformed address
            raise SweepError(
                f"--scheduler {scheduler!r} is not a Dask scheduler address ({exc}); give e.g. tcp://host:8786"
            ) from None
        except OSError as exc:  # refused, timed out
            raise SweepError(
                f"no Dask scheduler answered at {scheduler!r} within {wait:g} s ({type(exc).__name__}: "
                f"{exc}); start one with `dask scheduler` and give its address, e.g. tcp://host:8786"
            ) from None
        try:
            client.wait_for_workers(1, timeout=wait)
        except TimeoutError:
            client.close()
            raise SweepError(
                f"the scheduler at {scheduler!r} has no workers after {wait:g} s; start some with "
                f"`dask worker {scheduler}` (with this package installed) and re-run"
            ) from None
        return client, None
    cluster = local_cluster(workers or os.cpu_count() or 1, threads, memory_limit)
    return Client(cluster), cluster


@dataclass(frozen=True)
class SweepCluster:
    """Where a sweep's points run, checked when made (``SweepError``): ``workers`` local worker
    processes (default one per core), or ``scheduler`` an existing cluster's address
    (``tcp://host:port``), or ``client`` a ``distributed.Client`` used as is — at most one of
    them; ``threads`` per worker (and Numba threads per task); ``retries``: Dask's retries of a
    task whose worker died."""

    workers: int | None = None
    scheduler: str | None = None
    client: Any = None
    threads: int = 1
    retries: int = 2

    def __post_init__(self) -> None:
        workers, scheduler = self.workers, self.scheduler
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
            raise SweepError(f"workers must be a positive integer; got {workers!r}")
        if not isinstance(self.threads, int) or self.threads < 1:
            raise SweepError(f"threads must be a positive integer; got {self.threads!r}")
        if scheduler is not None and not str(scheduler).strip():
            raise SweepError(
                "--scheduler is empty; give an address such as tcp://host:8786 (or leave it out)"
            )
        if scheduler is not None:
            scheduler_host_port(str(scheduler))  # a port out of range: refused now, not after the wait
        if sum(x is not None for x in (workers, scheduler, self.client)) > 1:
            raise SweepError("give at most one of workers, scheduler and client")


@dataclass(frozen=True)
class SweepSpec:
    """A sweep as asked for, checked once when made (``SweepError``; nothing written yet): the
    grid (``grid`` and ``zipped``, :func:`expand_grid`, expanded into ``points``), the fixed
    settings (``quick``, ``sets``: ``--set`` values as text or values, ``seed``), the sweep's
    directory ``out`` (default :func:`sweep_dir`; made absolute here, so the workers of an
    existing cluster write where the driver looks), where the points run (``cluster``), and
    ``retry_failed``, ``progress``, ``on_point``, ``metrics`` as :func:`run_sweep` takes them.
    Every point's config is checked by :func:`plan_sweep`."""

    experiment: str
    grid: dict[str, list]
    zipped: dict[str, list] = dataclasses.field(default_factory=dict)
    quick: bool = False
    sets: dict[str, Any] = dataclasses.field(default_factory=dict)
    seed: int | None = None
    #: given as str, Path or None (:func:`sweep_dir`); an absolute Path once made
    out: Path = None  # type: ignore[assignment]
    cluster: SweepCluster = dataclasses.field(default_factory=SweepCluster)
    retry_failed: bool = False
    progress: bool = True
    on_point: Callable[[str, dict], None] | None = None
    metrics: tuple[str, ...] = ()
    points: list[dict[str, Any]] = dataclasses.field(init=False)

    def __post_init__(self) -> None:
        put = partial(object.__setattr__, self)  # frozen: the checked values are set so
        put("zipped", dict(self.zipped or {}))
        put("sets", dict(self.sets or {}))
        put("metrics", tuple(self.metrics))
        put("points", expand_grid(self.grid, self.zipped))
        _refuse_cluster_keys(self.experiment, {**self.zipped, **self.grid}, self.sets)
        put("out", _sweep_out(self))
        other = _sweep_experiment(self.out)
        if other not in (None, self.experiment):  # its checkpoint would be dropped as not this sweep's
            raise SweepError(
                f"{self.out} holds a sweep of {other}, not {self.experiment}; give another --out"
            )


def _sweep_out(spec: SweepSpec) -> Path:
    """The spec's directory, absolute: ``SweepError`` unless it is one that can be made."""
    out = spec.out
    if out is not None and not str(out).strip():
        raise SweepError("--out is empty; give a directory (or leave --out out for the default)")
    out = (
        Path(out)
        if out
        else sweep_dir(
            spec.experiment, spec.grid, spec.zipped, quick=spec.quick, sets=spec.sets, seed=spec.seed
        )
    )
    out = out.absolute()
    if out.exists() and not out.is_dir():
        raise SweepError(f"--out {out} is a file; give a directory (new or an earlier sweep's)")
    parent = next(p for p in (out, *out.parents) if p.exists())
    if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise SweepError(f"--out {out} cannot be made: {parent} is not a writable directory")
    return out


@dataclass(frozen=True)
class SweepPlan:
    """What a :class:`SweepSpec` needs done, known before any work: every point's key ->
    (values, checked config) in the grid's order (``configs``), each config's ``digests``
    (less its output path) and the task ``tokens`` (config, code and changed settings), the
    points' ``code`` key, the checkpoint's rows of that code (``stored``), the points resumed
    from it (``done``) and those to run (``todo``, before the memory check), the points only
    other code finished (``n_other_code`` of ``todo``, their ``other_revisions``), the
    ``--plot`` metrics left to check on the first finished point (``need``), each point's
    memory ``estimates``, and this driver's code ``revision``, package ``versions`` and start
    time ``t_start``."""

    spec: SweepSpec
    configs: dict[str, tuple[dict, dict]]
    digests: dict[str, str]
    code: str
    module: str
    stored: dict[str, dict]
    done: frozenset[str]
    todo: tuple[str, ...]
    n_other_code: int
    other_revisions: list[str]
    need: tuple[str, ...]
    estimates: dict[str, int | None]
    tokens: dict[str, str]
    revision: str
    versions: dict
    t_start: float


def _ck_config(experiment: str) -> dict:
    """The config a sweep's checkpoint (``points.jsonl``) is keyed by."""
    return {"experiment": experiment, "sweep_format": 1}


def plan_sweep(spec: SweepSpec) -> SweepPlan:
    """The :class:`SweepPlan` of ``spec``: every point's config built and checked
    (:func:`_point_configs`), the checkpoint read (nothing written), the ``--plot`` metrics
    checked (:func:`_check_plot_metrics`) and every point's memory estimated."""
    configs = _point_configs(
        spec.experiment, spec.points, spec.out, spec.quick, spec.sets, spec.seed, tuple(spec.zipped)
    )  # checks all
    t_start = time.perf_counter()
    # one checkpoint per directory; a row counts as done only while its own config (less its
    # output path) is unchanged, so adding values to a grid re-runs nothing already written
    digests = {
        k: content_hash({x: v for x, v in c.items() if x != "out"}, 16) for k, (_, c) in configs.items()
    }
    # the points' code: what the experiment's module imports (a comment edit, or an edit of a
    # module it cannot run, reuses every point)
    code = _code(_module(spec.experiment))
    stored = Checkpoint.peek(spec.out / "points.jsonl", _ck_config(spec.experiment), code=code)
    # this grid's points finished only by other code: run again, their old rows kept as history
    other_code = _other_code_rows(Checkpoint.history(spec.out / "points.jsonl"), configs, stored)
    done = _resumed(spec, configs, digests, stored)
    todo = tuple(k for k in configs if k not in done)
    other_revisions = sorted({str(other_code[k]) for k in todo if k in other_code})
    n_other_code = sum(k in other_code for k in todo)
    if n_other_code:
        log.warning(
            "sweep %s: %d points were computed by other code (revisions %s; the sources changed since): "
            "re-run; their old rows stay in points.jsonl",
            spec.out,
            n_other_code,
            other_revisions,
        )
    finished_ok = [stored[k] for k in configs if k in done and stored[k]["status"] == "ok"]
    need = _check_plot_metrics(spec.experiment, list(spec.metrics), finished_ok, configs, spec.out)
    module = _module(spec.experiment)
    estimates = {k: memory_estimate(spec.experiment, cfg) for k, (_, cfg) in configs.items()}
    revision, vers = code_revision(), versions()
    # a task's identity of its point: the config (less its output path), the code and the
    # tolerances set away from their defaults (none: the key it always had)
    settings = _config_changed()
    ident = [code, settings] if settings else [code]
    tokens = {k: content_hash([digests[k], *ident], 16) for k in configs}
    return SweepPlan(
        spec,
        configs,
        digests,
        code,
        module,
        stored,
        frozenset(done),
        todo,
        n_other_code,
        other_revisions,
        tuple(need),
        estimates,
        tokens,
        revision,
        vers,
        t_start,
    )


def _resumed(spec: SweepSpec, configs: dict, digests: dict[str, str], stored: dict[str, dict]) -> set[str]:
    """The points of ``configs`` the checkpoint's ``stored`` rows finish: of the same config,
    ok (or failed, unless ``retry_failed``), and for an ok one with its outputs still there."""
    done = {
        k
        for k, r in stored.items()
        if k in configs
        and r.get("config_digest") == digests[k]
        and (r["status"] == "ok" or not spec.retry_failed)
    }
    lost = sorted(
        k
        for k in done
        if stored[k]["status"] == "ok" and not (spec.out / "points" / k / "summary.json").is_file()
    )
    if lost:  # a point's outputs were deleted: run it again rather than keep a row without them
        log.warning(
            "sweep %s: %d finished points lost their outputs (points/<key>/summary.json); re-run: %s",
            spec.out,
            len(lost),
            lost[:5],
        )
        done -= set(lost)
    return done


def execute_sweep(plan: SweepPlan) -> dict:
    """Run ``plan``'s points (module docstring): lock the directory, refuse the points too
    large for the workers, start or connect to the cluster, submit the rest and record each as
    it finishes in the checkpoint and the table; returns the summary (:func:`run_sweep`), also
    written to ``DIR/sweep.json`` — as ``stopped`` when the sweep is stopped."""
    spec, out = plan.spec, plan.spec.out
    with contextlib.ExitStack() as stack:
        if out.is_dir():  # a sweep running there already stops this one before it starts a cluster
            _lock(out, stack)
        client, todo, refused = _connect(plan, stack)
        for k, msg in refused.items():
            log.info("sweep point %s %s", k, msg)
        if not out.is_dir():
            _lock(out, stack)  # made now, after the scheduler checked out: one sweep at a time in out
        ckpt = _checkpoint(out, _ck_config(spec.experiment), plan.code)
        _remove_stale_plots(out)
        run = _SweepRun(plan, ckpt, refused, todo)
        atomic_write_bytes(  # stale from an earlier grid until this one ends
            out / "sweep.json",
            (
                json.dumps(
                    {
                        "experiment": spec.experiment,
                        "status": "running",
                        "pid": os.getpid(),
                        "grid": spec.grid,
                    }
                )
                + "\n"
            ).encode(),
        )
        try:
            if todo:
                c = spec.cluster
                points = _Points(
                    spec.experiment,
                    plan.module,
                    plan.configs,
                    plan.tokens,
                    plan.estimates,
                    c.threads,
                    c.retries,
                )
                _run_points(client, points, todo, spec.progress, run.record, ckpt, list(plan.need))
        except BaseException:
            run.finish("stopped")
            raise
        return run.finish("complete")


def _connect(plan: SweepPlan, stack: contextlib.ExitStack) -> tuple[Any, list[str], dict[str, str]]:
    """(client, the points to run, key -> refusal message of the points refused for memory):
    on this machine the points too large for a worker's share are refused before its cluster
    starts (none starts for points all refused); an existing cluster is connected to (and its
    scheduler checked) before anything is written, and its points checked against its workers'
    limit; a client given as is, likewise.  The client and cluster close with ``stack``."""
    cl = plan.spec.cluster
    client, todo = cl.client, list(plan.todo)
    refused: dict[str, str] = {}
    local_limit = None
    if todo and client is None and not cl.scheduler:
        # this machine's workers: min(workers, points) shares of its memory each, known before
        # they start, so a point too large for a share is refused first (and no cluster is
        # started for nothing).  The workers keep that share when refusals leave fewer points
        # than workers: a point's refusal does not depend on which others were refused
        from .parallel import local_memory_limit

        cores = os.cpu_count() or 1
        local_limit = local_memory_limit(min(cl.workers or cores, len(todo)))
        refused = _refusals(plan.configs, todo, plan.estimates, local_limit, _local_fix(cores))
        todo = [k for k in todo if k not in refused]
    if todo and client is None:  # connect (and check the scheduler) before writing anything
        client = _start_client(cl, len(todo), local_limit, stack)
        if cl.scheduler:
            log.info(
                "workers write each point's outputs under %s: a file system they must share", plan.spec.out
            )
            refused = _refusals(plan.configs, todo, plan.estimates, worker_memory_limit(client), _cluster_fix)
    elif todo:  # a client given as is
        refused = _refusals(plan.configs, todo, plan.estimates, worker_memory_limit(client), _cluster_fix)
    return client, [k for k in todo if k not in refused], refused


def _start_client(cl: SweepCluster, n_todo: int, local_limit: int | None, stack: contextlib.ExitStack) -> Any:
    """The client of ``cl``'s scheduler, or of a local cluster of ``min(workers, n_todo)``
    workers (no idle processes: never more local workers than points to run) of
    ``local_limit`` bytes each (:func:`_client`); closed with ``stack``."""
    cores = os.cpu_count() or 1
    if not cl.scheduler and cl.threads * (cl.workers or cores) > cores:
        log.warning("%d workers x %d threads oversubscribe %d cores", cl.workers or cores, cl.threads, cores)
    n_local = None if cl.scheduler else min(cl.workers or cores, n_todo)
    client, own = _client(n_local, cl.scheduler, cl.threads, local_limit)
    if own is not None:
        stack.callback(own.close)
    stack.callback(client.close)  # runs first (last in, first out)
    return client


class _SweepRun:
    """One execution of a :class:`SweepPlan`: its checkpoint, the points refused for memory,
    the points submitted (``todo``) and those recorded so far (``fresh``); it records each
    finished point and writes the table and ``sweep.json``."""

    def __init__(self, plan: SweepPlan, ckpt: Checkpoint, refused: dict[str, str], todo: list[str]) -> None:
        self.plan, self.ckpt, self.refused, self.todo = plan, ckpt, refused, todo
        self.fresh: set[str] = set()
        self.varied = list(plan.spec.points[0])
        self.table = plan.spec.out / "table.parquet"

    def grid_rows(self) -> list[dict]:
        """This grid's rows in the grid's order: resumed or recorded by this run (a stored
        row being re-run — lost outputs, --retry-failed — is not one until it is recorded
        again), and the refused points'."""
        plan, rows = self.plan, []
        for k, (values, cfg) in plan.configs.items():
            if k in plan.done or k in self.fresh:
                rows.append({**self.ckpt.rows[k], "memory_estimate_bytes": plan.estimates[k]})
            elif k in self.refused:
                rows.append(
                    {
                        "key": k,
                        "values": values,
                        "status": "refused",
                        "error": self.refused[k],
                        "seconds": None,
                        "seed": cfg.get("seed"),
                        "git_revision": plan.revision,
                        "versions": plan.versions,
                        "metrics": {},
                        "memory_estimate_bytes": plan.estimates[k],
                    }
                )
        return rows

    def record(self, key: str, res: dict) -> None:
        """Checkpoint a finished point's result ``res`` (:func:`run_point`), rewrite the table."""
        plan = self.plan
        values, cfg = plan.configs[key]
        row = {
            "config_digest": plan.digests[key],
            "values": values,
            "status": res["status"],
            "error": res["error"],
            "seconds": res["seconds"],
            "peak_rss_bytes": res.get("peak_rss_bytes"),
            "seed": cfg.get("seed"),
            "git_revision": plan.revision,
            "versions": plan.versions,
            "metrics": flatten_scalars(res["summary"]) if res["summary"] else {},
        }
        if res["status"] != "ok":
            log.warning("sweep point %s %s: %s", key, res["status"], _last_line(res["error"]))
        self.ckpt.add(key, row)
        self.fresh.add(key)
        write_table(self.table, self.grid_rows(), self.varied)
        if plan.spec.on_point is not None:
            plan.spec.on_point(key, self.ckpt.rows[key])

    def finish(self, status: str) -> dict:
        """Write this grid's table and sweep.json (also when stopped), return the summary."""
        plan, spec = self.plan, self.plan.spec
        rows = self.grid_rows()
        write_table(self.table, rows, self.varied)
        revisions = sorted({r["git_revision"] for r in rows if r["status"] != "refused"})
        if len(revisions) > 1:
            log.warning(
                "sweep %s: its rows come from %d code revisions %s", spec.out, len(revisions), revisions
            )
        failed = [r for r in rows if r["status"] not in ("ok", "refused")]
        n_refused = sum(r["status"] == "refused" for r in rows)
        summary = {
            "experiment": spec.experiment,
            "status": status,
            "grid": spec.grid,
            "zip": spec.zipped,
            "quick": spec.quick,
            "sets": {k: _cli_value(v) for k, v in spec.sets.items()},
            "n_points": len(plan.configs),
            "n_ok": len(rows) - len(failed) - n_refused,
            "n_failed": len(failed),
            "n_refused": n_refused,
            "n_resumed": len(plan.done),
            "n_submitted": len(self.todo),
            "n_other_code": plan.n_other_code,
            "other_code_revisions": plan.other_revisions,
            "failed": [{"point": r["key"], "error": _last_line(r["error"])} for r in failed[:5]],
            "refused": [{"point": k, "error": msg} for k, msg in self.refused.items()],
            "table": str(self.table),
            "git_revision": plan.revision,
            "row_revisions": revisions,
            "seconds": time.perf_counter() - plan.t_start,
        }
        atomic_write_bytes(
            spec.out / "sweep.json", (json.dumps(_jsonable(summary), indent=2) + "\n").encode()
        )
        return summary


# the public keyword API of cli.py, the tests and benchmarks/bench_sweep.py: it only packs its
# options into a SweepCluster and a SweepSpec
def run_sweep(  # noqa: PLR0913 — public keyword API (above)
    experiment: str,
    grid: dict[str, list],
    zipped: dict[str, list] | None = None,
    *,
    quick: bool = False,
    sets: dict[str, Any] | None = None,
    seed: int | None = None,
    out: str | Path | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    client: Any = None,
    threads: int = 1,
    retries: int = 2,
    retry_failed: bool = False,
    progress: bool = True,
    on_point: Callable[[str, dict], None] | None = None,
    metrics: list[str] | tuple[str, ...] = (),
) -> dict:
    """Run ``experiment`` at every point of the grid (module docstring); returns the
    sweep's summary (``n_points``, ``n_ok``, ``n_failed``, ``n_resumed``, ``n_submitted``,
    ``n_other_code`` — points run again because only other code had finished them — and
    ``other_code_revisions``, ``table``, ``seconds``), also written to ``DIR/sweep.json``.

    grid, zipped : key -> JSON list (:func:`expand_grid`); sets : fixed ``--set`` values
    (text or values); quick, seed : as ``workbench run``; out : the sweep's directory
    (default :func:`sweep_dir`); workers : local cluster size (default one per core),
    or scheduler : an existing cluster's address (``tcp://host:port``), or client : a
    ``distributed.Client`` to use as is; threads : threads per worker (and Numba threads per
    task); retries : Dask's retries of a task whose worker died; retry_failed : run points
    recorded as failed again; on_point : called as ``on_point(key, row)`` by the driver after
    each finished point (a hook for tests and progress); metrics : table columns the caller
    needs (e.g. to plot): checked before any work (:func:`_check_plot_metrics`), or — when
    nothing knows the experiment's columns yet — on the first finished point, where the sweep
    stops; ``SweepError`` names the closest columns there are.  The summary also counts the
    points refused for memory (``n_refused``, ``refused``: each point and its message).

    ``out`` is made absolute here, so the workers of an existing cluster write each point's
    outputs where the driver looks (they must share its file system; started in another
    directory, a relative path would land in theirs).  Nothing is written, and no cluster
    started, before the grid, the directory and the scheduler check out.  The table holds the
    points of this grid (``points.jsonl`` keeps every point ever finished in ``out``, by any
    code revision; the ``plot_*.png`` of earlier runs are removed).

    In three steps: the options checked once into a :class:`SweepSpec` (with its
    :class:`SweepCluster`), planned (:func:`plan_sweep`: every point's config, key and whether
    the checkpoint has it already) and executed (:func:`execute_sweep`).
    """
    cluster = SweepCluster(workers, scheduler, client, threads, retries)
    spec = SweepSpec(
        experiment,
        grid,
        zipped or {},
        quick,
        dict(sets or {}),
        seed,
        out,
        cluster,
        retry_failed,
        progress,
        on_point,
        tuple(metrics),
    )
    return execute_sweep(plan_sweep(spec))


def _config_changed() -> dict:
    """The driver's tolerances and defaults away from their defaults (a point's identity; the
    run settings change no number and are not in it)."""
    from .. import config

    return config.changed(numbers_only=True)


def _code(module: str) -> str:
    """The code a sweep's points are keyed by: what ``module`` imports in the package
    (:func:`~workbench.code_key.code_digest`); for an experiment module outside the package
    (a user's own), the whole package's :func:`~workbench.runner.results.code_hash` and that module's
    normalised source."""
    from importlib.util import find_spec

    from ..code_key import normalized_source
    from .results import code_hash

    try:
        return code_digest(module)
    except ValueError:
        spec = find_spec(module)
        own = normalized_source(spec.origin) if spec is not None and spec.origin else b""
        return content_hash([code_hash(), own.decode()], 16)


def _module(experiment: str) -> str:
    """The module of ``experiment`` in this process's registry (the workers import it by name)."""
    from .experiment_config import EXPERIMENTS

    return EXPERIMENTS[experiment]


@dataclass(frozen=True)
class _Points:
    """What a sweep's tasks are made of: the experiment and its module, key -> (values,
    config), key -> token and memory estimate, threads per task and Dask's retries."""

    experiment: str
    module: str
    configs: dict
    tokens: dict
    estimates: dict
    threads: int
    retries: int


def _run_points(
    client: Any,
    points: _Points,
    todo: list[str],
    progress: bool,
    record: Callable[[str, dict], None],
    ckpt: Checkpoint,
    need: list[str],
) -> None:
    """Submit ``todo``'s points and record each as it finishes, releasing its result at once;
    a point whose worker the nanny restarts for memory while it runs alone there is cancelled
    and recorded as ``killed`` (module docstring).  Stop (cancelling the rest) when a needed
    metric is missing or the first ``config.RUN.sweep_stop_after_failures`` finished
    points all failed."""
    from distributed import as_completed

    from .parallel import WorkerLoss

    futures = _submit(client, points, todo)
    watch = _WorkerWatch(client)
    tally = _Tally(points.experiment, len(todo), progress, record, ckpt, need)
    ac = as_completed(list(futures))
    lost = WorkerLoss(client)
    try:
        while futures:
            done = _collect(ac.next_batch(block=False), futures, watch, points, ac)
            done += _cancel_killed(client, futures, watch, points)
            for key, res in done:
                watch.finished(key)
                tally.add(key, res, pending=bool(futures))
            if not done:
                lost.check(len(futures))
                time.sleep(0.05)  # as_completed's own wait polls every 0.1 s too
    except BaseException:
        client.cancel(list(futures))  # one call: a cancel per future is a round trip each
        raise
    finally:
        watch.close()
        tally.close()


def _submit(client: Any, points: _Points, todo: list[str]) -> dict[Any, str]:
    """future -> key of each of ``todo``'s points, submitted as :func:`run_point` tasks under the
    driver's changed settings (read once: every point runs under them)."""
    from .. import config

    settings = config.changed()
    return {
        client.submit(
            run_point,
            points.experiment,
            points.configs[k][1],
            points.threads,
            module=points.module,
            point=k,
            token=points.tokens[k],
            settings=settings,
            key=f"sweep-{k}",
            pure=False,
            retries=points.retries,
        ): k
        for k in todo
    }


def _collect(
    batch: list, futures: dict[Any, str], watch: _WorkerWatch, points: _Points, ac: Any
) -> list[tuple[str, dict]]:
    """(key, result) of each finished future of ``batch``, taken out of ``futures`` and released.
    A future whose result went with its worker before it was fetched (the cluster scaled down
    or the worker died: the task is pending again) goes back to ``futures`` and ``ac`` (the
    ``as_completed``), for the caller's no-worker watch to judge, rather than being waited on."""
    from .. import config

    done: list[tuple[str, dict]] = []
    for fut in batch:
        key = futures.pop(fut, None)
        if key is None:  # cancelled here after a memory restart: recorded already
            continue
        try:
            res = fut.result(timeout=config.RUN.cluster_no_worker_s)
        except TimeoutError:
            futures[fut] = key
            ac.add(fut)
            continue
        except Exception as exc:  # the task could not run at all (e.g. its workers kept dying)
            res = _lost_point(key, exc, watch, points)
        fut.release()  # a result kept referenced is computed again if its worker dies
        done.append((key, res))
    return done


def _cancel_killed(
    client: Any, futures: dict[Any, str], watch: _WorkerWatch, points: _Points
) -> list[tuple[str, dict]]:
    """(key, ``killed`` result) of each pending point whose worker the nanny restarted for memory
    while it ran alone there, cancelled and taken out of ``futures``."""
    done = []
    for key in watch.killed_alone(set(futures.values())):
        fut = next(f for f, k in futures.items() if k == key)
        client.cancel([fut])  # the same worker limit would only kill it again
        del futures[fut]
        done.append((key, _killed_point(key, watch, points)))
    return done


class _Tally:
    """The driver's count of a sweep's finished points: records each, advances the progress bar,
    checks the ``--plot`` metrics still ``need``ed on the first ok point, and stops the sweep when
    the first ``config.RUN.sweep_stop_after_failures`` (read now) points all failed."""

    def __init__(
        self,
        experiment: str,
        total: int,
        progress: bool,
        record: Callable[[str, dict], None],
        ckpt: Checkpoint,
        need: list[str],
    ) -> None:
        from .. import config

        self.record, self.ckpt, self.need = record, ckpt, need
        self.stop_after = config.RUN.sweep_stop_after_failures
        self.n_ok = self.n_failed = 0
        self.bar = None
        if progress:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=f"sweep {experiment}", unit="point")

    def add(self, key: str, res: dict, pending: bool) -> None:
        """Record point ``key``'s result; ``pending``: points are left to run (to cancel)."""
        self.record(key, res)
        if self.bar is not None:
            self.bar.update()
        self.n_ok += res["status"] == "ok"
        self.n_failed += res["status"] != "ok"
        if self.need and res["status"] == "ok":
            _check_metrics(self.ckpt.rows[key], self.need)
            self.need = []
        if self.stop_after and self.n_ok == 0 and self.n_failed >= self.stop_after and pending:
            raise SweepError(
                f"the first {self.n_failed} points all failed, so the sweep stopped (the rest cancelled); "
                f"last error: {_last_line(res['error'])}. Fix the setting and re-run; failed points "
                "run again with --retry-failed (their tracebacks: the table's error column)"
            )

    def close(self) -> None:
        """Close the progress bar."""
        if self.bar is not None:
            self.bar.close()


class _WorkerWatch:
    """The driver's view of which points each worker process runs (:data:`POINT_TOPIC`) and of
    the nannies' memory restarts (:data:`MEMORY_TOPIC`), from Dask's events.  The handlers run
    on the client's event-loop thread; the driver reads the lists they append to."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self.events: list[tuple[str, dict]] = []  # (topic, msg) in arrival order
        self.running: dict[tuple[str, int], set[str]] = {}  # (worker, pid) -> points running there
        self.memory_kills: dict[str, list[dict]] = {}  # point -> the restarts of its workers
        self.alone: set[str] = set()  # points killed for memory with no other point beside them
        self.limits: dict[tuple[str, int], int | None] = {}  # (worker, pid) -> its memory limit
        self._seen = 0
        client.subscribe_topic(POINT_TOPIC, lambda ev: self.events.append((POINT_TOPIC, ev[1])))
        client.subscribe_topic(MEMORY_TOPIC, lambda ev: self.events.append((MEMORY_TOPIC, ev[1])))

    def _update(self) -> None:
        while self._seen < len(self.events):
            topic, msg = self.events[self._seen]
            self._seen += 1
            where = (msg.get("worker"), msg.get("pid"))
            if topic == POINT_TOPIC:
                self.limits[where] = msg.get("memory_limit")
                pts = self.running.setdefault(where, set())
                (pts.add if msg.get("phase") == "start" else pts.discard)(msg.get("point"))
                continue
            victims = self.running.pop(where, set())
            for p in victims:
                kill = {**msg, "beside": sorted(victims - {p}), "memory_limit": self.limits.get(where)}
                self.memory_kills.setdefault(p, []).append(kill)
            if len(victims) == 1:
                self.alone |= victims
            log.warning(
                "the nanny restarted worker %s (pid %s) for memory (%.2f GiB) while it ran %s",
                msg.get("worker"),
                msg.get("pid"),
                (msg.get("rss") or 0) / GiB,
                sorted(victims) or "no sweep point",
            )

    def killed_alone(self, pending: set[str]) -> list[str]:
        """The pending points whose worker was restarted for memory while it ran them alone."""
        self._update()
        return sorted(self.alone & pending)

    def kills(self, point: str) -> list[dict]:
        """The memory restarts of the workers that ran ``point``."""
        self._update()
        return self.memory_kills.get(point, [])

    def finished(self, point: str) -> None:
        """``point`` is recorded: no longer one to cancel."""
        self.alone.discard(point)

    def close(self) -> None:
        """Stop listening (the handlers would outlive the sweep on a client that does)."""
        for topic in (POINT_TOPIC, MEMORY_TOPIC):
            with contextlib.suppress(Exception):  # the client may be closing already
                self.client.unsubscribe_topic(topic)


def _memory_text(key: str, points: _Points) -> str:
    """``estimate ~14.0 GiB (mesh=[144,72])``: a point's estimate and values, for its row."""
    est = points.estimates.get(key)
    values = _values_text(points.configs[key][0])
    return f"estimate ~{est / GiB:.1f} GiB ({values})" if est else f"no memory estimate ({values})"


def _unfinished(status: str, error: str, peak_rss_bytes: int | None = None) -> dict:
    """The result of a point whose task did not return one (killed, or its workers died)."""
    return {
        "status": status,
        "summary": None,
        "seconds": float("nan"),
        "error": error,
        "peak_rss_bytes": peak_rss_bytes,
    }


def _killed_point(key: str, watch: _WorkerWatch, points: _Points) -> dict:
    """The row of a point whose worker the nanny restarted for memory while it ran alone there."""
    kill = watch.kills(key)[-1]
    limit = kill.get("memory_limit") or _restart_limit(watch.client)
    rss = kill.get("rss") or 0
    where = f"{limit / GiB:.1f} GiB limit" if limit else "memory limit"
    return _unfinished(
        "killed",
        f"killed for memory: its worker exceeded {_terminate_fraction():.0%} of its {where} (RSS "
        f"{rss / GiB:.1f} GiB) running it and was restarted; {_memory_text(key, points)}. Not retried on "
        "a worker of the same limit: re-run with more memory per worker (fewer --workers, or larger "
        "ones) and --retry-failed",
        rss or None,
    )


def _restart_limit(client: Any) -> int | None:
    """The memory limit of a restarted worker: its nanny logs only the RSS, so the cluster's
    (:func:`worker_memory_limit`: the largest of unequal limits)."""
    try:
        return worker_memory_limit(client)
    except Exception:  # the scheduler is busy replacing the worker; the message does without
        return None


def _lost_point(key: str, exc: Exception, watch: _WorkerWatch, points: _Points) -> dict:
    """The row of a point whose task could not finish: its traceback, then (the error's last
    line, the one the summary shows) whether its workers were restarted for memory and beside
    which points, else that they died for another reason."""
    tb = traceback.format_exc().rstrip()
    if type(exc).__name__ != "KilledWorker":
        return _unfinished("failed", tb)
    kills = watch.kills(key)
    if kills:
        beside = sorted({p for k in kills for p in k["beside"]})
        rss = max(k.get("rss") or 0 for k in kills)
        return _unfinished(
            "killed",
            f"{tb}\nkilled for memory: its workers were restarted for memory {len(kills)} times running it"
            + (f" beside other points {beside}" if beside else "")
            + f" (largest RSS {rss / GiB:.1f} GiB); {_memory_text(key, points)}",
        )
    return _unfinished(
        "failed",
        f"{tb}\nKilledWorker: the workers running it died {getattr(exc, 'allowed_failures', 0) + 1} times, "
        "not for memory (no nanny restarted one for memory): a crash or a killed process — see the "
        f"workers' logs; {_memory_text(key, points)}",
    )


def _lock(out: Path, stack: contextlib.ExitStack) -> None:
    """An exclusive lock on ``out`` (made if need be), held until ``stack`` closes: a second
    sweep into the same directory stops at once instead of running every point again into
    the same folders.  The lock file ``out/.sweep.lock`` is removed when ``stack`` closes (while
    still locked); a sweep that locked a file removed meanwhile takes the new one."""
    import fcntl

    path = out / ".sweep.lock"
    for _ in range(3):  # a file removed between our open and our lock is not the lock any more
        try:
            out.mkdir(parents=True, exist_ok=True)
            lock = open(path, "a+")
        except OSError as exc:
            raise SweepError(f"--out {out} cannot be written ({exc}); give a writable directory") from None
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            raise SweepError(
                f"another sweep is running in {out}; wait for it to end (then resume there) or give "
                "another --out"
            ) from None
        try:
            current = os.path.samestat(os.fstat(lock.fileno()), os.stat(path))
        except FileNotFoundError:
            current = False
        if current:
            stack.callback(lock.close)
            stack.callback(fcntl.flock, lock, fcntl.LOCK_UN)
            stack.callback(_unlink, path)  # runs first: removed while still held
            return
        lock.close()
    raise SweepError(f"other sweeps keep starting in {out}; give another --out")


def _unlink(path: Path) -> None:
    """Remove ``path`` if it is there."""
    with contextlib.suppress(FileNotFoundError):
        path.unlink()


def _checkpoint(out: Path, ck_config: dict, code: str) -> Checkpoint:
    """The sweep's checkpoint (``out/points.jsonl``, its rows keyed by ``code``, keeping the rows
    of other code and other sweep formats as history); ``SweepError`` if it cannot be written."""
    try:
        return Checkpoint(out / "points.jsonl", ck_config, keep_other=True, code=code)
    except OSError as exc:
        raise SweepError(f"--out {out} cannot be written ({exc}); give a writable directory") from None


def _other_code_rows(history: list[dict], configs: dict, stored: dict) -> dict[str, str]:
    """key -> the code revision of the last row of each of this grid's points that
    ``points.jsonl`` holds only from other code (a point's key fixes its config, so a row
    that is not resumed is another code's or another sweep format's)."""
    return {
        r["key"]: r.get("git_revision", "?")
        for r in history
        if r["key"] in configs and r["key"] not in stored
    }


def _refuse_cluster_keys(experiment: str, swept: dict, sets: dict) -> None:
    """``SweepError`` for an experiment's own :data:`CLUSTER_KEYS` in the grid or ``--set``:
    a point runs serially in one task of the sweep's cluster, so they would be ignored."""
    import importlib

    from .experiment_config import EXPERIMENTS

    if experiment not in EXPERIMENTS:  # build_config names the known ones
        return
    own = importlib.import_module(EXPERIMENTS[experiment]).DEFAULT_CONFIG
    given = [k for k in CLUSTER_KEYS if k in own and (k in swept or k in sets)]
    if given:
        where = "--grid/--zip" if any(k in swept for k in given) else "--set"
        raise SweepError(
            f"{given} in {where}: {experiment}'s own {'/'.join(CLUSTER_KEYS)} keys place its rows on a "
            "cluster, but in a sweep every point runs serially in one task of the sweep's cluster, so "
            "they would be ignored; size that cluster with --workers N or --scheduler ADDRESS instead"
        )


def _remove_stale_plots(out: Path) -> None:
    """Remove ``out``'s ``plot_*.png`` of earlier runs: the table is rewritten now, so they may
    show other points (``workbench sweep --plot`` writes the ones asked for again)."""
    for old in sorted(out.glob("plot_*.png")):
        with contextlib.suppress(OSError):
            old.unlink()
            log.info("removed %s (from an earlier run of this sweep)", old)


def _last_line(error: str | None) -> str:
    """The last line of a traceback (the exception and its message)."""
    lines = (error or "").strip().splitlines()
    return lines[-1] if lines else ""


def _sweep_experiment(out: Path) -> str | None:
    """The experiment of the sweep in ``out`` (its sweep.json), if any."""
    try:
        return json.loads((out / "sweep.json").read_text()).get("experiment")
    except (OSError, ValueError, AttributeError):
        return None


#: the sweep's own number columns, whatever the experiment (:func:`_table_rows`)
OWN_NUMBERS = ("seconds", "seed", "memory_estimate_GiB", "peak_rss_GiB")
#: the sweep's own text columns
OWN_TEXT = ("status", "error", "git_revision")


def _check_metrics(row: dict, names: list[str], where: str | None = None) -> None:
    """``SweepError`` unless every name is a number column of a finished point's row (a null
    value counts: the column is NaN there), with the closest column names as a hint; ``where``
    says what the row is (default: the point it was checked on)."""
    # the experiment's numbers and the table's own columns (``seconds`` a number, ``status`` not)
    metrics = {**row["metrics"], **dict.fromkeys(OWN_NUMBERS, 0.0), **dict.fromkeys(OWN_TEXT, "")}
    numbers = sorted(
        k
        for k, v in metrics.items()
        if v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
    )
    where = where or f"checked on point {row.get('key')}"
    for name in names:
        if name in numbers:
            continue
        what = "is not a number" if name in metrics else "is not a column"
        raise SweepError(f"{name!r} {what} of this sweep's table ({where}); " + column_hint(name, numbers))


def _check_plot_metrics(
    experiment: str, names: list[str], finished_ok: list[dict], configs: dict, out: Path
) -> list[str]:
    """Check the ``--plot`` metrics ``names`` before any work (module docstring); returns the
    names left to check on the first finished point (all of them when nothing here knows the
    experiment's columns, else none).  ``SweepError`` for a name that is not a number column.

    The sources, most exact first: this sweep's finished rows; the experiment module's
    ``summary_columns(config)`` (its summary's dotted number paths for the first point's
    config); the number columns of earlier sweeps of the experiment in ``out``'s parent and in
    ``results/sweeps``, and of its ``results/<experiment>*/summary.json``.  An earlier run may
    have had other settings, so there a name passes when it matches a column up to its
    numeric parts (``maps.20.min`` matches ``maps.0.min``)."""
    import importlib

    from .experiment_config import EXPERIMENTS

    if not names:
        return []
    if finished_ok:
        _check_metrics(finished_ok[0], names)
        return []
    own = {k: 0.0 for k in OWN_NUMBERS} | {k: "" for k in OWN_TEXT}
    declare = getattr(importlib.import_module(EXPERIMENTS[experiment]), "summary_columns", None)
    if declare is not None:
        first = next(iter(configs.values()))[1]
        row = {"metrics": dict.fromkeys(declare(first), 0.0)}
        _check_metrics(row, names, f"checked before any work against the columns {experiment} declares")
        return []
    columns, sources = _earlier_columns(experiment, out)
    if not sources:
        log.info(
            "no earlier table or summary of %s to check --plot %s against: checked on the first "
            "finished point",
            experiment,
            names,
        )
        return names
    columns |= own
    numbers = sorted(
        k
        for k, v in columns.items()
        if v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
    )
    shapes = {_shape(k) for k in numbers}
    for name in names:
        if name in numbers or (name not in columns and _shape(name) in shapes):
            continue
        what = "is not a number" if name in columns else "is not a column"
        raise SweepError(
            f"{name!r} {what} of {experiment}'s tables (checked before any work against {len(sources)} "
            f"earlier runs, e.g. {sources[0]}); {column_hint(name, numbers)}. If that column appears "
            "only under this sweep's settings, run without --plot, then the same command with --plot "
            "(nothing is recomputed)"
        )
    return []


def _shape(name: str) -> str:
    """A column name with its numeric parts as ``#`` (list indices, bottle numbers)."""
    return ".".join("#" if part.isdigit() else part for part in name.split("."))


def _earlier_columns(experiment: str, out: Path) -> tuple[dict[str, Any], list[str]]:
    """(column -> a sample value, the files read): the columns of earlier sweeps of
    ``experiment`` (their ``table.parquet`` schema) beside ``out`` and in ``results/sweeps``,
    and of its ``results/<experiment>*/summary.json`` (:func:`flatten_scalars`)."""
    columns: dict[str, Any] = {}
    sources = _earlier_tables(experiment, out, columns)
    sources += _earlier_summaries(experiment, columns)
    return columns, sources


def _earlier_tables(experiment: str, out: Path, columns: dict[str, Any]) -> list[str]:
    """Add the columns of earlier sweeps' tables (:func:`_earlier_columns`) to ``columns``;
    returns the tables read."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    sources: list[str] = []
    dirs = {
        p.resolve() for base in (out.parent, Path("results") / "sweeps") for p in base.glob("*/sweep.json")
    }
    for sweep_json in sorted(dirs):
        table = sweep_json.parent / "table.parquet"
        if sweep_json.parent == out.resolve() or _sweep_experiment(sweep_json.parent) != experiment:
            continue
        try:
            schema = pq.read_schema(table)
        except (OSError, pa.ArrowException):
            continue
        for field in schema:
            if pa.types.is_integer(field.type) or pa.types.is_floating(field.type):
                columns[field.name] = 0.0  # a number in any earlier run is one
            else:
                columns.setdefault(field.name, "")
        sources.append(str(table))
    return sources


def _earlier_summaries(experiment: str, columns: dict[str, Any]) -> list[str]:
    """Add the columns of the experiment's ``results/<experiment>*/summary.json``
    (:func:`_earlier_columns`) to ``columns``; returns the summaries read."""
    sources: list[str] = []
    for summary in sorted(Path("results").glob(f"{experiment}*/summary.json")):
        try:
            data = json.loads(summary.read_text())
        except (OSError, ValueError):
            continue
        if isinstance(data, dict) and data.get("experiment") == experiment:
            for k, v in flatten_scalars(data).items():
                if v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)):
                    columns[k] = 0.0
                else:
                    columns.setdefault(k, v)
            sources.append(str(summary))
    return sources


def close_columns(name: str, columns: list[str], n: int | None = None) -> list[str]:
    """Up to ``n`` (default ``config.RUN.sweep_column_hints``, read now) of ``columns``
    closest to ``name``: difflib's close matches of the whole dotted path, then the columns
    whose last part is ``name``'s last part (``recall`` finds ``...6dls.recall``)."""
    import difflib

    from .. import config

    n = config.RUN.sweep_column_hints if n is None else n
    close = difflib.get_close_matches(name, columns, n=n, cutoff=0.5)
    leaf = name.rsplit(".", 1)[-1]
    close += [c for c in columns if c not in close and c.rsplit(".", 1)[-1] == leaf]
    return close[:n]


def column_hint(name: str, columns: list[str]) -> str:
    """ "did you mean [...]?" for a name that is not one of ``columns``, and the columns
    themselves only when they are few (a summary has ~200 number columns)."""
    close = close_columns(name, columns)
    text = f"did you mean {close}? " if close else "no column name is close; "
    if len(columns) <= 20:
        return text + f"number columns: {columns}"
    return text + f"{len(columns)} number columns in all (pandas.read_parquet(<table>).columns lists them)"


def _cli_value(v: Any) -> Any:
    """A ``--set`` value as the JSON value it stands for (a bare word is a string)."""
    from .experiment_config import _CliText, _parse_value

    return _parse_value(str(v)) if isinstance(v, _CliText) else v


def plot_sweep(
    table: str | Path,
    key: str,
    metric: str,
    out: str | Path | None = None,
    zipped: list[str] | tuple[str, ...] | None = None,
) -> Path:
    """Figure of ``metric`` against ``key`` from a sweep table (one line per combination of
    the other varied keys); written next to the table as ``plot_<key>_<metric>.png``.

    zipped : the sweep's ``--zip`` keys (default: those of the ``sweep.json`` beside the
    table).  When ``key`` is one of them, the others vary with it along the line and do not
    split lines (:func:`line_keys`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    from .. import config
    from .results import save_figure

    df = read_table(table)
    if key not in _varied(df):
        raise SweepError(f"{key!r} is not a swept key of {table}; plot against one of {_varied(df)}")
    numbers = [
        c
        for c in df.columns
        if pd.api.types.is_numeric_dtype(df[c]) and not pd.api.types.is_bool_dtype(df[c])
    ]
    if metric not in numbers:
        what = "is not a number column" if metric in df.columns else "is not a column"
        raise SweepError(f"{metric!r} {what} of {table}; " + column_hint(metric, sorted(numbers)))
    ok = df[df["status"] == "ok"]
    zipped = _zip_keys(Path(table).parent) if zipped is None else list(zipped)
    others = line_keys(_varied(df), key, metric, zipped)  # one line per combination of these
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    groups = ok.groupby(others) if others else [((), ok)]
    for label, g in groups:
        g = g.sort_values(key, key=_grid_order)
        name = (
            ", ".join(
                f"{o}={v}"
                for o, v in zip(others, label if isinstance(label, tuple) else (label,), strict=True)
            )
            or None
        )
        ax.plot(g[key], g[metric], "o-", label=name)
    x_log = pd.api.types.is_numeric_dtype(df[key]) and geometric(df[key].tolist())
    if x_log:
        ax.set_xscale("log")
        y = ok[metric].dropna().to_numpy(dtype=float)
        if y.size and (y > 0).all() and y.max() > config.RUN.sweep_log_min_span * y.min():
            ax.set_yscale("log")  # a power law of a geometric grid: a straight line
    experiment = _table_experiment(df, Path(table).parent)
    ax.set_xlabel(axis_label(key, experiment))
    ax.set_ylabel(axis_label(metric, experiment))
    if others:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"plot_{key}_{metric}")
    path = Path(out) if out else Path(table).parent / f"{safe}.png"
    return save_figure(fig, path)


def geometric(values: list) -> bool:
    """True when the distinct values of a grid are positive numbers in roughly constant ratio
    (``config.RUN.sweep_log_step_spread``) that span more than ``sweep_log_min_span`` or
    step by at least ``sweep_log_min_step`` (read at call time): plotted on a log axis.  Two
    values count when their ratio is that large."""
    import math

    from .. import config

    dft = config.RUN

    try:
        v = sorted(
            {float(x) for x in values if x is not None and not (isinstance(x, float) and math.isnan(x))}
        )
    except (TypeError, ValueError):
        return False
    if len(v) < 2 or v[0] <= 0 or not all(math.isfinite(x) for x in v):
        return False
    steps = [math.log(b / a) for a, b in zip(v, v[1:], strict=False)]
    if max(steps) > dft.sweep_log_step_spread * min(steps):
        return False
    return v[-1] / v[0] > dft.sweep_log_min_span or min(steps) >= math.log(dft.sweep_log_min_step)


#: units of names by their last part's suffix (CONVENTIONS.md: SI, a quantity named with its
#: unit, e.g. ``stiffness_N_per_m``, ``closing_mm``, ``wall_time_s``); the longest suffix wins
UNIT_SUFFIXES = {
    "N_per_m": "N/m",
    "N_per_mm": "N/mm",
    "m_per_N": "m/N",
    "Nm": "N·m",
    "N": "N",
    "GPa": "GPa",
    "MPa": "MPa",
    "kPa": "kPa",
    "Pa": "Pa",
    "mm": "mm",
    "um": "µm",
    "m": "m",
    "ms": "ms",
    "s": "s",
    "rad": "rad",
    "deg": "deg",
    "mJ": "mJ",
    "J": "J",
    "GiB": "GiB",
    "bytes": "B",
    "Hz": "Hz",
    "kg": "kg",
}
#: whole names with a unit and no suffix: the sweep's own columns
UNIT_NAMES = {"seconds": "s"}
_SUFFIX = re.compile("_(" + "|".join(sorted(map(re.escape, UNIT_SUFFIXES), key=len, reverse=True)) + ")$")


def unit_of(name: str, experiment: str | None = None) -> str | None:
    """The unit of a table column or config key, or None: the unit of the experiment's config
    key of that name (its ``KEYS``, :mod:`workbench.runner.experiment_keys`; for keys named without
    one, such as ``E`` or ``thickness``), else :data:`UNIT_NAMES`, else the name's suffix
    (:data:`UNIT_SUFFIXES`).  List indices are skipped: ``w_max_N.2`` is in N."""
    import importlib

    from .experiment_config import EXPERIMENTS, key_specs

    parts = [p for p in name.split(".") if not p.isdigit()] or [name]
    if experiment in EXPERIMENTS:
        try:
            specs = key_specs(importlib.import_module(EXPERIMENTS[experiment]))
        except ImportError:
            specs = {}
        units = {k: spec.unit for k, spec in specs.items() if spec.unit}
        for candidate in (name, parts[-1]):
            if candidate in units:
                return units[candidate]
    if parts[-1] in UNIT_NAMES:
        return UNIT_NAMES[parts[-1]]
    m = _SUFFIX.search(parts[-1])
    return UNIT_SUFFIXES[m.group(1)] if m else None


def axis_label(name: str, experiment: str | None = None) -> str:
    """``name [unit]`` (:func:`unit_of`), or the name alone when its unit is unknown."""
    unit = unit_of(name, experiment)
    return f"{name} [{unit}]" if unit else name


def _grid_order(column: Any) -> Any:
    """Sort key of a table column: numbers as they are; JSON lists of numbers (``[96, 48]``)
    by their values, not their text (where ``[144, 72]`` sorts before ``[96, 48]``)."""
    import pandas as pd

    if pd.api.types.is_numeric_dtype(column):
        return column

    def parsed(text: Any) -> tuple:
        try:
            v = json.loads(text)
        except (TypeError, ValueError):
            return (1, str(text))
        flat = v if isinstance(v, list) else [v]
        if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in flat):
            return (0, *flat)
        return (1, str(text))

    return column.map(parsed)


def _table_experiment(df: Any, out: Path) -> str | None:
    """The experiment of a sweep table (its ``experiment`` column, else its sweep.json)."""
    if "experiment" in df.columns:
        names = df["experiment"].dropna().unique()
        if len(names) == 1:
            return str(names[0])
    return _sweep_experiment(out)


def line_keys(varied: list[str], key: str, metric: str, zipped: list[str]) -> list[str]:
    """The varied keys that split a plot of ``metric`` against ``key`` into lines: every
    other varied key, less the keys zipped with ``key`` (paired with it, they vary along the
    line: one line per combination of the ``--grid`` keys)."""
    along = set(zipped) if key in zipped else set()
    return [c for c in varied if c not in (key, metric) and c not in along]


def _zip_keys(out: Path) -> list[str]:
    """The ``--zip`` keys of the sweep in ``out`` (its sweep.json), ``[]`` if none or unknown."""
    try:
        return list(json.loads((out / "sweep.json").read_text()).get("zip") or {})
    except (OSError, ValueError, AttributeError):
        return []


def _varied(df: Any) -> list[str]:
    """The table's varied-key columns: those before ``status``."""
    cols = list(df.columns)
    return cols[1 : cols.index("status")]
