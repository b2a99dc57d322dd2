"""``workbench report`` (workbench/runner/report.py): claims judged on summaries, Markdown rendering,
missing keys, the CLI, and the repository's own committed results."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import pytest

from workbench.runner import report
from workbench.runner.cli import main
from workbench.runner.report import (
    CLAIMS,
    DIFFERS,
    ITEMS,
    MATCH,
    Claim,
    evaluate,
    printed_half_unit,
    printed_numbers,
    render_markdown,
    within_pm,
    within_printed,
    write_report,
)

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"


def _write(path: Path, obj: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(obj))


def test_printed_numbers_and_their_rounding():
    assert printed_numbers("[0, -0.5657, 0, 0]^T") == [0.0, -0.5657, 0.0, 0.0]
    assert printed_numbers("2,932") == [2932.0]
    assert printed_numbers("0.011 ± 0.006") == [0.011, 0.006]
    assert printed_numbers("the quartic and ellipsoidal 6DLS models reached as low as 0.02") == [0.02]
    assert printed_numbers("S_1 and S_2, 3D nonplanar [4]: 2.62s / 1.3ms, below 4%") == [4, 2.62, 1.3, 4]
    assert printed_half_unit("0.0018") == pytest.approx(5e-5)
    assert printed_half_unit("1592") == 0.5
    assert printed_half_unit("[0, 0.018, -0.04]^T") == pytest.approx(5e-4)


def _synthetic_claims() -> list[Claim]:
    f = "toy/summary.json"
    return [
        Claim(
            "Table 3.3",
            "a mean within the printed ±",
            "0.011 ± 0.006",
            "Table 3.3",
            lambda s: (s.num(f, "fit.mean"), s.num(f, "fit.std")),
            within_pm("0.011 ± 0.006"),
            report.RULE_PM,
            "workbench run toy",
        ),
        Claim(
            "Table 3.2",
            "a value off its printed rounding",
            "0.64",
            "Table 3.2",
            lambda s: s.get(f, "wmax"),
            within_printed("0.64"),
            report.RULE_PRINTED,
            "workbench run toy",
            why="off by {{toy/summary.json|wmax|.2f}}",
        ),
        Claim(
            "Fig 3.8",
            "a key the summary lacks",
            "below 4% with 300 triangles",
            "§3.5.1.2",
            lambda s: s.num(f, "error.at_300"),
            report.below_percent("below 4% with 300 triangles"),
            "match if below",
            "workbench run toy",
            figures=("toy/fig.png", "toy/absent.png"),
        ),
    ]


def test_rendering_on_a_synthetic_results_dir(tmp_path, caplog):
    _write(tmp_path / "toy" / "summary.json", {"fit": {"mean": 0.014, "std": 0.004}, "wmax": 0.5})
    (tmp_path / "toy" / "fig.png").write_bytes(b"png")
    with caplog.at_level(logging.WARNING, logger="workbench.runner.report"):
        rows = evaluate(tmp_path, _synthetic_claims())
    ok, off, lacking = rows
    assert ok.verdict.status == MATCH and ok.verdict.ours == "0.0140 ± 0.0040"
    assert ok.verdict.deviation.startswith("+0.003 (1.27×; 0.50 of")
    assert off.verdict.status == DIFFERS and off.verdict.deviation.startswith("-0.14, 0.78×")
    assert off.why == "off by 0.50"
    assert lacking.verdict is None and lacking.missing == "toy/summary.json:error.at_300"
    assert "toy/summary.json:error.at_300" in caplog.text
    assert lacking.figures == ("toy/fig.png",)

    text = render_markdown(rows, link_prefix="../")
    line = next(x for x in text.splitlines() if x.startswith("| a mean within"))
    assert "| 0.011 ± 0.006 |" in line and "| 0.0140 ± 0.0040 |" in line and "| **match** |" in line
    line = next(x for x in text.splitlines() if x.startswith("| a value off"))
    assert "| **differs** |" in line and "| 0.5 |" in line
    line = next(x for x in text.splitlines() if x.startswith("| a key the summary lacks"))
    assert "missing: toy/summary.json:error.at_300" in line
    assert "[toy/fig.png](../toy/fig.png)" in text and "Figures not found: `toy/absent.png`" in text
    assert "| [Table 3.3](#table-33) | 1 | 0 | 0 | 0 |" in text
    assert "| [Fig 3.8](#fig-38) | 0 | 0 | 0 | 1 |" in text
    assert "Regenerate: `workbench run toy`." in text


def test_a_partial_results_dir_gives_a_report_with_missing_rows(tmp_path, caplog):
    table = {"mean": 0.0149, "std": 0.0046}
    _write(
        tmp_path / "fem-fitting" / "summary.json",
        {"table_3_3_vs_thesis": {"thesis-code": {"quartic_values": table}}},
    )
    with caplog.at_level(logging.WARNING, logger="workbench.runner.report"):
        path = write_report(tmp_path)
    assert path == tmp_path / "REPORT.md"
    text = path.read_text()
    row = next(x for x in text.splitlines() if "(`quartic_values`)" in x and "thesis-code" in x)
    assert "| 0.011 ± 0.006 |" in row and "| 0.0149 ± 0.0046 |" in row and "**match**" in row
    assert "missing: parametric-surfaces/summary.json:example_3_2_5.pressure_center" in text
    assert "missing: benchmarks/grasp.json:ms_per_grasp.soft_point" in text
    assert "rows missing their summary keys" in caplog.text


def test_a_truncated_summary_is_named_unreadable_not_missing(tmp_path, caplog):
    """``summary.json`` cut off mid-write (a killed run before atomic writes, a full disk): its
    rows say the file cannot be read and to rerun it, not that a key is missing."""
    path = tmp_path / "parametric-surfaces" / "summary.json"
    path.parent.mkdir(parents=True)
    path.write_text('{"example_3_2_5": {"pressure_center": [0.0, 0.01')
    with caplog.at_level(logging.WARNING, logger="workbench.runner.report"):
        text = write_report(tmp_path).read_text()
    assert "parametric-surfaces/summary.json (unreadable — JSONDecodeError" in text
    assert "missing: parametric-surfaces/summary.json:example_3_2_5" not in text
    assert "exists but cannot be read" in caplog.text


def test_the_cli_writes_the_report(tmp_path, capsys):
    _write(tmp_path / "res" / "discretization" / "summary.json", {"max_error_rate_at_300": 0.0081})
    out = tmp_path / "docs" / "R.md"
    assert main(["report", "--results", str(tmp_path / "res"), "--out", str(out)]) == 0
    assert str(out) in capsys.readouterr().out
    text = out.read_text()
    row = next(x for x in text.splitlines() if x.startswith("| largest wrench error rate over S1–S6 at 300"))
    assert "| 0.81 % |" in row and "**match**" in row
    assert "(../res/discretization/fig_3_8_error_rate.png)" not in text  # absent figures are not linked
    assert "Figures not found: `discretization/fig_3_8_error_rate.png`" in text


def test_report_help_names_its_options(capsys):
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    help_text = capsys.readouterr().out
    assert "--results DIR" in help_text and "--out FILE" in help_text


def _summary(name: str) -> dict:
    return json.loads((RESULTS / name).read_text())


@pytest.mark.skipif(not (RESULTS / "fem-fitting" / "summary.json").is_file(), reason="no committed results/")
def test_the_repositorys_results_give_every_item_and_no_missing_row():
    rows = evaluate(RESULTS)
    assert {r.claim.item for r in rows} == set(ITEMS)
    assert [r.claim.quantity for r in rows if r.verdict is None] == []
    assert all(r.figures == r.claim.figures for r in rows)  # every linked figure is committed
    text = render_markdown(rows)
    for item in ITEMS:
        assert f"\n## {item}\n" in text
    assert not any("missing: " in line for line in text.splitlines() if line.startswith("| "))

    # Table 3.3, quartic, thesis-code protocol: the thesis's 0.011 ± 0.006 and ours from the summary
    fem = _summary("fem-fitting/summary.json")
    ours = fem["table_3_3_vs_thesis"]["thesis-code"]["quartic_values"]
    row = next(x for x in text.splitlines() if "(`quartic_values`)" in x and "thesis-code" in x)
    assert "| 0.011 ± 0.006 |" in row and f"| {ours['mean']:.4f} ± {ours['std']:.4f} |" in row
    status = "match" if abs(ours["mean"] - 0.011) <= 0.006 else "differs"
    assert f"**{status}**" in row and f"({ours['ratio_of_means']:.2f}×;" in row

    # the typed thesis numbers agree with the copies the experiments record
    by_q = {(c.item, c.quantity): c for c in CLAIMS}
    for model, key in [("quartic_values", "quartic"), ("ellipsoid_sdp", "ellipsoid")]:
        for claim in (c for c in CLAIMS if c.item == "Table 3.3" and f"(`{model}`)" in c.quantity):
            assert printed_numbers(claim.thesis) == fem["thesis_table_3_3"][key]
    count = by_q[("Table 3.3", "number of FEM contact profiles")]
    assert printed_numbers(count.thesis) == [fem["thesis_table_3_3"]["n_profiles"]]
    ps = _summary("parametric-surfaces/summary.json")
    for key, label in [
        ("6d_nonplanar", "6D nonplanar"),
        ("3d_nonplanar", "3D nonplanar [4]"),
        ("planar", "Planar"),
    ]:
        claim = by_q[("Table 3.2", f"{label}: f_x, f_y, f_z, τ_x, τ_y, τ_z max")]
        assert printed_numbers(claim.thesis) == ps["table_3_2_thesis"][key]
        dev = ps["table_3_2_max_abs_deviation"][key]
        row = next(x for x in text.splitlines() if x.startswith(f"| {label}: "))
        assert f"max abs deviation {dev:.2g}" in row
    lsf = _summary("ls-fitting/summary.json")["thesis"]["as_low_as"]
    low = next(c for c in CLAIMS if c.item == "Fig 3.9" and "as low as" in c.thesis)
    assert printed_numbers(low.thesis) == [lsf["quartic"], lsf["ellipsoid"]]
    disc = _summary("discretization/summary.json")["thesis_runtime_s"]
    speed = next(c for c in CLAIMS if c.item == "Fig 3.8" and "speedup" in c.thesis)
    cont_s, disc_ms = printed_numbers(speed.thesis)[:2]
    assert (cont_s, disc_ms * 1e-3) == pytest.approx((disc["continuous"], disc["discrete"]))
    mw = _summary("minimal-work/summary.json")
    for task, metrics in mw["thesis_table_4_6"].items():
        for metric, cells in metrics.items():
            claim = next(c for c in CLAIMS if c.quantity == f"{report.TASKS[task]}, {metric}, All")
            assert printed_numbers(claim.thesis) == [cells["All"]]
