"""REPORT.md's section on the engine judge's own knobs: how its verdicts, and the models' and
metrics' ranking against them, move with the judge's pad, friction, content mass, jaw force and
verdict limits (the sweeps and runs the README lists under "The judge's friction" and "Table 4.6
judged by the engine").  Each row is read from a ``summary.json`` (a sweep's from its points);
a run that is not in ``results/`` is left out and said so."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

#: Table 4.1 judged by the engine: (label, folder) of the default run and its knob sweeps
SENSITIVITY_RUNS = (
    ("default (pad 1 MPa, μ 0.3)", "sensitivity-engine"),
    ("40 grasps a seed", "sensitivity-engine-5x40"),
    ("pad modulus", "sensitivity-engine-pad-E"),
    ("friction μ", "sensitivity-engine-mu"),
    ("wrapped scene", "sensitivity-engine-wrapped"),
    ("bottle family", "sensitivity-engine-bottles"),
)
#: Table 4.6 judged by the engine: (label, folder)
WORK_RUNS = (
    ("default (10 N, filled mass)", "minimal-work-engine"),
    ("jaw force", "minimal-work-engine-force"),
    ("content mass 2×", "minimal-work-engine-mass-2x"),
    ("thesis-size (100 grasps / object)", "minimal-work-engine-thesis-size"),
)
METRICS = ("q_robust", "q_force", "q_work")
#: the experiments' default verdict limits (drift, turn), the runs' own rows
DEFAULT_LIMITS = "5mm_5deg"


def _read(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def _runs(results: Path, folder: str) -> list[tuple[str, dict]]:
    """``[(setting, summary)]`` of a run folder: its own summary, or each point of a sweep
    (``points.jsonl``'s values, ``points/<key>/summary.json``) in the grid's order."""
    own = _read(results / folder / "summary.json")
    if own is not None:
        return [("", own)]
    runs = []
    try:
        lines = (results / folder / "points.jsonl").read_text().splitlines()
    except OSError:
        return []
    points = [json.loads(line) for line in lines]
    # in the knob's order (a grid's points finish in any order)
    points.sort(key=lambda p: tuple(_order(v) for v in p["values"].values()))
    for point in points:
        summary = _read(results / folder / "points" / point["key"] / "summary.json")
        if point.get("status") == "ok" and summary is not None:
            values = point["values"].items()
            setting = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in values)
            runs.append((setting, summary))
    return runs


def _order(v: Any) -> tuple:
    """A grid value's place: numbers by value before anything else by its text."""
    return (0, v, "") if isinstance(v, (int, float)) else (1, 0, str(v))


def _f(x: Any, digits: int = 2) -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.{digits}f}"


def _ranking(scores: dict[str, float], digits: int = 2) -> str:
    """``name score`` pairs, best first (ties keep the given order)."""
    order = sorted(scores, key=lambda k: -scores[k] if scores[k] is not None else math.inf)
    return ", ".join(f"{k} {_f(scores[k], digits)}" for k in order)


def _sensitivity_rows(label: str, setting: str, s: dict, limits: bool) -> list[str]:
    acc = {m: v["vs_engine"]["accuracy"]["mean"] for m, v in s["models"].items()}
    rows = [
        f"| {label} | {setting or '—'} | {_f(s['engine_positive_fraction']['mean'])} "
        f"| {_f(s['exact_6dfw_vs_engine']['accuracy']['mean'])} | {_ranking(acc)} |"
    ]
    for name, v in s.get("verdict_thresholds", {}).items() if limits else ():
        if name == DEFAULT_LIMITS:  # the row above
            continue
        acc = {m: r["accuracy"] for m, r in v["models"].items()}
        limit = name.replace("_", " / ")
        rows.append(f"| {label}: verdict limits | {limit} | {_f(v['held_fraction'])} | — | {_ranking(acc)} |")
    return rows


def _work_rows(label: str, setting: str, s: dict, limits: bool) -> list[str]:
    rows = []
    for task, t in s["table_4_6_engine"].items():
        bal = s["class_balance"][task]
        held = f"{bal['engine_success']} / {bal['engine_success'] + bal['engine_failure']}"
        ba = {m: t[m]["All"] for m in METRICS}
        ci = s["table_4_6_engine_interval_95"][task]
        shown = ", ".join(
            f"{m} {_f(ba[m], 3)}" + (f" [{_f(ci[m][0])}, {_f(ci[m][1])}]" if ci.get(m) else "")
            for m in METRICS
        )
        name = task.replace("_", " ")
        rows.append(f"| {label} | {setting or '—'} | {name} | {held} | {shown} | {_ranking(ba, 3)} |")
    for name, v in s.get("verdict_thresholds", {}).items() if limits else ():
        for task, t in v.items():
            ba = {m: t[m] for m in METRICS if m in t}
            if name == DEFAULT_LIMITS or not ba:  # the default's row above; a task with one class
                continue
            shown = ", ".join(f"{m} {_f(ba[m], 3)}" for m in METRICS)
            rows.append(
                f"| {label}: verdict limits | {name.replace('_', ' / ')} | {task.replace('_', ' ')} "
                f"| {_f(t['held_fraction'])} held | {shown} | {_ranking(ba, 3)} |"
            )
    return rows


def _table(results: Path, runs: tuple, rows, missing: list[str]) -> list[str]:
    """Every row of ``runs`` ((label, folder), the first one's verdict limits too) by ``rows``;
    the folders not in ``results`` appended to ``missing``."""
    out: list[str] = []
    for label, folder in runs:
        found = _runs(results, folder)
        missing += [folder] if not found else []
        for setting, s in found:
            out += rows(label, setting, s, limits=folder == runs[0][1])
    return out


def render_judge_sections(results_dir: str | Path, link_prefix: str = "") -> str:
    """The Markdown section (a string starting with a newline; empty when no run is present)."""
    results = Path(results_dir)
    out: list[str] = []
    missing: list[str] = []
    sens = _table(results, SENSITIVITY_RUNS, _sensitivity_rows, missing)
    work = _table(results, WORK_RUNS, _work_rows, missing)
    if not sens and not work:
        return ""
    out += [
        "",
        "## The engine judge's knobs",
        "",
        "How the simulated judge's verdicts — and the models' ranking against them — move with the "
        "judge's own settings: its pad, its friction, the content's mass, the jaw force and the "
        "verdict's limits (drift / turn in the gripper, re-read from each trial's recorded motion). "
        "A ranking that holds across them is a property of the models; one that flips is a property "
        "of the judge.",
        "",
    ]
    if sens:
        out += [
            "Table 4.1's question (every contact model's accuracy against the engine, mean over seeds):",
            "",
            "| run | setting | engine holds | exact 6DFW agrees | accuracy, best first |",
            "|---|---|---|---|---|",
            *sens,
            "",
        ]
    if work:
        out += [
            "Table 4.6's metrics (balanced accuracy against the engine on the held-out half, 95 % bootstrap "
            "interval; a column whose held-out half has one outcome class has no interval):",
            "",
            "| run | setting | task | engine held | balanced accuracy | best first |",
            "|---|---|---|---|---|---|",
            *work,
            "",
        ]
    if missing:
        out += [f"Not in this results folder: {', '.join(f'`{link_prefix}{m}/`' for m in missing)}.", ""]
    return "\n".join(out)


__all__ = ["SENSITIVITY_RUNS", "WORK_RUNS", "render_judge_sections"]
