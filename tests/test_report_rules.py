"""The claim record's readers and rules (workbench/runner/report_rules.py): printed numbers and
their rounding, the summaries' key paths, and each rule's verdict on hand-worked pairs."""

from __future__ import annotations

import json

import pytest

from workbench.runner.report_rules import (
    DIFFERS,
    MATCH,
    NOT_COMPARABLE,
    MissingKey,
    Summaries,
    below_percent,
    check_gain,
    mean_std_not_comparable,
    not_comparable,
    printed_half_unit,
    printed_numbers,
    trend,
    within_pm,
    within_printed,
)


def test_printed_numbers_and_their_rounding():
    assert printed_numbers("[0, -0.5657, 0, 0]^T") == [0.0, -0.5657, 0.0, 0.0]
    assert printed_numbers("2,932") == [2932.0]
    assert printed_numbers("0.011 ± 0.006") == [0.011, 0.006]
    assert printed_numbers("the quartic and ellipsoidal 6DLS models reached as low as 0.02") == [0.02]
    assert printed_numbers("S_1 and S_2, 3D nonplanar [4]: 2.62s / 1.3ms, below 4%") == [4, 2.62, 1.3, 4]
    assert printed_half_unit("0.0018") == pytest.approx(5e-5)
    assert printed_half_unit("1592") == 0.5
    assert printed_half_unit("[0, 0.018, -0.04]^T") == pytest.approx(5e-4)


def test_summaries_walk_key_paths_and_name_what_is_missing(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "summary.json").write_text(
        json.dumps({"x": {"v": [1.5, 2.5]}, "flag": True, "n": None})
    )
    s = Summaries(tmp_path)
    assert s.get("a/summary.json", "x.v.1") == 2.5 and s.get("a/summary.json", "x.v.-2") == 1.5
    assert s.num("a/summary.json", "x.v.0") == 1.5
    for path in ("x.v.2", "x.w", "flag", "n"):  # out of range, absent, a bool and a null are no numbers
        with pytest.raises(MissingKey) as exc:
            s.num("a/summary.json", path)
        assert exc.value.where == f"a/summary.json:{path}"
    with pytest.raises(MissingKey, match="b/summary.json:x"):
        s.get("b/summary.json", "x")
    assert s.read[:2] == ["a/summary.json:x.v.1", "a/summary.json:x.v.-2"]


def test_within_printed_judges_by_the_printed_rounding():
    one = within_printed("0.64")(0.5)  # 0.5 - 0.64 = -0.14, 0.5 / 0.64 = 0.78
    assert (one.status, one.ours, one.deviation) == (DIFFERS, "0.5", "-0.14, 0.78× (rounding ±0.005)")
    assert within_printed("0.64")(0.644).status == MATCH  # 0.004 within ±0.005
    vec = within_printed("[0, 0.018]")([0.0004, 0.0183])  # largest deviation 4e-4 within ±5e-4
    assert vec.status == MATCH and vec.deviation == "max abs deviation 0.0004 (rounding ±0.0005)"
    assert within_printed("[0, 0.018]")([0.0]).status == DIFFERS  # one component of two
    assert within_printed("0.02 and 0.04", pick=1)(0.0449).status == MATCH
    assert within_printed("0.02 and 0.04", pick=1)(0.0451).status == DIFFERS


def test_within_pm_and_below_percent():
    v = within_pm("0.011 ± 0.006")((0.014, 0.004))  # +0.003 is half the printed ±
    assert (v.status, v.ours) == (MATCH, "0.0140 ± 0.0040")
    assert v.deviation == "+0.003 (1.27×; 0.50 of the thesis's ±)"
    assert within_pm("0.011 ± 0.006")((0.018, 0.001)).status == DIFFERS  # +0.007 > 0.006
    below = below_percent("below 4% with 300 triangles")(0.039)
    assert (below.status, below.ours, below.deviation) == (MATCH, "3.9 %", "0.97× the bound")
    tenth = below_percent("below 4%", factor=0.1)(0.005)  # bound 0.4 %
    assert (tenth.status, tenth.deviation) == (DIFFERS, "1.25× the bound")


def test_not_comparable_rules_show_the_difference_only():
    v = not_comparable("24%")(30)
    assert (v.status, v.ours, v.deviation) == (NOT_COMPARABLE, "30", "+6 (1.25×)")
    shown = not_comparable("24%", show=lambda v: f"{len(v)} levels")([0.5, 0.9])  # not a number
    assert (shown.ours, shown.deviation) == ("2 levels", "—")
    m = mean_std_not_comparable("0.80 ± 0.01")((0.75, 0.02))
    assert (m.status, m.ours, m.deviation) == (NOT_COMPARABLE, "0.75 ± 0.02", "-0.05 (mean)")


def test_a_gain_holds_only_when_every_pair_is_above():
    judge = trend(check_gain("6dls"))
    won = judge({"planar": (0.8, 0.7), "6dfw": (0.8, 0.75)})
    assert won.status == MATCH and won.ours == "6dls 0.800 vs planar 0.700; 6dls 0.800 vs 6dfw 0.750"
    assert won.deviation == "+0.100; +0.050"
    lost = judge({"planar": (0.8, 0.7), "6dfw": (0.8, 0.85)})
    assert lost.status == DIFFERS and lost.deviation == "+0.100; -0.050"
