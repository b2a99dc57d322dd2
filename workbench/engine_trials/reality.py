"""The engine judged against reality: the REACH cube trials (ABB YuMi, silicone pads, a 3 cm cube
of 3 g; 25 grasps × 5 repeats, their gripper poses identical per grasp), each grasp simulated
once at its recorded pose by :func:`~.trial.simulate_gripper` — the robot's protocol: the cube on
a table, the jaws closing by the YuMi's 20 N, lifting — and the verdicts scored against the 125
real outcomes with no threshold fitted (the verdict is binary)."""

from __future__ import annotations

import time
from functools import lru_cache

import numpy as np


@lru_cache(maxsize=1)
def reach_cube_inputs():
    """(trials, mesh) of the packaged REACH cube trials, read once per process."""
    import trimesh

    from ..sources.trials import default_mesh_path, default_trials_path, read_trials

    return read_trials(default_trials_path()), trimesh.load(default_mesh_path(), force="mesh")


def reach_trial(grasp: int) -> dict:
    """Grasp ``grasp`` (0-24) of the packaged REACH cube trials simulated at its recorded pose:
    its real success rate over the repeats, the engine's verdict, reason, drift [mm], turn
    [deg], wall and simulated seconds, engine warnings."""
    from ..sources.gripper import yumi
    from .trial import EngineObject, simulate_gripper

    trials, mesh = reach_cube_inputs()
    known = sorted(set(trials.grasp_index.tolist()))
    if isinstance(grasp, bool) or grasp not in known:
        raise ValueError(
            f"grasp must be a grasp index of the REACH cube trials, one of {known}; got {grasp!r}"
        )
    i = int(np.flatnonzero(trials.grasp_index == grasp)[0])
    t0 = time.perf_counter()
    obj = EngineObject(mass=trials.mass, down=trials.down[i])
    r = simulate_gripper(mesh, yumi(), trials.gripper_pose[i], obj=obj)
    real = trials.success[trials.grasp_index == grasp]
    return {
        "grasp": int(grasp),
        "real_success_rate": float(real.mean()),
        "held": bool(r.held),
        "reason": r.reason,
        "drift_mm": r.drift * 1e3,
        "turn_deg": r.turn_deg,
        "wall_s": time.perf_counter() - t0,
        "simulated_s": r.steps * 1e-3,
        "engine_warnings": r.engine_warnings,
    }


def excursion(row: dict, max_drift_mm: float, max_turn_deg: float) -> float:
    """How far a trial's object moved in the gripper, in units of the verdict's limits:
    ``max(drift / max_drift, turn / max_turn)`` — held iff <= 1.  Its negative ranks the grasps
    for an AUC: the limits scale it, they are not fitted to any outcome."""
    return max(row["drift_mm"] / max_drift_mm, row["turn_deg"] / max_turn_deg)


def score_reach(rows: list[dict]) -> dict:
    """The verdicts of :func:`reach_trial` rows against every real trial of their grasps:
    balanced accuracy, true-positive and true-negative rates, real failures predicted, the ROC AUC
    of the object's :func:`excursion` in the gripper (at :class:`~.trial.TrialPhases`' limits; each
    real repeat scored by its grasp's trial), seconds per trial (median, worst) and simulated
    seconds per wall second."""
    from ..grasp.crossval import roc_auc
    from .trial import TrialPhases

    trials, _ = reach_cube_inputs()
    held = {row["grasp"]: row["held"] for row in rows}
    limits = TrialPhases()
    moved = {row["grasp"]: excursion(row, limits.max_drift * 1e3, limits.max_turn_deg) for row in rows}
    mask = np.isin(trials.grasp_index, list(held))
    pred = np.array([held[k] for k in trials.grasp_index[mask]], dtype=bool)
    real = trials.success[mask].astype(bool)
    score = -np.array([moved[k] for k in trials.grasp_index[mask]], dtype=float)
    tpr = float((pred & real).sum() / real.sum()) if real.any() else float("nan")
    tnr = float((~pred & ~real).sum() / (~real).sum()) if (~real).any() else float("nan")
    walls = [row["wall_s"] for row in rows]
    return {
        "what": "REACH cube trials simulated on MuJoCo (engine_trials.simulate_gripper) vs the real outcomes",
        "n_grasps": len(rows),
        "n_trials": int(mask.sum()),
        "real_failures": int((~real).sum()),
        "balanced_accuracy": (tpr + tnr) / 2,
        "true_positive_rate": tpr,
        "true_negative_rate": tnr,
        "failures_predicted": int((~pred & ~real).sum()),
        "roc_auc": roc_auc(score, real) if real.any() and (~real).any() else float("nan"),
        "auc_score": "-(the object's excursion in the gripper / the verdict's limits), max of drift and turn",
        "seconds_per_trial": {"median": float(np.median(walls)), "worst": float(np.max(walls))},
        "simulated_seconds_per_wall_second": float(sum(r["simulated_s"] for r in rows) / sum(walls)),
        "rows": rows,
    }
