"""The report's Chapter 4 claims judged by an existing engine (MuJoCo) instead of our own
truth: Table 4.1 on the elliptic-cylinder scene and on the bottle family's side grasps, and
Table 4.6's candidates (slip only), as data.

Each table below is a tuple of :class:`~workbench.runner.report_rules.Claim`; the thesis's
printed values are :mod:`workbench.runner.report_claims_ch4`'s, quoted once there.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .report_claims_ch4 import GAIN_4_1, GAIN_4_6, PRINTED_4_6, TABLE_4_1, TASKS, check_work_above, work_vs
from .report_rules import (
    RULE_NOT_COMPARABLE,
    Claim,
    Summaries,
    check_gain,
    mean_std_not_comparable,
    not_comparable,
    trend,
)

TRUTH_SE = (
    "simulated on an existing engine (MuJoCo: the scene's object between silicone pads moulded to it, "
    "the disturbance applied and held); it shares the patch geometry, mu, force and disturbance with the "
    "models, not their pressure law, fixed normal forces or resistance program"
)
TRUTH_SEB = (
    "simulated on an existing engine (MuJoCo: the rigid bottle mesh between flat silicone pads, the "
    "disturbance applied and held); it shares the mesh, grasp, mu, force, disturbance and pad size with the "
    "models, not our FEM pad's contact profile, fixed normal forces or resistance program"
)


@dataclass(frozen=True)
class EngineScene:
    """One engine-judged Table 4.1 scene: its summary, section, command, what it is, its truth."""

    file: str
    section: str
    run: str
    what: str
    truth: str
    figures: tuple[str, ...]


ENGINE_SCENES = (
    EngineScene(
        "sensitivity-engine/summary.json",
        "Table 4.1 (engine)",
        "workbench run sensitivity-engine",
        "the elliptic-cylinder scene's grasps",
        TRUTH_SE,
        ("sensitivity-engine/table_4_1_engine.png",),
    ),
    EngineScene(
        "sensitivity-engine-bottles/summary.json",
        "Table 4.1 (engine, bottle family)",
        "workbench run sensitivity-engine-bottles",
        "side grasps of the bottle family (FEM pad profiles)",
        TRUTH_SEB,
        ("sensitivity-engine-bottles/table_4_1_engine_bottles.png",),
    ),
)


def _engine_recall(f: str, model: str) -> Callable[[Summaries], Any]:
    """``model``'s recall against the engine (%) in ``f``: ``(mean, std)`` over seeds."""
    return lambda s: (
        100 * s.num(f, f"models.{model}.vs_engine.recall.mean"),
        100 * s.num(f, f"models.{model}.vs_engine.recall.std"),
    )


def _engine_gains(f: str) -> Callable[[Summaries], Any]:
    """``{baseline: (6dls's, baseline's mean recall against the engine)}`` in ``f``."""

    def gains(s: Summaries) -> dict:
        def get(m):
            return s.num(f, f"models.{m}.vs_engine.recall.mean")

        return {m: (get("6dls"), get(m)) for m in ("planar", "6dfw", "3dls_nonplanar")}

    return gains


def scene_claims(scene: EngineScene) -> tuple[Claim, ...]:
    """Table 4.1's rows and its 6DLS claim against the engine's verdicts on one ``scene``."""
    f = scene.file
    why = (
        f"the thesis's 1,035 physical grasps of ten 3D-printed objects; here {scene.what} judged by MuJoCo, "
        f"mean ± std over {{{{{f}|n_seeds|.0f}}}} seeds"
    )
    rows = tuple(
        Claim(
            scene.section,
            f"{name} (`{model}`), recall against the engine's verdicts (%)",
            printed,
            f"Table 4.1, row {name}",
            _engine_recall(f, model),
            mean_std_not_comparable(printed),
            RULE_NOT_COMPARABLE,
            scene.run,
            why=why,
            truth=scene.truth,
            figures=scene.figures,
        )
        for name, (model, printed) in TABLE_4_1.items()
    )
    gain = Claim(
        scene.section,
        "6DLS recall above 3DLS-planar, 6DFW and 3DLS-nonplanar, against the engine",
        GAIN_4_1,
        "§4.1.3.4, Table 4.1",
        _engine_gains(f),
        trend(check_gain("6dls")),
        "match if 6dls's mean recall against the engine exceeds each of the three's",
        scene.run,
        why="the engine's jaws are force-controlled and its pads deform: a load that wedges the curved "
        "contact is held by normal forces the models' fixed pressure does not have",
        truth=scene.truth,
        figures=scene.figures,
    )
    return (*rows, gain)


# ---------------------------------------------------------------- Table 4.6 against MuJoCo trials

MWE = "minimal-work-engine/summary.json"
RUN_MWE = "workbench run minimal-work-engine"
TRUTH_MWE = (
    "simulated on an existing engine (MuJoCo: silicone flex pads close with a fixed force on the rigid "
    "object as convex slabs, lift, turn, hold); it shares the mesh, mu, mass, grasp pose, force and pad size "
    "with the metrics, not the REACH profiles, 6DLS, exact 6DFW, stiffness map or wall FEM — and it judges "
    "slip only (no validated shell: engine-validation (d))"
)
FIG_MWE = ("minimal-work-engine/table_4_6_engine.png",)


def _ba_interval(task: str, metric: str) -> Callable[[Summaries], Any]:
    def ours(s: Summaries) -> Any:
        ci = s.get(MWE, f"table_4_6_engine_interval_95.{task}.{metric}")
        return (s.num(MWE, f"table_4_6_engine.{task}.{metric}.All"), *(ci or (float("nan"), float("nan"))))

    return ours


def _show_ba_interval(v: Any) -> str:
    """``BA [low, high]``, or the reason there is no interval (one class among the judged grasps)."""
    if v[1] != v[1]:  # NaN: quality_table gives no interval with fewer than two grasps of a class
        return f"{v[0]:.3f} (one outcome class: no interval)"
    return f"{v[0]:.3f} [{v[1]:.2f}, {v[2]:.2f}]"


_WHY_MWE = (
    "the thesis's 230 real trials a task; here {{minimal-work-engine/summary.json|n_grasps_judged|.0f}} "
    "candidates judged by MuJoCo, thresholds on a training half, 95 % bootstrap interval on the rest"
)

TABLE_4_6_ENGINE: tuple[Claim, ...] = (
    *(
        Claim(
            "Table 4.6 (engine)",
            f"{TASKS[task]}, {metric}, All, against the engine [95 % CI]",
            printed,
            f"Table 4.6, row All, {TASKS[task]}",
            _ba_interval(task, metric),
            not_comparable(printed, show=_show_ba_interval),
            RULE_NOT_COMPARABLE,
            RUN_MWE,
            why=_WHY_MWE,
            truth=TRUTH_MWE,
            figures=FIG_MWE,
        )
        for task, metrics in PRINTED_4_6.items()
        for metric, printed in metrics.items()
    ),
    *(
        Claim(
            "Table 4.6 (engine)",
            f"q_work above {other}, All, both tasks, against the engine",
            GAIN_4_6,
            "§4.3.4, Table 4.6",
            work_vs(other, MWE, "table_4_6_engine"),
            trend(check_work_above(other)),
            f"match if q_work's balanced accuracy against the engine exceeds {other}'s in both tasks",
            RUN_MWE,
            why="the engine judges slip only, not the deformation q_work adds",
            truth=TRUTH_MWE,
            figures=FIG_MWE,
        )
        for other in ("q_force", "q_robust")
    ),
)

#: the engine-judged claims, in report order
CLAIMS: tuple[Claim, ...] = (*(c for scene in ENGINE_SCENES for c in scene_claims(scene)), *TABLE_4_6_ENGINE)

__all__ = ["CLAIMS", "ENGINE_SCENES", "TABLE_4_6_ENGINE", "EngineScene", "scene_claims"]
