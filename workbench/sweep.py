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

The table has one row per point: ``point`` (its key), every varied key (JSON text for a
list or object value), ``status``, ``error``, ``seconds``, ``seed``, ``git_revision``,
``version.<package>`` and every scalar number or flag of the experiment's summary as a
column named by its path (``table_4_6.vertical_lifting.q_work.All``).
"""

from __future__ import annotations

import contextlib
import itertools
import json
import logging
import os
import re
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .results import Checkpoint, _jsonable, atomic_write_bytes, code_revision, content_hash, versions

log = logging.getLogger(__name__)

__all__ = [
    "SweepError",
    "expand_grid",
    "flatten_scalars",
    "line_keys",
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
                    f"{kind} {key}=...: expected a JSON list of values, e.g. {key}=[0.3, 0.5]; "
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


def run_point(experiment: str, config: dict, threads: int = 1) -> dict:
    """Run one point (in a Dask worker): ``{"status", "summary", "seconds", "error"}``.

    An exception is caught and returned as ``status="failed"`` with its traceback, so one
    bad point never stops a sweep; ``threads`` caps Numba's threads in this process."""
    import importlib

    from .experiment_config import EXPERIMENTS

    try:
        import numba

        from .parallel import pin_numba_threads_env

        pin_numba_threads_env()  # a kernel compiled in this worker would raise otherwise
        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    except Exception as exc:  # a worker without Numba threads still runs, serially
        log.warning("could not set Numba's threads: %s", exc)
    t0 = time.perf_counter()
    try:
        summary = importlib.import_module(EXPERIMENTS[experiment]).run(dict(config))
        return {
            "status": "ok",
            "summary": _jsonable(summary),
            "seconds": time.perf_counter() - t0,
            "error": None,
        }
    except Exception:
        return {
            "status": "failed",
            "summary": None,
            "seconds": time.perf_counter() - t0,
            "error": traceback.format_exc(),
        }


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

    from .experiment_config import EXPERIMENTS, ConfigValueError, build_config

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
        row.update(
            status=r["status"],
            error=r["error"],
            seconds=r["seconds"],
            seed=r["seed"],
            git_revision=r["git_revision"],
        )
        row.update({f"version.{k}": v for k, v in r["versions"].items()})
        row.update(r["metrics"])
        table.append(row)
    return table


def write_table(path: Path, rows: list[dict], varied: list[str]) -> Path:
    """Write the sweep's rows as one Parquet table, atomically (module docstring)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table_rows = _table_rows(rows, varied)
    columns: dict[str, list] = {}
    for i, row in enumerate(table_rows):
        for k in row:
            columns.setdefault(k, [None] * i)
        for k, col in columns.items():
            col.append(row.get(k))
    arrays = {}
    for k, col in columns.items():
        kinds = {type(v) for v in col if v is not None}
        if not kinds:  # null in every row (an undefined number): a NaN column, plottable
            col = [float("nan")] * len(col)
        elif kinds <= {int, float} and float in kinds:
            col = [None if v is None else float(v) for v in col]  # ints and floats: one float column
        elif len(kinds) > 1:
            col = [None if v is None else json.dumps(v) for v in col]  # mixed kinds: JSON text
        arrays[k] = pa.array(col)
    sink = pa.BufferOutputStream()
    pq.write_table(pa.table(arrays), sink)
    return atomic_write_bytes(Path(path), sink.getvalue().to_pybytes())


def read_table(path: Path) -> Any:
    """The sweep table as a ``pandas.DataFrame``."""
    import pandas as pd

    return pd.read_parquet(path)


def scheduler_host_port(address: str) -> tuple[str, int] | None:
    """(host, port) of a TCP scheduler address (``tcp://host:port``, ``tls://...``, a bare
    ``host:port``; an IPv6 host in brackets), or None for another protocol or no port (Dask
    judges those).  ``SweepError`` for a port that is not a number in 1-65535."""
    proto, sep, rest = address.strip().partition("://")
    if not sep:
        proto, rest = "tcp", address.strip()
    if proto not in ("tcp", "tls"):
        return None
    host, colon, port_text = rest.rstrip("/").rpartition(":")
    if not colon or host.count(":") and not host.startswith("["):  # no port, or a bare IPv6 host
        return None
    if not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise SweepError(
            f"--scheduler {address!r}: port {port_text!r} is not a TCP port (1-65535); give the address "
            "`dask scheduler` printed, e.g. tcp://host:8786"
        )
    return host.strip("[]") or "127.0.0.1", int(port_text)


def _probe_scheduler(address: str, timeout: float) -> None:
    """``SweepError`` at once when nothing listens at ``address``'s host and port (connection
    refused, host unknown or unreachable), instead of the Dask client's full wait; a probe
    that times out returns (the client's own wait then decides)."""
    import socket

    host_port = scheduler_host_port(address)
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
        raise SweepError(
            f"--scheduler {address!r}: host {host!r} is unknown ({exc.strerror or exc}); give the "
            "scheduler's host name or IP address, e.g. tcp://10.0.0.5:8786"
        ) from None
    except OSError as exc:  # refused, unreachable
        raise SweepError(
            f"no Dask scheduler at {address!r}: {host}:{port} refused the connection "
            f"({exc.strerror or exc}); start one with `dask scheduler --port {port}` there, or give "
            "the address a running scheduler printed"
        ) from None


def _client(workers: int | None, scheduler: str | None, threads: int) -> tuple[Any, Any]:
    """(client, cluster or None): a local cluster of ``workers`` processes with ``threads``
    threads each (default one per core; :func:`workbench.parallel.local_cluster`), or a
    client of the scheduler at ``scheduler`` once it has a worker — ``SweepError`` at once if
    its host:port refuses a connection (:func:`_probe_scheduler`,
    ``config.DEFAULTS.scheduler_probe_s``), else if it does not answer, or has no worker,
    within ``config.DEFAULTS.scheduler_wait_s`` (both read now)."""
    import os

    from distributed import Client

    from . import config
    from .parallel import local_cluster

    if scheduler:
        wait = config.DEFAULTS.scheduler_wait_s
        _probe_scheduler(scheduler, config.DEFAULTS.scheduler_probe_s)
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
    cluster = local_cluster(workers or os.cpu_count() or 1, threads)
    return Client(cluster), cluster


def run_sweep(
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
    needs (e.g. to plot): checked against the first finished point, and the sweep stops
    there with ``SweepError`` naming the columns there are if one is missing or not a number.

    ``out`` is made absolute here, so the workers of an existing cluster write each point's
    outputs where the driver looks (they must share its file system; started in another
    directory, a relative path would land in theirs).  Nothing is written, and no cluster
    started, before the grid, the directory and the scheduler check out.  The table holds the
    points of this grid (``points.jsonl`` keeps every point ever finished in ``out``, by any
    code revision; the ``plot_*.png`` of earlier runs are removed).
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise SweepError(f"workers must be a positive integer; got {workers!r}")
    if not isinstance(threads, int) or threads < 1:
        raise SweepError(f"threads must be a positive integer; got {threads!r}")
    if scheduler is not None and not str(scheduler).strip():
        raise SweepError("--scheduler is empty; give an address such as tcp://host:8786 (or leave it out)")
    if scheduler is not None:
        scheduler_host_port(str(scheduler))  # a port out of range: refused now, not after the wait
    if sum(x is not None for x in (workers, scheduler, client)) > 1:
        raise SweepError("give at most one of workers, scheduler and client")
    sets = dict(sets or {})
    points = expand_grid(grid, zipped)
    _refuse_cluster_keys(experiment, {**(zipped or {}), **grid}, sets)
    if out is not None and not str(out).strip():
        raise SweepError("--out is empty; give a directory (or leave --out out for the default)")
    out = Path(out) if out else sweep_dir(experiment, grid, zipped, quick=quick, sets=sets, seed=seed)
    out = out.absolute()
    if out.exists() and not out.is_dir():
        raise SweepError(f"--out {out} is a file; give a directory (new or an earlier sweep's)")
    parent = next(p for p in (out, *out.parents) if p.exists())
    if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise SweepError(f"--out {out} cannot be made: {parent} is not a writable directory")
    other = _sweep_experiment(out)
    if other not in (None, experiment):  # its checkpoint would be dropped as not this sweep's
        raise SweepError(f"{out} holds a sweep of {other}, not {experiment}; give another --out")
    configs = _point_configs(experiment, points, out, quick, sets, seed, tuple(zipped or {}))  # checks all
    varied = list(points[0])
    t_start = time.perf_counter()
    # one checkpoint per directory; a row counts as done only while its own config (less its
    # output path) is unchanged, so adding values to a grid re-runs nothing already written
    digests = {
        k: content_hash({x: v for x, v in c.items() if x != "out"}, 16) for k, (_, c) in configs.items()
    }
    ck_config = {"experiment": experiment, "sweep_format": 1}
    stored = Checkpoint.peek(out / "points.jsonl", ck_config)
    # this grid's points finished only by other code: run again, their old rows kept as history
    other_code = _other_code_rows(Checkpoint.history(out / "points.jsonl"), configs, stored)
    done = {
        k
        for k, r in stored.items()
        if k in configs and r.get("config_digest") == digests[k] and (r["status"] == "ok" or not retry_failed)
    }
    lost = sorted(
        k for k in done if stored[k]["status"] == "ok" and not (out / "points" / k / "summary.json").is_file()
    )
    if lost:  # a point's outputs were deleted: run it again rather than keep a row without them
        log.warning(
            "sweep %s: %d finished points lost their outputs (points/<key>/summary.json); re-run: %s",
            out,
            len(lost),
            lost[:5],
        )
        done -= set(lost)
    n_resumed = len(done)
    todo = [k for k in configs if k not in done]
    other_revisions = sorted({str(other_code[k]) for k in todo if k in other_code})
    n_other_code = sum(k in other_code for k in todo)
    if n_other_code:
        log.warning(
            "sweep %s: %d points were computed by other code (revisions %s; the sources changed since): "
            "re-run; their old rows stay in points.jsonl",
            out,
            n_other_code,
            other_revisions,
        )
    need = list(metrics)
    finished_ok = [stored[k] for k in configs if k in done and stored[k]["status"] == "ok"]
    if need and finished_ok:
        _check_metrics(finished_ok[0], need)
        need = []
    revision, vers = code_revision(), versions()
    fresh: set[str] = set()
    with contextlib.ExitStack() as stack:
        if out.is_dir():  # a sweep running there already stops this one before it starts a cluster
            _lock(out, stack)
        if todo and client is None:  # connect (and check the scheduler) before writing anything
            cores = os.cpu_count() or 1
            if not scheduler and threads * (workers or cores) > cores:
                log.warning(
                    "%d workers x %d threads oversubscribe %d cores", workers or cores, threads, cores
                )
            # no idle processes: never more local workers than points to run
            client, own = _client(None if scheduler else min(workers or cores, len(todo)), scheduler, threads)
            if own is not None:
                stack.callback(own.close)
            stack.callback(client.close)  # runs first (last in, first out)
            if scheduler:
                log.info("workers write each point's outputs under %s: a file system they must share", out)
        if not out.is_dir():
            _lock(out, stack)  # made now, after the scheduler checked out: one sweep at a time in out
        ckpt = _checkpoint(out, ck_config)
        _remove_stale_plots(out)

        def grid_rows() -> list[dict]:
            """This grid's finished rows: resumed or recorded by this run (a stored row being
            re-run — lost outputs, --retry-failed — is not one until it is recorded again)."""
            return [ckpt.rows[k] for k in configs if k in done or k in fresh]

        def finish(status: str) -> dict:
            """Write this grid's table and sweep.json (also when stopped), return the summary."""
            rows = grid_rows()
            write_table(out / "table.parquet", rows, varied)
            revisions = sorted({r["git_revision"] for r in rows})
            if len(revisions) > 1:
                log.warning(
                    "sweep %s: its rows come from %d code revisions %s", out, len(revisions), revisions
                )
            failed = [r for r in rows if r["status"] != "ok"]
            summary = {
                "experiment": experiment,
                "status": status,
                "grid": grid,
                "zip": zipped or {},
                "quick": quick,
                "sets": {k: _cli_value(v) for k, v in sets.items()},
                "n_points": len(configs),
                "n_ok": len(rows) - len(failed),
                "n_failed": len(failed),
                "n_resumed": n_resumed,
                "n_submitted": len(todo),
                "n_other_code": n_other_code,
                "other_code_revisions": other_revisions,
                "failed": [{"point": r["key"], "error": _last_line(r["error"])} for r in failed[:5]],
                "table": str(out / "table.parquet"),
                "git_revision": revision,
                "row_revisions": revisions,
                "seconds": time.perf_counter() - t_start,
            }
            atomic_write_bytes(out / "sweep.json", (json.dumps(_jsonable(summary), indent=2) + "\n").encode())
            return summary

        def record(key: str, res: dict) -> None:
            values, cfg = configs[key]
            row = {
                "config_digest": digests[key],
                "values": values,
                "status": res["status"],
                "error": res["error"],
                "seconds": res["seconds"],
                "seed": cfg.get("seed"),
                "git_revision": revision,
                "versions": vers,
                "metrics": flatten_scalars(res["summary"]) if res["summary"] else {},
            }
            if res["status"] != "ok":
                log.warning("sweep point %s failed: %s", key, _last_line(res["error"]))
            ckpt.add(key, row)
            fresh.add(key)
            write_table(out / "table.parquet", grid_rows(), varied)
            if on_point is not None:
                on_point(key, ckpt.rows[key])

        atomic_write_bytes(  # stale from an earlier grid until this one ends
            out / "sweep.json",
            (
                json.dumps({"experiment": experiment, "status": "running", "pid": os.getpid(), "grid": grid})
                + "\n"
            ).encode(),
        )
        try:
            if todo:
                _run_points(client, experiment, configs, todo, threads, retries, progress, record, ckpt, need)
        except BaseException:
            finish("stopped")
            raise
        return finish("complete")


def _run_points(client, experiment, configs, todo, threads, retries, progress, record, ckpt, need) -> None:
    """Submit ``todo``'s points and record each as it finishes; stop (cancelling the rest) when
    a needed metric is missing or the first ``config.DEFAULTS.sweep_stop_after_failures``
    finished points all failed."""
    from distributed import as_completed

    from . import config

    futures = {
        client.submit(
            run_point, experiment, configs[k][1], threads, key=f"sweep-{k}", pure=False, retries=retries
        ): k
        for k in todo
    }
    stop_after = config.DEFAULTS.sweep_stop_after_failures
    n_ok = n_failed = 0
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(todo), desc=f"sweep {experiment}", unit="point")
    try:
        for fut in as_completed(futures):
            key = futures[fut]
            try:
                res = fut.result()
            except Exception:  # the task could not run at all (e.g. its workers kept dying)
                res = {
                    "status": "failed",
                    "summary": None,
                    "seconds": float("nan"),
                    "error": traceback.format_exc(),
                }
            record(key, res)
            if bar is not None:
                bar.update()
            n_ok += res["status"] == "ok"
            n_failed += res["status"] != "ok"
            if need and res["status"] == "ok":
                _check_metrics(ckpt.rows[key], need)
                need = []
            if stop_after and n_ok == 0 and n_failed >= stop_after and n_failed < len(futures):
                raise SweepError(
                    f"the first {n_failed} points all failed, so the sweep stopped (the rest cancelled); "
                    f"last error: {_last_line(res['error'])}. Fix the setting and re-run; failed points "
                    "run again with --retry-failed (their tracebacks: the table's error column)"
                )
    except BaseException:
        client.cancel(list(futures))  # one call: a cancel per future is a round trip each
        raise
    finally:
        if bar is not None:
            bar.close()


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


def _checkpoint(out: Path, ck_config: dict) -> Checkpoint:
    """The sweep's checkpoint (``out/points.jsonl``, keeping the rows of other code and other
    sweep formats as history); ``SweepError`` if it cannot be written."""
    try:
        return Checkpoint(out / "points.jsonl", ck_config, keep_other=True)
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


def _check_metrics(row: dict, names: list[str]) -> None:
    """``SweepError`` unless every name is a number column of a finished point's row (a null
    value counts: the column is NaN there), with the closest column names as a hint."""
    # the experiment's numbers and the table's own columns (``seconds`` a number, ``status`` not)
    metrics = {
        **row["metrics"],
        **{k: row.get(k) for k in ("seconds", "seed", "status", "error", "git_revision")},
    }
    numbers = sorted(
        k
        for k, v in metrics.items()
        if v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
    )
    for name in names:
        if name in numbers:
            continue
        what = "is not a number" if name in metrics else "is not a column"
        raise SweepError(
            f"{name!r} {what} of this sweep's table (checked on point {row['key']}); "
            + column_hint(name, numbers)
        )


def close_columns(name: str, columns: list[str], n: int | None = None) -> list[str]:
    """Up to ``n`` (default ``config.DEFAULTS.sweep_column_hints``, read now) of ``columns``
    closest to ``name``: difflib's close matches of the whole dotted path, then the columns
    whose last part is ``name``'s last part (``recall`` finds ``...6dls.recall``)."""
    import difflib

    from . import config

    n = config.DEFAULTS.sweep_column_hints if n is None else n
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
        g = g.sort_values(key)
        name = (
            ", ".join(
                f"{o}={v}"
                for o, v in zip(others, label if isinstance(label, tuple) else (label,), strict=True)
            )
            or None
        )
        ax.plot(g[key], g[metric], "o-", label=name)
    ax.set_xlabel(key)
    ax.set_ylabel(metric)
    if others:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"plot_{key}_{metric}")
    path = Path(out) if out else Path(table).parent / f"{safe}.png"
    return save_figure(fig, path)


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
