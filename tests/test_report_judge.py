"""workbench.runner.report_judge: REPORT.md's section on the engine judge's knobs, from summaries only."""

import json

from workbench.runner.report_judge import render_judge_sections


def _sens(acc: dict, held: float, agree: float, limits: dict | None = None) -> dict:
    return {
        "engine_positive_fraction": {"mean": held},
        "exact_6dfw_vs_engine": {"accuracy": {"mean": agree}},
        "models": {m: {"vs_engine": {"accuracy": {"mean": a}}} for m, a in acc.items()},
        "verdict_thresholds": limits or {},
    }


def _write(path, obj):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(obj))


def test_rows_rank_best_first_sweeps_in_the_knobs_order_and_missing_runs_are_named(tmp_path):
    def acc(a6, ap):
        return {"6dls": {"accuracy": a6}, "planar": {"accuracy": ap}}

    limits = {
        "2mm_2deg": {"held_fraction": 0.5, "models": acc(0.9, 0.95)},
        "5mm_5deg": {"held_fraction": 0.8, "models": acc(0.7, 0.6)},
    }
    sens = tmp_path / "sensitivity-engine/summary.json"
    _write(sens, _sens({"planar": 0.6, "6dls": 0.7}, 0.8, 0.65, limits))
    # a sweep whose points finished out of order, one of them failed
    points = [
        {"key": "mu=0.6-b", "values": {"mu": 0.6}, "status": "ok"},
        {"key": "mu=0.15-a", "values": {"mu": 0.15}, "status": "ok"},
        {"key": "mu=0.3-c", "values": {"mu": 0.3}, "status": "error"},
    ]
    (tmp_path / "sensitivity-engine-mu").mkdir()
    (tmp_path / "sensitivity-engine-mu/points.jsonl").write_text("\n".join(json.dumps(p) for p in points))
    sweep = tmp_path / "sensitivity-engine-mu/points"
    _write(sweep / "mu=0.6-b/summary.json", _sens({"planar": 0.9, "6dls": 0.95}, 0.97, 0.9))
    _write(sweep / "mu=0.15-a/summary.json", _sens({"planar": 0.5, "6dls": 0.4}, 0.5, 0.7))
    task = {"q_robust": {"All": 0.6}, "q_force": {"All": 0.7}, "q_work": {"All": 0.5}}
    _write(
        tmp_path / "minimal-work-engine/summary.json",
        {
            "table_4_6_engine": {"lift_and_rotate": task},
            "table_4_6_engine_interval_95": {"lift_and_rotate": {"q_robust": [0.4, 0.8], "q_force": None}},
            "class_balance": {"lift_and_rotate": {"engine_success": 30, "engine_failure": 18}},
        },
    )
    text = render_judge_sections(tmp_path, "../results/")
    lines = text.splitlines()
    row = next(x for x in lines if x.startswith("| default (pad"))
    assert row.endswith("| 0.80 | 0.65 | 6dls 0.70, planar 0.60 |")
    # the default limits are the run's own row; the others get one each, the best model first
    limit_rows = [x for x in lines if "verdict limits" in x]
    assert limit_rows == [
        "| default (pad 1 MPa, μ 0.3): verdict limits | 2mm / 2deg | 0.50 | — | planar 0.95, 6dls 0.90 |"
    ]
    mu = [x for x in lines if x.startswith("| friction μ")]
    assert mu == [
        "| friction μ | mu = 0.15 | 0.50 | 0.70 | planar 0.50, 6dls 0.40 |",
        "| friction μ | mu = 0.6 | 0.97 | 0.90 | 6dls 0.95, planar 0.90 |",
    ]
    work = next(x for x in lines if x.startswith("| default (10 N"))
    assert "| 30 / 48 | q_robust 0.600 [0.40, 0.80], q_force 0.700, q_work 0.500 |" in work
    assert work.endswith("| q_force 0.700, q_robust 0.600, q_work 0.500 |")
    assert "`../results/sensitivity-engine-pad-E/`" in text
    assert "`../results/minimal-work-engine-force/`" in text
    assert "`../results/sensitivity-engine/`" not in text


def test_no_engine_run_no_section(tmp_path):
    assert render_judge_sections(tmp_path) == ""
