"""Peak memory of a wall-stiffness point against its mesh: the measurements behind
:func:`workbench.experiments.wall_stiffness.memory_estimate`, written to
``results/benchmarks/memory_model.json``.

A sweep refuses, before it runs, a point whose estimated peak memory exceeds its Dask
worker's ``memory_limit`` (:mod:`workbench.runner.sweep`); for wall-stiffness that estimate comes
from the model fitted here.  Each measurement is one fresh interpreter running one
``wall-stiffness --quick`` point as a sweep's task would (serially, ``workers=1``) with
``mesh=[n_theta, n_z]`` — nothing else in the process — and reporting its own peak
resident set size (``resource.getrusage(RUSAGE_SELF).ru_maxrss``: the kernel's high-water
mark, what a Dask nanny watches, not a sampled value), the wall's free dofs and the
non-zeros of its factor (L + U, :class:`workbench.fem.sparse_factor.SPDFactor`).  One
process at a time (the machine is shared).

The model, physically: a wall's memory is its factor (SuperLU's L and U plus the blocked
solves' row-major copies of them, and the factorisation's work space), so

* ``nnz(dofs) = a · dofs^p`` — a power law fitted in log-log to the measured factors (nested
  dissection of a closed shell: slightly above linear), and
* ``peak = base + bytes_per_nnz · nnz`` — least squares on the measured peaks: ``base`` is
  the interpreter, the imports, the ring validation and the figures; ``bytes_per_nnz`` the
  factor's storage and work space per non-zero.

Extra runs check how walls add up in one point — three bottles (the cache of
``_bottle_wall`` keeps two factored walls) and a mesh-convergence study (its walls one after
another) — against the model's prediction with this fit (``estimate_over_measured``).

The library's constants, ``workbench.experiments.wall_stiffness.MEMORY_MODEL``, are this
fit's, copied by hand with the date; ``tests/test_sweep_memory.py`` checks that they agree
with this file and that every measured peak is within 10 % of the estimate.

The largest mesh measured is [96, 48] (5.6 GiB); [144, 72] is not run (~14 GiB: the
point the model exists to refuse).  Run: python benchmarks/bench_memory.py [--quick]
(--quick: the three smallest meshes, no extra runs; does not overwrite the model's file
unless --out is given).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from workbench.runner.results import code_revision, versions, write_json

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "benchmarks" / "memory_model.json"
MESHES = ([24, 12], [48, 24], [72, 36], [96, 48])

#: one point in a fresh interpreter; prints one JSON line (its peak RSS read before anything
#: else is allocated, then the wall's dofs and factor non-zeros from the per-process cache)
CHILD = r"""
import importlib, json, resource, sys, time
from workbench.runner.experiment_config import EXPERIMENTS, build_config

sets, out = json.loads(sys.argv[1]), sys.argv[2]
cfg = build_config("wall-stiffness", True, out, None, sets)
mod = importlib.import_module(EXPERIMENTS["wall-stiffness"])
t0 = time.perf_counter()
mod.run(cfg)
seconds = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux
nt, nz = cfg["mesh"]
_, wall = mod._bottle_wall(
    cfg["seed"], cfg["bottles"][-1], float(cfg["E"]), float(cfg["nu"]), float(cfg["thickness"]), nt, nz
)
L, U = wall.lu.rows
print(json.dumps({
    "peak_rss_bytes": peak, "seconds": seconds, "free_dofs": int(wall.free.size),
    "factor_nnz": int(L.nnz + U.nnz),
}))
"""


def measure(sets: dict) -> dict:
    """One point's peak RSS, run time, free dofs and factor non-zeros (a fresh interpreter)."""
    env = {**os.environ, "TQDM_DISABLE": "1", "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    env["OPENBLAS_NUM_THREADS"] = env["MKL_NUM_THREADS"] = "1"  # as in a sweep's worker
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        res = subprocess.run(
            [sys.executable, "-c", CHILD, json.dumps({"workers": 1, **sets}), str(Path(tmp) / "point")],
            capture_output=True,
            text=True,
            env=env,
        )
    if res.returncode != 0:
        raise RuntimeError(f"point {sets} failed:\n{res.stderr[-3000:]}")
    row = json.loads(res.stdout.strip().splitlines()[-1])
    row.update(sets=sets, process_s=time.perf_counter() - t0)
    print(
        f"  {json.dumps(sets)}: peak {row['peak_rss_bytes'] / 2**30:.3f} GiB, {row['free_dofs']} dofs, "
        f"{row['factor_nnz'] / 1e6:.1f} M nnz, {row['seconds']:.1f} s",
        flush=True,
    )
    return row


def fit(rows: list[dict]) -> dict:
    """The model's constants from single-wall runs (module docstring)."""
    dofs = np.array([r["free_dofs"] for r in rows], dtype=float)
    nnz = np.array([r["factor_nnz"] for r in rows], dtype=float)
    peak = np.array([r["peak_rss_bytes"] for r in rows], dtype=float)
    p, log_a = np.polyfit(np.log(dofs), np.log(nnz), 1)
    A = np.column_stack([np.ones_like(nnz), nnz])
    (base, per_nnz), *_ = np.linalg.lstsq(A, peak, rcond=None)
    pred = base + per_nnz * np.exp(log_a) * dofs**p
    return {
        "nnz_coefficient": float(np.exp(log_a)),
        "nnz_exponent": float(p),
        "base_bytes": float(base),
        "bytes_per_nnz": float(per_nnz),
        "nnz_fit_max_rel_err": float(np.max(np.abs(np.exp(log_a) * dofs**p / nnz - 1))),
        "peak_fit_max_rel_err": float(np.max(np.abs(pred / peak - 1))),
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="three smallest meshes, no extra runs")
    parser.add_argument("--out", default=None, help=f"output JSON (default {OUT.relative_to(ROOT)})")
    args = parser.parse_args()
    out = Path(args.out) if args.out else (None if args.quick else OUT)
    t0 = time.perf_counter()
    print("wall-stiffness --quick, one bottle, by mesh:", flush=True)
    single = [measure({"mesh": m}) for m in (MESHES[:3] if args.quick else MESHES)]
    model = fit(single)
    checks = []
    if not args.quick:
        print("how walls add up in one point:", flush=True)
        from workbench.experiments.wall_stiffness import memory_estimate
        from workbench.runner.experiment_config import build_config

        for sets in (
            {"mesh": [48, 24], "bottles": [0, 5, 20]},
            {"mesh": [24, 12], "convergence_meshes": [[32, 16], [48, 24], [64, 32]]},
        ):
            row = measure(sets)
            cfg = build_config("wall-stiffness", True, None, None, {"workers": 1, **sets})
            est = memory_estimate(cfg, model)  # this fit: what the library's MEMORY_MODEL copies
            row["estimate_bytes"] = est
            row["estimate_over_measured"] = est / row["peak_rss_bytes"]
            checks.append(row)
    result = {
        "benchmark": "peak memory of wall-stiffness points against their mesh",
        "measured_on": datetime.date.today().isoformat(),
        "method": "one wall-stiffness --quick point (workers=1) per fresh interpreter; its peak RSS "
        "from getrusage(RUSAGE_SELF).ru_maxrss after the run",
        "model": "peak = base_bytes + bytes_per_nnz * nnz_coefficient * free_dofs**nnz_exponent "
        "(free_dofs = 36 * n_theta * n_z for a wall clamped at its base)",
        "fit": model,
        "single_wall": single,
        "checks": checks,
        "machine": {
            "cpu_count": os.cpu_count(),
            "memory_bytes": os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"),
        },
        "code_revision": code_revision(),
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t0,
    }
    print(json.dumps(model, indent=2))
    if out is not None:
        write_json(out, result)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
