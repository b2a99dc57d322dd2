"""Candidate grasps read back by another judge: minimal-work's ``grasps.csv`` as rows, and a
seeded sample of each object's candidates that every larger sample contains.

``grasps.csv`` holds one row per candidate (:func:`~.work_table.grasp_row`): ``object``,
``grasp``, the contact points and axis (``p1_x`` … ``axis_z``, object frame [m]) and per task of
:data:`~.work_table.TASKS` its simulated truth and Table 4.6 metrics (``<task>_truth``,
``<task>_q_robust``, ``<task>_f_sum`` [N], ``<task>_W`` [J]).  An unresisted task's cost is
written as empty, ``None``, ``nan`` or ``inf``; it reads as inf (always predicted to fail).
"""

from __future__ import annotations

import csv
import numbers
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .work_table import TASKS

__all__ = ["cost_from_csv", "read_candidates_csv", "sample_candidates"]


def cost_from_csv(text: str) -> float:
    """A cost cell of a CSV (a minimal force [N] or work [J]) as a float: ``""``, ``"None"`` and
    ``"nan"`` (the task is not resisted) as inf, any other cell as ``float(text)``."""
    x = float(text) if text not in ("", "None") else float("nan")
    return float("inf") if np.isnan(x) else x


def read_candidates_csv(path: str | Path, tasks: Sequence[str] = TASKS) -> list[dict]:
    """The candidates of a minimal-work ``grasps.csv`` (module docstring), in file order:
    ``{"object", "grasp", "p1", "p2", "axis", <task>: {"truth", "q_robust", "f_sum", "W"}}`` per
    row, ``p1``, ``p2``, ``axis`` as 3-lists [m], the costs by :func:`cost_from_csv`."""
    rows = []
    with Path(path).open() as f:
        for r in csv.DictReader(f):
            row = {"object": r["object"], "grasp": int(r["grasp"])}
            for v in ("p1", "p2", "axis"):
                row[v] = [float(r[f"{v}_{c}"]) for c in "xyz"]
            for t in tasks:
                row[t] = {
                    "truth": r[f"{t}_truth"] == "True",
                    "q_robust": float(r[f"{t}_q_robust"]),
                    "f_sum": cost_from_csv(r[f"{t}_f_sum"]),
                    "W": cost_from_csv(r[f"{t}_W"]),
                }
            rows.append(row)
    return rows


def sample_candidates(
    grasps: Sequence[dict], objects: Sequence[str], n_per_object: int, seed: int
) -> list[dict]:
    """``n_per_object`` of each object's candidates drawn without replacement (all of them when
    it has fewer), object by object in the order of ``objects``, each object's in the order of
    ``grasps`` (rows with an ``"object"`` key).

    Each object's draw is the first ``n_per_object`` of one permutation of its ``k`` candidates,
    from the stream ``numpy.random.default_rng([seed, k])``: a smaller sample is part of a larger
    one of the same seed (a judge that checkpoints its trials resumes them all).  ``seed`` is an
    int, not a Generator: the stream is keyed by the object's candidate count."""
    if isinstance(n_per_object, bool) or not isinstance(n_per_object, numbers.Integral) or n_per_object < 1:
        raise ValueError(
            f"n_per_object must be an integer >= 1 (candidates per object); got {n_per_object!r}"
        )
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
        raise ValueError(
            f"seed must be an integer (e.g. 0); got {seed!r} — a Generator cannot key each object's stream"
        )
    out = []
    for name in objects:
        mine = [g for g in grasps if g["object"] == name]
        pick = np.sort(np.random.default_rng([seed, len(mine)]).permutation(len(mine))[:n_per_object])
        out += [mine[i] for i in pick]
    return out
