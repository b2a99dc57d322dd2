"""Example 3.2.5, Table 3.2 (S1, same rows for S2-S6), exact w_max, PCA of sampled wrenches, Fig 3.3 renders.

Thesis §3.2.5 and §3.5.1.1.  Continuous surfaces are integrated adaptively
(workbench.sources.surfaces); ``w_max`` is the exact support function from the six
canonical twists; PCA uses normalised wrenches ``ŵ = w ⊘ w_max`` (Eq. 3.10)
of thesis-sampled twists (§3.3.2).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench import config as settings  # `config` is the run's dict here
from workbench import project_to_plane, sample_twists_thesis, surface_moments, surface_w_max, surface_wrenches
from workbench.limit_surface.normalize import wrench_pca
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.results import save_figure, write_csv, write_summary
from workbench.sources.surface_catalog import PLANAR_NORMAL, THESIS_SURFACES, example_3_2_5
from workbench.sources.surfaces import check_rtol, mesh_profile
from workbench.twists import twists_from_plucker
from workbench.wrench import check_mu

NAME = "parametric-surfaces"

DEFAULT_CONFIG = {
    "seed": 0,
    "mu": 1.0,  # §3.5.1: μ = 1, normalised uniform pressure
    "example_mu": 0.3,  # §3.2.5
    "quad_rtol": 1e-7,  # w_max / example accuracy (scaled error)
    "n_pca": 1000,  # Fibonacci directions -> 2n twists (rotations + translations)
    "pca_rtol": 1e-4,  # quadrature tolerance for the PCA wrenches
    "figure_surfaces": list(THESIS_SURFACES),
    "figure_elements": 500,
}
QUICK_CONFIG = {"n_pca": 120, "figure_surfaces": ["S1"], "quad_rtol": 1e-6}
#: what each key means, its unit and plausible range (``workbench run parametric-surfaces --help``)
KEYS = {
    "mu": Key("friction coefficient of Table 3.2's w_max, > 0 (thesis §3.5.1: 1)", "", "mu"),
    "example_mu": Key("friction coefficient of Example 3.2.5's wrench, > 0 (thesis: 0.3)", "", "mu"),
    "quad_rtol": Key("relative accuracy of w_max and the example (adaptive quadrature), > 0"),
    "n_pca": Key("Fibonacci directions of the PCA wrenches (2 n twists: rotations and translations)"),
    "pca_rtol": Key("relative accuracy of the PCA wrenches, > 0"),
    "figure_surfaces": Key("thesis surfaces drawn", choices=lambda: tuple(THESIS_SURFACES)),
    "figure_elements": Key("triangles of each drawn surface's mesh"),
}

THESIS_TABLE_3_2 = {
    "6d_nonplanar": [0.64, 0.64, 1.00, 0.34, 0.69, 0.59],
    "3d_nonplanar": [0.64, 0.00, 1.00, 0.00, 0.69, 0.00],
    "planar": [1.00, 0.00, 1.00, 0.00, 0.59, 0.00],
}
THREE_D_MASK = np.array([1.0, 0.0, 1.0, 0.0, 1.0, 0.0])  # thesis ref. [4]: keep f_x, f_z, τ_y
COMPONENTS = ["f_x", "f_y", "f_z", "tau_x", "tau_y", "tau_z"]


def check_config(config: dict) -> None:
    """What the defaults cannot tell, before any work (``build_config``): μ > 0, known
    figure surfaces and quadrature tolerances > 0."""
    for key, spec in KEYS.items():  # μ and the surface names (also for run(config))
        check_key(key, spec, config[key])
    check_mu(config["mu"], what="Table 3.2's w_max")  # and not 0 (the Key's range takes it)
    check_mu(config["example_mu"], what="Example 3.2.5's wrench")
    for key in ("quad_rtol", "pca_rtol"):  # named by the key, not as the quadrature's rtol mid-run
        check_rtol(config[key], key)


def example(config: dict) -> dict:
    """Example 3.2.5: o, F, w⊥ and the wrench of e = [0, -1, 0], m = 0, h = 0."""
    ex = example_3_2_5()
    mom = surface_moments(ex)
    xi = twists_from_plucker([0.0, -1.0, 0.0], [0.0, 0.0, 0.0], 0.0)[0]
    t0 = time.perf_counter()
    w, err = surface_wrenches(ex, xi, config["example_mu"], rtol=config["quad_rtol"], return_error=True)
    return {
        "pressure_center": mom.pressure_center,
        "F": mom.F,
        "normal_wrench": mom.normal_wrench,
        "frictional_wrench": w,
        # relative: scaled by μF (forces) and μF·l_s (torques), so it does not grow with μ
        "frictional_wrench_error_estimate": err,
        "normalized_pressure": 1.0 / mom.area,
        "runtime_s": time.perf_counter() - t0,
    }


def table_rows(surface, config: dict) -> dict:
    """The three Table 3.2 rows for one surface (normalised uniform pressure)."""
    six = surface_w_max(surface.normalized(), config["mu"], rtol=config["quad_rtol"])
    planar = surface_w_max(
        project_to_plane(surface, PLANAR_NORMAL).normalized(), config["mu"], rtol=config["quad_rtol"]
    )
    return {"6d_nonplanar": six, "3d_nonplanar": six * THREE_D_MASK, "planar": planar}


def pca(surface, w_max_exact: np.ndarray, config: dict, seed: int) -> dict:
    """PCA of normalised wrenches ŵ = w ⊘ w_max (Eq. 3.10) of thesis-sampled twists
    (:func:`workbench.limit_surface.normalize.wrench_pca`)."""
    s = surface.normalized()
    xi = sample_twists_thesis(config["n_pca"], s.length_scale, seed)
    t0 = time.perf_counter()
    w = surface_wrenches(s, xi, config["mu"], rtol=config["pca_rtol"])
    dt = time.perf_counter() - t0
    res = wrench_pca(
        w,
        w_max_exact,
        retained_variance=settings.TOL.pca_retained_variance,
        significant_fraction=settings.TOL.pca_significant_fraction,
    )
    return {
        "explained_variance_ratio": res.explained_variance_ratio,
        "n_significant": res.n_retained,
        "n_above_fraction": res.n_above_fraction,
        "w_max_sampled": np.abs(w).max(axis=0),
        "n_twists": len(xi),
        "seconds_per_wrench": dt / len(xi),
    }


def figures(config: dict, out: Path, rows: dict, pcas: dict) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from workbench.runner.viz import render_friction_arrows

    written = []
    # Table 3.2 for S1 as grouped bars, thesis values as markers
    fig, ax = plt.subplots(figsize=(7, 3.2))
    x = np.arange(6)
    for j, (model, vals) in enumerate(rows["S1"].items()):
        ax.bar(x + (j - 1) * 0.27, vals, 0.27, label=model.replace("_", " "))
        ax.plot(x + (j - 1) * 0.27, THESIS_TABLE_3_2[model], "k_", ms=10)
    ax.set_xticks(x, [c.replace("tau", "τ") for c in COMPONENTS])
    ax.set_ylabel("w_max (normalised, μ = 1)")
    ax.set_title("Table 3.2, S1 (bars: this workbench, black ticks: thesis)")
    ax.legend(fontsize=8)
    written.append(str(save_figure(fig, out / "table_3_2_S1.png")))
    # PCA spectra
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for j, (name, res) in enumerate(pcas.items()):
        ax.bar(np.arange(1, 7) + (j - 2.5) * 0.13, res["explained_variance_ratio"], 0.13, label=name)
    ax.axhline(settings.TOL.pca_significant_fraction, color="k", ls="--", lw=0.8, label="1% of variance")
    ax.set_yscale("log")
    ax.set_xlabel("principal component")
    ax.set_ylabel("explained variance ratio")
    ax.set_title("PCA of sampled normalised 6D frictional wrenches")
    ax.legend(fontsize=7, ncol=4)
    written.append(str(save_figure(fig, out / "pca_explained_variance.png")))
    # Fig 3.3-style renders: rotation about -y through o, translation along -z
    twists = {
        "(a) rotation about -y": np.array([0, 0, 0, 0, -1.0, 0]),
        "(b) translation along -z": np.array([0, 0, -1.0, 0, 0, 0]),
    }
    surfaces = {"example-3.2.5": example_3_2_5(), **THESIS_SURFACES}
    for name in ["example-3.2.5", *config["figure_surfaces"]]:
        prof = mesh_profile(surfaces[name], config["figure_elements"])
        written.append(str(render_friction_arrows(prof, twists, out / f"friction_{name}.png", title=name)))
    return written


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    ex = example(config)
    rows, w_exact, pcas = {}, {}, {}
    for i, (name, surface) in enumerate(tqdm(THESIS_SURFACES.items(), desc="surfaces", unit="surface")):
        rows[name] = table_rows(surface, config)
        w_exact[name] = rows[name]["6d_nonplanar"]
        pcas[name] = pca(surface, w_exact[name], config, config["seed"] + i)
    dev = {m: float(np.abs(np.asarray(rows["S1"][m]) - THESIS_TABLE_3_2[m]).max()) for m in THESIS_TABLE_3_2}
    write_csv(
        out / "table_3_2.csv",
        ["surface", "model", *COMPONENTS],
        [[s, m, *np.round(v, 6)] for s, r in rows.items() for m, v in r.items()],
    )
    write_csv(
        out / "pca.csv",
        ["surface", "n_retain_99pct", "n_above_1pct", *[f"pc{k}" for k in range(1, 7)]],
        [
            [s, r["n_significant"], r["n_above_fraction"], *r["explained_variance_ratio"]]
            for s, r in pcas.items()
        ],
    )
    figs = figures(config, out, rows, pcas)
    summary = {
        "example_3_2_5": ex,
        "table_3_2": rows["S1"],
        "table_3_2_thesis": THESIS_TABLE_3_2,
        "table_3_2_max_abs_deviation": dev,
        "table_3_2_all_surfaces": rows,
        "w_max_exact": w_exact,
        "w_max_sampled": {s: r["w_max_sampled"] for s, r in pcas.items()},
        "pca_components": {s: r["n_significant"] for s, r in pcas.items()},
        "pca_explained_variance_ratio": {s: r["explained_variance_ratio"] for s, r in pcas.items()},
        "pca_rule": f"smallest k retaining {settings.TOL.pca_retained_variance:.0%} of the variance",
        "pca_components_above_1pct": {s: r["n_above_fraction"] for s, r in pcas.items()},
        "pca_significance_fraction": settings.TOL.pca_significant_fraction,
        "continuous_seconds_per_wrench": {s: r["seconds_per_wrench"] for s, r in pcas.items()},
        "figures": figs,
        "headline": [
            f"Example 3.2.5: o = {np.round(ex['pressure_center'], 4).tolist()}, F = {ex['F']:.4f}, "
            f"w_perp_y = {ex['normal_wrench'][1]:.4f}, tau_y = {ex['frictional_wrench'][4]:.4f}",
            f"Table 3.2 S1 6D = {np.round(rows['S1']['6d_nonplanar'], 2).tolist()} "
            f"(max |dev| vs thesis over 3 rows: {max(dev.values()):.4f})",
            "PCA components retaining 99% of variance: "
            + str({s: r["n_significant"] for s, r in pcas.items()})
            + "; each >= 1%: "
            + str({s: r["n_above_fraction"] for s, r in pcas.items()}),
        ],
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))
