"""Chapter 3's claim tables (workbench/runner/report_claims_ch3.py): the thesis numbers typed
there agree with the copies the experiments record, and the tables judge hand-made summaries
as their rules say."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from workbench.runner.report import evaluate
from workbench.runner.report_claims_ch3 import (
    CLAIMS,
    EXAMPLE_3_2_5,
    FIG_3_8,
    FIG_3_9,
    FIG_3_11,
    TABLE_3_2,
    TABLE_3_3,
)
from workbench.runner.report_rules import DIFFERS, MATCH, printed_numbers

RESULTS = Path(__file__).resolve().parents[1] / "results"
committed = pytest.mark.skipif(
    not (RESULTS / "fem-fitting" / "summary.json").is_file(), reason="no committed results/"
)


def _summary(name: str) -> dict:
    return json.loads((RESULTS / name).read_text())


def test_the_tables_are_chapter_3s_items_in_order():
    assert [c.item for c in CLAIMS] == [
        *["Example 3.2.5"] * 5,
        *["Table 3.2"] * 4,
        *["Fig 3.8"] * 5,
        *["Fig 3.9"] * 9,
        *["Fig 3.11"] * 2,
        *["Table 3.3"] * 12,  # six rows on each object set: the thesis's meshes, then our family
    ]
    assert CLAIMS == (*EXAMPLE_3_2_5, *TABLE_3_2, *FIG_3_8, *FIG_3_9, *FIG_3_11, *TABLE_3_3)
    assert [c.quantity.rsplit("; ", 1)[-1] for c in TABLE_3_3] == [
        *["the 24 thesis meshes"] * 6,
        *["our bottle family"] * 6,
    ]


def test_example_3_2_5_judges_the_printed_rounding(tmp_path):
    # the thesis's frictional wrench is [0, 0, 0, 0.0018, 0] (τ_y non-zero): rounding ±5e-5
    (tmp_path / "parametric-surfaces").mkdir()
    path = tmp_path / "parametric-surfaces" / "summary.json"
    friction = next(c for c in EXAMPLE_3_2_5 if c.quantity.startswith("frictional wrench"))
    for tau_y, status in [(0.00184, MATCH), (0.00186, DIFFERS)]:
        path.write_text(json.dumps({"example_3_2_5": {"frictional_wrench": [0, 0, 0, 0, tau_y, 0]}}))
        (row,) = evaluate(tmp_path, [friction])
        assert row.verdict.status == status


def test_fig_3_8_trends_on_hand_made_error_rates(tmp_path):
    # S1, S2 lowest at both sizes and every surface's error falls 20×: both trends hold
    errors = {f"S{i}": {"100": 0.02 * i, "1000": 0.001 * i} for i in range(1, 7)}
    (tmp_path / "discretization").mkdir()
    (tmp_path / "discretization" / "summary.json").write_text(json.dumps({"error_rate": errors}))
    falls, lowest = (c for c in FIG_3_8 if c.quantity.startswith(("error rate vs", "surfaces with")))
    rows = evaluate(tmp_path, [falls, lowest])
    assert [r.verdict.status for r in rows] == [MATCH, MATCH]
    assert rows[0].verdict.ours == "coarsest/finest error 20–20× (100→1000 elements)"
    errors["S3"]["1000"] = 0.0001  # S3 now the lowest at 1,000 elements
    (tmp_path / "discretization" / "summary.json").write_text(json.dumps({"error_rate": errors}))
    assert evaluate(tmp_path, [lowest])[0].verdict.deviation == "not at [1000]"


@committed
def test_the_typed_thesis_numbers_agree_with_the_experiments_copies():
    fem = _summary("fem-fitting/summary.json")
    for model, key in [("quartic_values", "quartic"), ("ellipsoid_sdp", "ellipsoid")]:
        for claim in (c for c in TABLE_3_3 if f"(`{model}`)" in c.quantity):
            assert printed_numbers(claim.thesis) == fem["thesis_table_3_3"][key]
    for count in (c for c in TABLE_3_3 if c.quantity.startswith("number of FEM contact profiles")):
        assert printed_numbers(count.thesis) == [fem["thesis_table_3_3"]["n_profiles"]]
    ps = _summary("parametric-surfaces/summary.json")
    for key, label in [
        ("6d_nonplanar", "6D nonplanar"),
        ("3d_nonplanar", "3D nonplanar [4]"),
        ("planar", "Planar"),
    ]:
        claim = next(c for c in TABLE_3_2 if c.quantity == f"{label}: f_x, f_y, f_z, τ_x, τ_y, τ_z max")
        assert printed_numbers(claim.thesis) == ps["table_3_2_thesis"][key]
    lsf = _summary("ls-fitting/summary.json")["thesis"]["as_low_as"]
    low = next(c for c in FIG_3_9 if "as low as" in c.thesis)
    assert printed_numbers(low.thesis) == [lsf["quartic"], lsf["ellipsoid"]]
    disc = _summary("discretization/summary.json")["thesis_runtime_s"]
    speed = next(c for c in FIG_3_8 if "speedup" in c.thesis)
    cont_s, disc_ms = printed_numbers(speed.thesis)[:2]
    assert (cont_s, disc_ms * 1e-3) == pytest.approx((disc["continuous"], disc["discrete"]))


@committed
def test_the_committed_results_give_every_chapter_3_row():
    rows = evaluate(RESULTS, CLAIMS)
    assert [r.claim.quantity for r in rows if r.verdict is None] == []
    ps = _summary("parametric-surfaces/summary.json")
    for row in (r for r in rows if r.claim in TABLE_3_2[:3]):
        key = {"6D nonplanar": "6d_nonplanar", "3D nonplanar [4]": "3d_nonplanar", "Planar": "planar"}[
            row.claim.quantity.split(":")[0]
        ]
        dev = ps["table_3_2_max_abs_deviation"][key]
        assert row.verdict.deviation.startswith(f"max abs deviation {dev:.2g}")
