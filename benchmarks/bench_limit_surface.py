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


def sdp_active_constraint(repeats: int, n_grasps: int = 20) -> dict:
    """The SDP ellipsoid where A ⪰ 0 is active: the training sets ("thesis" sampler, the default
    contact) of the REACH contacts of ``n_grasps`` antipodal grasps of the thesis bottle 0014 (a
    box where the data is absent) whose least-squares A is indefinite, fitted by the interior point
    and by Clarabel: median ms, each fit's Eq. 3.11 objective over the interior point's, Clarabel's
    fits that fell back to the projected least squares, and the median smallest eigenvalue."""
    import logging

    from bench_grasp_path import _mesh

    from workbench.grasp.sampling import GraspSampling, antipodal_grasps
    from workbench.limit_surface.cache import SamplerSpec
    from workbench.limit_surface.ellipsoid import _lsq
    from workbench.limit_surface.normalize import prepare
    from workbench.sources.reach import fine_surface, jaw_profiles

    mesh, name = _mesh()
    grasps = antipodal_grasps(
        mesh, n_grasps, 0.5, GraspSampling(max_width=0.1, max_samples=4000), seed=0, progress=False
    )
    fine_surface(mesh, 1e-3)
    spec = SamplerSpec(kind="thesis", cell_fraction=0.0)
    sets = []
    for g in grasps:
        for prof in jaw_profiles(mesh, g, 20.0):
            prof = prof.normalized()
            W, wm = spec.training(prof, 0.3)[1], w_max(prof, 0.3)
            _, _, _, x, sub = prepare(W, wm)
            if _lsq(x @ sub.basis)[1] is not None:  # indefinite: the constraint is active
                sets.append((W, wm))
    out: dict = {"mesh": name, "contacts": 2 * len(grasps), "active": len(sets)}
    fits: dict = {}
    level = logging.getLogger("workbench.limit_surface.ellipsoid").level
    logging.getLogger("workbench.limit_surface.ellipsoid").setLevel(logging.ERROR)  # counted below
    try:
        for solver in ("IPM", "CLARABEL"):
            t, m = zip(
                *(
                    timed(lambda W=W, wm=wm, s=solver: fit_ellipsoid(W, "sdp", w_max=wm, solver=s), repeats)
                    for W, wm in sets
                ),
                strict=True,
            )
            fits[solver] = m
            out[f"{solver}_ms_median"] = 1e3 * float(np.median(t))
    finally:
        logging.getLogger("workbench.limit_surface.ellipsoid").setLevel(level)

    def objective(model, W) -> float:
        f = model.value(W)
        return float(((f - 1.0) ** 2).sum())

    ratio = [
        objective(c, W) / objective(i, W)
        for (W, _), i, c in zip(sets, fits["IPM"], fits["CLARABEL"], strict=True)
    ]
    out["clarabel_over_ipm_ms"] = out["CLARABEL_ms_median"] / out["IPM_ms_median"]
    out["clarabel_objective_over_ipm"] = {
        "median": float(np.median(ratio)),
        "max": float(np.max(ratio)),
        "min": float(np.min(ratio)),
    }
    out["clarabel_fell_back_to_least_squares"] = sum(m.info["solver"] != "CLARABEL" for m in fits["CLARABEL"])
    out["ipm_fell_back"] = sum(m.info["solver"] != "IPM" for m in fits["IPM"])
    for solver, ms in fits.items():
        lam = [np.linalg.eigvalsh(m.subspace.basis.T @ m.A_e @ m.subspace.basis)[0] for m in ms]
        out[f"{solver}_smallest_eigenvalue_median"] = float(np.median(lam))
    return out


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
            "ellipsoid_sdp (IPM)": lambda W=W, wm=wm: fit_ellipsoid(W, "sdp", w_max=wm, solver="IPM"),
            "ellipsoid_sdp (CLARABEL)": lambda W=W, wm=wm: fit_ellipsoid(
                W, "sdp", w_max=wm, solver="CLARABEL"
            ),
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
    active = sdp_active_constraint(repeats)
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
        # S1-S6's least-squares ellipsoids are positive definite (the SDP returns them, no conic
        # solve): the constraint's cost is measured where it is active
        "ellipsoid_sdp_active_constraint": active,
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
