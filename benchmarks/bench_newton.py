"""One Newton step of the geometrically nonlinear wall, part by part, against what it replaced.

On a measured grasp of the plastic cup (``wall-nonlinear``'s default mesh, grasp frame; the
mesh from ``../shared/data/deformable_objects``, CC BY-NC 4.0, read by path; skipped with a
message when absent), each timed in this one process, median of ``--repeats`` after a warm-up:

* the St. Venant–Kirchhoff tangent and force by the Numba element loop
  (:func:`workbench.fem.svk.svk_tangent`), with an estimate of its flops against one core's
  measured FMA throughput;
* the linear stiffness by that kernel at u = 0 (:func:`workbench.fem.svk.linear_stiffness`,
  what a linear wall assembles) against scikit-fem's ``linear_elasticity`` form (what it used);
* the factorisation of the free block: CHOLMOD's numeric Cholesky with the symbolic analysis
  reused (:class:`workbench.fem.sparse_factor.Refactor`) against SuperLU in the same
  nested-dissection order (:func:`workbench.fem.sparse_factor.factor_spd`, what each step used),
  with the Cholesky's flop count ``Σ_j c_j²`` (``c_j`` the entries of column j of L).

Writes results/benchmarks/newton.json.  Run: python benchmarks/bench_newton.py
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
from bench_wrench import machine_roofline

from workbench.runner.results import code_revision, versions, write_json

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data" / "deformable_objects"
OUT = ROOT / "results" / "benchmarks" / "newton.json"
GRASP = 14  # a mid-height grasp of the cup map (wall-nonlinear's second)


def _median(fn, repeats: int) -> float:
    fn()  # warm-up (and the kernels' JIT or cache load)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _svk_flops(n_elements: int, n_q: int, nn: int) -> float:
    """Flops of one tangent by the element loop: per Gauss point the kinematics (~40 nn) and,
    per node pair n <= p, two dot products (10) and nine entries of ~8 each."""
    pairs = nn * (nn + 1) / 2
    return float(n_elements * n_q * (pairs * (10 + 9 * 8) + 40 * nn))


def run(repeats: int) -> dict:
    from cvxopt import cholmod
    from skfem import asm
    from skfem.models.elasticity import linear_elasticity

    from workbench.experiments import wall_nonlinear as wn
    from workbench.fem.material import Material
    from workbench.fem.sparse_factor import Refactor, factor_spd, nested_dissection, restrict_order
    from workbench.fem.svk import linear_stiffness, svk_tangent
    from workbench.fem.wall_nonlinear import grasp_frame_wall

    cfg = dict(wn.DEFAULT_CONFIG)
    geo, _, L, _ = wn.object_inputs(cfg)
    n = len(L) // 2
    pet = Material(2.0e8, cfg["nu"])  # about wall-nonlinear's calibrated modulus
    wall, _ = grasp_frame_wall(geo, pet, L[GRASP], L[GRASP + n], n_theta=cfg["mesh"][0])
    b, m = wall.basis, wall.material
    # a small random state (strains ~1e-5): the tangent stays positive definite; at 1e-6 m the random
    # stresses' geometric stiffness makes it indefinite and every factor falls back to SuperLU
    u = 1e-9 * np.random.default_rng(0).standard_normal(b.N)
    cache: dict = {}
    t_tangent = _median(lambda: svk_tangent(b, u, m.mu, m.lam, cache), repeats)
    t_force = _median(lambda: svk_tangent(b, u, m.mu, m.lam, cache, tangent=False), repeats)
    t_linear = _median(lambda: linear_stiffness(b, m.mu, m.lam, cache), repeats)
    t_skfem = _median(lambda: asm(linear_elasticity(m.lam, m.mu), b), max(1, repeats // 2))
    K_lin, K_ref = linear_stiffness(b, m.mu, m.lam, cache), asm(linear_elasticity(m.lam, m.mu), b)
    K, _ = svk_tangent(b, u, m.mu, m.lam, cache)
    free = wall.free
    order = restrict_order(nested_dissection(K), free)
    t0 = time.perf_counter()
    chol = Refactor(K, free, order)
    t_symbolic = time.perf_counter() - t0
    t_cholmod = _median(lambda: chol.factor(K), repeats)
    Kff = K[free][:, free]
    t_superlu = _median(lambda: factor_spd(Kff, perm=order), repeats)
    rhs = np.random.default_rng(1).standard_normal(free.size)
    lu = factor_spd(Kff, perm=order)
    x_ch, x_lu = chol.factor(K).solve(rhs), lu.solve(rhs)
    Lc = cholmod.getfactor(chol._F)  # the numeric factor of the last factor() as a sparse matrix
    counts = np.bincount(np.array(Lc.J).ravel(), minlength=free.size).astype(float)
    chol_flops = float((counts**2).sum())
    roof = machine_roofline(quick=True)
    per_core = roof["fma_gflops_measured"] / max(roof["threads"], 1)
    n_e, n_q = cache["w"].shape
    tangent_flops = _svk_flops(n_e, n_q, cache["G"].shape[2])
    return {
        "object": "plastic_cup",
        "grasp": GRASP,
        "dofs": int(b.N),
        "free_dofs": int(free.size),
        "elements": int(b.element_dofs.shape[1]),
        "tangent_and_force_s": t_tangent,
        "force_only_s": t_force,
        "tangent_gflops_estimate": tangent_flops / t_tangent / 1e9,
        "linear_stiffness_kernel_s": t_linear,
        "linear_stiffness_skfem_s": t_skfem,
        "speedup_linear_assembly": t_skfem / t_linear,
        "linear_stiffness_max_rel_diff": float(abs(K_lin - K_ref).max() / abs(K_ref).max()),
        "cholmod_symbolic_s": t_symbolic,
        "cholmod_numeric_s": t_cholmod,
        "superlu_factor_s": t_superlu,
        "speedup_factor": t_superlu / t_cholmod,
        "cholmod_fallbacks_to_superlu": chol.fallbacks,  # 0: every timed factor was CHOLMOD's
        "cholesky_nnz_L": len(Lc.V),
        "superlu_nnz_L_plus_U": int(lu.lu.L.nnz + lu.lu.U.nnz),
        "cholesky_gflops": chol_flops / t_cholmod / 1e9,
        "solution_max_rel_diff": float(np.abs(x_ch - x_lu).max() / np.abs(x_lu).max()),
        "machine": {**roof, "fma_gflops_per_core": per_core},
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=5, help="timed runs per measurement (median)")
    args = ap.parse_args()
    if not (DATA / "meshes" / "plastic_cup.obj").is_file():
        print(f"bench_newton: skipped - {DATA}/meshes/plastic_cup.obj not found")
        return 0
    res = run(args.repeats)
    if res["cholmod_fallbacks_to_superlu"]:
        print("bench_newton: the tangent was not positive definite; the CHOLMOD timing is SuperLU's")
    res.update({"code_revision": code_revision(), "versions": versions()})
    write_json(OUT, res)
    print(json.dumps({k: v for k, v in res.items() if k not in ("versions", "machine")}, indent=1))
    print(
        f"tangent {res['tangent_and_force_s'] * 1e3:.0f} ms "
        f"(~{res['tangent_gflops_estimate']:.1f} GFLOP/s of "
        f"{res['machine']['fma_gflops_per_core']:.1f} per core); linear stiffness "
        f"{res['speedup_linear_assembly']:.1f}x faster than scikit-fem's form; factor: CHOLMOD "
        f"{res['cholmod_numeric_s'] * 1e3:.0f} ms vs SuperLU {res['superlu_factor_s'] * 1e3:.0f} ms "
        f"({res['speedup_factor']:.1f}x, {res['cholesky_gflops']:.1f} GFLOP/s)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
