"""The report's inventory (workbench/runner/report_inventory.py): every table and numbered figure
of the thesis's chapters 3–4 and of the 6DFC paper, checked against the captions in the seeds'
text, each with a status in the committed REPORT.md."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from workbench.runner.report import ITEMS
from workbench.runner.report_inventory import (
    INVENTORY,
    JUDGED,
    NOT_YET,
    OUT_OF_SCOPE,
    STATUSES,
    Entry,
    render_inventory,
)

ROOT = Path(__file__).resolve().parents[1]
SEEDS = ROOT.parent / "shared" / "seeds"
THESIS = SEEDS / "thesis_nonplanar_frictional_contacts.txt"
PAPER = SEEDS / "paper_6dfc_icra2020.txt"
REPORT = ROOT / "results" / "REPORT.md"


def _seed_items() -> set[str]:
    """Every table and figure of chapters 3–4 the thesis names (a caption, or a mention in the text:
    Table 4.2's caption did not survive the text extraction), and every caption of the paper."""
    thesis = THESIS.read_text(encoding="utf-8")
    found = {
        f"{'Fig' if kind == 'Figure' else 'Table'} {n}"
        for kind, n in re.findall(r"\b(Figure|Table) ([34]\.\d+)\b", thesis)
    }
    paper = PAPER.read_text(encoding="utf-8")
    for kind, n in re.findall(r"^(Fig\.|TABLE) (\d+|[IVX]+):", paper, re.M):
        found.add(f"6DFC {'Fig' if kind == 'Fig.' else 'Table'} {n}")
    return found


@pytest.mark.skipif(
    not (THESIS.is_file() and PAPER.is_file()), reason="the seeds' text is not beside the repository"
)
def test_the_inventory_is_every_table_and_figure_the_seeds_print():
    items = [e.item for e in INVENTORY]
    assert len(items) == len(set(items)), "an item listed twice"
    seeds = _seed_items()
    assert set(items) == seeds, (
        f"in the seeds but not the inventory: {sorted(seeds - set(items))}; "
        f"in the inventory but not the seeds: {sorted(set(items) - seeds)}"
    )
    # 33 of the thesis (32 captions and Table 4.2), 5 of the paper
    assert len(items) == 38


def test_every_report_section_judges_an_item_and_every_judged_item_has_sections():
    judged = {s for e in INVENTORY for s in e.sections}
    assert judged == set(ITEMS), f"sections no item names: {sorted(set(ITEMS) - judged)}"
    for e in INVENTORY:
        assert e.status in STATUSES
        assert bool(e.sections) if e.status == JUDGED else (not e.sections or e.status == NOT_YET)


def test_an_entry_refuses_an_unknown_status_misplaced_sections_and_a_silent_one():
    with pytest.raises(ValueError, match="status must be one of"):
        Entry("Fig 9.9", "x", "done")
    with pytest.raises(ValueError, match="names its sections"):
        Entry("Fig 9.9", "x", JUDGED)
    with pytest.raises(ValueError, match="no other does"):
        Entry("Fig 9.9", "x", OUT_OF_SCOPE, "why", sections=("Fig 3.8",))
    assert Entry("Fig 9.9", "x", NOT_YET, "half done", sections=("Fig 3.8",)).sections == ("Fig 3.8",)
    with pytest.raises(ValueError, match="says why in one line"):
        Entry("Fig 9.9", "x", OUT_OF_SCOPE)


def test_render_links_present_figures_counts_rows_and_names_absent_ones(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "here.png").write_bytes(b"png")
    inventory = (
        Entry("Fig 3.8", "errors", JUDGED, sections=("Fig 3.8", "Fig 3.9"), ours=("a/here.png",)),
        Entry("Fig 3.1", "photos", OUT_OF_SCOPE, "no data", ours=("a/gone.png",)),
    )
    counts = {"Fig 3.8": {"match": 4, "not comparable": 1}}
    lines = render_inventory(counts, tmp_path, "../r/", inventory)
    text = "\n".join(lines)
    assert "The 2 tables and numbered figures" in text
    assert "1 judged, 0 not comparable, 1 out of scope, 0 not yet reproduced" in text
    row = next(x for x in lines if x.startswith("| Fig 3.8 |"))
    assert "[Fig 3.8](#fig-38): 4 match, 1 not comparable; [Fig 3.9](#fig-39): no rows" in row
    assert "[here.png](../r/a/here.png)" in row
    row = next(x for x in lines if x.startswith("| Fig 3.1 |"))
    assert "| **out of scope** | no data | `a/gone.png` (not found) |" in row


@pytest.mark.skipif(not REPORT.is_file(), reason="no committed results/REPORT.md")
def test_the_committed_report_gives_every_item_a_status():
    text = REPORT.read_text(encoding="utf-8")
    table = text.split("\n## Every table and figure\n", 1)[1].split("\n## ", 1)[0]
    rows = {
        m.group(1): m.group(2)
        for m in re.finditer(r"^\| ([^|]+?) \| [^|]+ \| \*\*([^*]+)\*\* \|", table, re.M)
    }
    assert rows == {e.item: e.status for e in INVENTORY}
    # every item is covered: none is left "not yet reproduced"
    assert sorted(i for i, s in rows.items() if s == NOT_YET) == []
