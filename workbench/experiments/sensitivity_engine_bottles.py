"""Thesis Table 4.1 / Fig 4.4's question on the bottle family's side grasps, judged by MuJoCo.

:mod:`.sensitivity_engine` judges the §4.1.3 scene (one elliptic-cylinder patch).  Here the
grasps are the parallel-jaw side grasps of the thesis's bottle family (§3.5.2, Fig 3.11(a):
tapered, waisted, twisted and leaning walls; :mod:`workbench.sources.bottle_scene`), each jaw the
flat 20 × 40 × 5 mm silicone pad of chapter 3.  Per seed, ``n_grasps`` grasps are drawn from the
pool of kept grasps, each with the §4.1.3.1 lever disturbance (weights at lever arms, in the grasp
frame), a force-sensor reading and the noisy true μ and force of :mod:`.sensitivity`.

- **The models** see each grasp's FEM pad profiles (:func:`workbench.sources.fem_jaw.fem_jaw_profiles`:
  our pad pressed on the rigid bottle mesh to the sensor's force) and predict "resisted" at the
  nominal μ — each contact model built from those profiles (:func:`workbench.grasp.models.contact_sets`).
- **The old truth** is the exact 6DFW set of the same profiles
  (:func:`workbench.grasp.simulated_truth.truth_deciders`) at the noisy true μ and force — the
  truth :mod:`.sensitivity` uses.
- **The engine** (:func:`workbench.engine_trials.disturbance.simulate_disturbance`) presses two flat
  MuJoCo pads of the same size and modulus on the same mesh with the true force, applies and holds
  the disturbance at the true μ, and says whether the bottle moved.

What the engine's truth shares with the models: the bottle mesh, the grasp, μ, the grasp force,
the disturbance, the pad's size and modulus.  What it does not: our FEM pad's profile (the
engine's pad makes its own contact and pressure), a fixed normal force (its jaws are
force-controlled), rigid quasi-statics (its pads deform, the object may creep).
"""

from __future__ import annotations

import time
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from workbench.code_key import code_digest, normalized_function
from workbench.engine_trials.trial import VERDICT_LIMITS
from workbench.experiments import sensitivity as _scene
from workbench.experiments import sensitivity_engine as _judged
from workbench.grasp.crossval import seed_summary
from workbench.grasp.judged import judged_headline, model_tables, recall_gain_claims, verdict_limit_tables
from workbench.grasp.lever_scene import predict_grasp, scene_inputs
from workbench.grasp.models import MODELS, ModelParameters
from workbench.grasp.precision import scores
from workbench.grasp.simulated_truth import truth_deciders
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import run_checkpointed
from workbench.runner.results import content_hash, sources_hash, write_csv, write_summary
from workbench.runner.trial_figures import judged_figure

NAME = "sensitivity-engine-bottles"

#: the disturbance and noise keys, as the sensitivity experiment has them
_SCENE_KEYS = (
    "mu",
    "force_range",
    "noise_mu",
    "noise_force",
    "truth_start_wrenches",
    "lever_x",
    "lever_z",
    "M",
)

DEFAULT_CONFIG = {
    **{k: _scene.DEFAULT_CONFIG[k] for k in _SCENE_KEYS},
    # a flat pad on a bottle's wall touches less than the wrapped patch of §4.1.3: lighter weights
    # keep both verdicts in the sample (the old truth holds about half at this range)
    "weight_range": [1.0, 12.0],
    "seeds": [0, 1, 2, 3, 4],  # the thesis ran each model's predictions five times (§4.1.3.4)
    "n_grasps": 20,  # grasps per seed, drawn from the pool without repeats within a seed
    "models": list(_scene.DEFAULT_CONFIG["models"]),
    # the bottles: fem-fitting's family (§3.5.2), the last n_asymmetric leaning
    "n_bottles": 24,
    "n_asymmetric": 8,
    "family_seed": 0,
    "height_fractions": [0.3, 0.45, 0.6, 0.75],  # grasp heights, fractions of the bottle's height
    "n_angles": 6,  # grasp-axis angles in [0, pi) per height
    # the pad, ours and the engine's: chapter 3's 20 x 40 x 5 mm silicone pad
    "pad_E": 1e6,  # Pa
    "pad_nu": 0.45,
    "object_mass": 0.1,  # kg (inertia only: no gravity acts)
    # the verdict: resisted iff the object moved less than these relative to the gripper
    "max_drift": 0.005,  # m
    "max_turn_deg": 5.0,  # deg (the thesis's rotation threshold, §4.1.3.1)
    "workers": 0,
    "scheduler": "",
}
KEYS = {
    **{k: _scene.KEYS[k] for k in (*_SCENE_KEYS, "weight_range")},
    "seeds": Key("seeds of the grasp draw, disturbances and noise, one set of grasps each"),
    "n_grasps": Key("grasps per seed, >= 1, at most the pool's size"),
    "models": Key("contact models scored, at least one", choices=lambda: MODELS),
    "n_bottles": Key("bottles of the family, >= 1"),
    "n_asymmetric": Key("the last n_asymmetric bottles lean, 0..n_bottles"),
    "family_seed": Key("seed of the bottle family's shapes (fem-fitting's: 0)"),
    "height_fractions": Key("grasp heights as fractions of the bottle's height, in (0, 1)"),
    "n_angles": Key("grasp-axis angles per height, >= 1"),
    "pad_E": Key("pad Young's modulus (our FEM pad and the engine's)", "Pa", "pad_modulus"),
    "pad_nu": Key("pad Poisson ratio", "", "poisson"),
    "object_mass": Key("the bottle's mass (inertia only: no gravity acts)", "kg", "mass"),
    **_judged.VERDICT_KEYS,
}
QUICK_CONFIG = {
    "seeds": [0],
    "n_grasps": 3,
    "n_bottles": 4,
    "n_asymmetric": 1,
    "height_fractions": [0.45, 0.6],
    "models": ["point", "planar", "6dls"],
    "M": 100,
}

#: the FEM pad's size (width, length, thickness) [m], the engine's pad too
PAD = (0.02, 0.04, 0.005)


def check_config(config: dict) -> None:
    """Refuse, before any trial runs, what the run would refuse later: implausible numbers
    (:data:`KEYS`), no model or seed, fewer than one grasp, μ = 0, a bad family or grid, a turn
    limit outside [1, 90] degrees (the trials' own rule)."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    for key in ("n_grasps", "n_bottles", "n_angles"):
        if isinstance(config[key], bool) or not isinstance(config[key], int) or config[key] < 1:
            raise ValueError(f"{key} must be an integer >= 1; got {config[key]!r}")
    if not 0 <= config["n_asymmetric"] <= config["n_bottles"]:
        raise ValueError(
            f"n_asymmetric must be in [0, n_bottles={config['n_bottles']}]; got {config['n_asymmetric']}"
        )
    fr = config["height_fractions"]
    if not isinstance(fr, list) or not fr or not all(isinstance(f, (int, float)) and 0 < f < 1 for f in fr):
        raise ValueError(
            f"height_fractions must be a list of fractions in (0, 1), e.g. [0.3, 0.6]; got {fr!r}"
        )
    _judged.check_judged_run(config)


@lru_cache(maxsize=4)
def _pool(
    n_bottles: int, n_asymmetric: int, family_seed: int, fractions: tuple, n_angles: int, mu: float
) -> list:
    from workbench.sources.bottle_scene import bottle_grasp_pool

    return bottle_grasp_pool(n_bottles, n_asymmetric, family_seed, fractions, n_angles, mu, pad=PAD[:2])


def pool_of(config: dict) -> list[dict]:
    """The kept side grasps of the config's bottles (cached per process)."""
    return _pool(
        config["n_bottles"], config["n_asymmetric"], config["family_seed"],
        tuple(config["height_fractions"]), config["n_angles"], config["mu"],
    )  # fmt: skip


def _check_pool_size(n: int, pool: list) -> None:
    """n_grasps drawn without repeats: at most the pool's size."""
    if n > len(pool):
        raise ValueError(
            f"n_grasps = {n} is more than the {len(pool)} grasps in the pool: lower n_grasps or add "
            "bottles, heights or angles (n_bottles, height_fractions, n_angles)"
        )


def _inputs(config: dict, seed: int):
    """The seed's draw: pool indices (n,), disturbances in the object frame (n, 6), sensor
    forces, noisy true μ and forces (n,).  The disturbances, forces and noise are the
    sensitivity experiment's draw for that seed (:func:`~workbench.grasp.lever_scene.scene_inputs`),
    in each grasp's frame; the grasps come from a second stream of the same seed
    (:func:`~workbench.sources.bottle_scene.draw_pool_grasps`)."""
    from workbench.sources.bottle_scene import draw_pool_grasps

    n, pool = config["n_grasps"], pool_of(config)
    _check_pool_size(n, pool)
    W, forces, mu_true, f_true = scene_inputs({**config, "seed": seed, "n_disturbances": n})
    idx, W_obj = draw_pool_grasps(pool, W, seed)
    return idx, W_obj, forces, mu_true, f_true


@lru_cache(maxsize=1)
def _process_cache() -> LimitSurfaceCache:
    return LimitSurfaceCache()


@lru_cache(maxsize=1)
def _fem_pad(E: float, nu: float):
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad

    return condense_pad(PadGeometry(width=PAD[0], length=PAD[1], thickness=PAD[2]), Material(E=E, nu=nu))


def _mesh(config: dict, k: int):
    from workbench.fem.bottle import bottle_family
    from workbench.sources.bottle_scene import bottle_mesh

    family = bottle_family(config["n_bottles"], config["n_asymmetric"], config["family_seed"])
    return bottle_mesh(family[pool_of(config)[k]["bottle"]])


def _row(task: tuple, config: dict) -> dict:
    """One row (driver or Dask worker): the engine's trial ``("engine", seed, i)`` or the
    models' predictions and the exact truth on the FEM profiles ``("models", seed, i)``."""
    kind, seed, i = task
    idx, W, forces, mu_true, f_true = _inputs(config, seed)
    k = int(idx[i])
    g = pool_of(config)[k]
    grasp = {key: g[key] for key in ("p1", "p2", "axis")}
    mesh = _mesh(config, k)
    if kind == "engine":
        from workbench.engine_trials import EngineObject, EnginePad
        from workbench.engine_trials.disturbance import DisturbancePhases, simulate_disturbance

        outcome = simulate_disturbance(
            mesh,
            grasp,
            W[i],
            force=float(f_true[i]),
            obj=EngineObject(mass=config["object_mass"], mu=float(mu_true[i]), com=mesh.center_mass),
            pad=EnginePad(size=PAD, E=config["pad_E"], nu=config["pad_nu"], up=(0.0, 0.0, 1.0)),
            # the verdicts are read at the run's limits and VERDICT_LIMITS only: a trial stops once
            # its object is past them all
            phases=DisturbancePhases(
                max_drift=config["max_drift"], max_turn_deg=config["max_turn_deg"], stop_when_lost=True
            ),
        )
        return {**outcome.row(), "pool_index": k}
    from workbench.sources.fem_jaw import fem_jaw_profiles

    t0 = time.perf_counter()
    profiles = fem_jaw_profiles(
        mesh, grasp, float(forces[i]), pad=_fem_pad(config["pad_E"], config["pad_nu"])
    )
    fem_s = time.perf_counter() - t0
    # the truth at the true force: the sensor's profiles scaled by the true / read force
    (truth,) = truth_deciders(
        profiles, [float(mu_true[i])], [f_true[i] / forces[i]], config["truth_start_wrenches"]
    )
    held = truth(W[i])
    pred, ms = {}, {}
    params = ModelParameters(M=config["M"])
    for m in config["models"]:
        pred[m], ms[m] = predict_grasp(profiles, m, W[i], config["mu"], params, _process_cache())
    return {
        "pred": pred,
        "ms": ms,
        "exact": held,
        "fem_seconds": fem_s,
        "contact_area_mm2": [float(p.areas.sum() * 1e6) for p in profiles],
        "pool_index": k,
    }


def _key(task: tuple) -> str:
    return "/".join(map(str, task))


def _tasks(config: dict, kind: str) -> list[tuple]:
    """The rows of one ``kind`` ("engine" or "models"), every seed's grasps."""
    return [(kind, s, i) for s in config["seeds"] for i in range(config["n_grasps"])]


def _engine_code() -> str:
    """What an engine row depends on besides its config: the engine trials' package, the bottle
    scene and family, the grasp sampler, the disturbance draw, this module's row, pool and input
    functions (the grasp draw they call is in the bottle scene's module, hashed whole), MuJoCo's
    version — rows keyed by it survive edits elsewhere in the package."""
    from importlib.metadata import version

    return content_hash(
        [
            sources_hash(
                "workbench.engine_trials",
                "workbench.config",
                "workbench.sources.bottle_scene",
                "workbench.fem.bottle",
                "workbench.grasp.sampling",
                "workbench.grasp.tasks",
            ),  # fmt: skip
            *(normalized_function(f) for f in (_row, _inputs, _pool, pool_of, _mesh, scene_inputs)),
            version("mujoco"),
        ]
    )


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    pool = pool_of(config)  # refuses an empty pool before any trial
    _check_pool_size(config["n_grasps"], pool)  # and too small a one, before any row
    engine, rows, n_resumed, ran_on = _run_rows(config, out)
    seeds, n = config["seeds"], config["n_grasps"]
    held = {s: np.array([r["held"] for r in engine[s]], dtype=bool) for s in seeds}
    exact = {s: np.array([r["exact"] for r in rows[s]], dtype=bool) for s in seeds}
    pred = {
        m: {s: np.array([r["pred"][m] for r in rows[s]], dtype=bool) for s in seeds} for m in config["models"]
    }
    ms = {m: float(np.median([r["ms"][m] for s in seeds for r in rows[s]])) for m in config["models"]}
    per_model = model_tables(pred, held, exact, seeds, ms)
    trials = [r for s in seeds for r in engine[s]]
    secs = np.array([r["seconds"] for r in trials])
    summary = {
        **_judge_text(config),
        "n_seeds": len(seeds),
        "n_grasps": n,
        "pool": _pool_use(pool, engine, seeds),
        "engine_positive_fraction": seed_summary([{"f": float(held[s].mean())} for s in seeds])["f"],
        "exact_positive_fraction": seed_summary([{"f": float(exact[s].mean())} for s in seeds])["f"],
        "exact_6dfw_vs_engine": seed_summary([scores(exact[s], held[s]) for s in seeds]),
        "models": per_model,
        "thesis_claims": recall_gain_claims(per_model),
        "verdict_thresholds": verdict_limit_tables(pred, engine, seeds, VERDICT_LIMITS),
        "engine_seconds_per_trial": {"median": float(np.median(secs)), "worst": float(secs.max())},
        "fem_seconds_per_grasp": float(np.median([r["fem_seconds"] for s in seeds for r in rows[s]])),
        "engine_trials_warned": sum(bool(r["engine_warnings"]) for r in trials),
        "engine_trials_not_simulated": sum(r["steps"] == 0 for r in trials),
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
    }
    _write_trials(out / "trials.csv", pool, engine, exact, seeds)
    summary["figures"] = [
        judged_figure(
            per_model,
            out / "table_4_1_engine_bottles.png",
            "Bottle-family side grasps: each model against the engine's verdicts and against the exact 6DFW",
        )
    ]
    summary["headline"] = judged_headline(summary, f"{len(seeds)} seeds x {n} bottle grasps on MuJoCo")
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _run_rows(config: dict, out: Path) -> tuple[dict, dict, int, dict]:
    """Every row not yet checkpointed: the engine trials keyed by what they depend on
    (:func:`_engine_code`: an edit of a contact model keeps them), the models' rows by the whole
    package; both resumable.  Returns ({seed: engine rows}, {seed: model rows}, rows resumed,
    where the trials ran)."""
    row = partial(_row, config=config)
    trials, n_resumed, ran_on = run_checkpointed(
        row, _tasks(config, "engine"), _key, out, config, desc=f"{NAME} trials", code=_engine_code()
    )
    models, n_resumed_m, _ = run_checkpointed(
        row,
        _tasks(config, "models"),
        _key,
        out / "models",
        config,
        desc=f"{NAME} models",
        code=code_digest(__name__),
    )
    seeds, n = config["seeds"], config["n_grasps"]
    engine = {s: [trials.rows[f"engine/{s}/{i}"] for i in range(n)] for s in seeds}
    rows = {s: [models.rows[f"models/{s}/{i}"] for i in range(n)] for s in seeds}
    return engine, rows, n_resumed + n_resumed_m, ran_on


def _judge_text(config: dict) -> dict:
    """The summary's account of the judge: what it is, what it shares with the models, what not."""
    return {
        "judge": (
            "MuJoCo (workbench.engine_trials.disturbance): the bottle mesh rigid, two flat 20 x 40 x 5 mm "
            "pads pressed by the true grasp force, the disturbance applied and held; resisted iff the object "
            f"moved < {config['max_drift'] * 1e3:g} mm and < {config['max_turn_deg']:g} deg"
        ),
        "shares_with_the_models": (
            "the bottle mesh, the grasp, mu, the grasp force, the disturbance, the pad's size and modulus"
        ),
        "does_not_share": (
            "our FEM pad's contact profile (the engine's pad makes its own contact and pressure), a fixed "
            "normal force (the jaws are force-controlled), rigid quasi-statics (pads deform, objects creep)"
        ),
    }


def _pool_use(pool: list[dict], engine: dict, seeds: list) -> dict:
    """How much of the pool the seeds' grasps used: grasps and bottles, of the pool's."""
    used = sorted({r["pool_index"] for s in seeds for r in engine[s]})
    return {
        "grasps": len(pool),
        "bottles_with_grasps": len({g["bottle"] for g in pool}),
        "grasps_used": len(used),
        "bottles_used": len({pool[k]["bottle"] for k in used}),
    }


def _write_trials(path: Path, pool: list[dict], engine: dict, exact: dict, seeds: list) -> None:
    """trials.csv: per seed and grasp, the bottle, the grasp's height and width, both verdicts
    and the engine's motion."""
    cols = [
        "seed",
        "i",
        "bottle",
        "height_fraction",
        "width_mm",
        "held",
        "exact",
        "drift_mm",
        "turn_deg",
        "seconds",
        "reason",
    ]
    write_csv(
        path,
        cols,
        [
            [
                s,
                i,
                pool[r["pool_index"]]["bottle"],
                pool[r["pool_index"]]["height_fraction"],
                pool[r["pool_index"]]["width"] * 1e3,
                r["held"],
                bool(exact[s][i]),
                r["drift_mm"],
                r["turn_deg"],
                r["seconds"],
                r["reason"],
            ]  # fmt: skip
            for s in seeds
            for i, r in enumerate(engine[s])
        ],
    )
