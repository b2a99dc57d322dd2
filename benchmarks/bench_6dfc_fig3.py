"""The 6DFC paper's runtime figures, Fig. 3(c) and (d), on one contact of ours.

* ``fig_3c``: the sampling algorithms by number of wrenches K — the 6DFC paper's sampler
  (§IV-C.1: k1 = K/2 pure rotations about random axes through random centres, k2 = K/2 pure
  translations; :func:`workbench.twists.sample_twists_6dfc`) against the 6DLS paper's ([43] of
  the 6DFC paper, the thesis's §3.3.2: K/2 screw motions about Fibonacci-sphere axes with random
  centres and pitches, and the K/2 translations along them;
  :func:`workbench.twists.sample_twists_thesis`), each with its K frictional wrenches
  (:func:`workbench.wrench.frictional_wrenches`) — the median of ``runs`` runs per K (the paper:
  1,000), and the gain 1 − t(6DFC) / t(6DLS) (the paper: "up to 30 % faster").
* ``fig_3d``: REACH against 6DFC on the same surface patch meshed with m triangles — per grasp,
  the contact model built from the profiles (REACH: a point contact with a friction cone per
  triangle, unclustered; 6DFC: the limit surface fitted afresh, no cache) and the wrench
  resistance solved, median over ``grasps`` disturbances; the ratio REACH / 6DFC per m (the
  paper: "85x faster when analyzing the same number of triangles as REACH").

The contact is the elliptic-cylinder scene of Tables 4.2/4.3's benchmark (a = 30, b = 20 mm,
half angle 0.6 rad, 30 mm long, power law k = 2.4, 25 N a jaw).  Writes
results/benchmarks/fig3_6dfc.json with the machine's measured FMA throughput.
Run: python benchmarks/bench_6dfc_fig3.py [--quick]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from bench_wrench import machine_roofline  # the sibling benchmark's roofline

from workbench import frictional_wrenches, sample_twists_6dfc, sample_twists_thesis
from workbench.grasp import resists
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.tasks import lever_disturbances
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.results import versions, write_json
from workbench.sources.scenes import elliptic_cylinder_grasp

ROOT = Path(__file__).resolve().parents[1]
MU = 0.3


def sampler_times(profile, ks: list[int], runs: int, seed: int = 0) -> dict:
    """Median ms of twists + wrenches per K for both samplers, and the 6DFC gain per K."""
    ls = profile.length_scale
    rng = np.random.default_rng(seed)
    samplers = {
        "6dfc": lambda k: sample_twists_6dfc(k // 2, k - k // 2, ls, rng),
        "6dls": lambda k: sample_twists_thesis(k // 2, ls, rng),
    }
    ms: dict[str, list[float]] = {name: [] for name in samplers}
    for k in ks:
        for name, sample in samplers.items():
            frictional_wrenches(profile, sample(k), MU)  # warm-up
            times = []
            for _ in range(runs):
                t0 = time.perf_counter()
                frictional_wrenches(profile, sample(k), MU)
                times.append(time.perf_counter() - t0)
            ms[name].append(float(np.median(times) * 1e3))
    gain = [1.0 - a / b for a, b in zip(ms["6dfc"], ms["6dls"], strict=True)]
    return {"K": ks, "runs": runs, "ms": ms, "gain_6dfc": gain, "max_gain_6dfc": max(gain)}


def per_grasp_times(n_elements: list[int], grasps: int, seed: int = 1) -> dict:
    """Per m: the patch's actual triangle count and, per model, the median build and solve ms
    of one grasp (both jaws), the contact model built afresh for each grasp."""
    rng = np.random.default_rng(seed)
    W = lever_disturbances(rng, grasps)
    out: dict = {
        "n_triangles": [],
        "ms": {"reach": {"build": [], "solve": []}, "6dfc": {"build": [], "solve": []}},
    }
    for m in n_elements:
        profiles = elliptic_cylinder_grasp(force=25.0, n_elements=m)
        tri = len(profiles[0])
        out["n_triangles"].append(tri)
        params = {"reach": ModelParameters(reach_triangles=tri), "6dfc": ModelParameters()}
        for name, p in params.items():
            build, solve = [], []
            for i in range(grasps + 1):  # the first is a warm-up
                t0 = time.perf_counter()
                sets = [
                    c for prof in profiles for c in contact_sets(prof, name, p, cache=LimitSurfaceCache())
                ]
                t1 = time.perf_counter()
                resists(sets, W[i % grasps], MU)
                t2 = time.perf_counter()
                if i:
                    build.append(t1 - t0)
                    solve.append(t2 - t1)
            out["ms"][name]["build"].append(float(np.median(build) * 1e3))
            out["ms"][name]["solve"].append(float(np.median(solve) * 1e3))
    total = {n: [b + s for b, s in zip(v["build"], v["solve"], strict=True)] for n, v in out["ms"].items()}
    out["ms_total"] = total
    out["ratio_reach_over_6dfc"] = [r / f for r, f in zip(total["reach"], total["6dfc"], strict=True)]
    out["ratio_solve_only"] = [
        r / f for r, f in zip(out["ms"]["reach"]["solve"], out["ms"]["6dfc"]["solve"], strict=True)
    ]
    out["max_ratio"] = max(out["ratio_reach_over_6dfc"])
    out["grasps"] = grasps
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    # REACH's linear program grows with the triangles: the largest meshes are left to this flag
    parser.add_argument(
        "--triangles", default="16,64,256", help="element counts of the patch, comma-separated"
    )
    parser.add_argument(
        "--grasps", type=int, default=10, help="disturbances per mesh (each model built afresh)"
    )
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "fig3_6dfc.json"))
    args = parser.parse_args()
    profile = elliptic_cylinder_grasp(force=25.0)[0]
    ks = [100, 200, 500, 1000] if args.quick else [100, 200, 500, 1000, 2000]
    fig_3c = sampler_times(profile, ks, 20 if args.quick else 100)
    sizes = [int(x) for x in args.triangles.split(",")]
    fig_3d = per_grasp_times(sizes[:2] if args.quick else sizes, 3 if args.quick else args.grasps)
    out = {
        "setup": (
            f"elliptic-cylinder contact (a=30, b=20 mm, half angle 0.6 rad, length 30 mm, power law "
            f"k=2.4, 25 N), mu={MU}; Fig 3(c): twists + frictional wrenches, {len(profile)} triangles; "
            "Fig 3(d): both jaws, model built afresh per grasp (no cache), lever disturbances"
        ),
        "paper": {"fig_3c_gain": "up to 30%", "fig_3d_ratio": "85x on the same number of triangles"},
        "fig_3c": fig_3c,
        "fig_3d": fig_3d,
        "machine": machine_roofline(quick=True),
        "versions": versions(),
    }
    write_json(Path(args.out), out)
    print(f"wrote {args.out}")
    for k, a, b, g in zip(ks, fig_3c["ms"]["6dfc"], fig_3c["ms"]["6dls"], fig_3c["gain_6dfc"], strict=True):
        print(f"  K={k:>5}: 6dfc {a:.3f} ms, 6dls {b:.3f} ms, gain {100 * g:+.1f}%")
    for m, r, s in zip(
        fig_3d["n_triangles"], fig_3d["ratio_reach_over_6dfc"], fig_3d["ratio_solve_only"], strict=True
    ):
        print(f"  {m:>5} triangles: REACH / 6DFC {r:.1f}x per grasp (solve only {s:.1f}x)")


if __name__ == "__main__":
    main()
