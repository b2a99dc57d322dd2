"""What one row of the grasp dataset (thesis §4.2.2) costs, per contact model: a top grasp's pose
→ both pads pressed on the mesh → the model built → its nominal verdict and Eq. 2.101's q over
N_r = 10 perturbed samples (:func:`workbench.grasp.dataset_rows.score_candidate`).

One process; each model alone with a fresh limit-surface cache (6DFC then fits its own 6DLS, as a
user scoring only 6DFC pays), and the four together (6DFC reusing 6DLS's fit, as the dataset
runs); every candidate after a warm-up candidate; median and worst.  The mesh: a thesis bottle
(``0014_bottle-gen_bottle_100x030x030-03.obj``) when the data folder is beside the checkout,
else an 80 × 50 × 20 mm box.  Beside: grasps per second per core, what the thesis's 500K grasps
cost at it, and this machine's measured FMA throughput.  ``on_dask``: the same rows (every model)
as Dask tasks on a local cluster of one worker per core (``workbench.runner.parallel.map_rows``,
the experiments' row loop, after one warm-up row a worker): the wall time, the rows' own compute,
the workers' utilisation, the per-task overhead it implies, and the 500K cost at that utilisation.

Writes results/benchmarks/grasp_dataset.json.  Run: python benchmarks/bench_grasp_dataset.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np
import trimesh
from bench_wrench import machine_roofline

from workbench.experiments.grasp_dataset import DEFAULT_CONFIG, _gripper, _row_ms, _spec
from workbench.grasp.dataset_rows import DatasetOptions, dataset_cost, score_candidate
from workbench.grasp.inputs import Task
from workbench.grasp.rest_pose import rest_on_table
from workbench.grasp.robust import Perturbation
from workbench.grasp.top_grasps import sample_top_grasps
from workbench.runner.parallel import map_rows, row_client
from workbench.runner.results import CHECKOUT, code_revision, versions, write_json

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "grasp_dataset.json"
BOTTLE = CHECKOUT.parent / "shared" / "data" / "thesis_objects" / "0014_bottle-gen_bottle_100x030x030-03.obj"
MODELS = ("soft_point", "planar", "6dls", "6dfc")


def _mesh() -> tuple[trimesh.Trimesh, str]:
    if BOTTLE.is_file():
        return rest_on_table(trimesh.load(BOTTLE, force="mesh"))[0], BOTTLE.name
    box = trimesh.creation.box([0.08, 0.05, 0.02])
    return rest_on_table(box)[0], "box 80 x 50 x 20 mm"


def _ms(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return (time.perf_counter() - t0) * 1e3


def _on_dask(row, poses: list, quick: bool) -> dict:
    """``row(pose)`` for every pose, repeated to fill the workers, as Dask tasks on a local cluster
    of one worker per core: wall [s], the rows' own compute (the experiment's ``_row_ms``: contact,
    every model's build and q), the workers' utilisation (compute / (workers × wall)), the per-task
    overhead it implies and the 500K cost at that utilisation."""
    jobs = list(poses[1:]) * (2 if quick else 4)
    done: list = []
    with row_client(len(jobs), workers=0, min_rows=1) as client:
        n_workers = len(client.scheduler_info()["workers"])
        map_rows(row, [poses[0]] * n_workers, lambda j, r: None, client=client)  # warm-up: JIT, fine surface
        t0 = time.perf_counter()
        map_rows(row, jobs, lambda j, r: done.append(r), client=client)
        wall = time.perf_counter() - t0
    compute_ms = np.array([_row_ms(r, MODELS) for r in done])
    util = float(compute_ms.sum() / 1e3 / (n_workers * wall))
    overhead_ms = (n_workers * wall * 1e3 - compute_ms.sum()) / len(jobs)
    print(
        f"on dask    {len(jobs)} rows, {n_workers} workers: {wall:.1f} s, utilisation {util:.2f}", flush=True
    )
    return {
        "workers": n_workers,
        "rows": len(jobs),
        "wall_s": wall,
        "row_compute_ms_mean": float(compute_ms.mean()),
        "utilisation": util,
        "overhead_ms_per_task": float(overhead_ms),
        "cost_500k_all_models": dataset_cost(float(compute_ms.mean()), 500_000, utilisation=min(util, 1.0)),
    }


def run(quick: bool) -> dict:
    config = dict(DEFAULT_CONFIG)
    mesh, name = _mesh()
    n = 6 if quick else 21
    top = sample_top_grasps(mesh, n, config["sampling_mu"], _gripper(config), _spec(config), seed=0)
    task = Task(mass=config["mass_kg"], com=tuple(mesh.convex_hull.center_mass))
    opts = DatasetOptions(
        mu=config["mu"], robust=Perturbation(n_samples=config["robust_samples"]), settle=config["settle"]
    )
    gripper = _gripper(config)
    poses = [pose for _, pose in top]

    def times(models) -> list[float]:
        score_candidate(mesh, gripper, poses[0], task, models, opts)  # warm-up: JIT, the fine surface
        return [_ms(lambda p=p: score_candidate(mesh, gripper, p, task, models, opts)) for p in poses[1:]]

    per_model = {}
    for m in MODELS:
        t = times((m,))
        per_model[m] = {
            "ms_median": float(np.median(t)),
            "ms_worst": float(np.max(t)),
            "grasps_per_s_per_core": 1e3 / float(np.median(t)),
        }
        print(f"{m:11s} {np.median(t):7.1f} ms a grasp alone", flush=True)
    together = times(MODELS)
    contact = [
        score_candidate(mesh, gripper, p, task, ("soft_point",), opts)["t_contact_ms"] for p in poses[1:]
    ]
    ms_all = float(np.median(together))
    print(f"all four   {ms_all:7.1f} ms a grasp (contact {np.median(contact):.1f} ms)", flush=True)
    dask = _on_dask(
        partial(score_candidate, mesh, gripper, task=task, models=MODELS, options=opts), poses, quick
    )
    return {
        "what": "ms per grasp, one process: top-grasp pose -> both pads pressed to the force, the object "
        "settled between them -> model "
        "built -> nominal verdict and Eq. 2.101's q over N_r = 10 samples; each model alone with a fresh "
        "cache, and the four together (6DFC reusing 6DLS's fit)",
        "mesh": name,
        "n_grasps_timed": len(poses) - 1,
        "contact_ms_median": float(np.median(contact)),
        "models_alone": per_model,
        "all_models": {"ms_median": ms_all, "grasps_per_s_per_core": 1e3 / ms_all},
        "cost_500k_all_models": dataset_cost(ms_all, 500_000),
        "on_dask": dask,
        "machine": machine_roofline(quick=True),
        "versions": versions(),
        "code_revision": code_revision(),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="five grasps")
    args = ap.parse_args(argv)
    res = run(args.quick)
    write_json(OUT if not args.quick else OUT.with_name("grasp_dataset_quick.json"), res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
