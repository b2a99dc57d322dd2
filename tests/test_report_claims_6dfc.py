"""The 6DFC paper's claim table (workbench/runner/report_claims_6dfc.py): Table I's rows and its
mAR claim, judged on a hand-made physical-trials summary and on the committed one."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from workbench.runner.report import evaluate
from workbench.runner.report_claims_6dfc import CLAIMS, TABLE_I
from workbench.runner.report_rules import DIFFERS, MATCH, NOT_COMPARABLE, printed_numbers

RESULTS = Path(__file__).resolve().parents[1] / "results"


def _scores(recall: dict[str, float]) -> dict:
    """Robust-held scores per model: AP 0.8 ± 0.02 for every model, AR as given ± 0.01."""
    return {
        m: {
            "robust_held": {
                "average_precision": {"mean": 0.8, "std": 0.02},
                "average_recall": {"mean": ar, "std": 0.01},
            }
        }
        for m, ar in recall.items()
    }


def test_table_i_rows_then_the_mar_claim():
    assert [c.quantity for c in CLAIMS[:2]] == ["Point (`point`), mAP", "Point (`point`), mAR"]
    assert len(CLAIMS) == 2 * len(TABLE_I) + 1 and {c.item for c in CLAIMS} == {"6DFC Table I"}
    # the printed mean ± std of each row is the table's, in order mAP, mAR
    for i, (model, ap, ar) in enumerate(TABLE_I.values()):
        assert (CLAIMS[2 * i].thesis, CLAIMS[2 * i + 1].thesis) == (ap, ar)
        assert f"(`{model}`), mAP" in CLAIMS[2 * i].quantity
    assert printed_numbers(CLAIMS[-1].thesis) == [17, 6, 7]


def test_table_i_on_hand_made_scores(tmp_path):
    path = tmp_path / "physical-trials" / "summary.json"
    path.parent.mkdir()
    path.write_text(json.dumps({"scores": _scores({"point": 0.5, "reach": 0.6, "6dls": 0.62, "6dfc": 0.7})}))
    rows = evaluate(tmp_path, CLAIMS)
    point_ap, point_ar = rows[:2]  # the paper's Point: 0.80 ± 0.01 mAP, 0.50 ± 0.01 mAR
    assert (point_ap.verdict.status, point_ap.verdict.ours, point_ap.verdict.deviation) == (
        NOT_COMPARABLE,
        "0.80 ± 0.02",
        "+0.00 (mean)",
    )
    assert (point_ar.verdict.ours, point_ar.verdict.deviation) == ("0.50 ± 0.01", "+0.00 (mean)")
    assert rows[-1].verdict.status == MATCH and rows[-1].verdict.deviation == "+0.200; +0.100; +0.080"
    path.write_text(json.dumps({"scores": _scores({"point": 0.5, "reach": 0.75, "6dls": 0.62, "6dfc": 0.7})}))
    assert evaluate(tmp_path, CLAIMS[-1:])[0].verdict.status == DIFFERS  # REACH above 6DFC


@pytest.mark.skipif(
    not (RESULTS / "physical-trials" / "summary.json").is_file(), reason="no committed results/"
)
def test_the_committed_results_give_every_row():
    rows = evaluate(RESULTS, CLAIMS)
    assert [r.claim.quantity for r in rows if r.verdict is None] == []
