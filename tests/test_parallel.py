"""workbench.runner.parallel: rows give the same numbers serially and on Dask workers; results reach
the driver's callback; the auto rule picks serial for few rows and inside a worker."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from functools import partial

import pytest

from workbench import config
from workbench.runner.parallel import check_workers, map_rows, row_client, run_rows


def _square(x: int) -> list[int]:
    return [x * x]


class _Bar:
    def __init__(self):
        self.n = 0

    def update(self, n):
        self.n += n


def test_map_rows_serial_and_on_a_cluster_give_every_result_to_the_driver():
    from distributed import Client

    for client_kw in (None, {"processes": False, "n_workers": 2, "threads_per_worker": 1}):
        got, bar, calls = {}, _Bar(), []

        def meanwhile(got=got, calls=calls):  # the driver's own work while the rows run
            calls.append(len(got))
            return "figures"  # returned by map_rows

        keep = got.__setitem__
        if client_kw is None:
            out = map_rows(_square, range(7), keep, progress=bar, meanwhile=meanwhile)
        else:
            with Client(dashboard_address=None, **client_kw) as c:
                out = map_rows(_square, range(7), keep, client=c, progress=bar, meanwhile=meanwhile)
        assert got == {j: [j * j] for j in range(7)} and bar.n == 7
        # run once, before any result reached the driver (those finished meanwhile come after)
        assert out == "figures" and calls == [0]
        assert map_rows(_square, range(2), lambda j, r: None) is None


def _slow_square(x: int) -> list[int]:
    import time

    time.sleep(0.2)
    return [x * x]


def _fails(x: int) -> list[int]:
    raise ValueError(f"row {x} failed")


def test_map_rows_stops_when_the_cluster_is_left_without_workers_and_raises_a_tasks_error():
    """Workers that die with their nannies used to leave the driver waiting forever."""
    import time

    from distributed import Client

    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as c:
        got: dict = {}
        t0 = time.perf_counter()
        with config.override(cluster_no_worker_s=1.0):
            with pytest.raises(RuntimeError, match=r"no worker for \d+ s while \d+ task\(s\) wait"):
                # the driver scales the cluster to no worker once the rows are submitted (without the
                # check this waits forever)
                no_workers = lambda: c.cluster.scale(0)  # noqa: E731
                map_rows(_slow_square, range(20), got.__setitem__, client=c, meanwhile=no_workers)
        # the check waits its 1 s (probing each second), not forever; a row or two may have finished
        assert time.perf_counter() - t0 < 30 and len(got) < 20
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as c:
        with pytest.raises(ValueError, match="row 3 failed"):
            map_rows(_fails, [3], lambda j, r: None, client=c)


def test_run_rows_says_where_the_rows_ran_and_returns_the_drivers_share():
    for workers, where in ((1, "serial"), (2, "dask (2 workers)")):
        got = {}
        cfg = {"workers": workers, "scheduler": ""}
        extra, ran = run_rows(_square, range(5), got.__setitem__, cfg, min_rows=1, meanwhile=lambda: "figs")
        assert (extra, ran) == ("figs", where) and got == {j: [j * j] for j in range(5)}
    # the auto rule counts rows, not jobs: 5 jobs holding 1000 rows start a cluster
    _, ran = run_rows(_square, range(5), lambda j, r: None, {"workers": 0, "scheduler": ""}, n_rows=1000)
    assert ran.startswith("dask") or (os.cpu_count() or 1) == 1


def _settings_seen(_job) -> tuple[float, float]:
    return config.TOL.resist_rtol, config.DEFAULTS.work_eps


def test_worker_processes_compute_under_the_drivers_configure():
    # configure() used to change the driver only: rows on worker processes ran at the defaults
    from distributed import Client

    from workbench.runner.parallel import local_cluster

    default = _settings_seen(None)
    assert config.changed() == {}
    with config.override(resist_rtol=default[0] / 10, work_eps=default[1] * 2):
        assert config.changed() == {"resist_rtol": default[0] / 10, "work_eps": default[1] * 2}
        got = {}
        with local_cluster(1, 1) as cluster, Client(cluster) as c:  # leaves the driver's environment be
            map_rows(_settings_seen, range(2), got.__setitem__, client=c)
            assert c.run(_settings_seen, None) != {}  # the worker's own process keeps its defaults
            assert set(c.run(_settings_seen, None).values()) == {default}
    assert got == {0: (default[0] / 10, default[1] * 2), 1: (default[0] / 10, default[1] * 2)}
    assert config.changed() == {}


def _worker_environment() -> tuple[dict, int, list]:
    import numba
    from threadpoolctl import threadpool_info

    keys = ("MALLOC_TRIM_THRESHOLD_", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS")
    pools = [d["num_threads"] for d in threadpool_info()]
    return {k: os.environ.get(k) for k in keys}, numba.get_num_threads(), pools


def test_local_cluster_workers_start_with_one_thread_per_pool_and_glibcs_own_malloc_policy():
    # Dask's default MALLOC_TRIM_THRESHOLD_ turns off glibc's dynamic mmap threshold and made
    # the FEM solves slower in a worker (workbench.runner.parallel.local_cluster); the BLAS caps
    # must be in place before the BLAS is imported.  Dask writes the pre-spawn environment into
    # the driver too: Numba's thread count must not go there (the driver's Numba re-reads it
    # and refused: "Cannot set NUMBA_NUM_THREADS to a different value")
    import numba.core.config
    from distributed import Client

    from workbench.runner.parallel import local_cluster

    before = {k: os.environ.get(k) for k in ("NUMBA_NUM_THREADS", "TQDM_DISABLE")}
    with local_cluster(2, 1) as cluster, Client(cluster) as client:
        seen = list(client.run(_worker_environment).values())
        # the scheduler reads its queueing from config.RUN.cluster_worker_saturation (1.1:
        # a row at a time to whichever worker is free), also when it is overridden
        assert cluster.scheduler.WORKER_SATURATION == config.RUN.cluster_worker_saturation == 1.1
    with config.override(cluster_worker_saturation=math.inf), local_cluster(1, 1) as cluster:
        assert cluster.scheduler.WORKER_SATURATION == math.inf
    assert len(seen) == 2
    for env, _numba_threads, pools in seen:
        assert env == {
            "MALLOC_TRIM_THRESHOLD_": None,
            "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1",
            "NUMBA_NUM_THREADS": "1",
        }
        assert pools and set(pools) == {1}
    assert {k: os.environ.get(k) for k in before} == before
    numba.core.config.reload_config()  # raised in the driver when the cluster leaked the variable


def test_row_client_is_serial_for_few_rows_one_worker_or_nothing_to_do():
    for n_rows, workers in ((config.RUN.cluster_min_rows - 1, 0), (1000, 1), (0, 2)):
        with row_client(n_rows, workers) as c:
            assert c is None, (n_rows, workers)
    for bad in (-1, 1.5, True):
        with pytest.raises(ValueError, match="workers must be 0"):
            check_workers(bad, "")
    # an experiment's scheduler is judged as the sweep's is (a new-user trial found it ignored)
    with pytest.raises(ValueError, match=r"scheduler 'tcp://h:99999': port '99999' is not a TCP port"):
        check_workers(0, "tcp://h:99999")
    with pytest.raises(ValueError, match="workers=1 with scheduler='h:8786': the rows run on that cluster"):
        check_workers(1, "h:8786")  # refused before the address is tried
    check_workers(0, "inproc://x")  # a protocol Dask judges itself
    # an address where something listens passes; one where nothing does fails before any work
    import socket

    with socket.create_server(("127.0.0.1", 0)) as server:
        check_workers(0, f"tcp://127.0.0.1:{server.getsockname()[1]}")
    with pytest.raises(ValueError, match=r"no Dask scheduler at 'tcp://127.0.0.1:1': 127.0.0.1:1 refused"):
        check_workers(0, "tcp://127.0.0.1:1")


@pytest.mark.jit_only("over 15 s as pure Python")
def test_fem_fitting_tasks_are_the_same_serially_and_on_two_worker_processes(tmp_path):
    """The real task function — profile rows (condensed pad from the disk cache, contact
    solve, fits) and a condensed-vs-full-mesh reference case — through map_rows on two
    worker processes gives the serial run's numbers bit for bit: one BLAS, OpenMP and Numba
    thread per task in both."""
    from distributed import Client, LocalCluster

    from workbench.experiments.fem_fitting import reference_cases, run_task
    from workbench.runner.experiment_config import build_config

    sets = {
        "n_objects": 1,
        "n_asymmetric": 0,
        "approaches": {"major": 0.0, "minor": math.pi / 2},
        "n_wrenches": 130,
        "n_heldout": 100,
        "support_directions": 100,
        "thesis_code": True,
        "ablation_every": 0,
    }
    cfg = build_config("fem-fitting", True, str(tmp_path), None, sets)
    # one full-mesh check; the driver builds (or loads) the pad here, before any worker needs it
    (label, pose), *_ = reference_cases(cfg)
    jobs = [
        ("reference", label, pose),
        ("rows", (0, 0, 0.5, "major", 0.0, [0, 1, 2])),
        ("rows", (1, 0, 0.5, "minor", math.pi / 2, [1, 2])),
    ]
    fn = partial(run_task, config=cfg)

    def keep(into):
        return lambda job, res: into.update({job[1]: res} if job[0] == "reference" else res)

    serial, dist = {}, {}
    map_rows(fn, jobs, keep(serial))
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cl, Client(cl) as c:
        map_rows(fn, jobs, keep(dist), client=c)
    assert sorted(serial) == sorted(dist) and len(serial) == 6
    assert serial[label]["pressure_rel_l2"] < 0.02  # the check itself ran (test_experiments: its bound)

    def numbers(row):  # without the timings (condensed_ms, full_s, speed_ratio, *_ms, *_s)
        return {
            k: v for k, v in row.items() if not (k.endswith("_ms") or k.endswith("_s") or k == "speed_ratio")
        }

    for key in serial:
        assert json.dumps(numbers(serial[key]), sort_keys=True) == json.dumps(
            numbers(dist[key]), sort_keys=True
        ), key
    # a task of one profile (the driver's split) or of a resumed grasp's remaining ones solves
    # the displacements before it as the whole grasp does: the same row, bit for bit
    # (through map_rows: one Numba thread per task, as there — a parallel reduction on two threads
    # sums in another order)
    split = {}
    map_rows(
        fn,
        [("rows", (0, 0, 0.5, "major", 0.0, [2])), ("rows", (1, 0, 0.5, "minor", math.pi / 2, [1]))],
        keep(split),
    )
    assert len(split) == 2
    for key, row in split.items():
        assert json.dumps(numbers(row), sort_keys=True) == json.dumps(numbers(serial[key]), sort_keys=True)


@pytest.mark.slow
@pytest.mark.jit_only("over 15 s as pure Python")
def test_ls_fitting_surfaces_are_the_same_serially_and_on_two_worker_processes(tmp_path):
    """ls-fitting's surface rows (quadrature or mesh wrenches, every fit and error) on two
    worker processes give the serial run's errors bit for bit (only fit timings differ)."""
    from workbench.experiments import ls_fitting

    runs = {}
    for workers in (1, 2):
        cfg = {
            **ls_fitting.DEFAULT_CONFIG,
            **ls_fitting.QUICK_CONFIG,
            "surfaces": ["S1", "S3"],
            "K": [200],
            "n_heldout": 500,
            "thesis_code": False,
            "support_directions": 200,
            "solver_comparison_K": 200,
            "section_surface": "S3",
            "section_K": 200,
            "workers": workers,
            "out": str(tmp_path / f"w{workers}"),
        }
        runs[workers] = ls_fitting.run(cfg)
    assert runs[1]["surfaces_ran_on"] == "serial" and runs[2]["surfaces_ran_on"] == "dask (2 workers)"
    assert runs[1]["heldout_error"] == runs[2]["heldout_error"]
    assert runs[1]["support_error"] == runs[2]["support_error"]


@pytest.mark.slow
@pytest.mark.jit_only("over 15 s as pure Python")
def test_sensitivity_rows_are_the_same_in_any_order_and_on_two_worker_processes(tmp_path):
    """Each sensitivity row has its own cut store and exact contacts (the limit surfaces are
    a per-process cache of deterministic fits), so its numbers do not depend on which rows
    ran before it: forwards, backwards and on two worker processes alike."""
    from distributed import Client, LocalCluster

    from workbench.grasp.sensitivity_rows import row_key, row_tasks, sensitivity_row
    from workbench.runner.experiment_config import build_config

    sets = {
        "n_disturbances": 12,
        "models": ["planar", "6dls", "6dls_quartic"],  # the quartic's margins use cutting planes
        "training_models": ["6dls_quartic"],
        "training_samplers": ["thesis", "mix"],
        "k_values": [2.0],
        "mu_offsets": [0.2],
        "length_offsets": [-0.3],
        "robust_disturbances": 6,
    }
    cfg = build_config("sensitivity", True, str(tmp_path), None, sets)
    tasks = row_tasks(cfg)
    assert {t[0] for t in tasks} == {"margin", "truth", "setting", "robust"}
    fn = partial(sensitivity_row, config=cfg)

    def collect(into):
        return lambda task, row: into.__setitem__(row_key(task), row)

    forwards, backwards, dist = {}, {}, {}
    map_rows(fn, tasks, collect(forwards))
    map_rows(fn, tasks[::-1], collect(backwards))
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cl, Client(cl) as c:
        map_rows(fn, tasks, collect(dist), client=c)

    def numbers(rows):
        return json.dumps(
            {
                k: {a: b for a, b in r.items() if not a.endswith(("_ms", "_s", "_grasp"))}
                for k, r in rows.items()
            },
            sort_keys=True,
        )

    assert len(forwards) == len(tasks) == 3 + 2 + 2 + 3 * 3 + 1
    assert numbers(forwards) == numbers(backwards) == numbers(dist)


def test_fem_validation_fidelity_cases_are_the_same_serially_and_on_two_worker_processes(tmp_path):
    """The neo-Hookean fidelity cases (tasks of fem-validation) give the serial run's rows
    bit for bit on two worker processes (timings aside)."""
    from distributed import Client, LocalCluster

    from workbench.experiments.fem_validation import FIDELITY_CASES, fidelity_case
    from workbench.runner.experiment_config import build_config

    cfg = build_config("fem-validation", True, str(tmp_path), None, {"fidelity_deltas": [0.02, 0.2]})
    fn = partial(fidelity_case, config=cfg)
    serial, dist = {}, {}
    map_rows(fn, FIDELITY_CASES, serial.__setitem__)
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cl, Client(cl) as c:
        map_rows(fn, FIDELITY_CASES, dist.__setitem__, client=c)

    def numbers(rows):
        return json.dumps([{k: v for k, v in r.items() if k != "seconds"} for r in rows], sort_keys=True)

    assert set(serial) == set(FIDELITY_CASES)
    for name in FIDELITY_CASES:
        assert len(serial[name]) == 2 * 3  # per δ: the reference and two condensed levels
        assert numbers(serial[name]) == numbers(dist[name]), name


@pytest.mark.jit_only("over 15 s as pure Python")
def test_minimal_work_grasps_and_load_curves_are_the_same_serially_and_on_two_worker_processes(tmp_path):
    """minimal-work's tasks — the wall squeezes of a chunk of grasps (the wall built once per
    worker process), a candidate grasp's row (metrics and simulated truth) and a nonlinear
    wall's load curve — give the serial rows bit for bit on two worker processes (timings
    aside), and a chunk's squeezes are those of its grasps one at a time."""
    from pathlib import Path

    import numpy as np
    from distributed import Client, LocalCluster

    from workbench.experiments.minimal_work import DEFAULT_CONFIG
    from workbench.fem.grasp_walls import (
        NonlinearWallSettings,
        WallSettings,
        calibrated_stiffness,
        load_curve,
        load_mesh,
        object_files,
        wall_stiffness,
    )
    from workbench.grasp.sampling import horizontal_grasps
    from workbench.grasp.work_table import GraspRowSettings, grasp_row, measured_map
    from workbench.runner.experiment_config import build_config

    if not Path(DEFAULT_CONFIG["data_dir"], "meshes").is_dir():  # before build_config, which checks it
        pytest.skip("deformable_objects data not available (CC BY-NC, read by path)")
    small = {"objects": ["shampoo"], "mesh": [16, 8], "robust_samples": 4, "noise_samples": 2}
    cfg = build_config("minimal-work", True, str(tmp_path), None, small)
    mesh_path, map_path = (str(p) for p in object_files(cfg["data_dir"], "shampoo"))
    mesh = load_mesh(mesh_path)
    wall = WallSettings.from_config(cfg)

    # the experiment's three kinds of task, as its Dask adapters call the library
    def wall_task(job):  # (grasp numbers (m,), locations (2m, 3)): the first jaws, then the second
        ids, P = job
        return list(zip(ids, wall_stiffness(mesh_path, wall, P, ids), strict=True))

    def grasp_task(job):  # (grasp number, grasp, calibration scale, seed, its wall row)
        k, g, scale, seed, fem = job
        run, smap = GraspRowSettings.from_config(cfg), measured_map(map_path)
        s_fem = calibrated_stiffness(fem, scale)
        return grasp_row("shampoo", k, g, load_mesh(mesh_path), smap, s_fem, run, seed)

    def curve_task(job):  # (grasp number, grasp, calibration scale, jaw force to reach [N])
        _, g, scale, force = job
        return load_curve(mesh_path, g, scale, force, NonlinearWallSettings.from_config(cfg))

    lo, hi = mesh.bounds[:, 2]
    cands = horizontal_grasps(mesh, [lo + 0.4 * (hi - lo), lo + 0.6 * (hi - lo)], 2, cfg["mu"], pad=None)
    assert len(cands) >= 2
    # the candidate's wall row as the experiment's wall stage computes it (one task of its own)
    ((_, wall_row),) = wall_task(([0], np.array([cands[0]["p1"], cands[0]["p2"]])))
    grasps = [(0, cands[0], 0.5, 100, wall_row)]
    curves = [(1, cands[1], 0.5, 2.0)]
    walls = [([0, 1], np.array([c[p] for p in ("p1", "p2") for c in cands[:2]]))]
    tasks = (("grasp", grasp_task, grasps), ("curve", curve_task, curves), ("wall", wall_task, walls))

    def collect(into, tag):
        # the grasp's number: job[0] of a grasp or curve task, "wall" for the wall chunk
        return lambda job, row: into.__setitem__((tag, "wall" if tag == "wall" else job[0]), row)

    serial, dist = {}, {}
    for tag, f, jobs in tasks:
        map_rows(f, jobs, collect(serial, tag))
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cl, Client(cl) as c:
        for tag, f, jobs in tasks:
            map_rows(f, jobs, collect(dist, tag), client=c)

    def numbers(rows):
        def drop(r):  # timings aside
            return {a: b for a, b in r.items() if a != "seconds"}

        return json.dumps(
            {
                str(k): drop(r) if isinstance(r, dict) else [(a, drop(b)) for a, b in r]
                for k, r in rows.items()
            },
            sort_keys=True,
        )

    assert len(serial) == 3
    # the wall task's squeezes of two grasps at once are the squeezes one at a time
    one = [wall_task(([k], w[1][[k, k + 2]]))[0] for k in (0, 1) for w in walls]
    assert numbers({"one": one}) == numbers({"one": serial[("wall", "wall")]})
    assert serial[("curve", 1)]["curve"] is not None
    assert np.isfinite(serial[("grasp", 0)]["s_fem"])
    assert numbers(serial) == numbers(dist)


@pytest.mark.jit_only("over 15 s as pure Python")
def test_wall_stiffness_map_tasks_are_the_same_serially_and_on_two_worker_processes(tmp_path):
    """wall-stiffness's family tasks — a (bottle, height) row of the map, the wall built once
    per worker process, and the mesh-convergence study — give the serial rows bit for bit on
    two worker processes (timings aside)."""
    from distributed import Client, LocalCluster

    from workbench.experiments.wall_stiffness import task
    from workbench.runner.experiment_config import build_config

    cfg = build_config(
        "wall-stiffness", True, str(tmp_path), None, {"convergence_meshes": [[16, 8], [24, 12]]}
    )
    jobs = ["convergence", (0, 0.3, (0.0, 1.0)), (0, 0.7, (0.5,))]
    fn = partial(task, config=cfg)
    serial, dist = {}, {}
    map_rows(fn, jobs, lambda job, res: serial.__setitem__(str(job), res))
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cl, Client(cl) as c:
        map_rows(fn, jobs, lambda job, res: dist.__setitem__(str(job), res), client=c)

    def numbers(rows):
        def strip(r):
            return {k: v for k, v in r.items() if k not in ("ms", "build_s")}

        return json.dumps(
            {
                k: [strip(r) if isinstance(r, dict) else [r[0], strip(r[1])] for r in v]
                for k, v in rows.items()
            },
            sort_keys=True,
        )

    assert len(serial["convergence"]) == 4 and len(serial[str(jobs[1])]) == 2
    assert all(0 < r[1]["stiffness_N_per_m"] < 1e6 for r in serial[str(jobs[1])])
    assert numbers(serial) == numbers(dist)


_COMPILE_IN_A_WORKER = """
import numba  # the driver's main module imports Numba, as the workbench CLI does
import numpy as np
from distributed import Client

from workbench.runner.parallel import local_cluster, map_rows


def task(k):
    @numba.njit(parallel=True)  # a kernel no disk cache holds: compiled in the worker
    def total(x):
        s = 0.0
        for i in numba.prange(x.size):
            s += x[i] * k
        return s

    return total(np.ones(10))


if __name__ == "__main__":
    got = {}
    with local_cluster(2) as cluster, Client(cluster) as client:
        map_rows(task, range(4), got.__setitem__, client=client)
    print(sorted(got.items()))
"""


@pytest.mark.jit_only("the failure is Numba's compiler re-reading NUMBA_NUM_THREADS; no compile without JIT")
def test_a_kernel_compiled_inside_a_worker_runs(tmp_path):
    """A worker started by a driver whose main module imports Numba imports it again before the
    nanny's NUMBA_NUM_THREADS=1 is set: its pool starts with 2 threads, and compiling a kernel
    there re-read 1 and raised "Cannot set NUMBA_NUM_THREADS ..." (in a fresh clone every
    fem-fitting reference task, sensitivity and minimal-work failed so: their kernels were not
    in the disk cache yet).  Now the tasks' results come back."""
    script = tmp_path / "driver.py"
    script.write_text(_COMPILE_IN_A_WORKER)
    res = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path, timeout=300
    )
    assert res.returncode == 0, res.stderr[-3000:]
    assert res.stdout.strip().splitlines()[-1] == str([(k, 10.0 * k) for k in range(4)])


def test_map_rows_stats_account_for_every_task_serial_and_on_dask():
    """The stats of a run: every task's compute seconds, serially and from Dask's task stream
    (sleeping tasks of known length: busy = their sum within the timer's resolution)."""
    import time as _time

    from distributed import Client, LocalCluster

    from workbench.runner.parallel import map_rows

    naps = [0.05, 0.1, 0.15, 0.2]
    for client_kind in ("serial", "dask"):
        stats: dict = {}
        got = {}
        if client_kind == "serial":
            map_rows(_time.sleep, naps, got.__setitem__, stats=stats)
        else:
            with (
                LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as c,
                Client(c) as cl,
            ):
                map_rows(_time.sleep, naps, got.__setitem__, client=cl, stats=stats)
        assert len(got) == 4
        assert sum(w["tasks"] for w in stats["workers"].values()) == 4
        # a sleep lasts at least its length; on top, each task's own overhead (a call, or a
        # worker's deserialisation) stays far below 0.1 s even on a loaded machine
        assert sum(naps) <= stats["busy_s"] <= sum(naps) + 0.1 * len(naps)
        assert 0.2 <= stats["task_s"]["max"] <= 0.3
        assert 0 < stats["utilisation"] <= 1.0 + 1e-9
