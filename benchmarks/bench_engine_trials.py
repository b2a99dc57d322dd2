"""The MuJoCo engine trials judged against reality and timed: the REACH cube trials (ABB YuMi,
silicone pads, a 3 cm cube of 3 g; 25 grasps × 5 repeats, their gripper poses identical per
grasp) each simulated once at its recorded pose (``engine-validation``'s (e) rows when that ran at
this code, else here) by
:func:`workbench.engine_trials.simulate_gripper` (the robot's protocol: the cube on a table, the
jaws closing by 20 N, lifting) — the simulator's verdict against the 125 real outcomes
(balanced accuracy, true-positive and true-negative rates), with no threshold fitted (the
verdict is binary).  Seconds per trial (median, worst) beside this machine's measured FMA
throughput, and the simulated seconds per wall second.

Then the cost against the pads' vertex count (``scaling``): one trial of a box squarely gripped
(vertical lifting, 2.1 simulated seconds) at three pad grids, wall seconds per trial and per
simulated second.

Writes results/benchmarks/engine_trials.json.  Run: python benchmarks/bench_engine_trials.py [--quick]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from bench_wrench import machine_roofline

from workbench.engine_trials.reality import reach_cube_inputs, reach_trial, score_reach
from workbench.runner.results import code_hash, code_revision, versions, write_json

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


#: pad grids (width, length, thickness points) of the scaling runs; the first is the default
GRIDS = ((5, 9, 3), (7, 13, 3), (9, 17, 4))


def scaling(quick: bool) -> list[dict]:
    """Wall seconds of one trial per pad grid: a 60 x 40 x 80 mm box of 0.2 kg gripped across
    its 40 mm faces at 10 N per jaw (μ 0.5: held at 5x its weight), lifted and held."""
    import time

    import numpy as np
    import trimesh

    from workbench.engine_trials import EngineObject, EngineSettings, simulate_grasp

    box = trimesh.creation.box((0.06, 0.04, 0.08))
    grasp = {"p1": [0.0, -0.02, 0.0], "p2": [0.0, 0.02, 0.0], "axis": [0.0, 1.0, 0.0]}
    rows = []
    for grid in GRIDS[:2] if quick else GRIDS:
        settings = EngineSettings(pad_grid=grid)
        t0 = time.perf_counter()
        o = simulate_grasp(box, grasp, force=10.0, obj=EngineObject(mass=0.2, mu=0.5), settings=settings)
        wall = time.perf_counter() - t0
        sim = o.steps * settings.timestep
        rows.append(
            {
                "pad_grid": list(grid),
                "flex_vertices": 2 * int(np.prod(grid)),
                "held": o.held,
                "wall_s": wall,  # scene build and stepping: what a user pays per trial
                "stepping_s": o.seconds,
                "simulated_s": sim,
                "wall_s_per_simulated_s": wall / sim,
            }
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="every fifth grasp only")
    args = ap.parse_args(argv)
    out = run(args.quick)
    out["scaling"] = scaling(args.quick)
    out["machine"] = machine_roofline(args.quick)
    out["code"] = {"revision": code_revision(), "versions": versions()}
    out["quick"] = args.quick
    write_json(OUT, out)
    print(  # noqa: T201 (a benchmark script reports on stdout)
        f"engine trials vs REACH: balanced accuracy {out['balanced_accuracy']:.3f} "
        f"(TPR {out['true_positive_rate']:.3f}, TNR {out['true_negative_rate']:.3f}; "
        f"{out['failures_predicted']} of {out['real_failures']} real failures predicted), "
        f"{out['seconds_per_trial']['median']:.1f} s per trial "
        f"(worst {out['seconds_per_trial']['worst']:.1f}); by pad vertices: "
        + ", ".join(f"{r['flex_vertices']}: {r['wall_s']:.1f} s" for r in out["scaling"])
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
