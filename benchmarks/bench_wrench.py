"""6DFW throughput: Numba kernel vs the vectorized NumPy reference (same process),
an empirical roofline of this machine, and continuous-surface wrench cost.

Writes results/benchmarks/wrench.json.  Run: python benchmarks/bench_wrench.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np
from numba import get_num_threads, njit, prange, set_num_threads

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import naive  # noqa: E402

from workbench import ContactProfile, frictional_wrenches, sample_twists_thesis, surface_wrenches  # noqa: E402
from workbench.config import FASTMATH  # noqa: E402
from workbench.runner.results import versions, write_json  # noqa: E402
from workbench.sources.surface_catalog import THESIS_SURFACES  # noqa: E402
from workbench.timing import median_runtime  # noqa: E402

# Flops per (twist, element) pair in workbench._kernels (counting an FMA as 2):
# u = v + ω×r: 12, d = u·n: 5, t = u - d n: 6, |t|²: 5, |u|²: 5, threshold: 1,
# g = s t: 3, Σg: 3, Σ r×g: 12  -> 52 flops, plus 1 sqrt and 1 divide.
FLOPS_PER_PAIR = 52


def median_time(fn, repeats: int, warmup: int = 2) -> float:
    return median_runtime(fn, repeats, warmup)[0]


@njit(parallel=True, fastmath=set(FASTMATH))
def _fma_rate(x, reps):
    # 8 independent FMA chains per element: saturates the FMA pipes from L1
    n = x.shape[0]
    out = 0.0
    for i in prange(n):
        a0 = x[i]
        a1 = a0 + 1.0
        a2 = a0 + 2.0
        a3 = a0 + 3.0
        a4 = a0 + 4.0
        a5 = a0 + 5.0
        a6 = a0 + 6.0
        a7 = a0 + 7.0
        for _ in range(reps):
            a0 = a0 * 0.999999 + 1e-7
            a1 = a1 * 0.999999 + 1e-7
            a2 = a2 * 0.999999 + 1e-7
            a3 = a3 * 0.999999 + 1e-7
            a4 = a4 * 0.999999 + 1e-7
            a5 = a5 * 0.999999 + 1e-7
            a6 = a6 * 0.999999 + 1e-7
            a7 = a7 * 0.999999 + 1e-7
        out += a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7
    return out


@njit(parallel=True, fastmath=set(FASTMATH))
def _sqrt_div_rate(t, w, reps):
    # the irreducible sqrt + divide of every pair, vectorized like the kernel
    total = 0.0
    for r in prange(reps):
        s = 0.0
        for i in range(t.shape[0]):
            s += w[i] / np.sqrt(max(t[i] + r, 1e-300))
        total += s
    return total


def cpu_identity() -> dict:
    """What picks the arithmetic's last bits on this host: the CPU, the target Numba compiles its
    kernels for, and the kernel set the BLAS chose.  Two hosts that differ in these round
    differently (FMA contraction, vector width, summation order), so results compared across
    runs agree to round-off, not bit for bit, unless these match."""
    from pathlib import Path

    import llvmlite.binding as llvm
    from threadpoolctl import threadpool_info

    model = ""
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.exists():
        names = [ln for ln in cpuinfo.read_text().splitlines() if ln.startswith("model name")]
        model = names[0].split(":", 1)[1].strip() if names else ""
    blas = [f"{p.get('internal_api')} {p.get('architecture', '')}".strip() for p in threadpool_info()]
    return {"cpu_model": model, "llvm_host_cpu": llvm.get_host_cpu_name(), "blas_kernels": blas}


def on_one_core(fn, *args):
    """``fn(*args)`` with Numba's threads and the BLAS limited to one: what one core does (the
    per-grasp targets are one core's; a roofline measured inside is one core's too)."""
    from threadpoolctl import threadpool_limits

    threads = get_num_threads()
    set_num_threads(1)
    try:
        with threadpool_limits(1):
            return fn(*args)
    finally:
        set_num_threads(threads)


def machine_roofline(quick: bool) -> dict:
    x = np.random.default_rng(0).random(2 * 4096)
    reps = 2000 if quick else 20000
    dt = median_time(lambda: _fma_rate(x, reps), 3)
    gflops = 2 * 8 * x.size * reps / dt / 1e9
    t = np.random.default_rng(1).random(1000) + 0.5
    w = np.ones(1000)
    r2 = 2000 if quick else 20000
    dt2 = median_time(lambda: _sqrt_div_rate(t, w, r2), 3)
    ns_sqrt_div = dt2 / (r2 * t.size) * 1e9
    ns_flops = FLOPS_PER_PAIR / gflops
    return {
        **cpu_identity(),
        "threads": get_num_threads(),
        "fma_gflops_measured": gflops,
        "sqrt_div_ns_per_element_measured": ns_sqrt_div,
        "flops_ns_per_pair_bound": ns_flops,
        # the two resources overlap on different ports; the bound is the larger,
        # the sum is a pessimistic (no overlap) estimate
        "arith_limit_ns_per_pair": max(ns_flops, ns_sqrt_div),
        "arith_limit_no_overlap_ns_per_pair": ns_flops + ns_sqrt_div,
    }


def kernel_benchmark(n_elements: int, n_twists: int, repeats: int) -> dict:
    rng = np.random.default_rng(42)
    c, nrm, a, p = naive.random_profile(rng, n_elements)
    prof = ContactProfile(c, nrm, a, p)
    xi = sample_twists_thesis(n_twists // 2, prof, seed=1)
    assert xi.shape == (n_twists, 6)
    ref = naive.fw_vectorized(c, nrm, a, p, xi, 1.0)
    got = frictional_wrenches(prof, xi, 1.0)
    scale = np.array([prof.F] * 3 + [prof.F * prof.length_scale] * 3)
    max_err = float((np.abs(got - ref) / scale).max())
    t_numba = median_time(lambda: frictional_wrenches(prof, xi, 1.0), repeats)
    t_numpy = median_time(lambda: naive.fw_vectorized(c, nrm, a, p, xi, 1.0), max(3, repeats // 4))
    threads = get_num_threads()
    set_num_threads(1)
    t_serial = median_time(lambda: frictional_wrenches(prof, xi, 1.0), repeats)
    set_num_threads(threads)
    pairs = n_elements * n_twists
    return {
        "n_elements": n_elements,
        "n_twists": n_twists,
        "numba_s": t_numba,
        "numba_1thread_s": t_serial,
        "numpy_vectorized_s": t_numpy,
        "speedup_vs_numpy": t_numpy / t_numba,
        "us_per_wrench": t_numba / n_twists * 1e6,
        "ns_per_pair": t_numba / pairs * 1e9,
        "ns_per_pair_1thread": t_serial / pairs * 1e9,
        "max_scaled_error_vs_numpy": max_err,
    }


def continuous_benchmark(repeats: int) -> dict:
    out = {}
    for name, surface in THESIS_SURFACES.items():
        s = surface.normalized()
        xi = sample_twists_thesis(10, s.length_scale, seed=3)  # 20 twists
        ref = surface_wrenches(s, xi, 1.0, rtol=1e-10)
        w, est = surface_wrenches(s, xi, 1.0, rtol=1e-4, return_error=True)
        scale = np.array([1.0] * 3 + [s.length_scale] * 3)
        err = (np.abs(w - ref) / scale).max(axis=1)
        rel = np.linalg.norm((w - ref) / scale, axis=1) / np.linalg.norm(ref / scale, axis=1)
        batch = median_time(partial(surface_wrenches, s, xi, 1.0, rtol=1e-4), repeats) / len(xi)
        single = median_time(partial(surface_wrenches, s, xi[0], 1.0, rtol=1e-4), repeats)
        out[name] = {
            "ms_per_wrench_single": single * 1e3,
            "ms_per_wrench_batched": batch * 1e3,
            "max_scaled_error": float(err.max()),
            "max_relative_error": float(rel.max()),
            "max_error_estimate": float(est.max()),
        }
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "wrench.json"))
    args = parser.parse_args()
    repeats = 5 if args.quick else 21
    t0 = time.perf_counter()
    kern = kernel_benchmark(1000, 600, repeats)
    roof = machine_roofline(args.quick)
    cont = continuous_benchmark(3 if args.quick else 7)
    result = {
        "benchmark": "6D frictional wrench (thesis Eqs. 3.6–3.8)",
        "kernel_1000x600": kern,
        "machine": {**roof, "cpu_count": os.cpu_count()},
        "fraction_of_arith_limit": roof["arith_limit_ns_per_pair"] / kern["ns_per_pair"],
        "continuous_rtol_1e-4": cont,
        "thesis_matlab": {"discrete_ms_per_wrench": 1.3, "continuous_s_per_wrench": 2.62},
        "speedup_vs_thesis_discrete": 1.3e-3 / (kern["us_per_wrench"] * 1e-6),
        "speedup_vs_thesis_continuous": 2.62 / (max(v["ms_per_wrench_single"] for v in cont.values()) * 1e-3),
        "versions": versions(),
        "method": "median of repeats after 2 warm-up calls, one process",
        "wall_time_s": time.perf_counter() - t0,
    }
    write_json(Path(args.out), result)
    print(
        f"6DFW 1000x600: numba {kern['numba_s'] * 1e3:.3f} ms, "
        f"numpy {kern['numpy_vectorized_s'] * 1e3:.1f} ms "
        f"-> {kern['speedup_vs_numpy']:.0f}x; {kern['us_per_wrench']:.2f} us/wrench; "
        f"{kern['ns_per_pair']:.3f} ns/pair vs arithmetic limit "
        f"{roof['arith_limit_ns_per_pair']:.3f} ns/pair "
        f"({100 * result['fraction_of_arith_limit']:.0f}%)"
    )
    for name, v in cont.items():
        print(
            f"  continuous {name}: {v['ms_per_wrench_single']:.2f} ms single, "
            f"{v['ms_per_wrench_batched']:.3f} ms batched, "
            f"err {v['max_scaled_error']:.1e} (est {v['max_error_estimate']:.1e})"
        )


if __name__ == "__main__":
    main()
