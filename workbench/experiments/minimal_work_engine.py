"""Thesis Table 4.6 judged by an existing engine instead of a truth built from our own models.

The minimal-work experiment (:mod:`.minimal_work`) scores q_robust, q_force and q_work against a
simulated truth that asks the exact 6DFW sets of the same REACH profiles whether the task wrench is
resisted, and a closing limit from the wall FEM calibrated to the same stiffness map q_work reads.
Here the same candidate grasps of the three measured objects are run on MuJoCo
(:func:`workbench.engine_trials.simulate_grasp`): a parallel-jaw gripper with silicone flex pads
closes on the object with a fixed force, lifts it (and, for the second task, turns it 90° about
the grasp axis) against gravity, and holds it; the grasp succeeds iff the object stays within
``max_drift`` and ``max_turn_deg`` of its pose in the gripper.

What the engine's verdict shares with the metrics it scores: the object's mesh (MuJoCo collides
it as convex slabs across gravity, :mod:`workbench.engine_trials.collision`; how deep each grasp's
contact points lie inside them is reported), μ, the
filled mass and its centre, the grasp pose, the jaw force, the pad's size.  What it does not:
the REACH profiles, the 6DLS and its linearisation, the exact 6DFW, the stiffness map and the wall
FEM.  What it cannot judge: the object is a rigid stand-in (no validated shell: engine-validation
item (d)), so only the thesis's first success criterion (§4.3.4: the task is completed) is
judged, not the second and third (the object's shape recovers, the content stays in): q_work's
deformation term is scored only through whatever it shares with slip.

Steps: (1) the metrics of every candidate by the minimal-work experiment itself (written under
``out/metrics``: its own summary and ``grasps.csv``); (2) ``n_grasps`` of each object's candidates
(a seeded sample) as engine trials of both tasks, Dask tasks checkpointed in ``rows.jsonl``;
(3) Table 4.6 against the engine: normalisers on a training split of the judged grasps, balanced
accuracy on the rest with a bootstrap interval; beside it, the old truth scored against the
engine (how far the old judge is from this one).
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import numpy as np

from workbench.code_key import normalized_function
from workbench.engine_trials.trial import VERDICT_LIMITS
from workbench.experiments import minimal_work as _mw
from workbench.fem.grasp_walls import load_mesh, object_files
from workbench.grasp.candidates import read_candidates_csv, sample_candidates
from workbench.grasp.judged import moved_within
from workbench.grasp.quality_table import training_split
from workbench.grasp.work_table import METRICS, TASKS, nan_if_none
from workbench.runner.experiment_keys import Key, check_key, verdict_keys
from workbench.runner.parallel import check_workers, run_checkpointed
from workbench.runner.results import content_hash, save_figure, sources_hash, write_csv, write_summary
from workbench.units import check_turn_limit

NAME = "minimal-work-engine"

#: the candidates' and metrics' keys, as the minimal-work experiment has them (its defaults)
_MW_KEYS = (
    "data_dir",
    "objects",
    "mass_kg",
    "mu",
    "n_heights",
    "n_angles",
    "jaw",
    "grasp_force",
    "M",
    "robust_samples",
    "sigma",
    "train_fraction",
)

DEFAULT_CONFIG = {
    "seed": 0,  # the sample of judged grasps and the split (minimal-work's own seed too)
    **{k: _mw.DEFAULT_CONFIG[k] for k in _MW_KEYS},
    # grasps per object judged by the engine (a seeded sample of its candidates; all when fewer).
    # The thesis-size run (≥ 100 a task): --set n_grasps=100 --set n_heights=20 --set n_angles=12
    "n_grasps": 16,
    # the engine gripper's closing force per jaw: the force the profiles and q_robust assume
    "engine_force": _mw.DEFAULT_CONFIG["grasp_force"],
    "pad_E": 1e6,  # Pa, silicone (the REACH pad's modulus)
    "pad_nu": 0.45,
    "pad_thickness": 0.005,  # m
    # the verdict: the task completed iff the object moved less than these relative to the gripper
    "max_drift": 0.005,  # m
    "max_turn_deg": 5.0,  # deg (the thesis's rotation threshold, §4.1.3.1)
    "n_bootstrap": 2000,  # resamples of each balanced accuracy's interval
    "workers": 0,
    "scheduler": "",
}
KEYS = {
    **{k: _mw.KEYS[k] for k in _MW_KEYS},
    "n_grasps": Key("candidate grasps per object judged by the engine, >= 2"),
    "engine_force": Key("engine gripper's closing force per jaw", "N", "jaw_force"),
    "pad_E": Key("engine pad Young's modulus", "Pa", "pad_modulus"),
    "pad_nu": Key("engine pad Poisson ratio", "", "poisson"),
    "pad_thickness": Key("engine pad thickness", "m", "pad_thickness"),
    **verdict_keys("completed task"),
    "n_bootstrap": Key("bootstrap resamples of each interval, >= 100"),
}
QUICK_CONFIG = {"n_grasps": 2, "n_heights": 3, "n_angles": 2, "robust_samples": 8, "n_bootstrap": 200}
#: the keys a trial's outcome (or a candidate's index) depends on: its checkpoint's key
TRIAL_KEYS = (
    "data_dir",
    "objects",
    "mass_kg",
    "mu",
    "n_heights",
    "n_angles",
    "jaw",
    "engine_force",
    "pad_E",
    "pad_nu",
    "pad_thickness",
    "max_drift",
    "max_turn_deg",
)
#: grasps whose contact points lie deeper than this [m] inside the object as the engine collides
#: it touch, in the engine, a surface the real object does not have (counted in the summary)
SURFACE_GAP = 1e-3


def check_config(config: dict) -> None:
    """Refuse before any work what minimal-work or a trial would refuse later (:data:`KEYS`,
    the objects' files), fewer than two grasps per object, a turn limit outside [1, 90] deg.
    This experiment's own keys first: their refusal needs no data (minimal-work's check reads
    the objects' files, and a missing data_dir would hide a bad n_grasps behind it)."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    n = config["n_grasps"]
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise ValueError(f"n_grasps must be an integer >= 2 (a training and a held-out grasp); got {n!r}")
    b = config["n_bootstrap"]
    if isinstance(b, bool) or not isinstance(b, int) or b < 100:
        raise ValueError(f"n_bootstrap must be an integer >= 100 (e.g. 2000); got {b!r}")
    check_turn_limit(config["max_turn_deg"], "max_turn_deg")
    check_workers(config["workers"], config["scheduler"])
    _mw.check_config(_mw_config(config))


def _mw_config(config: dict) -> dict:
    """The minimal-work run that computes the candidates' metrics (no nonlinear work)."""
    quick = {k: v for k, v in _mw.QUICK_CONFIG.items() if k not in _mw.NL_KEYS} if config.get("quick") else {}
    return {
        **_mw.DEFAULT_CONFIG,
        **quick,
        **{k: config[k] for k in _MW_KEYS},
        "nl_work_objects": [],
        "seed": config["seed"],
        "quick": bool(config.get("quick")),
        "out": str(Path(config.get("out") or f"results/{NAME}") / "metrics"),
        "workers": config["workers"],
        "scheduler": config["scheduler"],
    }


def _trial(job: tuple, config: dict) -> dict:
    """Both tasks' engine trials of one grasp (driver or Dask worker): ``(object, grasp, p1, p2,
    axis)`` → {task: trial row}, stepped together up to the turn
    (:func:`~workbench.engine_trials.simulate_grasp_tasks`: each as it would be alone)."""
    from workbench.engine_trials import EngineObject, EnginePad, TrialPhases, simulate_grasp_tasks

    name, _, p1, p2, axis = job
    mesh = load_mesh(str(object_files(config["data_dir"], name)[0]))
    outcomes = simulate_grasp_tasks(
        mesh,
        {"p1": p1, "p2": p2, "axis": axis},
        force=config["engine_force"],
        obj=EngineObject(
            mass=config["mass_kg"][name],
            mu=config["mu"],
            com=mesh.convex_hull.center_mass,  # the filled object's centre, as minimal-work's
        ),
        tasks=TASKS,
        pad=EnginePad(
            size=(config["jaw"][0], config["jaw"][1], config["pad_thickness"]),
            E=config["pad_E"],
            nu=config["pad_nu"],
        ),
        # the verdicts are read at the run's limits and VERDICT_LIMITS only: a trial stops once
        # its object is past them all
        phases=TrialPhases(
            max_drift=config["max_drift"], max_turn_deg=config["max_turn_deg"], stop_when_lost=True
        ),
    )
    return {t: outcomes[t].row() for t in TASKS}


def _key(job: tuple) -> str:
    """``object/grasp/pose``: the pose's digest, so a candidate index that names another pose
    (a changed candidate sampler) is never read as this grasp's trials."""
    return f"{job[0]}/{job[1]}/{content_hash([job[2], job[3], job[4]], 10)}"


def _trial_code() -> str:
    """What a trial's outcome depends on besides its config: the engine trials' package, the
    tolerances, this module's trial function and MuJoCo's version (rows keyed by it survive
    edits elsewhere in the package)."""
    from importlib.metadata import version

    return content_hash(
        [
            sources_hash("workbench.engine_trials", "workbench.config", "workbench.sources.jaws"),
            normalized_function(_trial),
            normalized_function(load_mesh),
            version("mujoco"),
        ]
    )


def _surface_gap(grasps: list[dict], config: dict) -> np.ndarray:
    """(n,) how deep [m] each grasp's deeper contact point lies inside the object as the engine
    collides it (:func:`workbench.engine_trials.collision_gap.surface_gap`)."""
    from workbench.engine_trials import EngineSettings
    from workbench.engine_trials.collision_gap import surface_gap

    gap = np.zeros(len(grasps))
    for name in config["objects"]:
        idx = [i for i, g in enumerate(grasps) if g["object"] == name]
        if not idx:
            continue
        mesh = load_mesh(str(object_files(config["data_dir"], name)[0]))
        pts = np.array([[grasps[i]["p1"], grasps[i]["p2"]] for i in idx])  # (k, 2, 3)
        gap[idx] = surface_gap(mesh, pts, (0.0, 0.0, -1.0), EngineSettings().object_slab).max(axis=1)
    return gap


def _engine_trials(grasps: list[dict], out: Path, config: dict) -> tuple[dict, int, str]:
    """Step 2: both tasks' engine trials of every judged grasp (Dask tasks, checkpointed):
    ({(object, grasp, task): trial row}, rows resumed, where they ran)."""
    jobs = [(g["object"], g["grasp"], g["p1"], g["p2"], g["axis"]) for g in grasps]
    # the rows' key: what changes a trial's outcome or a candidate's index, so another sample, split or
    # number of resamples resumes every trial already run
    engine_config = {k: config[k] for k in (*TRIAL_KEYS, "workers", "scheduler")}
    ckpt, n_resumed, ran_on = run_checkpointed(
        partial(_trial, config=config),
        jobs,
        _key,
        out,
        engine_config,
        desc=NAME,
        unit="grasp",
        code=_trial_code(),
    )
    return {(j[0], j[1], t): ckpt.rows[_key(j)][t] for j in jobs for t in TASKS}, n_resumed, ran_on


def _score(
    held: np.ndarray,
    t: str,
    grasps: list[dict],
    split: np.ndarray,
    objs: np.ndarray,
    config: dict,
    n_resamples: int,
) -> dict:
    """Table 4.6 of task ``t`` against the verdicts ``held`` (n,) bool
    (:func:`~workbench.grasp.quality_table.quality_table`)."""
    from workbench.grasp.quality_table import quality_table

    return quality_table(
        held,
        split,
        objs,
        config["objects"],
        qualities={"q_robust": np.array([g[t]["q_robust"] for g in grasps])},
        costs={
            "q_force": np.array([nan_if_none(g[t]["f_sum"]) for g in grasps]),
            "q_work": np.array([nan_if_none(g[t]["W"]) for g in grasps]),
        },
        sigma=config["sigma"],
        n_resamples=n_resamples,
        seed=config["seed"],
    )


def _tables(
    grasps: list[dict], trial: dict, split: np.ndarray, objs: np.ndarray, config: dict
) -> tuple[dict, dict, dict]:
    """Step 3 per task: Table 4.6 against the engine, its class balance, and the old truth
    scored against the engine: (table, old, balance)."""
    from workbench.grasp.threshold import balanced_accuracy

    table, old, balance = {}, {}, {}
    for t in TASKS:
        held = np.array([trial[g["object"], g["grasp"], t]["held"] for g in grasps], dtype=bool)
        truth = np.array([g[t]["truth"] for g in grasps], dtype=bool)
        table[t] = _score(held, t, grasps, split, objs, config, config["n_bootstrap"])
        balance[t] = {
            "engine_success": int(held.sum()),
            "engine_failure": int((~held).sum()),
            "per_object_success": {
                n: [int(held[objs == n].sum()), int((objs == n).sum())] for n in config["objects"]
            },
            "held_out": int((~split).sum()),
        }
        old[t] = {
            "agreement": float((truth == held).mean()),
            "balanced_accuracy": balanced_accuracy(truth, held),
            "old_success": int(truth.sum()),
        }
    return table, old, balance


def _verdict_limits(
    grasps: list[dict], trial: dict, split: np.ndarray, objs: np.ndarray, config: dict
) -> dict:
    """The verdict at other limits, re-read from each trial's largest drift and turn."""
    limits = {}
    for d_mm, t_deg in VERDICT_LIMITS:
        at = {}
        for t in TASKS:
            rs = [trial[g["object"], g["grasp"], t] for g in grasps]
            # a trial that could not start has no drift (null): not held at any limit
            held = np.array(
                [moved_within(r, d_mm, t_deg) for r in rs],
                dtype=bool,
            )
            if held.all() or not held.any():  # one class: no normaliser to fit
                at[t] = {"held_fraction": float(held.mean())}
                continue
            acc = _score(held, t, grasps, split, objs, config, 100)["accuracy"]
            at[t] = {"held_fraction": float(held.mean()), **{m: acc[m]["All"] for m in METRICS}}
        limits[f"{d_mm:g}mm_{t_deg:g}deg"] = at
    return limits


def _write_trials(out: Path, grasps: list[dict], trial: dict, gap: np.ndarray) -> None:
    """``trials.csv``: one row per trial."""
    rows_out = [
        [
            g["object"],
            g["grasp"],
            t,
            f"{gap[i] * 1e3:.3f}",
            bool(g[t]["truth"]),
            r["held"],
            r["drift_mm"],
            r["turn_deg"],
            r["seconds"],
            r["reason"],
        ]
        for i, g in enumerate(grasps)
        for t in TASKS
        for r in [trial[g["object"], g["grasp"], t]]
    ]
    write_csv(
        out / "trials.csv",
        ["object", "grasp", "task", "surface_gap_mm", "old_truth", "engine_held", "drift_mm", "turn_deg"]
        + ["seconds", "reason"],
        rows_out,
    )


def _judge_notes(config: dict) -> dict:
    """What the engine judges, shares with the metrics, does not share, cannot judge."""
    return {
        "judge": (
            "MuJoCo (workbench.engine_trials.simulate_grasp): silicone flex pads "
            f"({config['pad_E']:g} Pa, {config['pad_thickness'] * 1e3:g} mm) close with "
            f"{config['engine_force']:g} N per jaw on the rigid object (convex slabs), lift 50 mm "
            "(and turn 90 deg about the grasp axis), hold; the task is completed iff the object moved "
            f"< {config['max_drift'] * 1e3:g} mm and < {config['max_turn_deg']:g} deg in the gripper"
        ),
        "shares_with_the_metrics": (
            "the object's mesh (as convex slabs), mu, the filled mass and centre, the grasp pose, "
            "the jaw force and the pad's size"
        ),
        "does_not_share": (
            "the REACH profiles, the 6DLS and its linearisation, the exact 6DFW, the stiffness map, "
            "the wall FEM"
        ),
        "cannot_judge": (
            "deformation: the object is rigid (no engine passed the shell validation, "
            "engine-validation (d)), so only the first success criterion of §4.3.4 (task completed) "
            "is judged, not shape recovery or content spill; q_work's deformation term is scored "
            "only through what it shares with slip"
        ),
    }


def _engine_stats(trial: dict, gap: np.ndarray) -> dict:
    """The engine's surface against the mesh at each grasp's contact points, and its trials' time
    (a grasp's tasks share their steps up to the turn: the time is per grasp, both tasks)."""
    per_grasp: dict = {}
    for (name, grasp, _), r in trial.items():
        if r["steps"]:
            per_grasp[name, grasp] = per_grasp.get((name, grasp), 0.0) + r["seconds"]
    secs = np.array(list(per_grasp.values()))
    return {
        # the engine's surface (convex slabs) against the mesh at each grasp's contact points
        "collision_surface": {
            "median_gap_mm": float(np.median(gap) * 1e3),
            "max_gap_mm": float(gap.max() * 1e3),
            "grasps_beyond_mm": SURFACE_GAP * 1e3,
            "n_grasps_beyond": int((gap > SURFACE_GAP).sum()),
        },
        "engine_seconds_per_grasp": (
            {"median": float(np.median(secs)), "worst": float(secs.max())} if secs.size else None
        ),
        "engine_trials_warned": sum(bool(r["engine_warnings"]) for r in trial.values()),
        "engine_trials_not_run": sum(not r["steps"] for r in trial.values()),
    }


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    # 1. every candidate's metrics and old truth: the minimal-work experiment itself
    mw_config = _mw_config(config)
    t_mw = time.perf_counter()
    mw_summary = _mw.run(mw_config)
    t_mw = time.perf_counter() - t_mw
    candidates = read_candidates_csv(Path(mw_config["out"]) / "grasps.csv")
    grasps = sample_candidates(candidates, config["objects"], config["n_grasps"], config["seed"])
    # 2. the engine trials
    trial, n_resumed, ran_on = _engine_trials(grasps, out, config)
    # 3. Table 4.6 against the engine, on the training split's normalisers
    objs = np.array([g["object"] for g in grasps])
    split = training_split(len(grasps), config["train_fraction"], config["seed"] + 1)
    gap = _surface_gap(grasps, config)
    table, old, balance = _tables(grasps, trial, split, objs, config)
    limits = _verdict_limits(grasps, trial, split, objs, config)
    _write_trials(out, grasps, trial, gap)
    summary = {
        **_judge_notes(config),
        "table_4_6_engine": {t: {m: table[t]["accuracy"][m] for m in METRICS} for t in TASKS},
        "table_4_6_engine_interval_95": {t: table[t]["interval_95"] for t in TASKS},
        "normalisers": {t: table[t]["normalisers"] for t in TASKS},
        "class_balance": balance,
        "old_truth_vs_engine": old,
        "verdict_thresholds": limits,
        # the same metrics against the old truth on all candidates (minimal-work's own table)
        "table_4_6_old_truth": mw_summary["table_4_6"],
        "thesis_table_4_6": _mw.THESIS_TABLE_4_6,
        "thesis_claims": _claims(table),
        "n_grasps_judged": len(grasps),
        "n_grasps_per_object": {n: int((objs == n).sum()) for n in config["objects"]},
        "n_candidates": mw_summary["n_grasps"],
        **_engine_stats(trial, gap),
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
        "seconds": {"metrics": t_mw, "total": time.perf_counter() - t_start},
    }
    summary["figures"] = [_figure(out, table, mw_summary["table_4_6"])]
    summary["headline"] = _headline(summary)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _claims(table: dict) -> dict:
    """The thesis's claim (§4.3.4): q_work predicts success best in both tasks, by the engine's verdicts."""
    out = {}
    for t in TASKS:
        ba = {m: table[t]["accuracy"][m]["All"] for m in METRICS}
        lo = (table[t]["interval_95"]["q_work"] or [np.nan])[0]
        others = max(ba["q_robust"], ba["q_force"])
        out[t] = {
            "claim": "q_work has the highest balanced accuracy (thesis: +28.8 / +22.7 % over the others)",
            "q_work_minus_best_other": ba["q_work"] - others,
            "reproduced": bool(ba["q_work"] > others),
            "q_work_interval_low_above_best_other": bool(lo > others),
        }
    return out


def _figure(out: Path, table: dict, old: dict) -> str:
    """Table 4.6's overall balanced accuracy per metric and task: engine (with its interval),
    the old truth, the thesis."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), sharey=True)
    x = np.arange(len(METRICS))
    for ax, t in zip(axes, TASKS, strict=True):
        eng = [table[t]["accuracy"][m]["All"] for m in METRICS]
        ci = [table[t]["interval_95"][m] or (e, e) for m, e in zip(METRICS, eng, strict=True)]
        err = np.array(
            [
                [e - c[0] for e, c in zip(eng, ci, strict=True)],
                [c[1] - e for e, c in zip(eng, ci, strict=True)],
            ]
        )
        ax.bar(x - 0.27, eng, 0.27, yerr=err, capsize=3, label="vs MuJoCo (95 % CI)")
        ax.bar(x, [old[t][m]["All"] for m in METRICS], 0.27, label="vs old truth (our models)")
        ax.bar(x + 0.27, [_mw.THESIS_TABLE_4_6[t][m]["All"] for m in METRICS], 0.27, label="thesis (real)")
        ax.axhline(0.5, color="0.5", lw=0.8, ls=":")
        ax.set_xticks(x, METRICS)
        ax.set_title(t.replace("_", " "))
        ax.set_ylim(0, 1.05)
    axes[0].set_ylabel("balanced accuracy (held out)")
    axes[1].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    path = out / "table_4_6_engine.png"
    save_figure(fig, path)
    plt.close(fig)
    return str(path)


def _headline(summary: dict) -> list[str]:
    lines = []
    for t in TASKS:
        row = summary["table_4_6_engine"][t]
        ci = summary["table_4_6_engine_interval_95"][t]
        cells = ", ".join(
            f"{m} {row[m]['All']:.3f}" + (f" [{ci[m][0]:.2f}, {ci[m][1]:.2f}]" if ci[m] else "")
            for m in METRICS
        )
        b = summary["class_balance"][t]
        o = summary["old_truth_vs_engine"][t]
        lines.append(
            f"{t}: vs MuJoCo {cells} ({b['engine_success']} held / {b['engine_failure']} not; the old truth "
            f"agrees on {o['agreement']:.2f})"
        )
    return lines
