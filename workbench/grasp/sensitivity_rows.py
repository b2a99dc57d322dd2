"""The rows of the sensitivity study (thesis Fig 4.4; 6DFC Fig 3) on the lever scene of
:mod:`.lever_scene`: each a task tuple, a checkpoint key and a computation that needs only the
task and the config, so rows run in any order, in any process, with the same numbers.

Tasks (``config`` as in :mod:`.lever_scene`, plus the experiment's series keys):

- ``("margin", model, sampler)`` — a model's resistance margins s* at the true parameters
  (:func:`~.margin.resistance_margin`), its limit surfaces trained by sampler kind ``sampler``
  (None: the configured default); key ``margin/<model>`` or ``margin/<model>@<sampler>``;
- ``("truth", "truth" | "truth-nominal")`` — the margins of the exact 6DFW set
  (:func:`~.simulated_truth.truth_deciders`) at each grasp's noisy true μ and force, or
  noise-free at the sensor force and nominal μ; key ``margin/truth`` / ``margin/truth-nominal``;
- ``("setting", series, x, model)`` — a model's plain predictions with *its assumed* parameter
  (series ``k``, ``mu_offset`` or ``length_offset`` at value x); key ``<series>/<x>/<model>``;
- ``("robust", n_r, sigma_r)`` — the 6DLS's q_robust >= 0.5 under pose noise (6DFC Fig 3);
  key ``robust/<n_r>/<sigma_r>``.

Predictions come back as ``pred`` (bool list) for the driver to score (:func:`scored`) against
the ground truth before they are checkpointed.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from functools import lru_cache, partial

import numpy as np

from ..limit_surface import LimitSurfaceCache, SamplerSpec
from ..profile import ContactProfile
from .contacts import ContactSet
from .lever_scene import predict_resisted, scene_inputs, scene_profiles, scene_sets
from .margin import resistance_margin
from .precision import scores
from .resistance import CutStore, resists
from .robust import Perturbation, q_robust
from .simulated_truth import truth_deciders

__all__ = [
    "as_twin",
    "margin_row",
    "model_margin_row",
    "process_cache",
    "row_inputs",
    "row_key",
    "row_tasks",
    "scored",
    "sensitivity_row",
    "setting_parameters",
]

#: the parameter series of Fig 4.4 (b)–(d): series name -> the config key of its values
SERIES = (("k", "k_values"), ("mu_offset", "mu_offsets"), ("length_offset", "length_offsets"))


def margin_row(model: str, deciders: Sequence[Callable], W: np.ndarray, steps: int) -> dict:
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


def model_margin_row(
    model: str, sets: Sequence[ContactSet], forces: np.ndarray, W: np.ndarray, config: Mapping, cuts: CutStore
) -> dict:
    """Margin row of a model's contact sets (at unit force), scaled by each disturbance's force
    reading ``forces`` (n,), at the nominal ``config["mu"]`` and ``config["margin_steps"]``."""
    grasps = [[c.with_force(c.force * f) for c in sets] for f in forces]
    deciders = [partial(resists, g, mu=config["mu"], cuts=cuts) for g in grasps]
    return margin_row(model, deciders, W, config["margin_steps"])


@lru_cache(maxsize=1)
def process_cache() -> LimitSurfaceCache:
    """The limit surfaces of this process (driver or Dask worker), shared by its rows: the
    fits are deterministic, so a row's numbers do not depend on what ran before it here."""
    return LimitSurfaceCache()


def row_tasks(config: Mapping) -> list[tuple]:
    """Every checkpointed row as a task, the longest (margin bisections) first."""
    tasks: list[tuple] = [("margin", m, None) for m in config["models"]]
    tasks += [("margin", m, k) for m in config["training_models"] for k in config["training_samplers"]]
    tasks += [("truth", "truth"), ("truth", "truth-nominal")]
    tasks += [
        ("setting", series, x, m) for series, key in SERIES for x in config[key] for m in config["models"]
    ]
    tasks += [("robust", n_r, sigma) for n_r in config["robust_n_r"] for sigma in config["robust_sigma_r"]]
    return tasks


def setting_parameters(task: tuple, config: Mapping) -> tuple[float, float, float]:
    """(k, contact length [m], μ) a setting task ``("setting", series, x, model)`` assumes:
    its series' parameter at x, the others true."""
    _, series, x, _ = task
    k = x if series == "k" else config["k_true"]
    length = config["length"] * (1 + x) if series == "length_offset" else config["length"]
    mu = config["mu"] * (1 + x) if series == "mu_offset" else config["mu"]
    return k, length, mu


def row_inputs(task: tuple, config: Mapping) -> tuple:
    """What a row computes from: rows with the same inputs are computed once — a margin with
    the default training sampler (``config.DEFAULTS.ls_training_sampler``) is the
    training-sampler row of that kind, and the zero μ and length offsets are the k-series row
    at ``k_true``."""
    kind = task[0]
    if kind == "margin":
        return ("margin", task[1], SamplerSpec(kind=task[2]))  # kind None: the default's
    if kind == "setting":
        return ("setting", *setting_parameters(task, config), task[3])
    return task


def as_twin(row: Mapping, task: tuple, source: str) -> dict:
    """Row ``row`` (checkpointed for ``source``) as the row of ``task``, which has its inputs."""
    row = {k: v for k, v in row.items() if k not in ("key", "config_hash")}
    if task[0] == "setting":
        row.update(series=task[1], x=task[2])
    return {**row, "same_inputs_as": source}


def row_key(task: tuple) -> str:
    """The checkpoint key of a task (module docstring)."""
    kind = task[0]
    if kind == "margin":
        return f"margin/{task[1]}" + (f"@{task[2]}" if task[2] else "")
    if kind == "truth":
        return f"margin/{task[1]}"
    if kind == "setting":
        return f"{task[1]}/{task[2]}/{task[3]}"
    return f"robust/{task[1]}/{task[2]}"


def sensitivity_row(task: tuple, config: Mapping) -> dict:
    """One row, in the driver or a Dask worker, with its own cut store (and exact contacts):
    margins, a setting's predictions or the robust metric's.  Predictions come back as
    ``pred`` (bool list): the driver scores them against the ground truth."""
    W, forces, mu_true, f_true = scene_inputs(config)
    cuts, cache = CutStore(), process_cache()
    kind = task[0]
    if kind == "setting":  # its own profile; every other row is at the true one
        return _setting_row(task, config, W, forces, cuts, cache)
    true_prof = scene_profiles(config, config["k_true"], config["length"])
    if kind == "margin":
        _, model, sampler = task
        return model_margin_row(
            model, scene_sets(true_prof, model, cache, config, sampler), forces, W, config, cuts
        )
    if kind == "truth":
        return _truth_margin_row(task[1], true_prof, (W, forces, mu_true, f_true), config)
    return _robust_row(task, true_prof, W, forces, config, cuts, cache)


def _setting_row(
    task: tuple, config: Mapping, W: np.ndarray, forces: np.ndarray, cuts: CutStore, cache: LimitSurfaceCache
) -> dict:
    _, series, x, model = task
    k, length, mu = setting_parameters(task, config)
    t0 = time.perf_counter()
    sets = scene_sets(scene_profiles(config, k, length), model, cache, config)
    build_s = time.perf_counter() - t0
    pred, ms = predict_resisted(sets, W, forces, mu, cuts)
    return {
        "series": series,
        "x": x,
        "model": model,
        "pred": pred.tolist(),
        "ms_per_grasp": ms,
        "build_s": build_s,
    }


def _truth_margin_row(which: str, true_prof: list[ContactProfile], inputs: tuple, config: Mapping) -> dict:
    """The exact 6DFW set's margins: ``which`` "truth" at the noisy true μ and force (the
    noise of the truth), "truth-nominal" at the sensor force and nominal μ."""
    W, forces, mu_true, f_true = inputs
    if which == "truth":  # the simulated truth's own margin (the noise of the truth)
        mu, scale = mu_true, f_true
    else:  # no noise: the sensor force and nominal μ, exactly
        mu, scale = [config["mu"]] * len(forces), forces
    deciders = truth_deciders(true_prof, mu, scale, config["truth_start_wrenches"])
    return margin_row(which, deciders, W, config["margin_steps"])


def _robust_row(
    task: tuple,
    true_prof: list[ContactProfile],
    W: np.ndarray,
    forces: np.ndarray,
    config: Mapping,
    cuts: CutStore,
    cache: LimitSurfaceCache,
) -> dict:
    """The robust metric (6DFC paper Fig 3): q_robust >= 0.5 under pose noise."""
    _, n_r, sigma = task
    nr = config["robust_disturbances"]
    base = scene_sets(true_prof, "6dls", cache, config)
    # pose noise only; the rotation σ is σ_r over a 3 cm lever (the contact's size: a = length = 0.03 m)
    p = Perturbation(
        n_samples=n_r, sigma_trans=sigma, sigma_rot=sigma / 0.03, sigma_mu=0.0, sigma_mass=0.0, sigma_com=0.0
    )
    t0 = time.perf_counter()
    pred = [
        q_robust(
            [c.with_force(c.force * forces[i]) for c in base],
            config["mu"],
            W[i],  # the disturbance
            p,
            seed=i,
            cuts=cuts,
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


def scored(row: dict, truth: np.ndarray) -> dict:
    """A row as checkpointed: its predictions ``pred`` scored against the truth (n,) bool
    (:func:`~.precision.scores` on the first len(pred) grasps); margin rows as they are."""
    if "pred" not in row:
        return row
    pred = np.array(row.pop("pred"), dtype=bool)
    return {**row, **scores(pred, truth[: len(pred)])}
