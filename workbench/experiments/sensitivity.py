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
(:mod:`workbench.grasp.exact`; a fixed sample of 6DFWs is an inner
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
from functools import lru_cache, partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.config import SAMPLER_KINDS
from workbench.grasp import CutStore, Perturbation, q_robust, resists
from workbench.grasp.exact import ExactContacts, resists_exact
from workbench.grasp.margin import check_steps, margin_vs_truth, resistance_margin
from workbench.grasp.models import MODELS, contact_sets
from workbench.grasp.precision import check_levels, matched_precision, recall_at_least, scores
from workbench.grasp.tasks import lever_disturbances
from workbench.limit_surface import LimitSurfaceCache, SamplerSpec
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import Checkpoint, save_figure, write_csv, write_summary
from workbench.sources.scenes import check_elliptic_cylinder, elliptic_cylinder_grasp
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


def _profiles(config: dict, k: float, length: float) -> list:
    return elliptic_cylinder_grasp(
        config["a"], config["b"], config["half_angle"], length, k, 1.0, config["n_elements"]
    )


def _sets(profiles, model: str, cache: LimitSurfaceCache, config: dict, sampler: str | None = None) -> list:
    spec = None if sampler is None else SamplerSpec(kind=sampler)
    return [c for p in profiles for c in contact_sets(p, model, cache=cache, M=config["M"], sampler=spec)]


def _predict(sets, W, forces, mu, cuts: CutStore) -> tuple[np.ndarray, float]:
    out, times = [], []
    for w, f in zip(W, forces, strict=True):
        t0 = time.perf_counter()
        out.append(bool(resists([c.with_force(c.force * f) for c in sets], w, mu, cuts=cuts)))
        times.append(time.perf_counter() - t0)
    return np.array(out), float(np.median(times) * 1e3)


def _margin_row(model: str, deciders, W: np.ndarray, steps: int) -> dict:
    """Checkpoint row of the margins of ``W`` (N, 6), one decider ``v -> bool`` per
    disturbance, and the time per disturbance."""
    t0 = time.perf_counter()
    margins = [resistance_margin(d, w, steps) for d, w in zip(deciders, W, strict=True)]
    return {
        "series": "margin",
        "model": model,
        "margins": margins,
        "s_per_grasp": (time.perf_counter() - t0) / len(W),
    }


def _model_margin_row(model: str, sets: list, forces: np.ndarray, W: np.ndarray, config: dict, cuts) -> dict:
    """Margin row of a model's contact sets, scaled by each disturbance's force reading."""
    grasps = [[c.with_force(c.force * f) for c in sets] for f in forces]
    deciders = [partial(resists, g, mu=config["mu"], cuts=cuts) for g in grasps]
    return _margin_row(model, deciders, W, config["margin_steps"])


def _training_distribution(config, ckpt, truth, true_margin, nominal) -> dict:
    """Margins of ``training_models`` with limit surfaces trained by each of
    ``training_samplers`` (rows ``margin/<model>@<kind>``): the capacity error against the
    noise-free exact margin ``nominal`` (the limit surface's own error — the noisy truth's
    margins differ from it by ~4 % median, which would hide it), against the noisy truth,
    and recall at matched precision."""
    out = {}
    for model in config["training_models"]:
        out[model] = {}
        for kind in config["training_samplers"]:
            s_m = np.array(ckpt.rows[f"margin/{model}@{kind}"]["margins"])
            pr = matched_precision(s_m, truth, config["precision_levels"])
            out[model][kind] = {
                "vs_exact_nominal": margin_vs_truth(s_m, nominal),
                "vs_noisy_truth": margin_vs_truth(s_m, true_margin),
                "recall_at_precision": dict(
                    zip(map(str, config["precision_levels"]), pr["at_levels"]["recall"], strict=True)
                ),
            }
    return out


def _inputs(config: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The disturbances W (n, 6), sensor forces (n,), and the noisy true μ and force
    factor (n,) of every grasp — from the seed, the same in the driver and each worker."""
    rng = np.random.default_rng(config["seed"])
    n = config["n_disturbances"]
    W = lever_disturbances(rng, n, config["weight_range"], config["lever_x"], config["lever_z"])
    forces = rng.uniform(*config["force_range"], n)  # sensor readings
    mu_true = config["mu"] * (1 + config["noise_mu"] * rng.standard_normal(n))
    f_true = forces * (1 + config["noise_force"] * rng.standard_normal(n))
    return W, forces, mu_true, f_true


@lru_cache(maxsize=1)
def _process_cache() -> LimitSurfaceCache:
    """The limit surfaces of this process (driver or Dask worker), shared by its rows: the
    fits are deterministic, so a row's numbers do not depend on what ran before it here."""
    return LimitSurfaceCache()


def _row_tasks(config: dict) -> list[tuple]:
    """Every checkpointed row as a task, the longest (margin bisections) first."""
    tasks: list[tuple] = [("margin", m, None) for m in config["models"]]
    tasks += [("margin", m, k) for m in config["training_models"] for k in config["training_samplers"]]
    tasks += [("truth", "truth"), ("truth", "truth-nominal")]
    tasks += [
        ("setting", series, x, m)
        for series, key in (
            ("k", "k_values"),
            ("mu_offset", "mu_offsets"),
            ("length_offset", "length_offsets"),
        )
        for x in config[key]
        for m in config["models"]
    ]
    tasks += [("robust", n_r, sigma) for n_r in config["robust_n_r"] for sigma in config["robust_sigma_r"]]
    return tasks


def _inputs_of(task: tuple, config: dict) -> tuple:
    """What a row computes from: rows with the same inputs are computed once (:func:`_rows_and_truth`)
    — a margin with the default training sampler (``config.DEFAULTS.ls_training_sampler``) is
    the training-sampler row of that kind, and the zero μ and length offsets are the k-series
    row at ``k_true``."""
    kind = task[0]
    if kind == "margin":
        return ("margin", task[1], SamplerSpec(kind=task[2]))  # kind None: the default's
    if kind == "setting":
        _, series, x, model = task
        k = x if series == "k" else config["k_true"]
        length = config["length"] * (1 + x) if series == "length_offset" else config["length"]
        mu = config["mu"] * (1 + x) if series == "mu_offset" else config["mu"]
        return ("setting", k, length, mu, model)
    return task


def _as(row: dict, task: tuple, source: str) -> dict:
    """Row ``row`` (checkpointed for ``source``) as the row of ``task``, which has its inputs."""
    row = {k: v for k, v in row.items() if k not in ("key", "config_hash")}
    if task[0] == "setting":
        row.update(series=task[1], x=task[2])
    return {**row, "same_inputs_as": source}


def _key(task: tuple) -> str:
    kind = task[0]
    if kind == "margin":
        return f"margin/{task[1]}" + (f"@{task[2]}" if task[2] else "")
    if kind == "truth":
        return f"margin/{task[1]}"
    if kind == "setting":
        return f"{task[1]}/{task[2]}/{task[3]}"
    return f"robust/{task[1]}/{task[2]}"


def _row(task: tuple, config: dict) -> dict:
    """One row, in the driver or a Dask worker, with its own cut store (and exact contacts):
    margins, a setting's predictions or the robust metric's.  Predictions come back as
    ``pred`` (bool list): the driver scores them against the ground truth."""
    W, forces, mu_true, f_true = _inputs(config)
    cuts, cache = CutStore(), _process_cache()
    kind = task[0]
    if kind == "setting":  # its own profile; every other row is at the true one
        _, series, x, model = task
        k = x if series == "k" else config["k_true"]
        length = config["length"] * (1 + x) if series == "length_offset" else config["length"]
        mu = config["mu"] * (1 + x) if series == "mu_offset" else config["mu"]
        t0 = time.perf_counter()
        sets = _sets(_profiles(config, k, length), model, cache, config)
        build_s = time.perf_counter() - t0
        pred, ms = _predict(sets, W, forces, mu, cuts)
        return {
            "series": series,
            "x": x,
            "model": model,
            "pred": pred.tolist(),
            "ms_per_grasp": ms,
            "build_s": build_s,
        }
    true_prof = _profiles(config, config["k_true"], config["length"])
    if kind == "margin":
        _, model, sampler = task
        return _model_margin_row(
            model, _sets(true_prof, model, cache, config, sampler), forces, W, config, cuts
        )
    if kind == "truth":
        exact = ExactContacts(true_prof, n_start=config["truth_start_wrenches"], seed=1)
        if task[1] == "truth":  # the simulated truth's own margin (the noise of the truth)
            deciders = [
                lambda v, f=f, m=m: resists_exact(exact, v, m, forces=exact.F * f)[0]
                for f, m in zip(f_true, mu_true, strict=True)
            ]
        else:  # no noise: the sensor force and nominal μ, exactly
            deciders = [
                lambda v, f=f: resists_exact(exact, v, config["mu"], forces=exact.F * f)[0] for f in forces
            ]
        return _margin_row(task[1], deciders, W, config["margin_steps"])
    _, n_r, sigma = task  # robust metric (6DFC paper Fig 3): q_robust >= 0.5 under pose noise
    nr = config["robust_disturbances"]
    base = _sets(true_prof, "6dls", cache, config)
    # pose noise only; the rotation σ is σ_r over a 3 cm lever (the contact's size: a = length = 0.03 m)
    p = Perturbation(
        n_samples=n_r, sigma_trans=sigma, sigma_rot=sigma / 0.03, sigma_mu=0.0, sigma_mass=0.0, sigma_com=0.0
    )
    t0 = time.perf_counter()
    pred = [
        q_robust(
            [c.with_force(c.force * forces[i]) for c in base],
            config["mu"],
            1.0,  # unused: the disturbance is W[i]
            np.zeros(3),
            p,
            seed=i,
            cuts=cuts,
            w_ext=W[i],
        )
        >= 0.5  # the 6DFC paper's success threshold on q_robust (a fraction of the samples)
        for i in range(nr)
    ]
    ms = (time.perf_counter() - t0) / nr * 1e3
    return {
        "series": "robust",
        "n_r": n_r,
        "sigma_r": sigma,
        "model": "6dls robust",
        "pred": pred,
        "ms_per_grasp": ms,
    }


def _scored(row: dict, truth: np.ndarray) -> dict:
    """A row as checkpointed: its predictions scored against the truth (margins as they are)."""
    if "pred" not in row:
        return row
    pred = np.array(row.pop("pred"), dtype=bool)
    return {**row, **scores(pred, truth[: len(pred)])}


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
    training = _training_distribution(config, ckpt, truth, true_margin, nominal)
    levels = config["precision_levels"]
    nonplanar = [m for m in ("6dls", "6dfc") if m in matched]
    baselines = [m for m in ("planar", "point") if m in matched]
    nonplanar_ge = recall_at_least(matched, nonplanar, baselines, levels)
    # the parameter series
    rows = [r for r in ckpt.rows.values() if r["series"] != "margin"]
    cols = ["series", "x", "n_r", "sigma_r", "model", "precision", "recall", "positives", "ms_per_grasp"]
    write_csv(out / "sensitivity.csv", cols, [[r.get(c, "") for c in cols] for r in rows])
    series_out = _series(ckpt, rows, config)
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
    summary["headline"] = _headline(
        truth, series_out, ms_model, matched, nonplanar_ge, margin_error, training, config
    )
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _rows_and_truth(ckpt: Checkpoint, config: dict) -> tuple[np.ndarray, float, dict]:
    """The rows not yet in ``ckpt`` run as Dask tasks (:func:`_row`) while the driver computes
    the ground truth — the true profile's 6DFW set, exactly (column generation), with
    per-grasp noise — that their predictions are scored against before they are checkpointed.
    Returns (truth (n,) bool, its ms per grasp, where the rows ran)."""
    W, _, mu_true, f_true = _inputs(config)
    n = len(W)
    same: dict[tuple, list[tuple]] = {}  # inputs -> the rows of them; the first is computed
    for t in _row_tasks(config):
        same.setdefault(_inputs_of(t, config), []).append(t)

    def copy_to_twins(first: tuple) -> None:  # row `first` as the rows of its twins not yet kept
        for twin in same[_inputs_of(first, config)][1:]:
            if _key(twin) not in ckpt:
                ckpt.add(_key(twin), _as(ckpt.rows[_key(first)], twin, _key(first)))

    def keep(task: tuple, row: dict) -> None:
        ckpt.add(_key(task), row)
        copy_to_twins(task)

    todo = []
    for first, *_ in same.values():
        if _key(first) in ckpt:  # a resume: the twins a killed run had not copied yet
            copy_to_twins(first)
        else:
            todo.append(first)
    got: dict = {}

    def ground_truth() -> None:
        true_prof = _profiles(config, config["k_true"], config["length"])
        exact = ExactContacts(true_prof, n_start=config["truth_start_wrenches"], seed=1)
        t0 = time.perf_counter()
        got["truth"] = np.array(
            [
                resists_exact(exact, w, m, forces=exact.F * f)[0]
                for w, f, m in tqdm(
                    zip(W, f_true, mu_true, strict=True), total=n, desc="ground truth", unit="grasp"
                )
            ]
        )
        got["truth_ms"] = (time.perf_counter() - t0) / n * 1e3

    with tqdm(total=len(todo), desc="sensitivity", unit="row") as bar:
        _, ran_on = run_rows(
            partial(_row, config=config),
            todo,
            lambda task, row: keep(task, _scored(row, got["truth"])),
            config,
            progress=bar,
            meanwhile=ground_truth,
        )
    return got["truth"], got["truth_ms"], ran_on


def _series(ckpt: Checkpoint, rows: list[dict], config: dict) -> dict:
    """Precision and recall per model along each parameter series, and the robust metric's rows."""
    series_out = {}
    for s, key in (("k", "k_values"), ("mu_offset", "mu_offsets"), ("length_offset", "length_offsets")):
        xs = config[key]
        series_out[s] = {
            "x": xs,
            **{
                m: {
                    "precision": [ckpt.rows[f"{s}/{x}/{m}"]["precision"] for x in xs],
                    "recall": [ckpt.rows[f"{s}/{x}/{m}"]["recall"] for x in xs],
                }
                for m in config["models"]
            },
        }
    # in (n_r, sigma_r) order, not the checkpoint's (the order the tasks finished in)
    series_out["robust"] = sorted(
        (
            {k: r[k] for k in ("n_r", "sigma_r", "precision", "recall", "ms_per_grasp")}
            for r in rows
            if r["series"] == "robust"
        ),
        key=lambda r: (r["n_r"], r["sigma_r"]),
    )
    return series_out


def _figures(out: Path, series_out: dict, matched: dict, config: dict) -> list[str]:
    figures = [str(_plot(out, series_out, config)), str(_plot_pr(out, matched, config))]
    try:
        figures.append(str(_render(out, _profiles(config, config["k_true"], config["length"]))))
    except Exception as exc:  # a render is a convenience
        import logging

        logging.getLogger(__name__).warning("offscreen rendering failed: %s", exc)
    return figures


def _num(value, spec: str) -> str:
    """``value`` formatted by ``spec``, or ``n/a`` where it is undefined: a recall with no
    positive truth, a precision with no positive prediction (NaN in a fresh row, None once
    checkpointed as JSON)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return "n/a"
    return format(value, spec)


def _headline(
    truth, series_out, ms_model, matched, nonplanar_ge, margin_error, training, config
) -> list[str]:
    """The summary's headline lines; undefined numbers (None or NaN) read ``n/a``."""
    levels = config["precision_levels"]
    return [
        f"truth: {_num(truth.mean(), '.0%')} of {len(truth)} disturbances resisted "
        "(simulated truth, exact 6DFW set)",
        *(
            f"{m}: recall vs k [{', '.join(_num(v, '.2f') for v in series_out['k'][m]['recall'])}], "
            f"{_num(ms_model[m], '.2f')} ms/grasp"
            for m in config["models"]
        ),
        "recall at matched precision "
        + "; ".join(
            f"P>={lv}: "
            + ", ".join(f"{m} {_num(matched[m]['at_levels']['recall'][j], '.2f')}" for m in config["models"])
            for j, lv in enumerate(levels)
        ),
        f"6DLS/6DFC recall >= planar and point at matched precision: {nonplanar_ge}",
        "resistance margin vs the truth's, median |log ratio| (bias): "
        + ", ".join(
            f"{m} {_num(e['median_abs_log_ratio'], '.3f')} ({_num(e['median_log_ratio'], '+.3f')})"
            for m, e in margin_error.items()
        ),
        *(
            f"training wrenches of {m}, margin vs the noise-free exact margin, median |log ratio| "
            "(bias): "
            + ", ".join(
                f"{k} {_num(e['vs_exact_nominal']['median_abs_log_ratio'], '.4f')} "
                f"({_num(e['vs_exact_nominal']['median_log_ratio'], '+.4f')})"
                for k, e in by.items()
            )
            for m, by in training.items()
        ),
    ]


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
