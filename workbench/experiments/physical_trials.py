"""Real robot grasps: every contact model's prediction on physical trials (6DFC Table I;
thesis Table 4.1), scored against the real outcomes.

The default trials are the REACH dataset's 125 physical grasps of one object (ABB YuMi,
3 mm silicone pads, 20 N, μ 0.3, a 3 cm cube of 3 g; MIT, packaged in
``workbench/data/reach_trials/`` with its notice) — one object of REACH's 21, 125 of its 2,625
trials.  Any file of that format runs with ``--set trials=PATH --set mesh=PATH``.

Per grasp (its gripper pose in the object's frame, gravity in that frame): the contact is
recomputed from the pose — both pads pressed, the object free to settle between them
(:mod:`workbench.grasp.settle`) — and every model judges it (:func:`judge_contact`: held at
the gripper's force, and the force margin ``1 − f_min / f``).  Qualities: ``nominal`` (the
margin at the recorded pose) and ``robust`` (the mean margin over N_r recomputed contacts at
perturbed poses, 6DFC §V-B.1; one value per robustness seed).  Thresholds only by
leave-one-grasp-out cross-validation (a grasp's trials never choose its own threshold).
The contact with each pad pressed alone (no settling) is recorded beside, to show what the
settle changes.
"""

from __future__ import annotations

import time
from functools import lru_cache, partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.grasp.gripper_eval import check_task, gripper_contact
from workbench.grasp.gripper_trials import (
    best_quality,
    crossval_by_model,
    nominal_fields,
    pose_seed,
    robust_fields,
    verdict_scores,
)
from workbench.grasp.inputs import Task
from workbench.grasp.models import MODELS
from workbench.grasp.pose_robust import PoseNoise
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import Checkpoint, save_figure, write_csv, write_summary

NAME = "physical-trials"

DEFAULT_CONFIG = {
    "seed": 0,
    "trials": "",  # a REACH trial JSON; "" = the packaged cube_3cm.json
    "mesh": "",  # the object's mesh [m]; "" = the packaged cube_3cm.obj
    "gripper": "yumi",  # "yumi" (the packaged preset) or a gripper yaml in the same format
    "mass": 0.0,  # kg; 0 = read by object name (REACH's masses: the cube 3 g)
    "mu": 0.0,  # friction coefficient; 0 = the gripper's own (YuMi: 0.3)
    "models": list(MODELS),
    "n_robust": 10,  # N_r pose samples per grasp (6DFC Fig. 3's best)
    "sigma_trans": 0.003,  # m, per axis (6DFC's sigma_r)
    "sigma_rot": 0.003,  # rad, per axis
    "robust_seeds": 5,  # robustness seeds: mAP ± std over them (6DFC Table I: 5 runs)
    "grasps": [],  # grasp indices to run; [] = all
    "workers": 0,  # 0 = one per core when there are many rows, 1 = serially here
    "scheduler": "",  # an existing Dask cluster's address
}
#: what each key means, its unit and plausible range (``workbench run physical-trials --help``);
#: mass carries no quantity: its 0 means "read by name", which the mass range refuses, so
#: check_config judges it when given
KEYS = {
    "trials": Key("a REACH trial JSON file; empty = the packaged cube_3cm.json"),
    "mesh": Key("the object's mesh file in metres; empty = the packaged cube_3cm.obj"),
    "gripper": Key("'yumi' (the packaged preset) or a gripper yaml file in the same format"),
    "mass": Key("object mass; REACH's by the object's name when 0 (the cube: 3 g)", "kg", "mass", unset=0.0),
    "mu": Key("friction coefficient; 0 = the gripper's own (YuMi: 0.3)", "", "mu"),
    "models": Key("contact models judged, at least one", choices=lambda: MODELS),
    "n_robust": Key("pose samples N_r per grasp, >= 1 (6DFC Fig. 3's best: 10)"),
    "sigma_trans": Key("pose noise per axis, translation (6DFC's sigma_r)", "m", "pose_noise_trans"),
    "sigma_rot": Key("pose noise per axis, rotation", "rad", "pose_noise_rot"),
    "robust_seeds": Key("robustness seeds: mAP +- std over them, >= 1 (6DFC Table I: 5)"),
    "grasps": Key("grasp indices to run; [] = all"),
}
QUICK_CONFIG = {
    "models": ["soft_point", "6dls", "6dfc"],
    "n_robust": 3,
    "robust_seeds": 2,
    "grasps": [0, 2, 5, 19],
}
WHERE_KEYS = ("out", "workers", "scheduler")


def check_config(config: dict) -> None:
    """What fails only inside a run, refused before any work."""
    check_workers(config["workers"], config["scheduler"])
    for key, spec in KEYS.items():  # μ and the model names (also for run(config))
        check_key(key, spec, config[key])
    if not config["models"]:
        raise ValueError(f"models must name at least one of {list(MODELS)}; got []")
    if config["robust_seeds"] < 1 or config["n_robust"] < 1:
        raise ValueError(
            "n_robust and robust_seeds must be counts >= 1; got "
            f"{config['n_robust']!r}, {config['robust_seeds']!r}"
        )
    PoseNoise(config["n_robust"], config["sigma_trans"], config["sigma_rot"]).resolved()
    for key, what in (("trials", "a REACH trial JSON file"), ("mesh", "a mesh file in metres")):
        if config[key] and not Path(config[key]).is_file():
            raise ValueError(f"{key} must be {what} or '' (the packaged cube); no file {config[key]!r}")
    if config["gripper"] != "yumi" and not Path(config["gripper"]).is_file():
        raise ValueError(
            f"gripper must be 'yumi' (the only packaged preset) or a gripper YAML file; got "
            f"{config['gripper']!r}, which is neither"
        )
    if config["grasps"]:  # indices of the trial file's grasps: checked against the file itself
        known = set(_inputs(config)[0].grasp_index.tolist())
        unknown = sorted(set(config["grasps"]) - known)
        if unknown:
            raise ValueError(
                f"grasps {unknown} are not grasp indices of the trial file (it has "
                f"{min(known)}-{max(known)}, {len(known)} grasps); [] runs all"
            )


def _inputs(config: dict):
    """(trials, mesh, gripper) of the config, read once per process."""
    return _read_inputs(config["trials"], config["mesh"], config["gripper"])


@lru_cache(maxsize=2)
def _read_inputs(trials_path: str, mesh_path: str, gripper: str):
    import trimesh

    from workbench.sources.gripper import gripper_from_yaml, yumi
    from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials

    trials = read_trials(trials_path or default_trials_path())
    mesh = trimesh.load(mesh_path or default_mesh_path(), force="mesh")
    gripper = yumi() if gripper == "yumi" else gripper_from_yaml(gripper)
    return trials, mesh, gripper


def _mass(config: dict, trials) -> float:
    """The object's mass [kg]: given, or read by the trials' object name."""
    if config["mass"]:
        return float(config["mass"])
    if trials.mass is None:
        raise ValueError(
            f"the mass of {trials.obj!r} is not known here (REACH's objects only): give it, "
            "e.g. --set mass=0.25 [kg]"
        )
    return float(trials.mass)


def _grasp_row(job, config: dict) -> list:
    """One Dask task: grasp ``g`` at robustness seed ``s`` — N_r recomputed contacts judged by
    every model; seed 0 also the nominal contact, settled and pressed jaw by jaw."""
    g, s = job
    trials, mesh, gripper = _inputs(config)
    grasp = trials.grasps()[g]
    mu = config["mu"] or gripper.mu
    task = Task(mass=_mass(config, trials), com=mesh.center_mass, down=grasp.down)
    judge = {"task": task, "mu": mu}
    cache = LimitSurfaceCache()
    models = config["models"]
    row = {"grasp": g, "seed": s}
    if s == 0:
        row.update(nominal_fields(mesh, gripper, grasp.pose, models, judge, cache))
    noise = PoseNoise(config["n_robust"], config["sigma_trans"], config["sigma_rot"])
    rng = pose_seed(config["seed"], g, s)
    row.update(robust_fields(mesh, gripper, grasp.pose, noise, rng, models, judge, cache))
    return [(f"{g}/{s}", row)]


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    trials, mesh, gripper = _inputs(config)
    mu = config["mu"] or gripper.mu
    check_task(mesh, _mass(config, trials), mu, (0.0, 0.0, -1.0))
    grasps = trials.grasps()
    todo_g = config["grasps"] or sorted(grasps)
    key_cfg = {k: v for k, v in config.items() if k not in WHERE_KEYS}
    ckpt = Checkpoint(out / "rows.jsonl", key_cfg, code=code_digest(__name__))
    jobs = [(g, s) for g in todo_g for s in range(config["robust_seeds"]) if f"{g}/{s}" not in ckpt.rows]

    def keep(job, res) -> None:
        for key, row in res:
            ckpt.add(key, row)

    with tqdm(total=len(jobs), desc="grasps x seeds", unit="row") as bar:
        _, ran_on = run_rows(partial(_grasp_row, config=config), jobs, keep, config, progress=bar)
    rows = {k: r for k, r in ckpt.rows.items() if r["grasp"] in todo_g}
    models = config["models"]
    scores, per_grasp = crossval_by_model(trials, rows, models, config["robust_seeds"])
    summary = _summary(trials, rows, scores, models, config, ran_on)
    _tables(out, trials, rows, models, todo_g)
    _figures(out, trials, rows, scores, models, todo_g, config)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _summary(trials, rows, scores, models, config, ran_on) -> dict:
    nominal_rows = [r for r in rows.values() if r["seed"] == 0]
    outcomes = {}
    for g in sorted({r["grasp"] for r in rows.values()}):
        sel = trials.grasp_index == g
        outcomes[str(g)] = int(trials.success[sel].sum())
    timing = {}
    for m in models:
        per = [
            (r["robust_contact_s"] + r[f"robust/{m}/s"]) * 1e3 for r in rows.values()
        ]  # what one model costs a user: N_r contacts + the model's judgements
        timing[m] = {"median_ms_per_grasp_n_robust": float(np.median(per)), "worst_ms": float(np.max(per))}

    def flips(label):
        return {m: int(sum(not r[f"{label}/{m}/held"] for r in nominal_rows)) for m in models}

    return {
        "data": "REACH physical trials: one object of REACH's 21, "
        f"{int(np.isin(trials.grasp_index, [r['grasp'] for r in nominal_rows]).sum())} of its 2,625 trials",
        "n_trials": int(np.isin(trials.grasp_index, [r["grasp"] for r in nominal_rows]).sum()),
        "n_grasps": len(nominal_rows),
        "successes_per_grasp": outcomes,
        "ran_on": ran_on,
        "scores": scores,
        "not_held_nominal": flips("nominal"),
        "not_held_pressed_jaw_by_jaw": flips("pressed"),
        "settle": {
            "tilt_deg": {str(r["grasp"]): r["nominal_tilt_deg"] for r in nominal_rows},
            "converged": int(sum(r["nominal_torque"] <= 1e-3 for r in nominal_rows if r["nominal_touches"])),
        },
        "verdict_scores": verdict_scores(trials, rows, models),
        "timing": timing,
        "best": best_quality(scores),
        "per_grasp": _per_grasp(trials, rows, scores, models),
    }


def _per_grasp(trials, rows, scores, models) -> dict:
    """Per grasp: its outcomes, contact and, per model, the qualities and the cross-validated
    predictions (robust qualities: seed 0)."""
    gi = trials.grasp_index
    grasps = sorted({r["grasp"] for r in rows.values()})
    first = {g: int(np.flatnonzero(gi[np.isin(gi, grasps)] == g)[0]) for g in grasps}
    out = {}
    for g in grasps:
        r = rows[f"{g}/0"]
        out[str(g)] = {
            "held": int(trials.success[gi == g].sum()),
            "trials": int((gi == g).sum()),
            "contact_area_mm2": r["nominal_area_mm2"],
            "settle_tilt_deg": r["nominal_tilt_deg"],
            "robust_misses_seed0": r["robust_misses"],
            "models": {
                m: {
                    "nominal_margin": r[f"nominal/{m}/margin"],
                    "robust_q": r[f"robust/{m}/q"],
                    "robust_p_held": r[f"robust/{m}/p_held"],
                    "reason": r[f"nominal/{m}/reason"],
                    **{
                        f"predicted_{lab}": bool(scores[m][key]["predicted"][first[g]])
                        for lab, key in (
                            ("nominal", "nominal"),
                            ("robust", "robust_seed0"),
                            ("robust_held", "robust_held_seed0"),
                        )
                    },
                }
                for m in models
            },
        }
    return out


def _tables(out, trials, rows, models, grasps) -> None:
    head = ["grasp", "successes", "area1_mm2", "area2_mm2", "tilt_deg"]
    head += [f"{lab}/{m}" for m in models for lab in ("nominal", "robust_seed0")]
    body = []
    for g in grasps:
        r = rows[f"{g}/0"]
        body.append(
            [
                g,
                int(trials.success[trials.grasp_index == g].sum()),
                *r["nominal_area_mm2"],
                r["nominal_tilt_deg"],
            ]
            + [x for m in models for x in (r[f"nominal/{m}/margin"], r[f"robust/{m}/q"])]
        )
    write_csv(out / "grasps.csv", head, body)


def _figures(out, trials, rows, scores, models, grasps, config) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from workbench.grasp.crossval import roc_curve_points

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    gi = trials.grasp_index
    keep = np.isin(gi, grasps)
    success = trials.success[keep]
    for m in models:
        q = np.array([rows[f"{g}/0"][f"robust/{m}/q"] for g in gi[keep]])
        fpr, tpr, prec, rec = roc_curve_points(q, success)
        axes[0].plot(fpr, tpr, label=f"{m} (AUC {scores[m]['robust_seed0']['roc_auc']:.2f})")
        axes[1].step(rec, prec, where="post", label=m)
    axes[0].plot([0, 1], [0, 1], "k:", lw=0.8)
    axes[0].set(
        xlabel="false positive rate", ylabel="true positive rate", title="ROC, robust quality (seed 0)"
    )
    axes[1].set(xlabel="recall", ylabel="precision", title="precision-recall, robust quality (seed 0)")
    axes[0].legend(fontsize=7)
    save_figure(fig, out / "roc_pr.png")
    plt.close(fig)
    _panels(out, trials, rows, models, grasps, plt, config)


def _panels(out, trials, rows, models, grasps, plt, config) -> None:
    """Per grasp: jaw 1's pad on the face where the object settled, its contact, the outcome and
    each model's robust quality (seed 0)."""
    from workbench.runner.trial_figures import facing_surface, grasp_panel

    _, mesh, gripper = _inputs(config)
    n = len(grasps)
    cols = int(np.ceil(np.sqrt(n)))
    fig, axes = plt.subplots(int(np.ceil(n / cols)), cols, figsize=(1.9 * cols, 2.2 * np.ceil(n / cols)))
    axes = np.atleast_1d(axes).ravel()
    for ax, g in zip(axes, grasps, strict=False):
        grasp = trials.grasps()[g]
        c = gripper_contact(mesh, gripper, grasp.pose)
        held = sum(grasp.outcomes)
        grasp_panel(
            ax,
            c,
            facing_surface(mesh, c.jaws[0]),
            title=f"grasp {g}",
            outcome=f"{held}/{len(grasp.outcomes)} held",
            qualities={m: rows[f"{g}/0"][f"robust/{m}/q"] for m in models},
            failed=held * 2 < len(grasp.outcomes),
        )
    for ax in axes[n:]:
        ax.set_axis_off()
    fig.suptitle(
        "jaw 1's pad (outline) on the face, the settled contact (pressure), robust quality q", fontsize=8
    )
    save_figure(fig, out / "grasp_panels.png", dpi=160)
    plt.close(fig)
