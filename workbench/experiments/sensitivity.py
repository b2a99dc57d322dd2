"""Sensitivity of grasp-success prediction to model parameters (thesis Fig 4.4; 6DFC Fig 3).

Scene: the thesis's §4.1.3 setting — a parallel-jaw grasp of
an elliptic cylinder (grasp axis x, cylinder axis z), each jaw's contact an
elliptic-cylinder patch with the power-law pressure of Eq. 4.3, μ = 0.3,
grasp forces 20–35 N read by a force sensor, and disturbances from weights hung
at lever arms (``(f_y, τ_x, τ_z)`` plus small off-plane parts).

**Ground truth.**  No physical grasp data exists here, so a grasp's "true"
outcome is wrench resistance computed with the 6DFW of the true profile
(k = 2.4, true contact length) and no limit-surface approximation — exactly, by
column generation over maximum-dissipation support wrenches
(:func:`workbench.grasp.simulated_truth.truth_deciders`; a fixed sample of 6DFWs is an inner
approximation that converges to it from below: 82/83/85 % vs 87 % resisted at
400/1,600/6,400 samples) — with per-grasp perturbations standing in for
physical noise (friction ±5 %, true grasp force ±3 % around the sensor reading).
Every number below is agreement with that simulated truth, not with robot trials.

Series (each model predicts with *its assumed* parameter, the truth stays put):
k of the assumed pressure (Fig 4.4(b)), μ offset (Fig 4.4(c)), contact-length
offset (Fig 4.4(d)), and for the robust metric (6DFC Fig 3) ``q_robust >= 0.5``
of the 6DLS with N_r samples of pose noise σ_r.  Per model: precision, recall
and the median prediction time per grasp.

**Comparable precision.**  Plain predictions trade precision for recall
differently per model (the planar model is optimistic on a curved contact), so
at the true parameters each model's resistance margin s* — the largest scale of
the disturbance it resists, by bisection — is thresholded at every safety
factor t, and recall is compared at precision levels 0.9/0.95/0.98
(``at_matched_precision``, ``precision_recall.png``).  The truth's own margin
gives each model's capacity error ``margin_vs_truth`` (median |log ratio| and
its sign: > 0 optimistic).  ``make reproduce`` also runs a more wrapped contact
(``half_angle=1.0`` → ``results/sensitivity-wrapped``), where nonplanarity matters more.
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.config import SAMPLER_KINDS
from workbench.grasp.lever_scene import scene_inputs, scene_profiles
from workbench.grasp.margin import check_steps, margin_vs_truth
from workbench.grasp.models import MODELS
from workbench.grasp.precision import check_levels, matched_precision, recall_at_least
from workbench.grasp.sensitivity_rows import as_twin, row_inputs, row_key, row_tasks, scored, sensitivity_row
from workbench.grasp.sensitivity_summary import headline, series_tables, training_distribution
from workbench.grasp.simulated_truth import truth_deciders
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import Checkpoint, save_figure, write_csv, write_summary
from workbench.sources.scenes import check_elliptic_cylinder
from workbench.sources.surfaces import check_n_elements

NAME = "sensitivity"

DEFAULT_CONFIG = {
    "seed": 0,
    "mu": 0.3,
    "k_true": 2.4,
    "a": 0.03,  # ellipse semi-axis along the grasp axis [m]
    "b": 0.02,  # semi-axis across [m]
    "half_angle": 0.6,  # the contact's angular half-width [rad]
    "length": 0.03,  # true contact length along the cylinder axis [m]
    "n_elements": 300,
    "n_disturbances": 150,
    "force_range": [20.0, 35.0],
    "noise_mu": 0.05,
    "noise_force": 0.03,
    "truth_start_wrenches": 200,  # starting columns of the exact column generation
    "weight_range": [2.0, 14.0],  # N
    "lever_x": 0.04,  # m, |r_x| (τ_z = −r_x m g)
    "lever_z": 0.025,  # m, |r_z| (τ_x = r_z m g: torsion about the grasp axis)
    "models": [
        "point",
        "soft_point",
        "planar",
        "3dls_nonplanar",
        "6dfw",
        "reach",
        "6dls",
        "6dls_quartic",
        "6dfc",
    ],
    "M": 200,
    "k_values": [1.5, 2.0, 2.4, 4.0, 8.0, 1e6],
    "mu_offsets": [-0.2, -0.1, 0.0, 0.1, 0.2],
    "length_offsets": [-0.3, -0.15, 0.0, 0.15, 0.3],
    "robust_n_r": [1, 5, 10, 20],
    "robust_sigma_r": [0.0005, 0.001, 0.002, 0.004],  # m (rotation σ = σ_r / 0.03 m)
    "robust_disturbances": 80,
    # precision-recall at the true parameters: each model's resistance margin s* (largest
    # scale of the disturbance it resists) thresholded at a safety factor t, to compare
    # recall at matched precision
    "precision_levels": [0.9, 0.95, 0.98],
    "margin_steps": 12,  # bisection steps on log2 s* in [-6, 6] (resolution 2^(12/2^12) ≈ 0.2 %)
    # which training wrenches give the best limit surface for grasp analysis: the
    # margins of these models with limit surfaces trained by each sampler kind (SamplerSpec)
    "training_samplers": ["thesis", "thesis-code", "mix"],
    "training_models": ["6dls", "6dls_quartic"],
    # where the rows run (workbench.runner.parallel.row_client): 0 = a local Dask cluster of one
    # worker per core when there are many rows, 1 = serially here, N = N local workers;
    # scheduler = an existing cluster's address.  Neither changes a number but the timings.
    "workers": 0,
    "scheduler": "",
}
#: what each key means, its unit and plausible range (``workbench run sensitivity --help``)
KEYS = {
    "mu": Key("true friction coefficient, > 0 (thesis §4.1.3: 0.3)", "", "mu"),
    "k_true": Key("true pressure exponent k of Eq. 4.3"),
    # the semi-axes are the contacts' offsets from the cylinder's axis: judged as lever arms
    # (a = 30 is "probably in millimetres"), the half-width as a wrapped contact's (34 is degrees)
    "a": Key("elliptic cylinder semi-axis along the grasp axis", "m", "lever"),
    "b": Key("elliptic cylinder semi-axis across the grasp axis", "m", "lever"),
    "half_angle": Key("the contact's angular half-width, < pi/2", "rad", "half_angle"),
    # the flat pad's length pressed along the cylinder: judged as a pad size
    "length": Key(
        "true contact length along the cylinder axis (the pad's length in contact)", "m", "pad_size"
    ),
    "n_elements": Key("triangles of each jaw's contact, >= 2"),
    "n_disturbances": Key("lever disturbances (grasps) of the series, >= 1"),
    "force_range": Key("grasp forces read by the force sensor, [lo, hi] per jaw", "N", "jaw_force"),
    "noise_mu": Key("truth: relative standard deviation of the friction coefficient", "", "relative_noise"),
    "noise_force": Key(
        "truth: relative standard deviation of the grasp force around the sensor reading",
        "",
        "relative_noise",
    ),
    "truth_start_wrenches": Key("starting columns of the exact column generation"),
    "weight_range": Key("weights hung at the lever arms, [lo, hi]", "N", "weight"),
    "lever_x": Key("lever arm |r_x| (tau_z = -r_x m g)", "m", "lever"),
    "lever_z": Key("lever arm |r_z| (tau_x = r_z m g: torsion about the grasp axis)", "m", "lever"),
    "models": Key("contact models compared, at least one", choices=lambda: MODELS),
    "M": Key("linearisation directions of C_outer (Eq. 3.28)"),
    "k_values": Key("assumed pressure exponents k of Fig 4.4(b)"),
    "mu_offsets": Key("relative offsets x of the assumed mu = mu (1 + x), Fig 4.4(c)"),
    "length_offsets": Key("relative offsets x of the assumed contact length (1 + x), Fig 4.4(d)"),
    "robust_n_r": Key("pose samples N_r of q_robust (6DFC Fig 3)"),
    "robust_sigma_r": Key(
        "pose noise sigma_r of q_robust (rotation sigma = sigma_r / 0.03 m)", "m", "pose_noise_trans"
    ),
    "robust_disturbances": Key("disturbances of the robust metric, in [1, n_disturbances]"),
    "precision_levels": Key("precision levels at which recall is matched, in (0, 1]"),
    "margin_steps": Key("bisection steps on log2 s* in [-6, 6]"),
    "training_samplers": Key(
        "sampler kinds whose limit surfaces are compared", choices=lambda: SAMPLER_KINDS
    ),
    "training_models": Key("models of that comparison, at least one", choices=lambda: MODELS),
}
QUICK_CONFIG = {
    "n_elements": 150,
    "n_disturbances": 40,
    "models": ["point", "soft_point", "planar", "6dls", "6dfc"],
    "M": 100,
    "k_values": [2.0, 8.0],
    "mu_offsets": [-0.2, 0.2],
    "length_offsets": [-0.3, 0.3],
    "robust_n_r": [5],
    "robust_sigma_r": [0.002],
    "robust_disturbances": 20,
    "margin_steps": 8,
    "training_models": ["6dls"],
}


def check_config(config: dict) -> None:
    """Refuse, before the ground truth is computed (``build_config`` calls this), what the run
    would refuse only after minutes of rows: implausible physical numbers, unknown models and
    sampler kinds (:data:`KEYS`: the library's own lists), μ = 0 (frictionless: the truth resists
    none of the disturbances, so every recall is undefined and the μ offsets, relative to μ, all
    collapse to 0), a scene the elliptic-cylinder grasp refuses (half_angle >= pi/2), fewer than
    one bisection step, a mesh of < 2 elements, more robust disturbances than disturbances and
    precision levels outside (0, 1].  Each check is the rule of the function that would raise
    later, called early."""
    for key, spec in KEYS.items():  # also for run(config) called directly
        check_key(key, spec, config[key])
    if config["mu"] == 0:  # the Key's range takes it
        raise ValueError(
            "mu = 0 is a frictionless grasp: the simulated truth resists none of the disturbances, "
            "so every recall is undefined, and the mu offsets (relative to mu) all collapse to 0; "
            "give mu > 0, e.g. --set mu=0.3 (the default)"
        )
    # the scene's own rule (half_angle < pi/2 too), before the cluster starts
    check_elliptic_cylinder(config["a"], config["b"], config["half_angle"], config["length"])
    check_steps(config["margin_steps"], "margin_steps")  # resistance_margin's rule
    check_n_elements(config["n_elements"])
    for key in ("models", "training_models"):
        if not config[key]:
            raise ValueError(f'{key} must name at least one model, e.g. ["6dls"]; got []')
    if config["n_disturbances"] < 1 or not 1 <= config["robust_disturbances"] <= config["n_disturbances"]:
        raise ValueError(
            "n_disturbances must be >= 1 and robust_disturbances in [1, n_disturbances] (the robust "
            f"metric's grasps are the first of them); got {config['n_disturbances']} and "
            f"{config['robust_disturbances']}"
        )
    check_levels(config["precision_levels"])  # matched_precision's rule
    check_workers(config["workers"], config["scheduler"])


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    n = config["n_disturbances"]
    ckpt = Checkpoint(
        out / "rows.jsonl",
        {k: v for k, v in config.items() if k not in ("out", "workers", "scheduler")},
        code=code_digest(__name__),
    )
    n_resumed = len(ckpt.rows)
    # every row (Dask), scored against the ground truth the driver computes meanwhile
    truth, truth_ms, ran_on = _rows_and_truth(ckpt, config)
    # margins at the true parameters: capacity error and recall at matched precision
    margins = {m: np.array(ckpt.rows[f"margin/{m}"]["margins"]) for m in config["models"]}
    true_margin = np.array(ckpt.rows["margin/truth"]["margins"])
    margin_error = {m: margin_vs_truth(s_m, true_margin) for m, s_m in margins.items()}
    matched = {m: matched_precision(s_m, truth, config["precision_levels"]) for m, s_m in margins.items()}
    nominal = np.array(ckpt.rows["margin/truth-nominal"]["margins"])
    training = training_distribution(ckpt.rows, config, truth, true_margin, nominal)
    levels = config["precision_levels"]
    nonplanar = [m for m in ("6dls", "6dfc") if m in matched]
    baselines = [m for m in ("planar", "point") if m in matched]
    nonplanar_ge = recall_at_least(matched, nonplanar, baselines, levels)
    # the parameter series
    rows = [r for r in ckpt.rows.values() if r["series"] != "margin"]
    cols = ["series", "x", "n_r", "sigma_r", "model", "precision", "recall", "positives", "ms_per_grasp"]
    write_csv(out / "sensitivity.csv", cols, [[r.get(c, "") for c in cols] for r in rows])
    series_out = series_tables(ckpt.rows, rows, config)
    ms_model = {
        m: float(np.median([r["ms_per_grasp"] for r in rows if r.get("model") == m]))
        for m in config["models"]
    }
    figures = _figures(out, series_out, matched, config)
    base_row = (
        {m: ckpt.rows[f"k/{config['k_true']}/{m}"] for m in config["models"]}
        if config["k_true"] in config["k_values"]
        else None
    )
    summary = {
        "ground_truth": (
            "simulated: the true profile's 6DFW set (no limit-surface model), membership decided exactly by "
            f"column generation over support wrenches, with per-grasp noise (mu ±{config['noise_mu']:.0%}, "
            f"force ±{config['noise_force']:.0%}); no physical grasp data"
        ),
        "truth_ms_per_grasp": truth_ms,
        "n_disturbances": n,
        "truth_positive_fraction": float(truth.mean()),
        "series": series_out,
        "ms_per_grasp": ms_model,
        "at_true_parameters": base_row,
        "at_matched_precision": {
            "method": "each model's margin s* (largest resisted scale of the disturbance, bisection); "
            "predict s* >= t; per precision level the best recall over t (t = 1: plain prediction)",
            "levels": levels,
            "recall": {m: matched[m]["at_levels"]["recall"] for m in config["models"]},
            "threshold": {m: matched[m]["at_levels"]["threshold"] for m in config["models"]},
            "nonplanar_recall_ge_planar_and_point": nonplanar_ge,
        },
        "margin_vs_truth": margin_error,
        "training_distribution": training,
        "pr_curves": {
            m: {k: matched[m][k] for k in ("threshold", "precision", "recall")} for m in config["models"]
        },
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
        "figures": figures,
    }
    summary["headline"] = headline(
        truth, series_out, ms_model, matched, nonplanar_ge, margin_error, training, config
    )
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _rows_and_truth(ckpt: Checkpoint, config: dict) -> tuple[np.ndarray, float, dict]:
    """The rows not yet in ``ckpt`` run as Dask tasks
    (:func:`~workbench.grasp.sensitivity_rows.sensitivity_row`) while the driver computes the
    ground truth — the true profile's 6DFW set, exactly (column generation), with
    per-grasp noise — that their predictions are scored against before they are checkpointed.
    Returns (truth (n,) bool, its ms per grasp, where the rows ran)."""
    W, _, mu_true, f_true = scene_inputs(config)
    n = len(W)
    same: dict[tuple, list[tuple]] = {}  # inputs -> the rows of them; the first is computed
    for t in row_tasks(config):
        same.setdefault(row_inputs(t, config), []).append(t)

    def copy_to_twins(first: tuple) -> None:  # row `first` as the rows of its twins not yet kept
        for twin in same[row_inputs(first, config)][1:]:
            if row_key(twin) not in ckpt:
                ckpt.add(row_key(twin), as_twin(ckpt.rows[row_key(first)], twin, row_key(first)))

    def keep(task: tuple, row: dict) -> None:
        ckpt.add(row_key(task), row)
        copy_to_twins(task)

    todo = []
    for first, *_ in same.values():
        if row_key(first) in ckpt:  # a resume: the twins a killed run had not copied yet
            copy_to_twins(first)
        else:
            todo.append(first)
    got: dict = {}

    def ground_truth() -> None:
        true_prof = scene_profiles(config, config["k_true"], config["length"])
        deciders = truth_deciders(true_prof, mu_true, f_true, config["truth_start_wrenches"])
        t0 = time.perf_counter()
        got["truth"] = np.array(
            [
                decide(w)
                for decide, w in tqdm(
                    zip(deciders, W, strict=True), total=n, desc="ground truth", unit="grasp"
                )
            ]
        )
        got["truth_ms"] = (time.perf_counter() - t0) / n * 1e3

    with tqdm(total=len(todo), desc="sensitivity", unit="row") as bar:
        _, ran_on = run_rows(
            partial(sensitivity_row, config=config),
            todo,
            lambda task, row: keep(task, scored(row, got["truth"])),
            config,
            progress=bar,
            meanwhile=ground_truth,
        )
    return got["truth"], got["truth_ms"], ran_on


def _figures(out: Path, series_out: dict, matched: dict, config: dict) -> list[str]:
    figures = [str(_plot(out, series_out, config)), str(_plot_pr(out, matched, config))]
    try:
        figures.append(str(_render(out, scene_profiles(config, config["k_true"], config["length"]))))
    except Exception as exc:  # a render is a convenience
        import logging

        logging.getLogger(__name__).warning("offscreen rendering failed: %s", exc)
    return figures


def _plot(out: Path, series: dict, config: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 4, figsize=(17, 7))
    titles = {
        "k": "power-law exponent k (truth 2.4)",
        "mu_offset": "μ offset",
        "length_offset": "contact length offset",
    }
    for j, s in enumerate(("k", "mu_offset", "length_offset")):
        xs = np.array(series[s]["x"], float)
        xplot = np.log10(xs) if s == "k" else 100 * xs
        for m in config["models"]:
            axes[0, j].plot(xplot, series[s][m]["precision"], "o-", label=m)
            axes[1, j].plot(xplot, series[s][m]["recall"], "o-", label=m)
        axes[1, j].set_xlabel("log10 k" if s == "k" else titles[s] + " [%]")
        axes[0, j].set_title(titles[s])
    axes[0, 0].set_ylabel("precision")
    axes[1, 0].set_ylabel("recall")
    rob = series["robust"]
    for n_r in sorted({r["n_r"] for r in rob}):
        sel = [r for r in rob if r["n_r"] == n_r]
        axes[0, 3].plot(
            [1e3 * r["sigma_r"] for r in sel], [r["precision"] for r in sel], "o-", label=f"N_r={n_r}"
        )
        axes[1, 3].plot(
            [1e3 * r["sigma_r"] for r in sel], [r["recall"] for r in sel], "o-", label=f"N_r={n_r}"
        )
    axes[0, 3].set_title("robust 6DLS (q_robust >= 0.5)")
    axes[1, 3].set_xlabel("σ_r [mm]")
    axes[0, 3].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    fig.suptitle("simulated ground truth: exact 6DFW set with per-grasp noise (no physical data)")
    fig.tight_layout()
    return save_figure(fig, out / "fig_4_4_sensitivity.png")


def _plot_pr(out: Path, matched: dict, config: dict) -> Path:
    """Precision-recall curves at the true parameters (threshold on the margin s*),
    the plain predictions (t = 1) marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 5))
    for j, (m, c) in enumerate(matched.items()):
        label = m if c["recall"] else f"{m} (resists none)"
        ls = "--" if m == "6dfc" else "-"  # 6DFC coincides with the 6DLS here
        ax.step(c["recall"], c["precision"], ls, where="post", color=f"C{j}", label=label)
        t = np.array(c["threshold"])
        if len(t):
            i = int(np.searchsorted(t, 1.0))  # the smallest threshold >= 1
            if i < len(t):
                ax.plot(c["recall"][i], c["precision"][i], "o", color=f"C{j}")
    for lv in config["precision_levels"]:
        ax.axhline(lv, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_xlim(0.6, 1.01)
    ax.set_ylim(0.6, 1.005)
    ax.set_title("true parameters: threshold t on the resistance margin (dot: t = 1)", fontsize=9)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    return save_figure(fig, out / "precision_recall.png")


def _render(out: Path, profiles: list) -> Path:
    """Both jaws' contact profiles on the elliptic cylinder (pressure colour), offscreen."""
    from workbench.runner.viz import _pyvista, profile_polydata, save_screenshot

    pv = _pyvista()
    pl = pv.Plotter(off_screen=True, window_size=(640, 480))
    # plotting constants: the cylinder a little inside the default a = 0.03, b = 0.02 m so the
    # patches on it stay visible, 6 cm tall; the jaw arrows 2 cm long, 6 cm out on the grasp axis
    cyl = pv.Cylinder(radius=1.0, height=0.06, direction=(0, 0, 1), resolution=64).scale(
        [0.0298, 0.0198, 1.0]
    )
    pl.add_mesh(cyl, color="lightgray", opacity=0.35)
    for p in profiles:
        pl.add_mesh(profile_polydata(p), scalars="pressure", cmap="viridis", show_scalar_bar=p is profiles[0])
    pl.add_arrows(
        np.array([[0.06, 0, 0], [-0.06, 0, 0]]),
        np.array([[-1.0, 0, 0], [1.0, 0, 0]]),
        mag=0.02,
        color="black",
        show_scalar_bar=False,
    )
    pl.camera_position = "iso"
    return save_screenshot(pl, out / "example_grasp.png")


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))
