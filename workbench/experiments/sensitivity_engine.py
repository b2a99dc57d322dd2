"""Thesis Table 4.1 / Fig 4.4's scene judged by an existing engine instead of our exact 6DFW.

The sensitivity experiment (:mod:`.sensitivity`) scores every contact model against a truth
built from the same kind of object it judges: the true profile's exact 6DFW set.  Here the
same grasps — the elliptic-cylinder scene of §4.1.3 (grasp axis x, cylinder axis z), the
same lever disturbances, the same noisy per-grasp μ and grasp force — are simulated on MuJoCo
(:func:`workbench.engine_trials.disturbance.simulate_disturbance`): the object is the convex
hull of the two contact patches (the thesis's type I objects, cut so a wrapping jaw touches
exactly the patch, §4.1.3.2), each jaw a silicone pad moulded to its patch and pressed by the
grasp force, the disturbance applied to the free object and held; the engine says whether it
moved.  No profile, pressure law, 6DFW, limit surface or resistance program of ours takes
part in the verdict.

What the engine's truth shares with the models it scores: the object's geometry (the patch
each model's profile is meshed on), μ, the grasp force, the disturbance.  What it does not:
the pressure distribution (the engine's pad makes its own; the models assume the power law
of Eq. 4.3 with k = 2.4), a fixed normal force (the engine's jaws are force-controlled: a
load that wedges the curved patch pushes them apart, or is held by the wedge), rigid-body
quasi-statics (the engine's pads deform and the object may creep).

Per model and seed: precision, recall, F1 and accuracy of its plain prediction (resisted at
the sensor's grasp force and the nominal μ) against the engine and, beside it, against the
exact-6DFW truth; mean ± std over the seeds (Table 4.1's form).  The exact truth itself is
scored against the engine too: how far the old truth is from the engine's.
"""

from __future__ import annotations

import time
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from workbench.code_key import code_digest
from workbench.engine_trials.trial import VERDICT_LIMITS
from workbench.experiments import sensitivity as _scene
from workbench.grasp import CutStore
from workbench.grasp.crossval import seed_summary
from workbench.grasp.judged import judged_headline, model_tables, recall_gain_claims, verdict_limit_tables
from workbench.grasp.lever_scene import predict_resisted, scene_inputs, scene_profiles, scene_sets
from workbench.grasp.models import MODELS
from workbench.grasp.precision import scores
from workbench.grasp.simulated_truth import truth_deciders
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.experiment_keys import Key, check_key, verdict_keys
from workbench.runner.parallel import check_workers, run_checkpointed
from workbench.runner.results import write_csv, write_summary
from workbench.runner.trial_figures import judged_figure
from workbench.sources.scenes import (
    check_elliptic_cylinder,
    elliptic_cylinder_patch_extent,
    elliptic_cylinder_solid,
)
from workbench.units import check_turn_limit

NAME = "sensitivity-engine"

#: the scene's keys, as the sensitivity experiment has them (its defaults)
_SCENE_KEYS = (
    "mu", "k_true", "a", "b", "half_angle", "length", "n_elements", "force_range", "noise_mu",
    "noise_force", "truth_start_wrenches", "weight_range", "lever_x", "lever_z", "M",
)  # fmt: skip

DEFAULT_CONFIG = {
    **{k: _scene.DEFAULT_CONFIG[k] for k in _SCENE_KEYS},
    "seeds": [0, 1, 2, 3, 4],  # the thesis ran each model's predictions five times (§4.1.3.4)
    "n_disturbances": 20,  # grasps per seed: more narrow the spread of the seeds (each a trial)
    "models": list(_scene.DEFAULT_CONFIG["models"]),
    # the engine's pads (thesis §4.1.3.1: deformable fin-ray jaws), moulded to the patch
    "pad_E": 1e6,  # Pa, silicone
    "pad_nu": 0.45,
    "pad_thickness": 0.005,  # m, at the patch's centre
    "object_mass": 0.05,  # kg: a 3D-printed part (no gravity acts; only its inertia)
    # the verdict: resisted iff the object moved less than these relative to the gripper
    "max_drift": 0.005,  # m
    "max_turn_deg": 5.0,  # deg (the thesis's rotation threshold, §4.1.3.1)
    "workers": 0,
    "scheduler": "",
}
#: the engine verdict's keys of every engine-judged Table 4.1 scene
VERDICT_KEYS = verdict_keys("resisted grasp")
KEYS = {
    **{k: _scene.KEYS[k] for k in _SCENE_KEYS},
    "seeds": Key("seeds of the disturbances and noise, one set of grasps each"),
    "n_disturbances": Key("lever disturbances (grasps) per seed, >= 1"),
    "models": Key("contact models scored, at least one", choices=lambda: MODELS),
    "pad_E": Key("engine pad Young's modulus", "Pa", "pad_modulus"),
    "pad_nu": Key("engine pad Poisson ratio", "", "poisson"),
    "pad_thickness": Key("engine pad thickness at the patch centre", "m", "pad_thickness"),
    "object_mass": Key("the object's mass (inertia only: no gravity acts)", "kg", "mass"),
    **VERDICT_KEYS,
}
QUICK_CONFIG = {
    "seeds": [0],
    "n_disturbances": 6,
    "n_elements": 150,
    "models": ["point", "planar", "6dls"],
    "M": 100,
}


def check_config(config: dict) -> None:
    """Refuse, before any trial runs, what the run would refuse later: implausible numbers
    (:data:`KEYS`), the scene's geometry (:func:`check_elliptic_cylinder`), no model, no seed,
    fewer than one disturbance, μ = 0, a turn limit outside [1, 90] degrees."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    check_elliptic_cylinder(config["a"], config["b"], config["half_angle"], config["length"])
    if config["n_disturbances"] < 1:
        raise ValueError(f"n_disturbances must be >= 1; got {config['n_disturbances']}")
    check_judged_run(config)


def check_judged_run(config: dict) -> None:
    """The rules every engine-judged Table 4.1 scene shares: at least one model, distinct seeds
    >= 0, μ > 0, the verdict's turn limit in [1, 90] degrees (the trials' own rule) and drift
    limit > 0, where the rows run."""
    if not config["models"]:
        raise ValueError('models must name at least one model, e.g. ["6dls"]; got []')
    seeds = config["seeds"]
    if not seeds or len(set(seeds)) != len(seeds) or any(not isinstance(s, int) or s < 0 for s in seeds):
        raise ValueError(f"seeds must be distinct integers >= 0, at least one; got {seeds!r}")
    if config["mu"] == 0:
        raise ValueError("mu = 0 is a frictionless grasp: give mu > 0, e.g. --set mu=0.3 (the default)")
    check_turn_limit(config["max_turn_deg"], "max_turn_deg")
    if not config["max_drift"] > 0:
        raise ValueError(f"max_drift must be > 0 [m] (9 mm is 0.009); got {config['max_drift']!r}")
    check_workers(config["workers"], config["scheduler"])


def _inputs(config: dict, seed: int):
    """The seed's disturbances W (n, 6), sensor forces, noisy true μ and forces (n,): the
    sensitivity experiment's draw (:func:`~workbench.grasp.lever_scene.scene_inputs`) for that seed."""
    return scene_inputs({**config, "seed": seed})


@lru_cache(maxsize=1)
def _process_cache() -> LimitSurfaceCache:
    return LimitSurfaceCache()


def _row(task: tuple, config: dict) -> dict:
    """One row (driver or Dask worker): an engine trial ``("engine", seed, i)``, a model's
    predictions ``("model", seed, name)`` or the exact truth ``("exact", seed)``."""
    kind, seed = task[0], task[1]
    W, forces, mu_true, f_true = _inputs(config, seed)
    if kind == "engine":
        from workbench.engine_trials import EngineObject, EnginePad
        from workbench.engine_trials.disturbance import DisturbancePhases, simulate_disturbance

        i = task[2]
        a, b, h, length = config["a"], config["b"], config["half_angle"], config["length"]
        outcome = simulate_disturbance(
            elliptic_cylinder_solid(a, b, h, length),
            {"p1": [-a, 0.0, 0.0], "p2": [a, 0.0, 0.0], "axis": [1.0, 0.0, 0.0]},
            W[i],
            force=float(f_true[i]),
            obj=EngineObject(mass=config["object_mass"], mu=float(mu_true[i]), com=[0.0, 0.0, 0.0]),
            # each pad exactly the patch: its chord across, the contact length along z
            pad=EnginePad(
                size=(*elliptic_cylinder_patch_extent(a, b, h, length), config["pad_thickness"]),
                E=config["pad_E"],
                nu=config["pad_nu"],
                up=(0.0, 0.0, 1.0),
                conform=True,
            ),
            # the verdicts are read at the run's limits and VERDICT_LIMITS only: a trial stops once
            # its object is past them all
            phases=DisturbancePhases(
                max_drift=config["max_drift"], max_turn_deg=config["max_turn_deg"], stop_when_lost=True
            ),
        )
        return outcome.row()
    profiles = scene_profiles(config, config["k_true"], config["length"])
    if kind == "exact":  # the sensitivity experiment's ground truth, for the same grasps
        deciders = truth_deciders(profiles, mu_true, f_true, config["truth_start_wrenches"])
        t0 = time.perf_counter()
        held = [decide(w) for decide, w in zip(deciders, W, strict=True)]
        return {"pred": held, "ms_per_grasp": (time.perf_counter() - t0) / len(W) * 1e3}
    model = task[2]
    sets = scene_sets(profiles, model, _process_cache(), config)
    pred, ms = predict_resisted(sets, W, forces, config["mu"], CutStore())
    return {"pred": pred.tolist(), "ms_per_grasp": ms}


def _key(task: tuple) -> str:
    return "/".join(map(str, task))


def _tasks(config: dict) -> list[tuple]:
    """Every row: the engine trials first (the longest), then each seed's truth and models."""
    n = config["n_disturbances"]
    tasks: list[tuple] = [("engine", s, i) for s in config["seeds"] for i in range(n)]
    tasks += [("exact", s) for s in config["seeds"]]
    tasks += [("model", s, m) for s in config["seeds"] for m in config["models"]]
    return tasks


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    ckpt, n_resumed, ran_on = run_checkpointed(
        partial(_row, config=config), _tasks(config), _key, out, config, desc=NAME, code=code_digest(__name__)
    )
    seeds, n = config["seeds"], config["n_disturbances"]
    engine = {s: [ckpt.rows[f"engine/{s}/{i}"] for i in range(n)] for s in seeds}
    held = {s: np.array([r["held"] for r in engine[s]], dtype=bool) for s in seeds}
    exact = {s: np.array(ckpt.rows[f"exact/{s}"]["pred"], dtype=bool) for s in seeds}

    pred = {
        m: {s: np.array(ckpt.rows[f"model/{s}/{m}"]["pred"], dtype=bool) for s in seeds}
        for m in config["models"]
    }
    ms = {
        m: float(np.median([ckpt.rows[f"model/{s}/{m}"]["ms_per_grasp"] for s in seeds]))
        for m in config["models"]
    }
    per_model = model_tables(pred, held, exact, seeds, ms)
    trials = [r for s in seeds for r in engine[s]]
    secs = np.array([r["seconds"] for r in trials])
    warned = sum(bool(r["engine_warnings"]) for r in trials)
    summary = {
        "judge": (
            "MuJoCo (workbench.engine_trials.disturbance): the object the hull of both patches, pads moulded "
            "to them and pressed by the grasp force, the disturbance applied and held; resisted iff the "
            f"object moved < {config['max_drift'] * 1e3:g} mm and < {config['max_turn_deg']:g} deg"
        ),
        "shares_with_the_models": "the patch geometry, mu, the grasp force, the disturbance",
        "does_not_share": (
            "the pressure distribution (the engine's pad makes its own), a fixed normal force (the jaws are "
            "force-controlled and may be wedged apart), rigid quasi-statics (pads deform, objects creep)"
        ),
        "n_seeds": len(seeds),
        "n_disturbances": n,
        "engine_positive_fraction": seed_summary([{"f": float(held[s].mean())} for s in seeds])["f"],
        "exact_positive_fraction": seed_summary([{"f": float(exact[s].mean())} for s in seeds])["f"],
        # the old truth scored as a predictor of the engine's verdicts
        "exact_6dfw_vs_engine": seed_summary([scores(exact[s], held[s]) for s in seeds]),
        "models": per_model,
        "thesis_claims": recall_gain_claims(per_model),
        "verdict_thresholds": verdict_limit_tables(pred, engine, seeds, VERDICT_LIMITS),
        "engine_seconds_per_trial": {"median": float(np.median(secs)), "worst": float(secs.max())},
        "engine_trials_warned": warned,
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
    }
    cols = ["seed", "i", "held", "exact", "drift_mm", "turn_deg", "seconds", "reason"]
    write_csv(
        out / "trials.csv",
        cols,
        [
            [s, i, r["held"], bool(exact[s][i]), r["drift_mm"], r["turn_deg"], r["seconds"], r["reason"]]
            for s in seeds
            for i, r in enumerate(engine[s])
        ],
    )
    summary["figures"] = [
        judged_figure(
            per_model,
            out / "table_4_1_engine.png",
            "Table 4.1's scene: each model against the engine's verdicts and against the exact 6DFW",
        )
    ]
    summary["headline"] = judged_headline(summary, f"{len(seeds)} seeds x {n} grasps on MuJoCo")
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)
