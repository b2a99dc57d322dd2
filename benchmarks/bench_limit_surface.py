"""Limit-surface fit and linearisation runtimes at K = 600 (medians over S1-S6 and repeats).

Writes results/benchmarks/limit_surface.json.  Run: python benchmarks/bench_limit_surface.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np
from bench_wrench import machine_roofline  # the sibling benchmark's FMA roofline

from workbench import (
    fit_ellipsoid,
    fit_quartic,
    frictional_wrenches,
    mesh_profile,
    sample_twists_thesis,
    w_max,
)
from workbench.runner.results import versions, write_json
from workbench.sources.surface_catalog import THESIS_SURFACES
from workbench.timing import median_runtime

ROOT = Path(__file__).resolve().parents[1]


def timed(fn, repeats: int) -> tuple[float, object]:
    return median_runtime(fn, repeats)  # warm-up covers JIT and the cvxpy problem build


def support_ratio(model, M: int, dirs: np.ndarray) -> float:
    """Mean over directions of h_outer(u) / h_inner(u) (support functions; LP for the outer)."""
    from scipy.optimize import linprog

    inner = model.linearize(M, "inner", seed=5).vertices
    outer = model.linearize(M, "outer", seed=5)
    ratios = []
    for u in dirs:
        res = linprog(-u, A_ub=outer.A, b_ub=outer.b, bounds=[(None, None)] * 6, method="highs")
        ratios.append(-res.fun / (inner @ u).max())
    return float(np.mean(ratios))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "limit_surface.json"))
    args = parser.parse_args()
    repeats = 2 if args.quick else 5
    K, M = 600, 1000
    rows: dict[str, list[float]] = {}
    errors: dict[str, list[float]] = {}
    t_start = time.perf_counter()
    for surface in THESIS_SURFACES.values():
        prof = mesh_profile(surface, 1500).normalized()
        xi = sample_twists_thesis(K // 2, prof, seed=1)
        W = frictional_wrenches(prof, xi)
        test = frictional_wrenches(prof, sample_twists_thesis(2500, prof, seed=2))
        wm = w_max(prof)
        cases = {
            "ellipsoid_lsq (numpy lstsq)": lambda W=W, wm=wm: fit_ellipsoid(W, "lsq", w_max=wm),
            "ellipsoid_sdp (CLARABEL)": lambda W=W, wm=wm: fit_ellipsoid(W, "sdp", w_max=wm),
            "ellipsoid_sdp (SCS)": lambda W=W, wm=wm: fit_ellipsoid(
                W, "sdp", w_max=wm, solver="SCS", warm_start=False
            ),
            "quartic (CLARABEL)": lambda W=W, wm=wm: fit_quartic(
                W, w_max=wm, solver="CLARABEL", fallback_solver=None
            ),
            "quartic+normals (CLARABEL)": lambda W=W, wm=wm, xi=xi: fit_quartic(
                W, twists=xi, w_max=wm, solver="CLARABEL", fallback_solver=None
            ),
            "quartic (IPM)": lambda W=W, wm=wm: fit_quartic(W, w_max=wm, solver="IPM", fallback_solver=None),
            "quartic+normals (IPM)": lambda W=W, wm=wm, xi=xi: fit_quartic(
                W, twists=xi, w_max=wm, solver="IPM", fallback_solver=None
            ),
            "quartic (SCS)": lambda W=W, wm=wm: fit_quartic(
                W, w_max=wm, solver="SCS", fallback_solver=None, warm_start=False
            ),
        }
        models = {}
        for label, fn in cases.items():
            t, model = timed(fn, repeats if "quartic" not in label else max(1, repeats // 2 + 1))
            rows.setdefault(label, []).append(t)
            errors.setdefault(label, []).append(model.fitting_error(test))
            models[label] = model
        for kind in ("inner", "outer"):
            for label in ("ellipsoid_lsq (numpy lstsq)", "quartic (CLARABEL)"):
                key = f"linearize {kind} M={M}: {label.split(' ')[0]}"
                t, _ = timed(lambda m=models[label], k=kind: m.linearize(M, k), 5 * repeats)
                rows.setdefault(key, []).append(t)
    # outer/inner gap vs M on S4 (mean support-function ratio over 40 random directions)
    gap = {}
    for label in ("ellipsoid_lsq (numpy lstsq)", "quartic (CLARABEL)"):
        model = models[label]
        dirs = np.random.default_rng(6).standard_normal((40, 6)) * model.scale
        gap[label.split(" ")[0]] = {
            str(M_): support_ratio(model, M_, dirs) for M_ in (50, 100, 200, 500, 1000, 2000)
        }
    med = {k: float(np.median(v)) for k, v in rows.items()}
    result = {
        "benchmark": "6D limit-surface fits at K = 600 and linearisation at M = 1,000",
        "machine": {
            **machine_roofline(quick=True),
            "cpu_count": os.cpu_count(),
            "loadavg_1_5_15": os.getloadavg(),
        },
        # the quartic fit by its own interior point against Clarabel, same process and data
        "quartic_clarabel_over_ipm": med["quartic (CLARABEL)"] / med["quartic (IPM)"],
        "quartic_normals_clarabel_over_ipm": med["quartic+normals (CLARABEL)"] / med["quartic+normals (IPM)"],
        "linearization_gap_support_ratio_S6": gap,
        "median_s": med,
        "per_surface_s": {k: dict(zip(THESIS_SURFACES, v, strict=True)) for k, v in rows.items()},
        "median_heldout_error": {k: float(np.median(v)) for k, v in errors.items()},
        "targets_s": {"ellipsoid_lsq": 1e-3, "ellipsoid_sdp": 0.05, "quartic": 0.5, "linearize_M1000": 1e-3},
        "notes": "cvxpy problems are built once per subspace dimension and re-solved with Parameters; "
        "SCS is timed cold (warm_start=False): repeats refit the same data, where a warm start "
        "would begin at the answer.",
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t_start,
    }
    write_json(Path(args.out), result)
    for k, v in result["median_s"].items():
        err = result["median_heldout_error"].get(k)
        print(f"{k:45s} {v * 1e3:9.3f} ms" + (f"   held-out error {err:.4f}" if err is not None else ""))


if __name__ == "__main__":
    main()
