"""Fig 3.8: wrench error rate of meshed S1-S6 vs number of triangles, continuous vs discrete runtime.

Thesis §3.5.1.2.  Ground truth is ``w_max`` of the continuous surface (exact
support function via canonical twists, adaptive quadrature at ``truth_rtol``);
the *wrench error rate* is the mean over the six components of
``|w_max,mesh - w_max,cont| / w_max,cont`` (μ = 1, normalised uniform pressure).
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench import (
    frictional_wrenches,
    sample_twists_thesis,
    surface_w_max,
    surface_wrenches,
    w_max,
)
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.results import save_figure, write_csv, write_summary
from workbench.sources.surface_catalog import THESIS_SURFACES
from workbench.sources.surfaces import check_rtol, mesh_profile, wrench_error_rate
from workbench.timing import median_runtime
from workbench.wrench import check_mu

NAME = "discretization"

DEFAULT_CONFIG = {
    "seed": 0,
    "mu": 1.0,
    "n_elements": [25, 50, 100, 200, 300, 400, 500, 600, 700, 800, 900, 1000],
    "truth_rtol": 1e-8,  # ground truth accuracy, far below the error rates measured
    "timing_rtol": 1e-4,  # accuracy of the timed continuous wrenches (acceptance: <= 1e-4)
    "timing_twists": 60,  # thesis-sampled twists (x2 with translations) per surface for timing
    "timing_repeats": 5,
}
#: what each key means, its unit and plausible range (``workbench run discretization --help``)
KEYS = {
    "mu": Key(
        "friction coefficient; wrenches scale with it, so the error rates do not (thesis: 1)", "", "mu"
    ),
    "n_elements": Key("target triangle counts of the meshed surfaces, each >= 2"),
    "truth_rtol": Key("relative accuracy of the ground-truth w_max (adaptive quadrature), > 0"),
    "timing_rtol": Key("relative accuracy of the timed continuous wrenches, > 0 (acceptance: <= 1e-4)"),
    "timing_twists": Key("thesis-sampled twists per surface for the timings (x2 with translations), >= 1"),
    "timing_repeats": Key("timing repeats (the median is reported), >= 1"),
}
QUICK_CONFIG = {"n_elements": [25, 100, 300, 1000], "timing_twists": 10, "timing_repeats": 3}


def check_config(config: dict) -> None:
    """μ > 0 before any work: the error rate is relative to w_max, which is 0 without friction."""
    for key, spec in KEYS.items():  # also for run(config) called directly
        check_key(key, spec, config[key])
    check_mu(config["mu"], what="relative error rate of w_max")  # and not 0 (the Key's range takes it)
    if not config["n_elements"] or min(config["n_elements"]) < 2:  # mesh_profile's own minimum
        raise ValueError(f"n_elements must be mesh sizes >= 2, e.g. [25, 100]; got {config['n_elements']!r}")
    for key in ("timing_rtol", "truth_rtol"):
        check_rtol(config[key], key)
    for key in ("timing_twists", "timing_repeats"):
        if config[key] < 1:
            raise ValueError(f"{key} must be >= 1 (a count); got {config[key]!r}")


def _median_time(fn, repeats: int) -> float:
    return median_runtime(fn, repeats)[0]


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    mu = config["mu"]
    rates: dict[str, dict[str, float]] = {}
    actual: dict[str, dict[str, int]] = {}
    t_cont, t_disc_single, t_disc_batch = {}, {}, {}
    rows = []
    for i, (name, surface) in enumerate(tqdm(THESIS_SURFACES.items(), desc="surfaces", unit="surface")):
        s = surface.normalized()
        truth = surface_w_max(s, mu, rtol=config["truth_rtol"])
        rates[name], actual[name] = {}, {}
        for n in config["n_elements"]:
            prof = mesh_profile(surface, n).normalized()
            rate = wrench_error_rate(w_max(prof, mu), truth)
            rates[name][str(n)] = rate
            actual[name][str(n)] = len(prof)
            rows.append([name, n, len(prof), rate])
        # runtime per wrench: continuous (adaptive, <= timing_rtol) vs discrete (1,000 triangles)
        xi = sample_twists_thesis(config["timing_twists"], s.length_scale, config["seed"] + i)
        t_cont[name] = _median_time(
            partial(surface_wrenches, s, xi, mu, rtol=config["timing_rtol"]), config["timing_repeats"]
        ) / len(xi)
        prof = mesh_profile(surface, 1000).normalized()
        t_disc_single[name] = _median_time(
            partial(frictional_wrenches, prof, xi[0], mu), 50 * config["timing_repeats"]
        )
        t_disc_batch[name] = _median_time(
            partial(frictional_wrenches, prof, xi, mu), config["timing_repeats"]
        ) / len(xi)
    write_csv(out / "error_rate.csv", ["surface", "n_target", "n_triangles", "error_rate"], rows)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for name in rates:
        ns = [actual[name][k] for k in rates[name]]
        axes[0].plot(ns, [100 * v for v in rates[name].values()], "o-", ms=3, label=name)
    axes[0].axhline(4.0, color="k", ls="--", lw=0.8)
    axes[0].axvline(300, color="gray", ls=":", lw=0.8)
    axes[0].set_xlabel("number of triangles")
    axes[0].set_ylabel("wrench error rate [%]")
    axes[0].set_yscale("log")
    axes[0].set_title("Fig 3.8: error of w_max vs mesh size (dashed: thesis 4% at 300)")
    axes[0].legend(fontsize=8)
    x = np.arange(len(t_cont))
    axes[1].bar(x - 0.2, [1e3 * v for v in t_cont.values()], 0.4, label="continuous (adaptive, ≤1e-4)")
    axes[1].bar(x + 0.2, [1e3 * v for v in t_disc_single.values()], 0.4, label="discrete, 1,000 triangles")
    axes[1].axhline(2620.0, color="C3", ls="--", lw=0.8, label="thesis MATLAB continuous 2.62 s")
    axes[1].axhline(1.3, color="C2", ls="--", lw=0.8, label="thesis MATLAB discrete 1.3 ms")
    axes[1].set_yscale("log")
    axes[1].set_xticks(x, list(t_cont))
    axes[1].set_ylabel("ms per wrench")
    axes[1].legend(fontsize=7)
    fig_path = save_figure(fig, out / "fig_3_8_error_rate.png")

    worst300 = max(r["300"] for r in rates.values()) if all("300" in r for r in rates.values()) else None
    worst1000 = max(r["1000"] for r in rates.values()) if all("1000" in r for r in rates.values()) else None
    summary = {
        "error_rate": rates,
        "n_triangles_actual": actual,
        "runtime_continuous_s": float(np.mean(list(t_cont.values()))),
        "runtime_discrete_s": float(np.mean(list(t_disc_single.values()))),
        "runtime_continuous_s_per_surface": t_cont,
        "runtime_discrete_s_per_surface": t_disc_single,
        "runtime_discrete_batched_s_per_wrench": t_disc_batch,
        "thesis_runtime_s": {"continuous": 2.62, "discrete": 1.3e-3},
        "max_error_rate_at_300": worst300,
        "max_error_rate_at_1000": worst1000,
        "figures": [str(fig_path)],
        "headline": [
            f"max error rate: {100 * worst300:.2f}% at 300 triangles, {100 * worst1000:.2f}% at 1,000"
            if worst300 is not None and worst1000 is not None
            else "error rates written",
            f"per wrench: continuous {1e3 * np.mean(list(t_cont.values())):.2f} ms (thesis 2,620 ms), "
            f"discrete {1e6 * np.mean(list(t_disc_single.values())):.1f} µs single / "
            f"{1e6 * np.mean(list(t_disc_batch.values())):.2f} µs batched (thesis 1,300 µs)",
        ],
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))
