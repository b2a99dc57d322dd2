"""Where one grasp's time goes, end to end, per contact model (issue: a grasp in <= 5 ms): a mesh
and an antipodal grasp -> both jaws' REACH patches -> the model's contact sets (twists, 6DFW,
fit, linearisation) -> the verdict (Eq. 2.100) -> the minimal force (Eq. 4.4) -> Eq. 2.101's q
over N_r = 10 perturbed samples (:func:`workbench.grasp.evaluate.evaluate_grasp`'s own stage
timings).

One process on one core (Numba's threads and BLAS limited to one: the issue's per-grasp targets
are one core's), one model at a time, each grasp with a fresh limit-surface cache (what a user
evaluating one grasp pays), medians over the grasps after a warm-up grasp, timed with no profiler
attached.  A second pass over the same grasps splits each model by cProfile into the library
functions it spends its time in.  Beside each model: the 6DFW element-twist pairs its grasps
evaluate (counted at the kernel's launch) and their time at the arithmetic limit of one core
(this machine's measured FMA and sqrt/divide rates, ``bench_wrench.machine_roofline`` on one
thread) — the bound of a contact model built from exact 6DFW samples.  The mesh: the
thesis bottle ``0014_bottle-gen_bottle_100x030x030-03.obj`` when the data folder is beside the
checkout (the issue's measurement), else an 80 × 50 × 20 mm box; 20 N a jaw, μ 0.3, 0.2 kg at the
filled object's centre.  Beside: this machine's measured FMA throughput.

Writes results/benchmarks/grasp_path.json.  Run: python benchmarks/bench_grasp_path.py [--quick]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import warnings
from pathlib import Path

import numpy as np
import trimesh
from bench_wrench import machine_roofline, on_one_core

from workbench import config
from workbench.grasp.evaluate import evaluate_grasp
from workbench.grasp.inputs import Jaws, ModelOptions, Task
from workbench.grasp.robust import Perturbation
from workbench.grasp.sampling import GraspSampling, antipodal_grasps
from workbench.limit_surface import LimitSurfaceCache
from workbench.plausible import ImplausibleWarning
from workbench.runner.results import CHECKOUT, code_revision, versions, write_json
from workbench.sources.reach import fine_surface

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "grasp_path.json"
BOTTLE = CHECKOUT.parent / "shared" / "data" / "thesis_objects" / "0014_bottle-gen_bottle_100x030x030-03.obj"
MODELS = ("soft_point", "planar", "6dls", "6dfc", "6dls_quartic")
STAGES = ("profiles", "contact_model", "resists", "min_grasp_force", "q_robust")
#: issue targets [ms], one core, mesh + grasp -> verdict and minimal force
#: (training sampler, cell [l_s]) of the 6DLS variants timed beside the default
TRAINING_VARIANTS = (("mix", 0.1), ("thesis", 0.15), ("thesis", 0.0))
TARGET_MS = {"soft_point": 1.0, "planar": 5.0, "6dls": 5.0, "6dfc": 5.0, "6dls_quartic": 20.0}


def _mesh() -> tuple[trimesh.Trimesh, str]:
    if BOTTLE.is_file():
        return trimesh.load(BOTTLE, force="mesh"), BOTTLE.name
    return trimesh.creation.box([0.08, 0.05, 0.02]), "box 80 x 50 x 20 mm"


def _functions(stats: pstats.Stats, n: int, top: int = 8) -> list[dict]:
    """The library functions with the most own time [ms a grasp], from a cProfile of ``n`` grasps."""
    rows = [
        (tt, f"{Path(fn).name}:{name}")
        for (fn, _, name), (_, _, tt, _, _) in stats.stats.items()  # type: ignore[attr-defined]
        if "workbench" in fn or "numpy" not in fn
    ]
    rows.sort(reverse=True)
    return [{"function": where, "ms_per_grasp": 1e3 * tt / n} for tt, where in rows[:top]]


class _PairCount:
    """Counts the element-twist pairs of the 6DFW kernel's launches (``workbench.wrench``)."""

    def __init__(self) -> None:
        import workbench.wrench as wrench

        self.module, self.launch, self.pairs = wrench, wrench.launch, 0

    def __enter__(self) -> _PairCount:
        def counted(kernel, work, *args):
            if kernel is self.module._kernels._fw_segments:
                self.pairs += work
            return self.launch(kernel, work, *args)

        self.module.launch = counted
        return self

    def __exit__(self, *exc) -> None:
        self.module.launch = self.launch


def run(quick: bool) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleWarning)
        return on_one_core(_run, quick)


def _run(quick: bool) -> dict:
    machine = machine_roofline(quick=True)  # one thread: the run's
    mesh, name = _mesh()
    n = 6 if quick else 20
    grasps = antipodal_grasps(
        mesh, n + 1, 0.5, GraspSampling(max_width=0.1, max_samples=4000), seed=0, progress=False
    )
    fine_surface(mesh, 1e-3)  # the mesh refined once, as the samplers leave it
    task = Task(mass=0.2, com=tuple(mesh.convex_hull.center_mass))
    jaws = Jaws(force=20.0)
    out: dict = {}

    def one(g, m: str, robust: bool = True):
        opts = ModelOptions(m, 0.3, min_force=True, robust=Perturbation(n_samples=10) if robust else None)
        return evaluate_grasp(mesh, g, task, jaws=jaws, options=opts, cache=LimitSurfaceCache())

    def timed(m: str) -> list[dict]:
        """Each grasp's stage timings [ms] of model ``m`` after a warm-up grasp."""
        one(grasps[0], m)
        return [one(g, m).timings_ms for g in grasps[1:]]

    def end_to_end(t: dict) -> float:
        return sum(t.get(s, 0.0) for s in STAGES[:4])

    def measure(m: str) -> dict:
        timings = timed(m)
        with _PairCount() as count:
            for g in grasps[1:]:
                one(g, m, robust=False)
        prof = cProfile.Profile()
        prof.enable()
        for g in grasps[1:]:
            one(g, m)
        prof.disable()
        stage = {s: float(np.median([t.get(s, 0.0) for t in timings])) for s in STAGES}
        nominal = [end_to_end(t) for t in timings]
        pairs = count.pairs / len(timings)
        bound_ms = pairs * machine["arith_limit_ns_per_pair"] * 1e-6
        print(
            f"{m:13s} end to end {np.median(nominal):7.1f} ms  6DFW bound {bound_ms:6.1f} ms  {stage}",
            flush=True,
        )
        return {
            "stage_ms_median": stage,
            "end_to_end_ms_median": float(np.median(nominal)),
            "with_q_robust_ms_median": float(np.median([sum(t.values()) for t in timings])),
            "target_ms": TARGET_MS[m],
            "fw_pairs_per_grasp": pairs,
            "fw_bound_ms": bound_ms,
            "contact_model_over_fw_bound": stage["contact_model"] / bound_ms if bound_ms else None,
            "top_functions": _functions(pstats.Stats(prof), len(timings)),
        }

    for m in MODELS:
        out[m] = measure(m)
    # the same models again in the reverse order: a model's time must not depend on what ran before
    for m in reversed(MODELS):
        again = float(np.median([end_to_end(t) for t in timed(m)]))
        out[m]["end_to_end_ms_median_reverse_order"] = again
        out[m]["reverse_over_forward"] = again / out[m]["end_to_end_ms_median"]
        print(f"{m:13s} in reverse order {again:7.1f} ms", flush=True)
    # the 6DLS trained on cheaper sets (config.DEFAULTS.ls_training_sampler / ls_training_cell_fraction):
    # what each costs in margin is results/benchmarks/training_sampler_margins.json
    variants = {}
    for kind, cell in TRAINING_VARIANTS:
        with config.override(ls_training_sampler=kind, ls_training_cell_fraction=cell):
            print(f"training {kind}, cell {cell:g} l_s:", flush=True)
            variants[f"{kind}@{cell:g}"] = {"ls_training_sampler": kind, "ls_training_cell_fraction": cell}
            variants[f"{kind}@{cell:g}"] |= measure("6dls")
    return {
        "what": "ms per grasp, one process on one core (Numba and BLAS on one thread), one model at a "
        "time with a fresh limit-surface cache: mesh + antipodal grasp -> REACH patches -> contact sets "
        "-> verdict -> minimal force (end_to_end), then Eq. 2.101's q over N_r = 10 rigid perturbed "
        "samples; medians after a warm-up, no profiler attached; end_to_end_ms_median_reverse_order: the "
        "models run again in the reverse order. fw_bound_ms: the grasp's 6DFW "
        "element-twist pairs (nominal contact, counted at the kernel's launch) at one core's "
        "arithmetic limit per pair (machine.arith_limit_ns_per_pair, measured on one thread). "
        "6dls_training_variants: the 6DLS again with its training wrenches from another sampler or a "
        "coarsened contact (kind@cell, cell in l_s)",
        "mesh": name,
        "n_grasps_timed": len(grasps) - 1,
        "models": out,
        "6dls_training_variants": variants,
        "machine": machine,
        "versions": versions(),
        "code_revision": code_revision(),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="five grasps")
    args = ap.parse_args(argv)
    res = run(args.quick)
    write_json(OUT if not args.quick else OUT.with_name("grasp_path_quick.json"), res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
