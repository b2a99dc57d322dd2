"""Which training wrenches the grasp models' 6DLS should use, judged where a grasp is judged: on
the jaw contacts of the grasp dataset's top grasps (thesis meshes, upright and lying; contacts no
experiment scores), each sampler kind's 6DLS resistance margin s* against the exact 6DFW set's,
for random disturbances (a force with a torque at a lever of a contact's size).

For each kind of ``limit_surface.SamplerSpec`` ("mix", the default; "thesis", "6dfc",
"thesis-code"), and for "mix" and "thesis" trained on the contact coarsened to cells of a fraction
of its l_s (``SamplerSpec.cell_fraction``, named ``kind@cell``): the median |log(s*_model / s*_exact)| and
its sign over every disturbance (the sensitivity experiment's criterion,
``grasp.margin.margin_vs_truth``), the time to build a contact's 6DLS (its training wrenches and
fit), and, against the default's, the difference in median |log ratio| with a 90 % interval from
resampling the grasps (the disturbances of one grasp share its contacts).  The exact margins and
each model's come from the same bisection (``grasp.margin.resistance_margin``).  The truth shares
the contact profiles with every model judged: it says what a training set costs in margin, not
whether a real grasp holds.

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

from workbench.grasp.margin import MARGIN_SPAN, margin_vs_truth, resistance_margin
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.resistance import CutStore, resists
from workbench.grasp.simulated_truth import truth_deciders
from workbench.limit_surface import LimitSurfaceCache, SamplerSpec
from workbench.runner.results import code_revision, versions, write_json

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "training_sampler_margins.json"
#: (kind, cell [l_s]) of each variant; cell 0 is named by its kind alone
VARIANTS = (
    ("mix", 0.0),
    ("thesis", 0.0),
    ("6dfc", 0.0),
    ("thesis-code", 0.0),
    ("mix", 0.05),
    ("mix", 0.1),
    ("mix", 0.2),
    ("thesis", 0.15),
)
BOOT = 2000  # grasp resamples of the interval
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
    for kind, cell in VARIANTS:
        params = ModelParameters(M=M, sampler=SamplerSpec(kind=kind, cell_fraction=cell))
        t0 = time.perf_counter()
        sets = [c for p in profiles for c in contact_sets(p, "6dls", params, cache=LimitSurfaceCache())]
        build_ms = (time.perf_counter() - t0) * 1e3 / len(profiles)
        decide = partial(resists, sets, mu=MU, cuts=CutStore())
        row[_name(kind, cell)] = {
            "margins": [resistance_margin(decide, w, STEPS) for w in W],
            "build_ms": build_ms,
        }
    return row


def _name(kind: str, cell: float) -> str:
    return kind if cell == 0 else f"{kind}@{cell:g}"


def _abs_log_error(rows: list[dict], name: str) -> np.ndarray:
    """(n,) |log(s*_name / s*_exact)| of the rows' margins, NaN where margin_vs_truth skips one."""
    s_m = np.concatenate([r[name]["margins"] for r in rows])
    exact = np.concatenate([r["exact"] for r in rows])
    ok = (s_m > 0) & (exact > 0) & (s_m < MARGIN_SPAN) & (exact < MARGIN_SPAN)
    with np.errstate(divide="ignore", invalid="ignore"):  # the pairs left out become NaN
        return np.where(ok, np.abs(np.log(s_m / exact)), np.nan)


def versus_default(rows: list[dict], name: str, seed: int = 0) -> dict:
    """Median |log ratio| of ``name`` minus the default's over the same disturbances, and its 90 %
    interval over ``BOOT`` resamples of the grasps (a grasp's disturbances share its contacts)."""
    per = np.array([len(r["exact"]) for r in rows])
    a, b = _abs_log_error(rows, name), _abs_log_error(rows, _name(*VARIANTS[0]))
    grasp = np.repeat(np.arange(len(rows)), per)

    def diff(idx: np.ndarray) -> float:
        take = np.concatenate([np.flatnonzero(grasp == g) for g in idx])
        return float(np.nanmedian(a[take]) - np.nanmedian(b[take]))

    rng = np.random.default_rng(seed)
    boot = [diff(rng.integers(0, len(rows), len(rows))) for _ in range(BOOT)]
    lo, hi = np.nanpercentile(boot, [5, 95])  # a resample of only unbracketed margins has none
    return {"minus_default": diff(np.arange(len(rows))), "ci90": [float(lo), float(hi)]}


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
    for name in (_name(*v) for v in VARIANTS):
        s_m = np.concatenate([r[name]["margins"] for r in rows])
        summary[name] = {
            **margin_vs_truth(s_m, exact),
            "build_ms_median": float(np.median([r[name]["build_ms"] for r in rows])),
            "median_abs_log_ratio_vs_default": versus_default(rows, name),
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
    for name, s in summary.items():
        err, bias, opt = s["median_abs_log_ratio"], s["median_log_ratio"], s["optimistic_fraction"]
        vs = s["median_abs_log_ratio_vs_default"]
        print(
            f"{name:12s} median |log ratio| {err:.4f} (bias {bias:+.4f}, optimistic {opt:.2f}, "
            f"n {s['n']}; vs default {vs['minus_default']:+.4f} [{vs['ci90'][0]:+.4f}, "
            f"{vs['ci90'][1]:+.4f}]), build {s['build_ms_median']:.1f} ms a contact"
        )


if __name__ == "__main__":
    main()
