"""Sweeps and memory: wall-stiffness's memory model against its measurements, points
too large for a worker refused before they run, a point whose worker is restarted for memory
reported as such, finished points never computed twice after a worker dies, ``--plot``
metrics checked before any work, and plots with log axes and units.

This module is also the ``counted`` experiment of its tests (registered by monkeypatching
``EXPERIMENTS``; worker processes import it by name): every run leaves a marker file, so a
test counts how often each point really ran.
"""

from __future__ import annotations

import json
import os
import signal
import time
import uuid
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from workbench.runner import cli
from workbench.runner.results import write_summary
from workbench.runner.sweep import GiB, SweepError, run_sweep

ROOT = Path(__file__).resolve().parents[1]
MiB = 2**20

NAME = "counted"
DEFAULT_CONFIG = {"seed": 0, "x": 1.0, "sleep": 0.0, "alloc_mb": 0, "estimate_mb": 0.0, "log": ""}
QUICK_CONFIG: dict = {}


def run(config: dict) -> dict:
    """``y = x²``; a marker file per run in ``log``; ``alloc_mb`` MiB held (touched) for 30 s."""
    log = Path(config["log"])
    log.mkdir(parents=True, exist_ok=True)
    (log / f"{config['x']}_{os.getpid()}_{uuid.uuid4().hex}").touch()
    if config["alloc_mb"]:
        block = np.ones(config["alloc_mb"] * MiB // 8)  # resident: every page written
        time.sleep(30)  # the nanny restarts the worker long before
        del block
    time.sleep(config["sleep"])
    return write_summary(Path(config["out"]), NAME, config, {"y": config["x"] ** 2}, 0.0)


def memory_estimate(config: dict) -> int | None:
    """The ``estimate_mb`` a test gives (0: no estimate)."""
    return int(config["estimate_mb"] * MiB) or None


def _runs(log: Path, x: float) -> list[Path]:
    """The marker files of the runs of point ``x``."""
    return sorted(log.glob(f"{float(x)}_*"))


@pytest.fixture
def counted(monkeypatch):
    monkeypatch.setitem(cli.EXPERIMENTS, "counted", __name__)


# -- the model --------------------------------------------------------------------------------


def test_wall_stiffness_memory_estimate_reproduces_the_measured_peaks():
    """The library's constants are the benchmark's fit, each measured one-bottle peak lies
    within 10 % of the estimate (the model's stated accuracy: the fit's worst residual is 6 %),
    the two checks of how walls add up too, and [144, 72] — killed at an 11.8 GiB worker
    limit in the trial — needs more than the 95 % of that limit at which the nanny restarts."""
    from workbench.experiments import wall_stiffness as ws
    from workbench.runner.experiment_config import build_config

    data = json.loads((ROOT / "results" / "benchmarks" / "memory_model.json").read_text())
    fit = data["fit"]
    for k in ("base_bytes", "bytes_per_nnz", "nnz_coefficient", "nnz_exponent"):
        assert ws.MEMORY_MODEL[k] == pytest.approx(fit[k], rel=1e-3), k
    assert ws.MEMORY_MODEL["measured_on"] == data["measured_on"]
    for row in data["single_wall"] + data["checks"]:
        cfg = build_config("wall-stiffness", True, None, None, {"workers": 1, **row["sets"]})
        nt, nz = cfg["mesh"]
        assert row["free_dofs"] == 36 * nt * nz  # the dofs the model counts
        assert ws.memory_estimate(cfg) == pytest.approx(row["peak_rss_bytes"], rel=0.10), row["sets"]
    big = build_config("wall-stiffness", True, None, None, {"mesh": [144, 72]})
    assert ws.memory_estimate(big) > 0.95 * 11.8 * GiB
    # the default config keeps two bottles' factored walls alive; object= one wall
    full = build_config("wall-stiffness", False, None, None, {"mesh": [48, 24]})
    base = ws.MEMORY_MODEL["base_bytes"]

    def one_wall(mesh: list) -> float:
        return ws.memory_estimate({**full, "mesh": mesh, "bottles": [0], "convergence_meshes": []}) - base

    conv = max(one_wall(m) for m in full["convergence_meshes"])
    assert len(full["bottles"]) == 3 and full["convergence_meshes"][-1] == [64, 32]
    assert ws.memory_estimate(full) == pytest.approx(base + max(2 * one_wall([48, 24]), conv), abs=2)
    assert ws.memory_estimate({**full, "object": "a.obj"}) == pytest.approx(base + one_wall([48, 24]), abs=2)


def test_experiments_without_an_estimate_give_none_and_a_bad_estimator_is_ignored(counted, monkeypatch):
    import sys

    from workbench.runner.experiment_config import build_config
    from workbench.runner.sweep import memory_estimate as estimate

    assert estimate("sensitivity", build_config("sensitivity", True, None, None, {})) is None
    cfg = build_config("counted", False, None, None, {"estimate_mb": 3.0})
    assert estimate("counted", cfg) == 3 * MiB
    for bad in (lambda c: -1, lambda c: float("nan"), lambda c: "3 GiB", lambda c: 1 / 0):
        monkeypatch.setattr(sys.modules[__name__], "memory_estimate", bad)
        assert estimate("counted", cfg) is None


# -- refused before it runs -------------------------------------------------------------------


def test_a_point_above_the_worker_limit_is_refused_up_front_and_the_rest_run(tmp_path, counted):
    from distributed import Client, LocalCluster

    log = tmp_path / "log"
    out = tmp_path / "sw"
    sets = {"log": str(log)}
    grid = {"x": [1.0, 2.0, 3.0], "estimate_mb": [512.0, 14.5 * 1024]}
    with (
        LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, memory_limit="4GiB", dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        s = run_sweep("counted", grid, sets=sets, out=out, client=client, progress=False)
        again = run_sweep("counted", grid, sets=sets, out=out, client=client, progress=False)
    assert (s["n_points"], s["n_ok"], s["n_refused"], s["n_failed"], s["n_submitted"]) == (6, 3, 3, 0, 3)
    df = pd.read_parquet(out / "table.parquet")
    refused = df[df.status == "refused"].sort_values("x")
    assert refused["x"].tolist() == [1.0, 2.0, 3.0]
    assert (
        refused["error"]
        .iloc[1]
        .startswith("refused: needs ~14.5 GiB, worker limit 4.0 GiB (x=2.0, estimate_mb=14848.0)")
    )
    assert refused["memory_estimate_GiB"].tolist() == [14.5] * 3
    assert (df[df.status == "ok"]["memory_estimate_GiB"] == 0.5).all()
    for x in (1.0, 2.0, 3.0):  # every small point ran once; no large one ran at all
        assert len(_runs(log, x)) == 1
    assert len(list((out / "points").iterdir())) == 3
    # refused points are not checkpointed: judged again on every run (larger workers run them)
    assert (again["n_resumed"], again["n_submitted"], again["n_refused"]) == (3, 0, 3)


def test_a_sweep_of_points_all_too_large_starts_no_cluster_and_says_what_fits(tmp_path, counted, monkeypatch):
    from workbench.runner.parallel import local_memory_limit

    monkeypatch.setattr("workbench.runner.sweep._client", lambda *a: pytest.fail("a cluster was started"))
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    between = (0.95 * local_memory_limit(2) + 0.95 * local_memory_limit(1)) / 2 / MiB
    s = run_sweep(
        "counted",
        {"estimate_mb": [between, 2 * local_memory_limit(1) / MiB]},
        sets={"log": str(tmp_path / "log")},
        out=tmp_path / "sw",
        progress=False,
    )
    assert (s["n_refused"], s["n_submitted"]) == (2, 0)
    first, second = (r["error"] for r in s["refused"])
    limit = f"worker limit {local_memory_limit(2) / GiB:.1f} GiB"
    assert limit in first and "run it with --workers 1" in first
    assert "needs more than this machine's" in second
    assert not (tmp_path / "log").exists()


def test_local_workers_keep_their_share_when_points_are_refused(tmp_path, counted, monkeypatch):
    """Two points on two cores: each worker gets half the memory; the point too large for a
    half is refused, and the one worker started for the other keeps the half (its refusal
    does not depend on which others were refused)."""
    from distributed import Client, LocalCluster

    from workbench.runner.parallel import local_memory_limit

    started = []

    def client_of(n, scheduler, threads, limit):
        started.append((n, limit))
        cluster = LocalCluster(
            n_workers=n, threads_per_worker=1, processes=False, memory_limit=limit, dashboard_address=None
        )
        return Client(cluster), cluster

    monkeypatch.setattr("workbench.runner.sweep._client", client_of)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    big = 0.99 * local_memory_limit(2) / MiB  # over the 95 % of a half at which a worker restarts
    s = run_sweep(
        "counted",
        {},
        {"x": [1.0, 2.0], "estimate_mb": [1.0, big]},
        sets={"log": str(tmp_path / "log")},
        out=tmp_path / "sw",
        progress=False,
    )
    assert started == [(1, local_memory_limit(2))]
    assert (s["n_ok"], s["n_refused"]) == (1, 1)
    assert "run it with --workers 1" in s["refused"][0]["error"]


def test_cli_lists_refused_points_and_exits_nonzero(tmp_path, capsys, monkeypatch):
    summary = {
        "n_points": 2,
        "n_ok": 1,
        "n_failed": 0,
        "n_refused": 1,
        "refused": [
            {"point": "mesh=[144,72]-ab", "error": "refused: needs ~14.0 GiB, worker limit 11.8 GiB"}
        ],
        "n_resumed": 0,
        "n_submitted": 1,
        "n_other_code": 0,
        "other_code_revisions": [],
        "seconds": 1.0,
        "table": str(tmp_path / "table.parquet"),
        "failed": [],
    }
    monkeypatch.setattr("workbench.runner.sweep.run_sweep", lambda *a, **k: summary)
    assert cli.main(["sweep", "wall-stiffness", "--grid", "mesh=[[24,12]]", "--out", str(tmp_path)]) == 1
    text = capsys.readouterr().out
    assert "1 refused for memory" in text
    assert "mesh=[144,72]-ab: refused: needs ~14.0 GiB, worker limit 11.8 GiB" in text


@pytest.mark.jit_only("a wall-stiffness --quick point: minutes as pure Python")
def test_the_trial_sweep_refuses_the_large_mesh_and_runs_the_small_one(tmp_path):
    """The new-user trial: mesh=[144,72] on 11.8 GiB workers ran 4 times into the limit each."""
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, memory_limit="11.8GiB", dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        s = run_sweep(
            "wall-stiffness",
            {"mesh": [[24, 12], [144, 72]]},
            quick=True,
            out=tmp_path / "sw",
            client=client,
            progress=False,
        )
    assert (s["n_ok"], s["n_refused"]) == (1, 1)
    df = pd.read_parquet(tmp_path / "sw" / "table.parquet").set_index("mesh")
    assert df.loc["[144, 72]", "error"].startswith(
        "refused: needs ~14.0 GiB, worker limit 11.8 GiB (mesh=[144,72])"
    )
    ok = df.loc["[24, 12]"]
    assert ok["status"] == "ok" and ok["memory_estimate_GiB"] == pytest.approx(0.68, abs=0.01)
    # measured in the worker (this process, one thread): the estimate is within the model's 10 %
    # of the point's own peak — or below it, this process holding pytest's own memory besides
    assert ok["peak_rss_GiB"] > 0.9 * ok["memory_estimate_GiB"]


# -- killed for memory ------------------------------------------------------------------------


@pytest.mark.jit_only("worker processes importing the package: slow as pure Python")
def test_a_point_whose_worker_is_restarted_for_memory_is_reported_not_retried(tmp_path, counted):
    """A point over its worker's limit used to be killed 4 times and recorded as a bare
    KilledWorker; now the nanny's first restart names it, with the limit and the estimate."""
    from distributed import Client, LocalCluster

    log = tmp_path / "log"
    with (
        LocalCluster(
            n_workers=1, threads_per_worker=1, memory_limit="700MiB", dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        s = run_sweep(
            "counted",
            {},
            {"x": [1.0, 2.0], "alloc_mb": [0, 1500], "estimate_mb": [0.0, 300.0]},
            sets={"log": str(log)},
            out=tmp_path / "sw",
            client=client,
            progress=False,
        )
    assert (s["n_ok"], s["n_failed"]) == (1, 1)
    df = pd.read_parquet(tmp_path / "sw" / "table.parquet").set_index("x")
    bad = df.loc[2.0]
    assert bad["status"] == "killed"
    assert bad["error"].startswith("killed for memory: its worker exceeded 95% of its 0.7 GiB limit (RSS ")
    assert "estimate ~0.3 GiB (x=2.0, alloc_mb=1500, estimate_mb=300.0)" in bad["error"]
    assert bad["peak_rss_GiB"] > 0.95 * 700 / 1024  # the RSS the nanny saw
    assert len(_runs(log, 2.0)) == 1  # not retried on a worker of the same limit
    assert df.loc[1.0, "status"] == "ok" and len(_runs(log, 1.0)) == 1


# -- finished points are never computed twice -------------------------------------------------


def test_a_task_resubmitted_after_it_finished_returns_its_recorded_result(tmp_path, counted):
    """What Dask does when a worker holding a finished result dies, or what a re-run finds
    after a driver killed between a point's end and its checkpoint line."""
    from workbench.runner.experiment_config import build_config
    from workbench.runner.sweep import POINT_FILE, run_point

    log = tmp_path / "log"
    cfg = build_config("counted", False, str(tmp_path / "p"), None, {"x": 3.0, "log": str(log)})
    first = run_point("counted", cfg, token="t1")
    again = run_point("counted", cfg, token="t1")
    assert (first["reused"], again["reused"]) == (False, True)
    assert again["summary"]["y"] == first["summary"]["y"] == 9.0 and len(_runs(log, 3.0)) == 1
    other = run_point("counted", cfg, token="t2")  # another config or code: run again
    assert not other["reused"] and len(_runs(log, 3.0)) == 2
    (tmp_path / "p" / "summary.json").unlink()  # outputs gone: run again
    assert not run_point("counted", cfg, token="t2")["reused"] and len(_runs(log, 3.0)) == 3
    failed = build_config(
        "counted", False, str(tmp_path / "f"), None, {"x": 3.0, "log": str(tmp_path / "nodir")}
    )
    (tmp_path / "nodir").write_text("a file where the log directory goes: the run fails")
    assert run_point("counted", failed, token="t3")["status"] == "failed"
    assert json.loads((tmp_path / "f" / POINT_FILE).read_text())["status"] == "failed"
    assert run_point("counted", failed, token="t3")["reused"] is False  # failures are not reused


@pytest.mark.jit_only("worker processes importing the package: slow as pure Python")
def test_finished_points_run_exactly_once_when_a_worker_is_killed(tmp_path, counted):
    """A worker killed after some points finished used to make Dask recompute the points whose
    results it held (the driver kept every future until the end)."""
    from distributed import Client

    from workbench.runner.parallel import local_cluster, local_memory_limit
    from workbench.runner.sweep import worker_memory_limit

    log = tmp_path / "log"
    seen: list[str] = []
    finished_before_kill: list[float] = []
    killed: list[int] = []

    def kill_after_two(key: str, row: dict) -> None:
        seen.append(key)
        if len(seen) == 2 and not killed:
            x = row["values"]["x"]
            finished_before_kill.extend(r["values"]["x"] for r in rows(tmp_path / "sw"))
            pid = int(_runs(log, x)[0].name.split("_")[1])  # the worker that ran (and holds) it
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    with local_cluster(2) as cluster, Client(cluster) as client:
        assert worker_memory_limit(client) == local_memory_limit(2)
        s = run_sweep(
            "counted",
            {"x": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]},
            sets={"log": str(log), "sleep": 1.0},
            out=tmp_path / "sw",
            client=client,
            progress=False,
            on_point=kill_after_two,
        )
    assert killed and len(finished_before_kill) == 2
    assert (s["n_ok"], s["n_failed"]) == (6, 0)
    for x in finished_before_kill:
        assert len(_runs(log, x)) == 1, f"point x={x} ran {len(_runs(log, x))} times"
    # only a point running on the killed worker may have started twice
    assert sum(len(_runs(log, x)) for x in range(1, 7)) <= 7
    assert len(pd.read_parquet(tmp_path / "sw" / "table.parquet")) == 6


def rows(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "points.jsonl").read_text().splitlines() if line.strip()]


# -- --plot metrics checked before any work ---------------------------------------------------


def test_plot_metrics_are_checked_against_declared_columns_before_any_work(tmp_path, counted, monkeypatch):
    import sys

    monkeypatch.setattr(sys.modules[__name__], "summary_columns", lambda config: ["y"], raising=False)
    monkeypatch.setattr("workbench.runner.sweep._client", lambda *a: pytest.fail("a cluster was started"))
    with pytest.raises(
        SweepError,
        match=r"'yy' is not a column .*before any work against the columns counted declares.*mean \['y'",
    ):
        run_sweep("counted", {"x": [1.0]}, out=tmp_path / "sw", progress=False, metrics=["yy"])
    assert not (tmp_path / "sw").exists()


def test_plot_metrics_are_checked_against_an_earlier_sweep_before_any_work(tmp_path, counted):
    from distributed import Client

    from workbench.runner.sweep import _check_plot_metrics

    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        run_sweep(
            "counted",
            {"x": [1.0]},
            sets={"log": str(tmp_path / "log")},
            out=tmp_path / "a",
            client=client,
            progress=False,
        )
    with pytest.raises(
        SweepError,
        match=r"'yy' is not a column of counted's tables \(checked before any work against 1 earlier runs",
    ):
        run_sweep("counted", {"x": [2.0]}, out=tmp_path / "b", progress=False, metrics=["yy"])
    with pytest.raises(SweepError, match="'status' is not a number"):
        run_sweep("counted", {"x": [2.0]}, out=tmp_path / "b", progress=False, metrics=["status"])
    assert not (tmp_path / "b").exists()
    b = tmp_path / "b"
    configs = {"k": ({"x": 2.0}, {"x": 2.0})}
    # the sweep's own columns and the earlier table's pass; nothing left for the first point
    assert _check_plot_metrics("counted", ["y", "seconds", "memory_estimate_GiB"], [], configs, b) == []
    # with nothing to check against, the first finished point checks it
    assert _check_plot_metrics("counted", ["yy"], [], configs, tmp_path / "elsewhere" / "c") == ["yy"]


def test_earlier_columns_match_up_to_their_numeric_parts(tmp_path, counted):
    """An earlier run of other settings (bottle 0) vouches for maps.20.min, not for maps.20.mni."""
    from distributed import Client

    from workbench.runner import sweep

    assert sweep._shape("maps.20.min") == sweep._shape("maps.0.min") == "maps.#.min"
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        run_sweep(
            "counted",
            {"x": [1.0]},
            sets={"log": str(tmp_path / "log")},
            out=tmp_path / "a",
            client=client,
            progress=False,
        )
    table = pd.read_parquet(tmp_path / "a" / "table.parquet")
    table["maps.0.min"] = 1.0
    table.to_parquet(tmp_path / "a" / "table.parquet")
    configs = {"k": ({"x": 2.0}, {"x": 2.0})}
    assert sweep._check_plot_metrics("counted", ["maps.20.min"], [], configs, tmp_path / "b") == []
    with pytest.raises(SweepError, match=r"'maps.20.mni' is not a column .*did you mean"):
        sweep._check_plot_metrics("counted", ["maps.20.mni"], [], configs, tmp_path / "b")


# -- plots: log axes on geometric grids, units ------------------------------------------------


@pytest.mark.parametrize(
    ("values", "log"),
    [
        ([0.001, 0.01, 0.1], True),  # decades
        ([25, 50, 100], True),  # doubling
        ([10, 20, 50, 100], True),  # a 1-2-5 series
        ([1e-4, 1e-2], True),  # two values two decades apart
        ([1, 1.5, 2.25, 3.375, 5.0625, 7.59, 11.39], True),  # ratio 1.5 over more than a decade
        ([0.3, 0.5, 0.7], False),  # linear, short
        ([1, 2, 3, 4], False),  # arithmetic
        ([96, 144], False),  # one step of 1.5
        ([0, 1, 10, 100], False),  # zero
        ([-10, -1], False),
        ([5.0], False),
        (["a", "b"], False),
    ],
)
def test_geometric_grids(values, log):
    from workbench.runner.sweep import geometric

    assert geometric(values) is log


def test_units_come_from_the_names_or_the_experiments_units(counted, monkeypatch):
    import sys

    from workbench.runner.sweep import axis_label, unit_of

    assert unit_of("maps.0.stiffness_N_per_m") == "N/m"
    assert unit_of("closing_mm") == "mm" and unit_of("wall_time_s") == "s" and unit_of("seconds") == "s"
    assert unit_of("w_max_N.2") == "N" and unit_of("E_Pa") == "Pa" and unit_of("memory_estimate_GiB") == "GiB"
    assert unit_of("compliance_m_per_N") == "m/N" and unit_of("ms_per_grasp.median") is None
    assert unit_of("precision") is None and unit_of("n_angles") is None
    from workbench.runner.experiment_keys import Key

    keys = {"x": Key("a length", "m"), "thickness": Key("a wall", "m")}
    monkeypatch.setattr(sys.modules[__name__], "KEYS", keys, raising=False)
    assert axis_label("x", "counted") == "x [m]" and axis_label("x") == "x"
    assert axis_label("a.thickness", "counted") == "a.thickness [m]"
    assert axis_label("y", "counted") == "y"
    # a real experiment's keys: the unit its --help gives
    assert axis_label("E", "wall-stiffness") == "E [Pa]" and axis_label("jaw", "wall-stiffness") == "jaw [m]"


def test_plot_sweep_uses_log_axes_on_a_geometric_grid_and_labels_units(tmp_path, counted, monkeypatch):
    import sys

    from distributed import Client

    from workbench.runner import results
    from workbench.runner.experiment_keys import Key
    from workbench.runner.sweep import plot_sweep

    keys = {"x": Key("a length", "m"), "y": Key("an area", "m²")}
    monkeypatch.setattr(sys.modules[__name__], "KEYS", keys, raising=False)
    figs = []
    real = results.save_figure
    monkeypatch.setattr(results, "save_figure", lambda fig, path: figs.append(fig) or real(fig, path))
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        for name, xs in (("geo", [0.01, 0.1, 1.0, 10.0]), ("lin", [1.0, 2.0, 3.0])):
            run_sweep(
                "counted",
                {"x": xs},
                sets={"log": str(tmp_path / "log")},
                out=tmp_path / name,
                client=client,
                progress=False,
            )
    plot_sweep(tmp_path / "geo" / "table.parquet", "x", "y")
    ax = figs[-1].axes[0]
    assert (ax.get_xscale(), ax.get_yscale()) == ("log", "log")  # y = x² over 6 decades
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x [m]", "y [m²]")
    plot_sweep(tmp_path / "lin" / "table.parquet", "x", "seconds")
    ax = figs[-1].axes[0]
    assert (ax.get_xscale(), ax.get_yscale(), ax.get_ylabel()) == ("linear", "linear", "seconds [s]")


def test_list_valued_keys_are_plotted_in_the_order_of_their_values():
    from workbench.runner.sweep import _grid_order

    col = pd.Series(["[144, 72]", "[96, 48]", "[24, 12]"])
    assert col.sort_values(key=_grid_order).tolist() == ["[24, 12]", "[96, 48]", "[144, 72]"]
    mixed = pd.Series(['["S3"]', "[1, 2]", '["S1"]'])
    assert mixed.sort_values(key=_grid_order).tolist() == ["[1, 2]", '["S1"]', '["S3"]']


def test_a_single_run_that_cannot_fit_this_machine_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    """`workbench run` asks the same memory model as a sweep: a mesh the machine cannot hold
    is refused with the figure, before anything is built or written."""
    import psutil

    free = psutil.virtual_memory().available
    monkeypatch.setattr("workbench.runner.sweep.memory_estimate", lambda name, config: 2 * free)
    out = tmp_path / "run"
    with pytest.raises(SystemExit) as exc:
        cli.main(["run", "wall-stiffness", "--quick", "--out", str(out), "--set", "mesh=[144,72]"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert f"needs ~{2 * free / GiB:.1f} GiB" in err and "coarser mesh" in err
    assert not out.exists()
