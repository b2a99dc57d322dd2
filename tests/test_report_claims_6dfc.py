"""The 6DFC paper's claim table (workbench/runner/report_claims_6dfc.py): Table I's rows and its
mAR claim, and Fig. 3(a, b)'s trends, judged on hand-made summaries and on the committed ones."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from workbench.runner.report import evaluate
from workbench.runner.report_claims_6dfc import (
    CLAIMS,
    FIG_3,
    FIG_3_BENCH,
    FIG_3_CURVES,
    FIG_3_RUNTIME,
    TABLE_I,
)
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
    table_i = CLAIMS[: 2 * len(TABLE_I) + 1]
    assert CLAIMS == (*table_i, *FIG_3, *FIG_3_RUNTIME) and {c.item for c in table_i} == {"6DFC Table I"}
    assert [c.quantity for c in FIG_3] == [
        "mAP against N_r",
        "mAR against N_r",
        "mAP against σ_r",
        "mAR against σ_r",
    ]
    # the printed mean ± std of each row is the table's, in order mAP, mAR
    for i, (model, ap, ar) in enumerate(TABLE_I.values()):
        assert (CLAIMS[2 * i].thesis, CLAIMS[2 * i + 1].thesis) == (ap, ar)
        assert f"(`{model}`), mAP" in CLAIMS[2 * i].quantity
    assert printed_numbers(table_i[-1].thesis) == [17, 6, 7]


def test_table_i_on_hand_made_scores(tmp_path):
    path = tmp_path / "physical-trials" / "summary.json"
    path.parent.mkdir()
    path.write_text(json.dumps({"scores": _scores({"point": 0.5, "reach": 0.6, "6dls": 0.62, "6dfc": 0.7})}))
    rows = evaluate(tmp_path, CLAIMS[: 2 * len(TABLE_I) + 1])
    point_ap, point_ar = rows[:2]  # the paper's Point: 0.80 ± 0.01 mAP, 0.50 ± 0.01 mAR
    assert (point_ap.verdict.status, point_ap.verdict.ours, point_ap.verdict.deviation) == (
        NOT_COMPARABLE,
        "0.80 ± 0.02",
        "+0.00 (mean)",
    )
    assert (point_ar.verdict.ours, point_ar.verdict.deviation) == ("0.50 ± 0.01", "+0.00 (mean)")
    assert rows[-1].verdict.status == MATCH and rows[-1].verdict.deviation == "+0.200; +0.100; +0.080"
    path.write_text(json.dumps({"scores": _scores({"point": 0.5, "reach": 0.75, "6dls": 0.62, "6dfc": 0.7})}))
    assert evaluate(tmp_path, CLAIMS[2 * len(TABLE_I) :][:1])[0].verdict.status == DIFFERS  # REACH above 6DFC


def _curves(values, ap: dict, ar: dict, std: float = 0.01) -> dict:
    def one(mean):
        return {"mean": mean, "std": [std] * len(mean)}

    return {
        "values": values,
        "models": {m: {"average_precision": one(ap[m]), "average_recall": one(ar[m])} for m in ap},
    }


def test_fig_3_trends_on_hand_made_curves(tmp_path):
    path = tmp_path / FIG_3_CURVES
    path.parent.mkdir()
    same = [0.80, 0.85, 0.90, 0.905]  # rises to N_r = 10, then within the std (0.01)
    ap = {"point": [0.5, 0.52, 0.55, 0.54], "reach": same, "6dls": same, "6dfc": same}
    ar = {m: [0.9, 0.9, 0.8, 0.7] for m in ap}
    sigma_ap = {m: [0.8, 0.9, 0.89, 0.88] for m in ap}
    sigma_ar = {m: [1.0, 0.95, 0.9, 0.93] for m in ap}  # rises 0.03 > 0.01 after the turn: differs
    path.write_text(
        json.dumps(
            {
                "n_robust": _curves([1, 3, 10, 20], ap, ar),
                "sigma_trans": _curves([0.001, 0.003, 0.005, 0.01], sigma_ap, sigma_ar),
            }
        )
    )
    rows = evaluate(tmp_path, FIG_3)
    assert [r.verdict.status for r in rows] == [MATCH, MATCH, MATCH, DIFFERS]
    # models whose every curve is identical are one entry, in every panel (the figure's legend):
    # point's mAR equals the others' but its mAP does not, so it stays apart; the turn is marked
    assert rows[0].verdict.ours == (
        "point 0.500 → 0.520 → 0.550 (at 10) → 0.540; "
        "reach = 6dls = 6dfc 0.800 → 0.850 → 0.900 (at 10) → 0.905"
    )
    assert rows[1].verdict.deviation == (
        "point: -0.1 from 10 to the last; reach = 6dls = 6dfc: -0.1 from 10 to the last"
    )
    assert rows[3].verdict.deviation == (
        "point: -0.02 from 0.003 to the last; +0.030 to 0.01; "
        "reach = 6dls = 6dfc: -0.02 from 0.003 to the last; +0.030 to 0.01"
    )
    # all four equal everywhere: one entry
    path.write_text(json.dumps({"n_robust": _curves([1, 3, 10, 20], {m: same for m in ap}, ar)}))
    assert evaluate(tmp_path, FIG_3[1:2])[0].verdict.deviation == (
        "point = reach = 6dls = 6dfc: -0.1 from 10 to the last"
    )
    # a model that keeps rising past the turn by more than the std, and one that never rises
    ap["6dfc"] = [0.8, 0.85, 0.9, 0.95]
    ap["point"] = [0.5, 0.5, 0.49, 0.49]
    path.write_text(json.dumps({"n_robust": _curves([1, 3, 10, 20], ap, ar)}))
    row = evaluate(tmp_path, FIG_3[:1])[0]
    assert row.verdict.status == DIFFERS
    assert row.verdict.deviation == "point: no rise; reach = 6dls: as stated; 6dfc: +0.050 at 20"


@pytest.mark.skipif(
    not (RESULTS / "physical-trials" / "summary.json").is_file(), reason="no committed results/"
)
def test_the_committed_results_give_every_row():
    rows = evaluate(RESULTS, CLAIMS)
    assert [r.claim.quantity for r in rows if r.verdict is None] == []
    # Fig. 3(a): on the cube 6dls and 6dfc are one curve (reach's parts from theirs only at the
    # widest σ_r), and its mAP still rises past N_r = 10
    fig_3a = next(r for r in rows if r.claim.quantity == "mAP against N_r")
    assert "; 6dls = 6dfc 0.827" in fig_3a.verdict.ours and fig_3a.verdict.status == DIFFERS


def test_fig_3_runtimes_on_a_hand_made_benchmark(tmp_path):
    path = tmp_path / FIG_3_BENCH
    path.parent.mkdir()
    bench = {
        "fig_3c": {"max_gain_6dfc": 0.302},
        "fig_3d": {
            "n_triangles": [16, 64, 256],
            "ratio_reach_over_6dfc": [2.0, 9.5, 40.0],
            "max_ratio": 40.0,
        },
    }
    path.write_text(json.dumps(bench))
    gain, ratio, scaling = evaluate(tmp_path, FIG_3_RUNTIME)
    # 30.2 % rounds to the printed 30; 40× is not 85×; the ratio rises with the triangles
    assert (gain.verdict.status, gain.verdict.ours) == (MATCH, "30.2")
    assert ratio.verdict.status == DIFFERS and ratio.verdict.deviation.startswith("-45")
    assert scaling.verdict.status == MATCH and scaling.verdict.ours == "16: 2.0×; 64: 9.5×; 256: 40.0×"
    bench["fig_3d"]["ratio_reach_over_6dfc"] = [2.0, 1.5, 40.0]
    path.write_text(json.dumps(bench))
    assert evaluate(tmp_path, FIG_3_RUNTIME[2:])[0].verdict.status == DIFFERS
