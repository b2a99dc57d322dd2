"""What a user pays per grasp of the REACH YuMi trials, per contact model: the gripper at its 4×4
pose → the settled contact → the model built and solved (verdict and minimal force), nominal
and with N_r = 10 pose samples whose contacts are recomputed (6DFC §V-B.1).

End to end through :func:`workbench.grasp.gripper_eval.evaluate_gripper`, one process, one
model at a time with a fresh limit-surface cache (nothing shared between models or grasps but
the mesh's subdivision, which every user's second grasp has too), on every third grasp after a
warm-up grasp; median and worst over the grasps.  Beside: the thesis's and 6DFC's per-grasp
times (6DFC Table I: Point 13.0, REACH 207.1, MFE 247.9, 6DFC 251.6 ms, building the model
included; 12-core i7-8700K, MATLAB) and this machine's measured FMA throughput.

Writes results/benchmarks/physical_trials.json.  Run: python benchmarks/bench_physical_trials.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import trimesh
from bench_wrench import machine_roofline

from workbench.grasp.gripper_eval import evaluate_gripper
from workbench.grasp.inputs import GripperOptions, Task
from workbench.grasp.models import MODELS
from workbench.grasp.pose_robust import PoseNoise
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.results import code_revision, versions, write_json
from workbench.sources.gripper import yumi
from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "physical_trials.json"
PAPER_MS = {"point": 13.0, "reach": 207.1, "6dls": 247.9, "6dfc": 251.6}  # 6DFC Table I (MFE = 6dls)


def _time(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return (time.perf_counter() - t0) * 1e3


def run(quick: bool) -> dict:
    trials = read_trials(default_trials_path())
    mesh = trimesh.load(default_mesh_path(), force="mesh")
    g = yumi()
    grasps = trials.grasps()
    picked = sorted(grasps)[:: 6 if quick else 3]
    models = ("soft_point", "6dls", "6dfc") if quick else MODELS
    noise = PoseNoise(10, 0.003, 0.003)
    mass = trials.mass
    out = {}
    for m in models:

        def one(gr, robust, m=m):
            return evaluate_gripper(
                mesh,
                g,
                gr.pose,
                Task(mass=mass, down=gr.down),
                model=m,
                options=GripperOptions(robust=robust),
                cache=LimitSurfaceCache(),
            )

        one(grasps[picked[0]], noise)  # warm-up: the kernels' JIT or cache load, the mesh's subdivision
        nominal = [_time(lambda gr=grasps[i]: one(gr, None)) for i in picked]
        robust = [_time(lambda gr=grasps[i]: one(gr, noise)) for i in picked]
        split = one(grasps[picked[len(picked) // 2]], noise).timings_ms
        out[m] = {
            "nominal_ms": {"median": float(np.median(nominal)), "worst": float(np.max(nominal))},
            "n_robust_10_ms": {"median": float(np.median(robust)), "worst": float(np.max(robust))},
            "split_ms_one_grasp": split,
            "paper_6dfc_table_1_ms": PAPER_MS.get(m),
        }
        print(
            f"{m:15s} nominal {np.median(nominal):7.1f} ms   N_r=10 {np.median(robust):8.1f} ms", flush=True
        )
    return {
        "what": "ms per grasp, end to end: gripper pose -> settled contact -> model built and solved "
        "(verdict and minimal force); N_r = 10 recomputes the contact at 10 perturbed poses",
        "grasps": picked,
        "models": out,
        "machine": machine_roofline(quick=True),
        "versions": versions(),
        "code_revision": code_revision(),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="three models, every sixth grasp")
    args = ap.parse_args(argv)
    res = run(args.quick)
    write_json(OUT if not args.quick else OUT.with_name("physical_trials_quick.json"), res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
