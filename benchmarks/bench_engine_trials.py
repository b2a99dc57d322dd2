"""The MuJoCo engine trials judged against reality and timed: the REACH cube trials (ABB YuMi,
silicone pads, a 3 cm cube of 3 g; 25 grasps × 5 repeats, their gripper poses identical per
grasp) each simulated once at its recorded pose by
:func:`workbench.engine_trials.simulate_gripper` (the robot's protocol: the cube on a table, the
jaws closing by 20 N, lifting) — the simulator's verdict against the 125 real outcomes
(balanced accuracy, true-positive and true-negative rates), with no threshold fitted (the
verdict is binary).  Seconds per trial (median, worst) beside this machine's measured FMA
throughput, and the simulated seconds per wall second.

Writes results/benchmarks/engine_trials.json.  Run: python benchmarks/bench_engine_trials.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import trimesh
from bench_wrench import machine_roofline

from workbench.engine_trials import simulate_gripper
from workbench.results import code_revision, versions, write_json
from workbench.sources.gripper import yumi
from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "engine_trials.json"


def run(quick: bool) -> dict:
    trials = read_trials(default_trials_path())
    mesh = trimesh.load(default_mesh_path(), force="mesh")
    g = yumi()
    grasps = sorted(set(trials.grasp_index.tolist()))[:: 5 if quick else 1]
    rows = []
    for k in grasps:
        i = int(np.flatnonzero(trials.grasp_index == k)[0])
        t0 = time.perf_counter()
        r = simulate_gripper(mesh, g, trials.gripper_pose[i], mass=trials.mass, down=trials.down[i])
        wall = time.perf_counter() - t0
        real = trials.success[trials.grasp_index == k]
        rows.append(
            {
                "grasp": k,
                "real_success_rate": float(real.mean()),
                "held": r.held,
                "reason": r.reason,
                "drift_mm": r.drift * 1e3,
                "turn_deg": r.turn_deg,
                "wall_s": wall,
                "simulated_s": r.steps * 1e-3,
                "engine_warnings": r.engine_warnings,
            }
        )
    held = {row["grasp"]: row["held"] for row in rows}
    mask = np.isin(trials.grasp_index, list(held))
    pred = np.array([held[k] for k in trials.grasp_index[mask]])
    real = trials.success[mask]
    tpr = float((pred & real).sum() / real.sum())
    tnr = float((~pred & ~real).sum() / (~real).sum()) if (~real).any() else float("nan")
    walls = [row["wall_s"] for row in rows]
    return {
        "what": "REACH cube trials simulated on MuJoCo (engine_trials.simulate_gripper) vs the real outcomes",
        "n_grasps": len(rows),
        "n_trials": int(mask.sum()),
        "real_failures": int((~real).sum()),
        "balanced_accuracy": (tpr + tnr) / 2,
        "true_positive_rate": tpr,
        "true_negative_rate": tnr,
        "failures_predicted": int((~pred & ~real).sum()),
        "seconds_per_trial": {"median": float(np.median(walls)), "worst": float(np.max(walls))},
        "simulated_seconds_per_wall_second": float(sum(r["simulated_s"] for r in rows) / sum(walls)),
        "rows": rows,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="every fifth grasp only")
    args = ap.parse_args(argv)
    out = run(args.quick)
    out["machine"] = machine_roofline(args.quick)
    out["code"] = {"revision": code_revision(), "versions": versions()}
    out["quick"] = args.quick
    write_json(OUT, out)
    print(  # noqa: T201 (a benchmark script reports on stdout)
        f"engine trials vs REACH: balanced accuracy {out['balanced_accuracy']:.3f} "
        f"(TPR {out['true_positive_rate']:.3f}, TNR {out['true_negative_rate']:.3f}; "
        f"{out['failures_predicted']} of {out['real_failures']} real failures predicted), "
        f"{out['seconds_per_trial']['median']:.1f} s per trial "
        f"(worst {out['seconds_per_trial']['worst']:.1f})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
