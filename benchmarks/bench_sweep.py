"""Sweeps on Dask: per-task overhead of the local cluster and the speed-up of two
workers over one on this machine, written to ``results/benchmarks/sweep.json``.

* **Overhead per task**: ``n`` no-op rows through :func:`workbench.runner.parallel.map_rows` (the
  row loop of every experiment and sweep: ``client.map``, the one-BLAS-thread wrapper on the
  worker, ``as_completed`` with results, the driver's callback) on a warm
  :func:`workbench.runner.parallel.local_cluster` of one single-threaded worker, the median of
  several batches divided by ``n``, with the scheduler's queue at its default, 1.1
  (``config.RUN.cluster_worker_saturation``: a row at a time to whichever worker is free),
  and beside it with the queue off (``inf``: every row handed out at submit, which splits
  fem-fitting's uneven rows by count — see the warm speed-up below).  Why the path is built
  as it is, and what it cost before: docs/decisions.md.
* **Speed-up**: one sweep of ``points`` equal points of a small ``discretization --quick``
  run, on a local cluster of 1 and then of 2 worker processes (one thread each, Numba's
  threads capped at 1), each a fresh sweep directory; wall time of ``run_sweep`` including
  the cluster's start, and without it (the sum of the points' own run times over the wall
  time of the task loop).

* **fem-fitting --quick**: the whole run with its tasks (12 profiles, 2 full-mesh
  reference cases) serially and on 2 local workers (cold cluster: its start and the
  workers' imports are in the time), medians of 3 runs each, each run a fresh
  ``workbench run`` process as a user starts it (run inside this process, after the other
  measurements, it reads a smaller speed-up), with the CPU seconds of all the run's processes:
  two workers spend more than the serial run (their imports and first calls, the nannies and
  the scheduler, and tasks slower beside each other).
* **fem-fitting --quick, warm**: the same run in steady state — one process, an already-running
  cluster of 2 workers (``scheduler=`` its address) against serial, each after a warm-up run:
  what a sweep or a researcher's repeated runs get once the cluster's start and the workers'
  imports are paid (:func:`fem_fitting_rows_warm`).
* **Memory bandwidth**: one process against two at once on a 320 MB stream: the ratio two
  workers cannot beat on bandwidth-bound work (it varies from run to run on this VM: its host
  shares the bandwidth, and how much varies).
* **Quartic fits**: one process against two at once on fem-fitting's dominant compute (a
  Clarabel quartic fit, cache-resident): the ceiling two workers have on its rows here.
* **fem-fitting full**: read from ``results/fem-fitting/summary.json`` (``make reproduce``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_wrench import machine_roofline  # the sibling benchmark's FMA roofline

from workbench.runner.results import code_revision, versions, write_json
from workbench.runner.sweep import run_sweep

ROOT = Path(__file__).resolve().parents[1]
SETS = {"n_elements": [25, 50, 100], "timing_twists": 2, "timing_repeats": 1}


def _noop(i: int) -> int:
    return i


def task_overhead(n: int, batches: int) -> dict:
    """Seconds a row costs beyond its own work on a warm local cluster of one worker: the median
    over ``batches`` of ``n`` no-op rows, at the configured queueing and with the queue off."""
    import math

    from workbench import config

    out = _overhead(n, batches)
    with config.override(cluster_worker_saturation=math.inf):
        off = _overhead(n, batches)
    return {
        "tasks_per_batch": n,
        "batches": batches,
        "median_ms": 1e3 * statistics.median(out),
        "all_ms": [1e3 * x for x in out],
        "worker_saturation": config.RUN.cluster_worker_saturation,
        "queue_off_median_ms": 1e3 * statistics.median(off),
        "goal_ms": 5.0,
        "path": "workbench.runner.parallel.map_rows (the experiments' and sweeps' row loop) of no-op rows",
    }


def _overhead(n: int, batches: int) -> list[float]:
    from distributed import Client

    from workbench.runner.parallel import local_cluster, map_rows

    # the experiments' own local cluster (workbench.runner.parallel.local_cluster: its queueing setting,
    # config.RUN.cluster_worker_saturation, is most of this number), one worker
    with local_cluster(1) as cluster, Client(cluster) as c:
        map_rows(_noop, range(10), lambda job, res: None, client=c)  # warm-up
        per_task = []
        for _ in range(batches):
            got: list[int] = []
            t0 = time.perf_counter()
            map_rows(_noop, range(n), lambda job, res, got=got: got.append(res), client=c)
            per_task.append((time.perf_counter() - t0) / n)
            assert sorted(got) == list(range(n))
    return per_task


def speedup(points: int) -> dict:
    out = {}
    for workers in (1, 2):
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            s = run_sweep(
                "discretization",
                {"mu": [0.5 + 0.1 * i for i in range(points)]},
                quick=True,
                sets=SETS,
                out=Path(tmp) / "sw",
                workers=workers,
                progress=False,
            )
            wall = time.perf_counter() - t0
            import pandas as pd

            df = pd.read_parquet(Path(tmp) / "sw" / "table.parquet")
        assert s["n_ok"] == points, s
        out[workers] = {"wall_s": wall, "sum_point_s": float(df["seconds"].sum()), "n_ok": s["n_ok"]}
    out["speedup_wall"] = out[1]["wall_s"] / out[2]["wall_s"]
    return out


def _one_vs_two(script: str, repeats: int) -> tuple[float, float]:
    """Medians of the seconds ``script`` prints, run alone and (the slower of) two at once, each
    a fresh interpreter with one BLAS, OpenMP and Numba thread."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}
    cmd = [sys.executable, "-c", script]

    def one() -> float:
        return float(subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout)

    def two() -> list[float]:
        ps = [subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True) for _ in range(2)]
        return [float(p.communicate()[0]) for p in ps]

    alone = statistics.median(one() for _ in range(repeats))
    return alone, statistics.median(max(two()) for _ in range(repeats))


_STREAM = """
import time, numpy as np
a = np.random.default_rng(0).random(40_000_000)  # 320 MB: far beyond any cache
b = np.empty_like(a)
np.multiply(a, 1.0, out=b)
t = time.perf_counter()
for _ in range(20):
    np.multiply(a, 1.0001, out=b)
print(time.perf_counter() - t)
"""


def memory_scaling(repeats: int = 3) -> dict:
    """The machine's memory bandwidth, one process against two at once (a STREAM-like scale of
    320 MB, one BLAS thread each): FEM solves and wrench sums over large profiles are bandwidth
    bound, so two workers cannot beat this ratio on them however the tasks are spread."""
    alone, pair = _one_vs_two(_STREAM, repeats)
    gbs = 20 * 2 * 8 * 40e6 / 1e9  # bytes read and written per run [GB]
    return {
        "one_process_GBps": gbs / alone,
        "two_processes_GBps": 2 * gbs / pair,
        "throughput_2_over_1": 2 * alone / pair,
        "what": "20 x b = 1.0001 a over 40e6 doubles (320 MB each), one process vs two at once",
    }


_FITS = """
import time, numpy as np
from workbench import fit_quartic
rng = np.random.default_rng(0)
G = rng.standard_normal((6, 6))
A = G @ G.T + 6 * np.eye(6)
x = rng.standard_normal((600, 6))
x /= np.sqrt(np.einsum("ij,jk,ik->i", x, A, x))[:, None] ** rng.uniform(0.9, 1.1, (600, 1))
fit_quartic(x)
t = time.perf_counter()
for _ in range(N):
    fit_quartic(x)
print(time.perf_counter() - t)
"""


def compute_scaling(fits: int = 20, repeats: int = 3) -> dict:
    """fem-fitting's dominant compute — the quartic fit (Clarabel, cache-resident: a 727-row
    KKT system) — in one process against two at once, one thread each: what two workers can
    gain on that share of its rows on this machine, whatever the scheduling (two virtual CPUs
    that share one physical core, or its caches, would give well below 2x)."""
    alone, pair = _one_vs_two(_FITS.replace("range(N)", f"range({fits})"), repeats)
    return {
        "one_process_s_per_fit": alone / fits,
        "two_processes_s_per_fit": pair / fits,
        "throughput_2_over_1": 2 * alone / pair,
        "what": f"{fits} quartic fits (600 wrenches, Clarabel) in one process vs two at once",
    }


def _children_cpu_s() -> float:
    """User + system CPU seconds of this process's finished children (and theirs)."""
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _medians(runs: dict[int, list[dict]], keys: tuple[str, ...]) -> dict:
    """Per worker count: the median of each of ``keys`` over its runs, where they ran, the runs."""
    return {
        workers: {
            **{k: statistics.median(r[k] for r in rs) for k in keys},
            "ran_on": rs[0]["ran_on"],
            "runs": rs,
        }
        for workers, rs in runs.items()
    }


def fem_fitting_rows(repeats: int = 3) -> dict:
    """``fem-fitting --quick`` (12 profiles in 4 grasps, 2 full-mesh reference cases) with its
    tasks serial and on 2 local workers, ``repeats`` times each (alternating), medians: the
    whole run's wall time and its tasks' (the rows and reference cases while the driver
    renders the examples; the cluster's start and the workers' imports included); the
    condensed pad comes from the user cache in both."""
    import json

    runs: dict[int, list[dict]] = {1: [], 2: []}
    for _ in range(repeats):
        for workers in (1, 2):
            with tempfile.TemporaryDirectory() as tmp:
                cmd = [sys.executable, "-m", "workbench.runner.cli", "run", "fem-fitting", "--quick"]
                t0 = time.perf_counter()
                cpu0 = _children_cpu_s()
                subprocess.run([*cmd, "--out", tmp, "--set", f"workers={workers}"], check=True)
                process_s = time.perf_counter() - t0
                cpu_s = _children_cpu_s() - cpu0  # the run's processes: driver, workers, nannies
                s = json.loads((Path(tmp) / "summary.json").read_text())
            keep = {
                "tasks_wall_s": "tasks_wall_s",
                "run_wall_s": "wall_time_s",
                "ran_on": "tasks_ran_on",
                "tasks_stream": "tasks_stream",
            }
            runs[workers].append(
                {**{k: s[v] for k, v in keep.items()}, "process_wall_s": process_s, "process_cpu_s": cpu_s}
            )
    out: dict = _medians(runs, ("tasks_wall_s", "run_wall_s", "process_wall_s"))
    # where the two workers' time goes (medians over runs): the tasks' compute against the
    # serial run's, i.e. what running on two fresh processes adds (imports, caches, the first
    # fit's set-up, sharing the cores with the driver's rendering), and the wall time left over
    busy1 = statistics.median(r["tasks_stream"]["busy_s"] for r in runs[1])
    busy2 = statistics.median(r["tasks_stream"]["busy_s"] for r in runs[2])
    out["decomposition"] = {
        "serial_task_compute_s": busy1,
        "two_workers_task_compute_s": busy2,
        "added_compute_s": busy2 - busy1,
        "two_workers_utilisation": statistics.median(r["tasks_stream"]["utilisation"] for r in runs[2]),
        # CPU seconds (user + sys) of every process of the run: what two worker processes cost
        # beyond the serial run's work (their imports and first calls, the nannies, the scheduler)
        "process_cpu_s": {w: statistics.median(r["process_cpu_s"] for r in runs[w]) for w in (1, 2)},
        "run_outside_tasks_s": {
            w: statistics.median(r["run_wall_s"] - r["tasks_wall_s"] for r in runs[w]) for w in (1, 2)
        },
    }
    out["speedup_tasks"] = out[1]["tasks_wall_s"] / out[2]["tasks_wall_s"]
    out["speedup_run"] = out[1]["run_wall_s"] / out[2]["run_wall_s"]
    out["speedup_process"] = out[1]["process_wall_s"] / out[2]["process_wall_s"]
    # Amdahl: the serial run's task compute split perfectly over two workers, nothing added (no
    # imports, no cluster) and the rest of the run left serial (the driver's examples, tables,
    # figures; they overlap the tasks only in part)
    serial_rest = out[1]["run_wall_s"] - busy1
    out["ceiling_speedup_rest_serial"] = out[1]["run_wall_s"] / (serial_rest + busy1 / 2)
    out["goal"] = 1.7
    return out


def fem_fitting_rows_warm(repeats: int = 3) -> dict:
    """``fem-fitting --quick`` in steady state, as a sweep or a researcher's repeated runs meet it:
    one process runs it ``repeats`` times serially and ``repeats`` times on an already-running
    local cluster of 2 workers (``scheduler=`` its address, as ``--scheduler`` does), alternating,
    after one warm-up run of each — the workers' and this process's imports, Numba cache loads,
    cvxpy and the condensed pad are paid before the clock starts.  The cold numbers
    (:func:`fem_fitting_rows`) add a fresh cluster's start and two fresh workers' warm-up, about
    as long as the quick run's own compute here."""
    from workbench.experiments.fem_fitting import run
    from workbench.runner.experiment_config import build_config
    from workbench.runner.parallel import local_cluster

    runs: dict[int, list[dict]] = {1: [], 2: []}
    with local_cluster(2) as cluster, tempfile.TemporaryDirectory() as tmp:
        address = cluster.scheduler_address
        for k in range(repeats + 1):  # the first of each is the warm-up
            for workers in (1, 2):
                sets = {"workers": 1} if workers == 1 else {"scheduler": address}
                cfg = build_config("fem-fitting", True, f"{tmp}/{k}-{workers}", None, sets)
                s = run(cfg)
                if k:
                    runs[workers].append(
                        {
                            "run_wall_s": s["wall_time_s"],
                            "tasks_wall_s": s["tasks_wall_s"],
                            "ran_on": s["tasks_ran_on"],
                            "busy_s": s["tasks_stream"]["busy_s"],
                        }
                    )
        n_workers = len(cluster.scheduler_info["workers"])
    out: dict = _medians(runs, ("run_wall_s", "tasks_wall_s", "busy_s"))
    out["cluster_workers"] = n_workers
    out["speedup_run"] = out[1]["run_wall_s"] / out[2]["run_wall_s"]
    out["speedup_tasks"] = out[1]["tasks_wall_s"] / out[2]["tasks_wall_s"]
    out["goal"] = 1.7
    return out


def fem_fitting_full() -> dict:
    """The full run's wall time as ``make reproduce`` wrote it (``results/fem-fitting``): not
    re-run here (about ten minutes on two cores)."""
    import json

    path = ROOT / "results" / "fem-fitting" / "summary.json"
    if not path.exists():
        return {"missing": str(path)}
    s = json.loads(path.read_text())
    return {
        "n_profiles": s["n_profiles"],
        "wall_time_s": s["wall_time_s"],
        "tasks_wall_s": s["tasks_wall_s"],
        "tasks_ran_on": s["tasks_ran_on"],
        "code": s.get("code"),
        "goal_s": 720.0,
        "source": "results/fem-fitting/summary.json",
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "sweep.json"))
    args = parser.parse_args()
    t0 = time.perf_counter()
    load_before = os.getloadavg()
    over = task_overhead(200 if args.quick else 500, 3 if args.quick else 5)
    sp = speedup(4 if args.quick else 8)
    ff = fem_fitting_rows(1 if args.quick else 3)
    warm = fem_fitting_rows_warm(1 if args.quick else 3)
    mem = memory_scaling(1 if args.quick else 3)
    fits = compute_scaling(5 if args.quick else 20, 1 if args.quick else 3)
    full = fem_fitting_full()
    load_after = os.getloadavg()
    out = {
        "benchmark": "workbench sweep on a local Dask cluster",
        "task_overhead": over,
        "sweep_speedup_2_over_1_workers": sp,
        "sweep_points": f"discretization --quick with {SETS}, mu varied",
        "fem_fitting_quick_2_over_1_workers": ff,
        "fem_fitting_quick_2_over_1_workers_warm": warm,
        "fem_fitting_full": full,
        "machine": {
            **machine_roofline(quick=True),
            "cpu_count": os.cpu_count(),
            "memory_bandwidth": mem,
            "quartic_fit_scaling": fits,
            "loadavg_1_5_15_before": load_before,
            "loadavg_1_5_15_after": load_after,
        },
        "code_revision": code_revision(),
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t0,
    }
    write_json(Path(args.out), out)
    print(f"wrote {args.out}")
    print(
        f"  fem-fitting --quick: run serial {ff[1]['run_wall_s']:.1f} s, "
        f"2 workers {ff[2]['run_wall_s']:.1f} s "
        f"-> {ff['speedup_run']:.2f}x (goal 1.7x; "
        f"with the rest serial at most {ff['ceiling_speedup_rest_serial']:.2f}x); "
        f"its tasks {ff['speedup_tasks']:.2f}x; whole processes {ff['speedup_process']:.2f}x"
    )
    print(
        f"  fem-fitting --quick, warm (a running 2-worker cluster vs serial, one process): run "
        f"{warm[1]['run_wall_s']:.2f} s vs {warm[2]['run_wall_s']:.2f} s -> {warm['speedup_run']:.2f}x, "
        f"tasks {warm['speedup_tasks']:.2f}x"
    )
    cpu = ff["decomposition"]["process_cpu_s"]
    print(f"  CPU of the run's processes: serial {cpu[1]:.1f} s, 2 workers {cpu[2]:.1f} s")
    if "wall_time_s" in full:
        print(
            f"  fem-fitting full: {full['n_profiles']} profiles in {full['wall_time_s']:.0f} s "
            f"({full['tasks_ran_on']}; goal {full['goal_s']:.0f} s)"
        )
    print(
        f"  overhead per task: {over['median_ms']:.3f} ms at worker-saturation "
        f"{over['worker_saturation']} (goal <= 5 ms; {over['queue_off_median_ms']:.3f} ms with the queue off)"
    )
    print(
        f"  memory bandwidth: one process {mem['one_process_GBps']:.1f} GB/s, two at once "
        f"{mem['two_processes_GBps']:.1f} GB/s -> {mem['throughput_2_over_1']:.2f}x"
    )
    print(
        f"  quartic fits: one process {fits['one_process_s_per_fit']:.3f} s a fit, two at once "
        f"{fits['two_processes_s_per_fit']:.3f} s -> {fits['throughput_2_over_1']:.2f}x"
    )
    print(
        f"  sweep of {sp[1]['n_ok']} points: 1 worker {sp[1]['wall_s']:.1f} s, "
        f"2 workers {sp[2]['wall_s']:.1f} s -> {sp['speedup_wall']:.2f}x"
    )
    print(
        f"  FMA {out['machine']['fma_gflops_measured']:.1f} GFLOP/s, "
        f"load {load_before[0]:.2f} -> {load_after[0]:.2f}"
    )


if __name__ == "__main__":
    main()
