"""What a grasp's contact patches cost on the thesis meshes: both jaws' REACH profiles of an
antipodal grasp (:func:`workbench.sources.reach.jaw_profiles`, what :func:`evaluate_grasp` pays
from a mesh), and the grasp dataset's settled contact (both pads pressed to the force, the object
turned until the torque balances, :func:`workbench.grasp.gripper_eval.gripper_contact`).

One process on one core (Numba's threads and BLAS limited to one), the fine surface of each mesh
made once before its grasps are timed (as a sampler or a dataset run leaves it), medians over each
mesh's grasps after a warm-up, then the median and the worst over the meshes.  Beside: the
profiles' elements, each mesh's fine sub-triangles, and this machine's measured FMA throughput and
copy bandwidth.  Without the data folder beside the checkout: an 80 × 50 × 20 mm box and a 30 mm
cylinder.

Writes results/benchmarks/contact_patch.json.  Run: python benchmarks/bench_contact_patch.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import trimesh
from bench_wrench import machine_roofline, on_one_core

from workbench.experiments.grasp_dataset import DEFAULT_CONFIG, _gripper
from workbench.grasp.gripper_eval import gripper_contact
from workbench.grasp.rest_pose import rest_on_table
from workbench.grasp.sampling import GraspSampling, antipodal_grasps
from workbench.grasp.top_grasps import sample_top_grasps
from workbench.plausible import ImplausibleWarning
from workbench.runner.results import CHECKOUT, code_revision, versions, write_json
from workbench.sources.reach import fine_surface, jaw_profiles

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "contact_patch.json"
OBJECTS = CHECKOUT.parent / "shared" / "data" / "thesis_objects"
TARGET_MS = 2.0  # issue: the contact patch on the thesis meshes


def _meshes(quick: bool) -> list[tuple[str, trimesh.Trimesh]]:
    files = sorted(OBJECTS.glob("*.obj")) if OBJECTS.is_dir() else []
    if not files:
        return [
            ("box 80 x 50 x 20 mm", trimesh.creation.box([0.08, 0.05, 0.02])),
            ("cylinder 30 x 100 mm", trimesh.creation.cylinder(radius=0.015, height=0.1, sections=64)),
        ]
    return [(f.name, trimesh.load(f, force="mesh")) for f in files[: 3 if quick else None]]


def _median_ms(fn, items) -> float:
    fn(items[0])  # warm-up: JIT and caches
    out = []
    for it in items[1:]:
        t0 = time.perf_counter()
        fn(it)
        out.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(out))


def _bandwidth_gbs() -> float:
    """Measured copy bandwidth [GB/s] (read + write) of a 64 MB array, best of five."""
    a = np.ones(8_000_000)
    b = np.empty_like(a)
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        np.copyto(b, a)
        best = min(best, time.perf_counter() - t0)
    return 2 * a.nbytes / best / 1e9


def run(quick: bool) -> dict:
    return on_one_core(_run, quick)


def _run(quick: bool) -> dict:
    n = 6 if quick else 21
    config = dict(DEFAULT_CONFIG)
    gripper = _gripper(config)
    gbs = _bandwidth_gbs()
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleWarning)
        for name, mesh in _meshes(quick):
            grasps = antipodal_grasps(
                mesh, n, 0.5, GraspSampling(max_width=0.1, max_samples=4000), seed=0, progress=False
            )
            cen = fine_surface(mesh, 1e-3)[0]
            reach_ms = _median_ms(lambda g, m=mesh: jaw_profiles(m, g, 20.0), grasps)
            n_elem = float(
                np.median([sum(len(p.areas) for p in jaw_profiles(mesh, g, 20.0)) for g in grasps])
            )
            rested = rest_on_table(mesh)[0]
            top = sample_top_grasps(
                rested, 6 if quick else 11, config["sampling_mu"], gripper, _spec(config), seed=0
            )
            settle_ms = (
                _median_ms(lambda p, m=rested: gripper_contact(m, gripper, p), [pose for _, pose in top])
                if len(top) > 1
                else None
            )
            rows.append(
                {
                    "mesh": name,
                    "fine_sub_triangles": len(cen),
                    "reach_ms_per_grasp": reach_ms,
                    "reach_profile_elements_per_grasp": n_elem,
                    "settled_ms_per_grasp": settle_ms,
                }
            )
            print(
                f"{name:45s} REACH {reach_ms:6.2f} ms  settled {settle_ms or float('nan'):7.1f} ms",
                flush=True,
            )
    reach = [r["reach_ms_per_grasp"] for r in rows]
    settled = [r["settled_ms_per_grasp"] for r in rows if r["settled_ms_per_grasp"] is not None]
    return {
        "what": "ms per grasp, both jaws, one process on one core, each mesh's fine surface made before its "
        "grasps: REACH profiles of antipodal grasps (jaw_profiles, 20 N) and the grasp dataset's settled "
        "contact (gripper_contact on top grasps of the mesh at rest); medians over each mesh's grasps",
        "target_ms": TARGET_MS,
        "reach_ms_median_over_meshes": float(np.median(reach)),
        "reach_ms_worst_mesh": float(np.max(reach)),
        "settled_ms_median_over_meshes": float(np.median(settled)) if settled else None,
        "settled_ms_worst_mesh": float(np.max(settled)) if settled else None,
        "meshes": rows,
        "machine": {**machine_roofline(quick=True), "copy_bandwidth_gbs_measured": gbs},
        "versions": versions(),
        "code_revision": code_revision(),
    }


def _spec(config: dict):
    from workbench.experiments.grasp_dataset import _spec as spec

    return spec(config)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="three meshes, five grasps each")
    ap.add_argument("--out", help="where to write (default results/benchmarks/contact_patch[_quick].json)")
    args = ap.parse_args(argv)
    res = run(args.quick)
    write_json(
        Path(args.out) if args.out else OUT.with_name(f"contact_patch{'_quick' * args.quick}.json"), res
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
