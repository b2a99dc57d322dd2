"""The MuJoCo engine trials judged against reality and timed: the REACH cube trials (ABB YuMi,
silicone pads, a 3 cm cube of 3 g; 25 grasps × 5 repeats, their gripper poses identical per
grasp) each simulated once at its recorded pose (``engine-validation``'s (e) rows when that ran at
this code, else here) by
:func:`workbench.engine_trials.simulate_gripper` (the robot's protocol: the cube on a table, the
jaws closing by 20 N, lifting) — the simulator's verdict against the 125 real outcomes
(balanced accuracy, true-positive and true-negative rates), with no threshold fitted (the
verdict is binary).  Seconds per trial (median, worst) beside this machine's measured FMA
throughput, and the simulated seconds per wall second.

Writes results/benchmarks/engine_trials.json.  Run: python benchmarks/bench_engine_trials.py [--quick]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from bench_wrench import machine_roofline

from workbench.engine_trials.reality import reach_cube_inputs, reach_trial, score_reach
from workbench.results import code_hash, code_revision, versions, write_json

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "engine_trials.json"


#: engine-validation's summary: its (e) rows are these trials, timed, at the same code
VALIDATION = OUT.parents[1] / "engine-validation" / "summary.json"


def run(quick: bool) -> dict:
    """The scored trials: engine-validation's (e) when it ran every grasp at this code (make
    reproduce runs it first; the trials are not simulated twice), else simulated here."""
    if not quick and VALIDATION.exists():
        s = json.loads(VALIDATION.read_text())
        if s.get("code", {}).get("hash") == code_hash() and s["e_reality"]["n_grasps"] == 25:
            return {**s["e_reality"], "from": str(VALIDATION.relative_to(OUT.parents[2]))}
    trials, _ = reach_cube_inputs()
    grasps = sorted(set(trials.grasp_index.tolist()))[:: 5 if quick else 1]
    return score_reach([reach_trial(k) for k in grasps])


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
