"""``workbench report`` (workbench/runner/report.py): claims judged on summaries, Markdown rendering,
missing keys, the CLI, and the repository's own committed results.  The rules are tested in
tests/test_report_rules.py, each claim table in tests/test_report_claims_*.py."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import pytest

from workbench.runner import (
    report,
    report_claims_6dfc,
    report_claims_ch3,
    report_claims_ch4,
    report_claims_engine,
)
from workbench.runner.cli import main
from workbench.runner.report import (
    CLAIMS,
    DIFFERS,
    ITEMS,
    MATCH,
    Claim,
    evaluate,
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
        {
            "object_sets": {
                "thesis_meshes": {"table_3_3_vs_thesis": {"thesis-code": {"quartic_values": table}}}
            }
        },
    )
    with caplog.at_level(logging.WARNING, logger="workbench.runner.report"):
        path = write_report(tmp_path)
    assert path == tmp_path / "REPORT.md"
    text = path.read_text()
    row = next(x for x in text.splitlines() if "(`quartic_values`)" in x and "thesis-code" in x)
    assert "| 0.011 ± 0.006 |" in row and "| 0.0149 ± 0.0046 |" in row and "**match**" in row
    assert "missing: parametric-surfaces/summary.json:example_3_2_5.pressure_center" in text
    assert "missing: benchmarks/grasp.json:build_plus_solve_ms.soft_point.median_ms" in text
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


def test_claims_join_the_chapter_tables_and_render_by_item_order():
    tables = (report_claims_ch3, report_claims_ch4, report_claims_6dfc, report_claims_engine)
    assert CLAIMS == tuple(c for t in tables for c in t.CLAIMS)
    assert {c.item for c in CLAIMS} == set(ITEMS)
    keys = [(c.item, c.quantity) for c in CLAIMS]
    assert len(set(keys)) == len(keys)  # no claim twice
    # the report groups rows by ITEMS: the order of the tables does not change it
    rows = evaluate(Path("no-results"), CLAIMS)
    last_first = sorted(rows, key=lambda r: -list(ITEMS).index(r.claim.item))  # stable within an item
    assert render_markdown(last_first) == render_markdown(rows)
