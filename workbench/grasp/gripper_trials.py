"""Physical gripper trials judged by every contact model (6DFC Table I; thesis Table 4.1): one
grasp's row of qualities and their scores against the real outcomes.

A grasp's row: at the recorded pose, the contact recomputed (both pads pressed, the object
settled between them — ``nominal`` — or each pad pressed alone — ``pressed``) and judged by each
model (:func:`~.gripper_eval.judge_contact`: held at the gripper's force, the force margin
``1 − f_min / f``); at N_r perturbed poses (:func:`~.pose_robust.pose_samples`, the stream of
:func:`pose_seed`) the robust quality, the mean margin (6DFC §V-B.1), and the fraction held.
Rows are flat dicts keyed ``<label>/<model>/<field>`` as the physical-trials experiment
checkpoints them.  Scores: thresholds only by leave-one-grasp-out cross-validation
(:func:`~.crossval.crossval_scores`: a grasp's trials never choose its own threshold).

``judge`` is the arguments of :func:`~.gripper_eval.judge_contact` but the contact, the model and
the cache: ``{"task": Task(mass=... [kg], com=(3,) [m], down=(3,)), "mu": ...}`` (a
:class:`~.inputs.Task`).  ``trials`` is a trial file as read by
:func:`workbench.sources.trials.read_trials` (``grasp_index`` (n,) int, ``success`` (n,) bool).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence

import numpy as np

from ..limit_surface import LimitSurfaceCache
from .crossval import crossval_scores, seed_summary
from .gripper_eval import gripper_contact, judge_contact
from .pose_robust import PoseNoise, pose_samples
from .precision import scores as scores_of
from .threshold import balanced_accuracy

__all__ = [
    "best_quality",
    "crossval_by_model",
    "judge_models",
    "nominal_fields",
    "pose_seed",
    "robust_fields",
    "verdict_scores",
]


def pose_seed(seed: int, g: int, s: int) -> np.random.Generator:
    """The pose samples' generator of grasp ``g`` at robustness seed ``s`` of a run's ``seed``:
    an independent stream per (seed, g, s)."""
    return np.random.default_rng([seed, g, s])


def judge_models(
    contact, models: Sequence[str], judge: Mapping, cache: LimitSurfaceCache
) -> tuple[dict, dict]:
    """({model: Verdict}, {model: seconds}) for one contact judged by every model of ``models``."""
    out, secs = {}, {}
    for m in models:
        t0 = time.perf_counter()
        out[m] = judge_contact(contact, m, cache=cache, **judge)
        secs[m] = time.perf_counter() - t0
    return out, secs


def nominal_fields(
    mesh, gripper, pose: np.ndarray, models: Sequence[str], judge: Mapping, cache: LimitSurfaceCache
) -> dict:
    """The row's fields of the recorded ``pose`` (4, 4): the contact settled (``nominal/…``)
    and pressed jaw by jaw (``pressed/…``), each judged by every model."""
    row = {}
    for label, settle in (("nominal", True), ("pressed", False)):
        t0 = time.perf_counter()
        c = gripper_contact(mesh, gripper, pose, settle=settle)
        row[f"{label}_contact_s"] = time.perf_counter() - t0
        verdicts, secs = judge_models(c, models, judge, cache)
        row[f"{label}_touches"] = c.touches
        row[f"{label}_tilt_deg"] = float(np.degrees(c.tilt))
        row[f"{label}_torque"] = c.torque
        row[f"{label}_reason"] = c.reason
        row[f"{label}_area_mm2"] = (
            [float(p.areas.sum() * 1e6) for p in c.profiles] if c.touches else [0.0, 0.0]
        )
        for m, v in verdicts.items():
            row[f"{label}/{m}/held"] = v.resisted
            row[f"{label}/{m}/margin"] = v.margin
            row[f"{label}/{m}/scale"] = v.scale if np.isfinite(v.scale) else None
            row[f"{label}/{m}/reason"] = v.reason
            row[f"{label}/{m}/s"] = secs[m]
    return row


def robust_fields(
    mesh,
    gripper,
    pose: np.ndarray,
    noise: PoseNoise,
    rng: np.random.Generator,
    models: Sequence[str],
    judge: Mapping,
    cache: LimitSurfaceCache,
) -> dict:
    """The row's robust fields: N_r contacts at poses around ``pose`` (4, 4) drawn by ``noise``
    from ``rng`` (:func:`pose_seed`), each judged by every model — per model the mean margin
    ``robust/<m>/q``, the fraction held ``robust/<m>/p_held`` and the seconds judging; the
    misses and the seconds computing contacts."""
    margins = {m: [] for m in models}
    held = {m: [] for m in models}
    contact_s, judge_s = [], {m: [] for m in models}
    misses = 0
    for T in pose_samples(pose, noise, seed=rng):
        t0 = time.perf_counter()
        c = gripper_contact(mesh, gripper, T)
        contact_s.append(time.perf_counter() - t0)
        misses += not c.touches
        verdicts, secs = judge_models(c, models, judge, cache)
        for m, v in verdicts.items():
            margins[m].append(v.margin)
            held[m].append(v.resisted)
            judge_s[m].append(secs[m])
    row = {"robust_misses": misses, "robust_contact_s": float(np.sum(contact_s))}
    for m in models:
        row[f"robust/{m}/q"] = float(np.mean(margins[m]))
        row[f"robust/{m}/p_held"] = float(np.mean(held[m]))
        row[f"robust/{m}/s"] = float(np.sum(judge_s[m]))
    return row


def crossval_by_model(
    trials, rows: Mapping[str, dict], models: Sequence[str], robust_seeds: int
) -> tuple[dict, dict]:
    """Per model and quality: cross-validated scores of ``rows`` (keyed ``<grasp>/<seed>``)
    against the trials' outcomes — ``nominal`` and ``pressed`` margins, and per robustness seed
    ``robust`` (q) and ``robust_held`` (p_held), summarised over the ``robust_seeds`` seeds
    (:func:`~.crossval.seed_summary`) and kept for seed 0.  Returns (scores, {model:
    {"nominal": {grasp: margin}, "pressed": {…}}})."""
    gi = trials.grasp_index
    keep = np.isin(gi, sorted({r["grasp"] for r in rows.values()}))
    group, success = gi[keep], trials.success[keep]
    per_grasp = {}
    scores = {}
    for m in models:
        nominal = {r["grasp"]: r[f"nominal/{m}/margin"] for r in rows.values() if r["seed"] == 0}
        pressed = {r["grasp"]: r[f"pressed/{m}/margin"] for r in rows.values() if r["seed"] == 0}
        out = {}
        for label, q in (("nominal", nominal), ("pressed", pressed)):
            out[label] = crossval_scores(np.array([q[g] for g in group]), success, group)
        for label, key in (("robust", "q"), ("robust_held", "p_held")):
            by_seed = []
            for s in range(robust_seeds):
                q = {r["grasp"]: r[f"robust/{m}/{key}"] for r in rows.values() if r["seed"] == s}
                by_seed.append(crossval_scores(np.array([q[g] for g in group]), success, group))
            out[label] = seed_summary(by_seed)
            out[f"{label}_seed0"] = by_seed[0]
        scores[m] = out
        per_grasp[m] = {"nominal": nominal, "pressed": pressed}
    return scores, per_grasp


def verdict_scores(trials, rows: Mapping[str, dict], models: Sequence[str]) -> dict:
    """Per model, the binary verdict "held at the gripper's force" at the recorded pose (the
    thesis's Table 4.1 kind of prediction: no threshold) against the outcomes: precision,
    recall, F1, accuracy and balanced accuracy, settled (``nominal``) and jaw by jaw
    (``pressed``)."""
    gi = trials.grasp_index
    grasps = sorted({r["grasp"] for r in rows.values()})
    keep = np.isin(gi, grasps)
    truth = trials.success[keep]
    out = {}
    for m in models:
        for label in ("nominal", "pressed"):
            pred = np.array([rows[f"{g}/0"][f"{label}/{m}/held"] for g in gi[keep]], dtype=bool)
            pr = scores_of(pred, truth)
            tp, fp, fn = int((pred & truth).sum()), int((pred & ~truth).sum()), int((~pred & truth).sum())
            f1 = 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else float("nan")
            out.setdefault(m, {})[label] = {
                **pr,
                "f1": f1,
                "accuracy": float((pred == truth).mean()),
                "balanced_accuracy": balanced_accuracy(pred, truth),
            }
    return out


def best_quality(scores: Mapping[str, dict]) -> dict:
    """The model and quality of :func:`crossval_by_model`'s ``scores`` with the highest
    cross-validated balanced accuracy (ties: ROC AUC; NaN counts as 0)."""
    cands = []
    for m, s in scores.items():
        for label in ("nominal", "pressed"):
            cands.append((s[label]["balanced_accuracy"], s[label]["roc_auc"], m, label))
        for label in ("robust", "robust_held"):
            r = s[label]
            cands.append((r["balanced_accuracy"]["mean"], r["roc_auc"]["mean"], m, label))
    ba, auc, m, label = max(cands, key=lambda c: (np.nan_to_num(c[0]), np.nan_to_num(c[1])))
    return {"model": m, "quality": label, "balanced_accuracy": ba, "roc_auc": auc}
