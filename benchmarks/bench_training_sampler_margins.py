"""Which training wrenches the grasp models' 6DLS should use, judged where a grasp is judged: on
the jaw contacts of the grasp dataset's top grasps (thesis meshes, upright and lying; contacts no
experiment scores), each sampler kind's 6DLS resistance margin s* against the exact 6DFW set's,
for random disturbances (a force with a torque at a lever of a contact's size).

For each kind of ``limit_surface.SamplerSpec`` ("mix", the default; "thesis", "6dfc",
"thesis-code"): the median |log(s*_model / s*_exact)| and its sign over every disturbance (the
sensitivity experiment's criterion, ``grasp.margin.margin_vs_truth``), and the time to build a
contact's 6DLS (its training wrenches and fit).  The exact margins and each model's come from the
same bisection (``grasp.margin.resistance_margin``).

Writes results/benchmarks/training_sampler_margins.json.
Run: python benchmarks/bench_training_sampler_margins.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import time
from functools import partial
from pathlib import Path

import numpy as np
from bench_training_sampler import MU, OBJECTS, top_grasp_contacts
from bench_wrench import machine_roofline

from workbench.grasp.margin import margin_vs_truth, resistance_margin
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.resistance import CutStore, resists
from workbench.grasp.simulated_truth import truth_deciders
from workbench.limit_surface import LimitSurfaceCache, SamplerSpec
from workbench.runner.results import code_revision, versions, write_json

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "training_sampler_margins.json"
KINDS = ("mix", "thesis", "6dfc", "thesis-code")
M = 200  # linearisation directions (the sensitivity experiment's)
STEPS = 12  # bisection steps on log2 s* (the sensitivity experiment's)
START = 200  # the exact column generation's starting columns (the sensitivity experiment's)
LEVER = 0.02  # m: a disturbance's torque is its force times a lever of about a contact's size


def _grasps(n_meshes: int, n_grasps: int):
    """(object, lying, jaw profiles) of the two-jaw contacts of ``n_grasps`` top grasps of every
    6th thesis mesh, upright and lying."""
    for stem, lying, contact in top_grasp_contacts(n_meshes, n_grasps):
        if len(contact.profiles) == 2:
            yield stem, lying, list(contact.profiles)


def _disturbances(n: int, seed: int) -> np.ndarray:
    """(n, 6) random disturbances: a unit force [N] and a torque of LEVER [N m], random directions."""
    rng = np.random.default_rng(seed)
    f = rng.normal(size=(n, 3))
    t = rng.normal(size=(n, 3))
    f /= np.linalg.norm(f, axis=1, keepdims=True)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    return np.hstack([f, LEVER * t])


def measure(profiles: list, W: np.ndarray) -> dict:
    """The exact margins of ``W`` on the grasp ``profiles`` and each sampler kind's 6DLS margins
    and build time [ms a contact]."""
    (exact,) = truth_deciders(profiles, [MU], [1.0], START)
    row: dict = {"exact": [resistance_margin(exact, w, STEPS) for w in W]}
    for kind in KINDS:
        params = ModelParameters(M=M, sampler=SamplerSpec(kind=kind))
        t0 = time.perf_counter()
        sets = [c for p in profiles for c in contact_sets(p, "6dls", params, cache=LimitSurfaceCache())]
        build_ms = (time.perf_counter() - t0) * 1e3 / len(profiles)
        decide = partial(resists, sets, mu=MU, cuts=CutStore())
        row[kind] = {"margins": [resistance_margin(decide, w, STEPS) for w in W], "build_ms": build_ms}
    return row


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(OUT))
    args = parser.parse_args()
    if not OBJECTS.is_dir():
        raise SystemExit(f"needs the thesis meshes in {OBJECTS}")
    t0 = time.perf_counter()
    n_dist = 3 if args.quick else 8
    rows = []
    for k, (obj, lying, profiles) in enumerate(_grasps(1 if args.quick else 4, 1 if args.quick else 3)):
        rows.append({"object": obj, "lying": lying, **measure(profiles, _disturbances(n_dist, k))})
    exact = np.concatenate([r["exact"] for r in rows])
    summary = {}
    for kind in KINDS:
        s_m = np.concatenate([r[kind]["margins"] for r in rows])
        summary[kind] = {
            **margin_vs_truth(s_m, exact),
            "build_ms_median": float(np.median([r[kind]["build_ms"] for r in rows])),
        }
    write_json(
        Path(args.out),
        {
            "what": __doc__.split("\n\n")[0],
            "n_grasps": len(rows),
            "n_disturbances": int(exact.size),
            "mu": MU,
            "M": M,
            "margin_steps": STEPS,
            "summary": summary,
            "rows": rows,
            "machine": {
                **machine_roofline(quick=True),
                "cpu_count": os.cpu_count(),
                "loadavg_1_5_15": os.getloadavg(),
            },
            "code_revision": code_revision(),
            "versions": versions(),
            "wall_time_s": time.perf_counter() - t0,
        },
    )
    for kind, s in summary.items():
        err, bias, opt = s["median_abs_log_ratio"], s["median_log_ratio"], s["optimistic_fraction"]
        print(
            f"{kind:12s} median |log ratio| {err:.4f} (bias {bias:+.4f}, optimistic {opt:.2f}, "
            f"n {s['n']}), build {s['build_ms_median']:.1f} ms a contact"
        )


if __name__ == "__main__":
    main()
