"""workbench sweep: grid expansion, checks before any work, failed points recorded, resume
with every point exactly once (driver killed), a worker killed mid-task, a separate-process
scheduler, and the Parquet table read back."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pandas as pd
import pytest

from workbench.runner import cli
from workbench.runner.sweep import SweepError, expand_grid, flatten_scalars, point_key, run_sweep

BIN = Path(sys.executable).parent
#: a discretization run of seconds: two meshes, few timing twists
TINY = ["--quick", "--set", "n_elements=[25,50]", "--set", "timing_twists=2", "--set", "timing_repeats=1"]
TINY_SETS = {"n_elements": [25, 50], "timing_twists": 2, "timing_repeats": 1}


def test_expand_grid_is_the_product_with_zipped_lists_as_one_axis():
    pts = expand_grid({"a": [1, 2], "b": ["x", "y", "z"]}, {"c": [10, 20], "d": [0.1, 0.2]})
    assert len(pts) == 2 * 3 * 2
    assert pts[0] == {"a": 1, "b": "x", "c": 10, "d": 0.1}
    assert pts[1] == {"a": 1, "b": "x", "c": 20, "d": 0.2}  # zipped: paired, never crossed
    assert {(p["c"], p["d"]) for p in pts} == {(10, 0.1), (20, 0.2)}
    assert pts[-1] == {"a": 2, "b": "z", "c": 20, "d": 0.2}
    assert expand_grid({}, {"c": [1, 2]}) == [{"c": 1}, {"c": 2}]
    assert point_key({"mu": 0.3}) != point_key({"mu": 0.5}) and point_key({"mu": 0.3}) == point_key(
        {"mu": 0.3}
    )
    assert point_key({"s": ["S1", "S3"]}).startswith("s=S1,S3-")


@pytest.mark.parametrize(
    "grid, zipped, match",
    [
        ({}, {}, "at least one --grid"),
        ({"a": []}, {}, r"a=\[\]: the list is empty"),
        ({"a": 0.3}, {}, "expected a JSON list"),
        ({"a": [1]}, {"a": [2]}, "in both --grid and --zip"),
        ({}, {"a": [1, 2], "b": [1]}, "one length"),
    ],
)
def test_bad_grids_are_refused(grid, zipped, match):
    with pytest.raises(SweepError, match=match):
        expand_grid(grid, zipped)


def test_flatten_scalars_keeps_numbers_by_path_and_drops_long_lists_and_metadata():
    """Short lists enter by index (a Table 3.2 row, w_max of a surface), long ones (per-grasp
    arrays) and the run metadata stay out."""
    from workbench.runner.sweep import MAX_LIST_COLUMNS

    s = {
        "experiment": "x",
        "config": {"a": 1},
        "versions": {},
        "headline": ["h"],
        "n": 3,
        "t": {"lift": {"q": 0.5, "All": 0.7}},
        "arr": [1, 2],
        "rows": [{"F": 1.5}, [0.25, None]],
        "long": list(range(MAX_LIST_COLUMNS + 1)),
        "none": None,
        "flag": False,
    }
    assert flatten_scalars(s) == {
        "experiment": "x",  # a string, as the docstring says (it was left out)
        "n": 3,
        "t.lift.q": 0.5,
        "t.lift.All": 0.7,
        "arr.0": 1,
        "arr.1": 2,
        "rows.0.F": 1.5,
        "rows.1.0": 0.25,
        "rows.1.1": None,  # a null keeps its column (NaN in the table)
        "none": None,
        "flag": False,
    }


@pytest.mark.parametrize(
    "args, match",
    [
        (["--grid", "nope=[1,2]"], "unknown config keys for discretization: ['nope']"),
        (["--grid", 'mu=[0.5,"high"]'], "mu expects float"),
        (["--grid", "mu=[]"], "the list is empty"),
        (["--grid", "mu=0.5"], "expected a JSON list"),
        (["--grid", "mu=[0.5,-1]"], "grid value mu=-1: mu expects float"),
        (["--grid", "mu=[0,0.5]"], "mu = 0 has no friction wrench"),  # the experiment's own check
        (["--grid", "mu=[0.5]", "--set", "mu=0.7"], "['mu'] are given both as --set and in the grid"),
        (["--grid", "mu"], "expects KEY=JSON_LIST"),
        (["--grid", "mu=[0.5", "--quick"], "not a JSON list"),
        (["--grid", "mu=[0.5]", "--workers", "0"], "workers must be a positive integer"),
        (["--grid", "mu=[0.5]", "--seed", "-1"], "--seed -1: seed expects int"),  # as --grid seed=[-1]
        (["--grid", "mu=[0.5]", "--scheduler", "tcp://127.0.0.1:99999"], "port '99999' is not a TCP port"),
    ],
)
def test_cli_refuses_bad_sweeps_before_any_work(tmp_path, capsys, args, match):
    out = tmp_path / "sw"
    with pytest.raises(SystemExit) as exc:
        cli.main(["sweep", "discretization", "--out", str(out), *args])
    assert exc.value.code == 2
    assert match in capsys.readouterr().err
    assert not out.exists()  # nothing was started


def test_sweep_help_documents_every_option(capsys):
    with pytest.raises(SystemExit):
        cli.main(["sweep", "--help"])
    text = capsys.readouterr().out
    for opt in (
        "--grid",
        "--zip",
        "--quick",
        "--set",
        "--seed",
        "--out",
        "--workers",
        "--scheduler",
        "--threads",
        "--retry-failed",
        "--plot",
        "table.parquet",
        "resumes",
    ):
        assert opt in text, opt


@pytest.fixture
def toy(monkeypatch):
    monkeypatch.setitem(cli.EXPERIMENTS, "toy", "sweep_toy")
    from distributed import Client

    with Client(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as client:
        yield client


def test_failed_point_is_recorded_and_the_rest_complete_and_a_rerun_submits_nothing(tmp_path, toy):
    out = tmp_path / "sw"
    seen = []
    paired = {"x": [1.0, 2.0, 30.0], "tag": ["p", "q", "r"]}

    def sweep(grid=None, zipped=None, fail_above=10.0, where=out, **kw):
        return run_sweep(
            "toy",
            grid or {},
            zipped,
            sets={"fail_above": fail_above},
            out=where,
            client=toy,
            progress=False,
            **kw,
        )

    s = sweep(zipped=paired, on_point=lambda k, r: seen.append(k))
    assert (s["n_points"], s["n_ok"], s["n_failed"], s["n_submitted"], s["n_resumed"]) == (3, 2, 1, 3, 0)
    df = pd.read_parquet(out / "table.parquet")
    assert len(df) == 3 and df["point"].is_unique and sorted(seen) == sorted(df["point"])
    for col in (
        "point",
        "x",
        "tag",
        "status",
        "error",
        "seconds",
        "seed",
        "git_revision",
        "version.numpy",
        "y",
        "nested.z",
        "nested.ok",
        "nested.name",
        "wall_time_s",
    ):
        assert col in df.columns, col
    assert "values" not in df.columns and "headline" not in df.columns
    ok = df[df.status == "ok"].sort_values("x")
    assert ok["y"].tolist() == [1.0, 4.0] and ok["nested.z"].tolist() == [2.0, 3.0]
    assert ok["tag"].tolist() == ["p", "q"]
    bad = df[df.status == "failed"].iloc[0]
    assert bad["x"] == 30.0 and "ValueError: x = 30.0 is above fail_above = 10.0" in bad["error"]
    assert pd.isna(bad["y"])
    assert (out / "points" / ok["point"].iloc[0] / "summary.json").exists()
    # a re-run submits nothing; retry_failed runs the failed point again (and it fails again)
    again = sweep(zipped=paired)
    assert (again["n_submitted"], again["n_resumed"]) == (0, 3)
    retry = sweep(zipped=paired, retry_failed=True)
    assert (retry["n_submitted"], retry["n_failed"]) == (1, 1)
    # a grid grown by one value runs only the new point; a changed fixed setting reruns all
    grown = sweep({"x": [1.0, 2.0, 30.0, 3.0]}, where=tmp_path / "g")
    grown2 = sweep({"x": [1.0, 2.0, 30.0, 3.0, 4.0]}, where=tmp_path / "g")
    assert (grown["n_submitted"], grown2["n_submitted"], grown2["n_resumed"]) == (4, 1, 4)
    changed = sweep({"x": [1.0, 2.0, 30.0, 3.0, 4.0]}, fail_above=100.0, where=tmp_path / "g")
    assert (changed["n_submitted"], changed["n_failed"]) == (5, 0)
    assert len(pd.read_parquet(tmp_path / "g" / "table.parquet")) == 5


def test_list_values_are_json_columns_and_the_plot_is_written(tmp_path, toy):
    from workbench.runner.sweep import plot_sweep

    out = tmp_path / "sw"
    run_sweep("toy", {"x": [1.0, 2.0, 3.0], "shape": [[1, 2], [3]]}, out=out, client=toy, progress=False)
    df = pd.read_parquet(out / "table.parquet")
    assert sorted(set(df["shape"])) == ["[1, 2]", "[3]"] and len(df) == 6
    fig = plot_sweep(out / "table.parquet", "x", "y")
    assert fig.name == "plot_x_y.png" and fig.stat().st_size > 5_000
    with pytest.raises(SweepError, match="'nope' is not a column"):
        plot_sweep(out / "table.parquet", "x", "nope")
    with pytest.raises(SweepError, match="'nested.name' is not a number column"):
        plot_sweep(out / "table.parquet", "x", "nested.name")
    with pytest.raises(SweepError, match="'y' is not a swept key"):
        plot_sweep(out / "table.parquet", "y", "x")


def test_a_point_is_the_same_whatever_the_key_order_or_number_spelling(tmp_path, toy):
    """--grid flags in another order, or 1 for 1.0, name the same points: resumed, not re-run
    (they were run again, under a second folder each)."""
    assert point_key({"x": 1.0, "tag": "p"}) == point_key({"tag": "p", "x": 1.0})
    out = tmp_path / "sw"
    first = run_sweep("toy", {"x": [1.0, 2.0], "tag": ["p", "q"]}, out=out, client=toy, progress=False)
    again = run_sweep("toy", {"tag": ["p", "q"], "x": [1, 2]}, out=out, client=toy, progress=False)
    assert (first["n_submitted"], again["n_submitted"], again["n_resumed"]) == (4, 0, 4)
    assert len(list((out / "points").iterdir())) == 4
    with pytest.raises(SweepError, match=r"the grid repeats a point: \{'x': 1\} is \{'x': 1.0\}"):
        run_sweep("toy", {"x": [1.0, 1]}, out=tmp_path / "dup", client=toy, progress=False)


def test_the_table_holds_the_grid_just_run_even_when_nothing_ran(tmp_path, toy):
    out = tmp_path / "sw"
    run_sweep("toy", {"x": [1.0, 2.0, 3.0]}, out=out, client=toy, progress=False)
    s = run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
    assert s["n_submitted"] == 0 and s["n_points"] == 2
    assert sorted(pd.read_parquet(out / "table.parquet")["x"]) == [1.0, 2.0]
    assert len(_rows(out / "points.jsonl")) == 3  # the third point is kept for a later grid


def test_a_missing_plot_metric_stops_the_sweep_at_its_first_point(tmp_path, toy):
    """With nothing to check against, checked on the first finished point, not after the
    whole sweep; when points are already finished, or an earlier sweep of the experiment
    lies beside this one, before anything is submitted."""
    out = tmp_path / "sw"
    seen = []
    with pytest.raises(SweepError, match=r"'yy' is not a column .* did you mean \['y'"):
        run_sweep(
            "toy",
            {"x": [1.0, 2.0, 3.0, 4.0]},
            sets={"sleep": 0.3},
            out=out,
            client=toy,
            progress=False,
            metrics=["yy"],
            on_point=lambda k, r: seen.append(k),
        )
    assert 1 <= len(seen) <= 2  # two threads: the first point, perhaps its neighbour
    # the stopped sweep "sw" beside "b" is an earlier table of toy: checked there, before any work
    with pytest.raises(SweepError, match="'nested.name' is not a number of toy's tables .*before any work"):
        run_sweep(
            "toy", {"x": [1.0]}, out=tmp_path / "b", client=toy, progress=False, metrics=["nested.name"]
        )
    assert not (tmp_path / "b").exists()
    run_sweep("toy", {"x": [1.0]}, out=tmp_path / "b", client=toy, progress=False, metrics=["y"])
    n = len(_rows(tmp_path / "b" / "points.jsonl"))
    with pytest.raises(SweepError, match="'nope' is not a column"):  # from the finished point
        run_sweep("toy", {"x": [1.0, 5.0]}, out=tmp_path / "b", client=toy, progress=False, metrics=["nope"])
    assert len(_rows(tmp_path / "b" / "points.jsonl")) == n  # x = 5 was not run
    s = run_sweep("toy", {"x": [1.0, 5.0]}, out=tmp_path / "b", client=toy, progress=False, metrics=["y"])
    assert s["n_submitted"] == 1


def test_the_plan_of_a_sweep_resumes_its_checkpoint_and_writes_nothing(tmp_path, toy):
    """validate / plan / execute: the spec is checked when made, the plan reads the checkpoint
    (the points finished are done, the new one is to run) and writes nothing, execute runs the rest."""
    from workbench.runner.sweep import SweepCluster, SweepSpec, execute_sweep, plan_sweep

    out = tmp_path / "sw"
    first = run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
    listing = sorted(p.name for p in out.rglob("*"))
    spec = SweepSpec("toy", {"x": [1.0, 2.0, 3.0]}, out=out, cluster=SweepCluster(client=toy), progress=False)
    plan = plan_sweep(spec)
    assert sorted(p.name for p in out.rglob("*")) == listing
    keys = list(plan.configs)
    assert [plan.configs[k][0] for k in keys] == [{"x": 1.0}, {"x": 2.0}, {"x": 3.0}]
    assert plan.done == set(keys[:2]) == set(_rows(out / "points.jsonl"))
    assert plan.todo == (keys[2],)
    s = execute_sweep(plan)
    assert (first["n_submitted"], s["n_resumed"], s["n_submitted"], s["n_ok"]) == (2, 2, 1, 3)
    with pytest.raises(SweepError, match="give at most one of workers, scheduler and client"):
        SweepCluster(workers=2, client=toy)
    (tmp_path / "afile").write_text("x")
    with pytest.raises(SweepError, match="is a file; give a directory"):
        SweepSpec("toy", {"x": [1.0]}, out=tmp_path / "afile")


def test_a_directory_of_another_sweep_or_a_file_is_refused_before_any_work(tmp_path, toy, monkeypatch):
    out = tmp_path / "sw"
    run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
    before = (out / "points.jsonl").read_bytes()
    with pytest.raises(SweepError, match="holds a sweep of toy, not discretization; give another --out"):
        run_sweep("discretization", {"mu": [0.5]}, sets=TINY_SETS, quick=True, out=out, progress=False)
    assert (out / "points.jsonl").read_bytes() == before
    (tmp_path / "afile").write_text("x")
    with pytest.raises(SweepError, match="is a file; give a directory"):
        run_sweep("toy", {"x": [1.0]}, out=tmp_path / "afile", client=toy, progress=False)
    with pytest.raises(SweepError, match="seed is swept by the grid and also given by --seed"):
        run_sweep("toy", {"seed": [1, 2]}, seed=3, out=tmp_path / "s", client=toy, progress=False)
    # a relative directory is the driver's, made absolute for the workers
    monkeypatch.chdir(tmp_path)
    s = run_sweep("toy", {"x": [1.0]}, out="rel", client=toy, progress=False)
    assert Path(s["table"]) == tmp_path / "rel" / "table.parquet"
    assert len(list((tmp_path / "rel" / "points").glob("*/summary.json"))) == 1
    assert not (tmp_path / "s").exists()


def test_no_scheduler_or_one_without_workers_is_an_error_before_anything_is_written(tmp_path, monkeypatch):
    import socket

    from distributed import LocalCluster

    from workbench import config

    monkeypatch.setitem(cli.EXPERIMENTS, "toy", "sweep_toy")
    with socket.socket() as sock:  # a port nothing listens on
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    out = tmp_path / "sw"
    # refused at once (a TCP probe), not after the client's whole wait (30 s by default)
    t0 = time.perf_counter()
    with pytest.raises(SweepError, match=f"no Dask scheduler at 'tcp://127.0.0.1:{port}': .* refused"):
        run_sweep("toy", {"x": [1.0]}, scheduler=f"tcp://127.0.0.1:{port}", out=out, progress=False)
    assert time.perf_counter() - t0 < 5
    for bad in ("tcp://127.0.0.1:99999", "tcp://127.0.0.1:0", "127.0.0.1:x"):
        with pytest.raises(SweepError, match="is not a TCP port"):
            run_sweep("toy", {"x": [1.0]}, scheduler=bad, out=out, progress=False)
    with config.override(scheduler_wait_s=2.0):
        with pytest.raises(SweepError, match="--scheduler 'nonsense' is not a Dask scheduler address"):
            run_sweep("toy", {"x": [1.0]}, scheduler="nonsense", out=out, progress=False)
        with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as empty:
            with pytest.raises(SweepError, match="has no workers after 2 s; start some with `dask worker"):
                run_sweep("toy", {"x": [1.0]}, scheduler=empty.scheduler_address, out=out, progress=False)
    assert not out.exists()


def test_cli_plot_key_is_checked_first_and_an_interrupt_says_how_to_resume(tmp_path, capsys, monkeypatch):
    out = tmp_path / "sw"
    with pytest.raises(SystemExit) as exc:
        cli.main(
            ["sweep", "discretization", *TINY, "--grid", "mu=[0.5]", "--out", str(out), "--plot", "nu", "y"]
        )
    assert (
        exc.value.code == 2
        and "'nu' is not a swept key; plot against one of ['mu']" in capsys.readouterr().err
    )
    assert not out.exists()

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("workbench.runner.sweep.run_sweep", interrupted)
    with pytest.raises(SystemExit) as exc:
        cli.main(["sweep", "discretization", *TINY, "--grid", "mu=[0.5]", "--out", str(out)])
    assert exc.value.code == 130 and "re-run the same command to resume" in capsys.readouterr().err


def _rows(path: Path) -> list[str]:
    return [json.loads(line)["key"] for line in path.read_text().splitlines() if line.strip()]


@pytest.mark.slow
@pytest.mark.jit_only("over 15 s as pure Python")
def test_killed_driver_resumes_with_every_point_exactly_once(tmp_path):
    out = tmp_path / "sw"
    cmd = [
        str(BIN / "workbench"),
        "sweep",
        "discretization",
        *TINY,
        "--grid",
        "mu=[0.5,1.0,1.5,2.0]",
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ckpt = out / "points.jsonl"
    t0 = time.time()
    while time.time() - t0 < 240 and not (ckpt.exists() and _rows(ckpt)):
        time.sleep(0.2)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    n_before = len(_rows(ckpt))
    assert 1 <= n_before < 4
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-2000:]
    assert f"{n_before} resumed, {4 - n_before} run" in res.stdout
    keys = _rows(ckpt)
    assert len(keys) == 4 and len(set(keys)) == 4
    df = pd.read_parquet(out / "table.parquet")
    assert sorted(df["mu"]) == [0.5, 1.0, 1.5, 2.0] and (df["status"] == "ok").all()
    again = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert "4 resumed, 0 run" in again.stdout


@pytest.mark.jit_only("over 15 s as pure Python")
def test_a_worker_killed_mid_task_is_retried_and_the_sweep_completes(tmp_path):
    from distributed import Client, LocalCluster

    with (
        LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster,
        Client(cluster) as c,
    ):
        pids = c.run(os.getpid)
        killed = []

        def kill_one_busy_worker():
            t0 = time.time()
            while time.time() - t0 < 120:
                busy = [w for w, tasks in c.processing().items() if tasks]
                if busy:
                    time.sleep(1.0)  # mid-task
                    os.kill(pids[busy[0]], signal.SIGKILL)
                    killed.append(busy[0])
                    return
                time.sleep(0.05)

        th = threading.Thread(target=kill_one_busy_worker)
        th.start()
        s = run_sweep(
            "discretization",
            {"mu": [0.5, 1.0, 1.5]},
            quick=True,
            sets=TINY_SETS,
            out=tmp_path / "sw",
            client=c,
            progress=False,
        )
        th.join()
    assert killed
    assert (s["n_points"], s["n_ok"], s["n_failed"]) == (3, 3, 0)
    assert len(pd.read_parquet(tmp_path / "sw" / "table.parquet")) == 3


@pytest.mark.slow
@pytest.mark.jit_only("over 15 s as pure Python")
def test_sweep_on_a_separate_process_scheduler_and_two_workers(tmp_path):
    sched_file = tmp_path / "scheduler.json"
    env = {**os.environ, "NUMBA_NUM_THREADS": "1", "TQDM_DISABLE": "1"}
    procs = [
        subprocess.Popen(
            [
                str(BIN / "dask"),
                "scheduler",
                "--scheduler-file",
                str(sched_file),
                "--no-dashboard",
                "--port",
                "0",
            ],
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        t0 = time.time()
        while not sched_file.exists() and time.time() - t0 < 60:
            time.sleep(0.2)
        address = json.loads(sched_file.read_text())["address"]
        # the workers run in another directory than the driver, as on a real cluster: the
        # driver's relative --out must still be where the points' outputs land
        driver_dir, worker_dir = tmp_path / "driver", tmp_path / "workers"
        driver_dir.mkdir()
        worker_dir.mkdir()
        for _ in range(2):
            procs.append(
                subprocess.Popen(
                    [str(BIN / "dask"), "worker", address, "--nthreads", "1", "--no-dashboard"],
                    cwd=worker_dir,
                    env=env,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
            )
        from distributed import Client

        with Client(address) as c:
            c.wait_for_workers(2, timeout=60)
            assert len(set(c.run(os.getpid).values()) - {os.getpid()}) == 2  # two processes, not this one
        out = driver_dir / "sw"
        res = subprocess.run(
            [
                str(BIN / "workbench"),
                "sweep",
                "discretization",
                *TINY,
                "--grid",
                "mu=[0.5,1.0]",
                "--scheduler",
                address,
                "--out",
                "sw",
            ],
            cwd=driver_dir,
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert res.returncode == 0, res.stderr[-2000:]
        assert "2 points (2 ok, 0 failed; 0 resumed, 2 run)" in res.stdout
        df = pd.read_parquet(out / "table.parquet")
        assert sorted(df["mu"]) == [0.5, 1.0] and df["error_rate.S1.25"].notna().all()
        assert all((out / "points" / k / "summary.json").is_file() for k in df["point"])
        assert not any(worker_dir.iterdir())  # nothing written in the workers' directory
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def test_other_fixed_settings_get_their_own_points_and_one_sweep_runs_at_a_time(tmp_path, toy):
    """The same swept value under another --set used to share (and overwrite) one point
    folder, each run recomputing the other's; two sweeps into one directory ran every point
    twice into the same folders."""
    from contextlib import ExitStack

    from workbench.runner.sweep import _lock

    out = tmp_path / "sw"
    a = run_sweep("toy", {"x": [1.0]}, sets={"fail_above": 10.0}, out=out, client=toy, progress=False)
    b = run_sweep("toy", {"x": [1.0]}, sets={"fail_above": 100.0}, out=out, client=toy, progress=False)
    a2 = run_sweep("toy", {"x": [1.0]}, sets={"fail_above": 10.0}, out=out, client=toy, progress=False)
    assert (a["n_submitted"], b["n_submitted"], a2["n_submitted"]) == (1, 1, 0)
    assert len(list((out / "points").iterdir())) == 2
    with ExitStack() as stack:  # a sweep holding the directory
        _lock(out, stack)
        with pytest.raises(SweepError, match="another sweep is running in .*give another --out"):
            run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
        # refused before a cluster is started (that takes seconds on two busy cores)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr("workbench.runner.sweep._client", lambda *a: pytest.fail("a cluster was started"))
            with pytest.raises(SweepError, match="another sweep is running"):
                run_sweep("toy", {"x": [1.0, 2.0]}, out=out, workers=1, progress=False)
    assert run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)["n_submitted"] == 1
    (tmp_path / "afile").write_text("x")
    with pytest.raises(SweepError, match="cannot be made: .*afile is not a writable directory"):
        run_sweep("toy", {"x": [1.0]}, out=tmp_path / "afile" / "sub", client=toy, progress=False)
    with pytest.raises(SweepError, match="--out is empty"):
        run_sweep("toy", {"x": [1.0]}, out="", client=toy, progress=False)


def test_a_sweep_whose_first_points_all_fail_stops_and_says_why(tmp_path, toy):
    from workbench import config

    out = tmp_path / "sw"
    # each point sleeps, so that points are still pending when the third failure is counted: with
    # instant points a slow driver (the no-JIT CI run) could see all 20 finish in one batch, and a
    # sweep with nothing left to cancel completes (as the re-run below does)
    with config.override(sweep_stop_after_failures=3):
        with pytest.raises(SweepError, match="the first 3 points all failed.*last error: ValueError: x = "):
            run_sweep(
                "toy",
                {"x": [float(x) for x in range(20, 40)]},
                sets={"sleep": 0.25},
                out=out,
                client=toy,
                progress=False,
            )
    status = json.loads((out / "sweep.json").read_text())
    assert status["status"] == "stopped" and 3 <= status["n_failed"] < 20
    # a re-run whose points all fail again, with none left to run after them, completes
    with config.override(sweep_stop_after_failures=3):
        s = run_sweep("toy", {"x": [20.0, 21.0, 22.0]}, out=tmp_path / "three", client=toy, progress=False)
    assert s["status"] == "complete" and s["n_failed"] == 3
    assert len(pd.read_parquet(out / "table.parquet")) == status["n_failed"]
    # failures among successes do not stop a sweep, and the summary names them
    s = run_sweep("toy", {"x": [1.0, 30.0, 2.0]}, out=tmp_path / "mixed", client=toy, progress=False)
    assert s["status"] == "complete" and s["n_failed"] == 1
    assert s["failed"][0]["error"] == "ValueError: x = 30.0 is above fail_above = 10.0"


def test_a_point_whose_outputs_were_deleted_runs_again(tmp_path, toy):
    import shutil

    out = tmp_path / "sw"
    run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
    shutil.rmtree(next((out / "points").iterdir()))
    s = run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False)
    assert (s["n_resumed"], s["n_submitted"]) == (1, 1)
    assert len(list((out / "points").glob("*/summary.json"))) == 2


def test_table_columns_of_the_sweep_itself_are_plot_metrics(tmp_path, toy):
    out = tmp_path / "sw"
    assert run_sweep("toy", {"x": [1.0]}, out=out, client=toy, progress=False, metrics=["seconds", "y"])
    with pytest.raises(SweepError, match="'status' is not a number"):
        run_sweep("toy", {"x": [1.0]}, out=out, client=toy, progress=False, metrics=["status"])


def test_scheduler_host_port_reads_tcp_addresses_only():
    from workbench.runner.sweep import scheduler_host_port

    assert scheduler_host_port("tcp://10.0.0.5:8786") == ("10.0.0.5", 8786)
    assert scheduler_host_port("10.0.0.5:8786") == ("10.0.0.5", 8786)
    assert scheduler_host_port("tls://[::1]:8786/") == ("::1", 8786)
    assert scheduler_host_port("inproc://10.0.0.5/1/2") is None and scheduler_host_port("nonsense") is None
    with pytest.raises(SweepError, match="port '65536' is not a TCP port"):
        scheduler_host_port("tcp://h:65536")


def test_null_summary_values_are_nan_columns_and_the_experiment_is_a_column(tmp_path, toy):
    """A null summary value (an undefined recall) had no column, so --plot called it "not a
    column"; the experiment name was left out though flatten_scalars' docstring includes strings."""
    from workbench.runner.sweep import plot_sweep

    out = tmp_path / "sw"
    run_sweep("toy", {"x": [1.0, 2.0]}, out=out, client=toy, progress=False, metrics=["undefined"])
    df = pd.read_parquet(out / "table.parquet")
    assert df["undefined"].dtype == float and df["undefined"].isna().all()
    assert (df["experiment"] == "toy").all()
    assert plot_sweep(out / "table.parquet", "x", "undefined").is_file()


def test_keys_zipped_with_the_x_key_do_not_split_the_plot_into_lines(tmp_path, toy, monkeypatch):
    """--plot n_wrenches ... with n_wrenches and n_heldout zipped drew one dot per line."""
    from workbench.runner import results
    from workbench.runner.sweep import line_keys, plot_sweep

    assert line_keys(["E", "n", "h"], "n", "y", ["n", "h"]) == ["E"]  # h varies along the line
    assert line_keys(["E", "n", "h"], "E", "y", ["n", "h"]) == ["n", "h"]  # one line per zip pair
    assert line_keys(["E", "n"], "E", "y", []) == ["n"]
    out = tmp_path / "sw"
    zipped = {"x": [1.0, 2.0, 3.0], "fail_above": [11.0, 12.0, 13.0]}
    run_sweep("toy", {"tag": ["p", "q"]}, zipped, out=out, client=toy, progress=False)
    figs = []
    real = results.save_figure
    monkeypatch.setattr(results, "save_figure", lambda fig, path: figs.append(fig) or real(fig, path))
    plot_sweep(out / "table.parquet", "x", "y")  # the zip keys read from sweep.json
    lines = figs[-1].axes[0].get_lines()
    assert len(lines) == 2 and all(len(line.get_xdata()) == 3 for line in lines)
    plot_sweep(out / "table.parquet", "tag", "y", zipped=["x", "fail_above"])
    assert len(figs[-1].axes[0].get_lines()) == 3  # one line per zipped pair


def test_cluster_keys_of_an_experiment_are_refused_in_a_sweep(tmp_path):
    """sensitivity's own workers/scheduler were accepted in --grid and silently ignored (a
    point runs serially in one task of the sweep's cluster)."""
    for args in (["--grid", "workers=[1,2]"], ["--zip", 'scheduler=["a","b"]'], ["--set", "workers=2"]):
        with pytest.raises(SweepError, match=r"\['(workers|scheduler)'\] in .* --workers N or --scheduler"):
            run_sweep(
                "sensitivity",
                *_grid_and_zip(args),
                quick=True,
                sets=cli._parse_sets(args[1:]) if args[0] == "--set" else None,
                out=tmp_path / "sw",
                progress=False,
            )
    assert not (tmp_path / "sw").exists()


def _grid_and_zip(args: list[str]) -> tuple[dict, dict]:
    grid = cli._parse_lists(args[1:], "--grid") if args[0] == "--grid" else {"mu": [0.3]}
    zipped = cli._parse_lists(args[1:], "--zip") if args[0] == "--zip" else {}
    return grid, zipped


def test_sweep_values_that_fail_in_the_run_are_refused_before_any_work(tmp_path):
    for grid, match in (
        ({"n_elements": [0, 1]}, "n_elements must be >= 2"),
        ({"models": [["6dls", "bogus"]]}, r"models must be one of \['point'.*'bogus' not"),
        ({"mu": [0, 0.3]}, "mu = 0 is a frictionless grasp"),
    ):
        with pytest.raises(SweepError, match=match):
            run_sweep("sensitivity", grid, quick=True, out=tmp_path / "sw", progress=False)
    with pytest.raises(SweepError, match="--seed -1: seed expects int") as exc:
        run_sweep("sensitivity", {"mu": [0.3]}, quick=True, seed=-1, out=tmp_path / "sw", progress=False)
    assert "thickness" not in str(exc.value)  # the note on sizes refused at 0 is not a seed's
    assert not (tmp_path / "sw").exists()


def test_a_list_valued_key_swept_by_scalars_says_to_give_a_list_of_lists(tmp_path):
    import shlex

    with pytest.raises(SweepError) as exc:
        run_sweep("sensitivity", {"force_range": [25, 40]}, quick=True, out=tmp_path / "sw", progress=False)
    msg = str(exc.value)
    assert "force_range takes a list" in msg and "list of lists" in msg, msg
    # the hint, pasted back, is a valid sweep of the values given (not of the default, 20-35)
    flag, item = shlex.split(msg.split("e.g. ")[-1])
    assert flag == "--grid" and cli._parse_lists([item], "--grid") == {"force_range": [[25, 40]]}
    with pytest.raises(SweepError, match="so --zip sweeps it by a list of lists"):
        run_sweep(
            "sensitivity", {}, {"force_range": [20, 35]}, quick=True, out=tmp_path / "s", progress=False
        )


def test_a_bad_plot_metric_gets_close_names_not_every_column(tmp_path, toy):
    from workbench.runner.sweep import close_columns, column_hint

    columns = [f"table.m{i}.recall" for i in range(200)] + ["table.6dls.precision"]
    hint = column_hint("table.6dls.precison", columns)
    assert hint.startswith("did you mean ['table.6dls.precision'") and "201 number columns in all" in hint
    assert "table.m150.recall" not in hint and len(hint) < 400
    close = close_columns("recall", columns, 3)  # a last part finds the dotted paths ending in it
    assert len(close) == 3 and all(c.endswith(".recall") for c in close)
    with pytest.raises(SweepError, match=r"'nested.zz' is not a column .* did you mean \['nested.z'"):
        run_sweep("toy", {"x": [1.0]}, out=tmp_path / "sw", client=toy, progress=False, metrics=["nested.zz"])


def test_points_of_other_code_are_re_run_with_a_reason_and_kept_as_history(tmp_path, toy, monkeypatch):
    """A re-run after a code change re-ran every point saying only "0 resumed, 3 run", and
    dropped the old rows from points.jsonl (documented as keeping every point ever finished);
    an earlier --plot's figure stayed beside the new table; the lock file stayed behind."""
    from workbench.runner import results

    out = tmp_path / "sw"
    first = run_sweep("toy", {"x": [1.0, 2.0, 3.0]}, out=out, client=toy, progress=False)
    assert first["n_other_code"] == 0 and not (out / ".sweep.lock").exists()
    (out / "plot_x_y.png").write_bytes(b"stale")
    monkeypatch.setattr(results, "code_hash", lambda n=16: "another-code"[:n])
    again = run_sweep("toy", {"x": [1.0, 2.0, 3.0]}, out=out, client=toy, progress=False)
    assert (again["n_resumed"], again["n_submitted"], again["n_other_code"]) == (0, 3, 3)
    assert again["other_code_revisions"] == [first["git_revision"]]
    assert len(_rows(out / "points.jsonl")) == 6  # the old code's rows kept as history
    assert len(pd.read_parquet(out / "table.parquet")) == 3
    assert not (out / "plot_x_y.png").exists() and not (out / ".sweep.lock").exists()
    third = run_sweep("toy", {"x": [1.0, 2.0, 3.0]}, out=out, client=toy, progress=False)
    assert (third["n_resumed"], third["n_other_code"]) == (3, 0)


def test_cli_says_why_points_ran_again(tmp_path, capsys, monkeypatch):
    summary = {
        "n_points": 3,
        "n_ok": 3,
        "n_failed": 0,
        "n_resumed": 0,
        "n_submitted": 3,
        "n_other_code": 3,
        "other_code_revisions": ["abc123"],
        "seconds": 1.0,
        "table": str(tmp_path / "table.parquet"),
        "failed": [],
    }
    monkeypatch.setattr("workbench.runner.sweep.run_sweep", lambda *a, **k: summary)
    assert cli.main(["sweep", "discretization", "--grid", "mu=[0.5]", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "0 resumed, 3 run" in text and "3 points were computed by other code (revisions abc123" in text


def test_a_point_runs_under_the_drivers_settings_and_restores_the_workers(tmp_path, monkeypatch):
    # configure() on the driver used to stay there: points ran on workers at the defaults
    from workbench import config
    from workbench.runner.sweep import run_point

    (tmp_path / "settings_toy.py").write_text(
        "from workbench import config\n\ndef run(c):\n    return {'rtol': config.TOL.resist_rtol}\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    before = config.TOL.resist_rtol
    settings = {"resist_rtol": before / 7}
    res = run_point("x", {"out": str(tmp_path / "o")}, module="settings_toy", settings=settings)
    assert res["status"] == "ok" and res["summary"]["rtol"] == before / 7
    assert config.TOL.resist_rtol == before


def test_a_sweep_whose_cluster_loses_every_worker_stops_and_keeps_its_points(tmp_path, toy):
    from workbench import config

    out = tmp_path / "sw"
    with config.override(cluster_no_worker_s=1.0):
        with pytest.raises(RuntimeError, match=r"no worker for \d+ s while \d+ task\(s\) wait"):
            run_sweep(
                "toy",
                {"x": [float(x) for x in range(1, 9)]},
                sets={"sleep": 0.3},
                out=out,
                client=toy,
                progress=False,
                # the cluster scales to no worker after the first point (without the check the
                # sweep waits forever)
                on_point=lambda key, row: toy.cluster.scale(0),
            )
    kept = pd.read_parquet(out / "table.parquet")
    assert 1 <= len(kept) < 8 and (kept["status"] == "ok").all()
