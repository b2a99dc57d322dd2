"""The thesis-vs-ours report (``workbench report``): every number of the thesis that the
experiments reproduce, side by side with ours, read from the committed summaries only.

A :class:`Claim` is one thesis statement: the value exactly as printed, where it is printed,
a function that reads our value from ``results/*/summary.json`` or
``results/benchmarks/*.json`` (through :class:`Summaries`, which records every key path it
reads), and a rule that judges the pair (:class:`Verdict`: match / differs / not comparable);
both, and the rules, are :mod:`workbench.runner.report_rules`'s.  The claims are data, one table
per thesis chapter or paper (:mod:`workbench.runner.report_claims_ch3`,
:mod:`workbench.runner.report_claims_ch4`, :mod:`workbench.runner.report_claims_engine`,
:mod:`workbench.runner.report_claims_6dfc`); :data:`CLAIMS` joins them.  :func:`evaluate`
reads a results directory into :class:`Row` s; :func:`render_markdown` turns rows into Markdown
(pure); :func:`write_report` does both and writes the file atomically.

No number in this module is ours or the thesis's: the thesis's are typed in the claim tables,
quoted as printed next to their citations; ours come from the summaries by key path.  A missing
file or key gives the row ``missing: <file>:<key path>`` (and a logged warning), never an
exception, so a partial ``results/`` still gives a report; a results directory that does not
exist or holds no summary at all is refused (:func:`check_results_dir`).
"""

from __future__ import annotations

import logging
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..atomic_io import atomic_write_bytes
from . import report_claims_6dfc, report_claims_ch3, report_claims_ch4, report_claims_engine

# the claim record and its rules are re-exported (see __all__): callers import the report's API from here
from .report_claims_ch4 import TASKS
from .report_rules import (
    DIFFERS,
    MATCH,
    NOT_COMPARABLE,
    RULE_NOT_COMPARABLE,
    RULE_PM,
    RULE_PRINTED,
    Claim,
    MissingKey,
    Summaries,
    Verdict,
    anchor,
    below_percent,
    fmt_g,
    not_comparable,
    printed_half_unit,
    printed_numbers,
    trend,
    within_pm,
    within_printed,
)

log = logging.getLogger(__name__)

#: the thesis items, in report order, with a section title each
ITEMS: dict[str, str] = {
    "Example 3.2.5": "contact wrench of a parametric nonplanar surface (§3.2.5)",
    "Table 3.2": "maximal frictional wrench w_max of S1, three contact models (§3.5.1.1)",
    "Fig 3.8": "surface discretization: wrench error rate and runtime (§3.5.1.2)",
    "Fig 3.9": "6DLS fitting error on S1–S6 (§3.5.1.3, §3.6)",
    "Fig 3.11": "the FEM study's 24 objects (§3.5.2, Fig. 3.11(b))",
    "Table 3.3": "6DLS fitting error on FEM contact profiles (§3.5.2)",
    "Fig 4.2": "the power-law pressure of Eq. 4.3 fitted to FEM contacts on elliptic cylinders (§4.1.3.2)",
    "Fig 4.4": "sensitivity of grasp-success prediction (§4.1.3.5)",
    "Tables 4.2/4.3": "grasp-analysis runtime per grasp (§4.1.4.5, §4.1.4.6)",
    "Figs 4.8/4.9": "a dataset of top grasps: the grasp axis and four models' quality maps (§4.2.2)",
    "Table 4.6": "balanced accuracy of q_robust, q_force, q_work (§4.3.4)",
    "Table 4.1": "prediction of physical grasps by each contact model (§4.1.3.4)",
    "Table 4.1 (engine)": "Table 4.1's scene judged by MuJoCo instead of our exact 6DFW (§4.1.3.4)",
    "Table 4.1 (engine, bottle family)": "Table 4.1's question on the bottle family's side grasps (MuJoCo)",
    "Table 4.6 (engine)": "Table 4.6's candidates judged by MuJoCo trials, slip only (§4.3.4)",
    "6DFC Table I": "mAP and mAR of physical grasps, robust qualities (6DFC §V-B)",
    "6DFC Fig 3": "the mAP and mAR against the robustness samples N_r and their spread σ_r (Fig. 3(a, b))",
}


@dataclass(frozen=True)
class Row:
    """A claim evaluated on one results directory: its verdict, or the first missing
    ``file:key`` it needed; the key paths it read; its figures that exist."""

    claim: Claim
    verdict: Verdict | None
    missing: str | None
    why: str
    read: tuple[str, ...]
    figures: tuple[str, ...] = field(default_factory=tuple)


def _claims() -> list[Claim]:
    """Every claim: Chapter 3's, Chapter 4's judged by our truth, the 6DFC paper's, and
    Chapter 4's judged by the engine (the report groups them by :data:`ITEMS`)."""
    return [
        *report_claims_ch3.CLAIMS,
        *report_claims_ch4.CLAIMS,
        *report_claims_6dfc.CLAIMS,
        *report_claims_engine.CLAIMS,
    ]


#: every claim of the report, in order
CLAIMS: tuple[Claim, ...] = tuple(_claims())

# ---------------------------------------------------------------- evaluate and render

_PLACEHOLDER = re.compile(r"\{\{([^|}]+)\|([^|}]+)(?:\|([^}]*))?\}\}")


def _fill(text: str, s: Summaries) -> str:
    """Replace ``{{file|key.path|format}}`` by the summary value (``missing: file:key`` if absent)."""

    def one(m: re.Match[str]) -> str:
        try:
            value = s.get(m.group(1), m.group(2))
        except MissingKey as exc:
            log.warning("report: missing %s", exc.where)
            return f"missing: {exc.where}"
        fmt = m.group(3)
        if fmt:
            return format(value, fmt)
        return fmt_g(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else str(value)

    return _PLACEHOLDER.sub(one, text)


def evaluate(results_dir: str | os.PathLike[str], claims: Sequence[Claim] = CLAIMS) -> list[Row]:
    """Judge every claim on the summaries under ``results_dir``; a missing file or key
    makes that row ``missing`` (logged as a warning), never an error."""
    s = Summaries(results_dir)
    rows = []
    for claim in claims:
        start = len(s.read)
        verdict, missing = None, None
        try:
            verdict = claim.judge(claim.ours(s))
        except MissingKey as exc:
            missing = exc.where
            log.warning("report: %s — %s: missing %s", claim.item, claim.quantity, missing)
        except (TypeError, ValueError, KeyError, IndexError, ZeroDivisionError) as exc:
            # a key holds something of another shape than the claim expects
            missing = s.read[-1] if len(s.read) > start else f"?:{claim.quantity}"
            log.warning("report: %s — %s: cannot use %s (%s)", claim.item, claim.quantity, missing, exc)
        read = tuple(dict.fromkeys(s.read[start:]))
        why = _fill(claim.why, s)
        figures = tuple(f for f in claim.figures if (Path(results_dir) / f).is_file())
        rows.append(Row(claim, verdict, missing, why, read, figures))
    return rows


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _sources(read: Sequence[str]) -> str:
    """Key paths read, grouped by file: ``file: a, b`` (long lists cut to the first three)."""
    by_file: dict[str, list[str]] = {}
    for where in read:
        file, key = where.split(":", 1)
        by_file.setdefault(file, []).append(key)
    parts = []
    for file, keys in by_file.items():
        shown = keys if len(keys) <= 3 else [*keys[:3], f"… ({len(keys)} keys)"]
        parts.append(f"`{file}`: " + ", ".join(f"`{k}`" for k in shown))
    return "; ".join(parts)


def _status(r: Row) -> str:
    return "missing" if r.verdict is None else r.verdict.status


def _preamble(title: str) -> list[str]:
    """The title, what the report is and how to read a status, and the head of the count table."""
    return [
        f"# {title}",
        "",
        "Written by `workbench report` from the committed summaries (`*/summary.json`, "
        "`benchmarks/*.json`) only; file paths are relative to the results directory. "
        "Thesis values are quoted as printed in J. Xu, *Modeling Nonplanar Frictional Surface Contacts "
        "for Robust Robot Grasping* (TUM, 2022), each with its place; ours are read by key path.",
        "",
        "Status: **match** follows the rule stated on the row (the printed rounding of a value, the "
        "printed ± of a mean ± std, a printed bound, or the sign/monotonicity of a trend); **differs** says "
        "by how much; **not comparable** says why in one line (no robot data, other hardware, unnamed "
        "objects). Trends are judged on the summaries' own series. A row whose summary key is absent "
        "says `missing: <file>:<key path>`.",
        "",
        "| item | match | differs | not comparable | missing |",
        "|---|---|---|---|---|",
    ]


def _count_rows(rows: Sequence[Row]) -> list[str]:
    """One line of the count table per item that has rows: its rows per status."""
    lines = []
    for item in ITEMS:
        mine = [_status(r) for r in rows if r.claim.item == item]
        if mine:
            counts = [mine.count(s) for s in (MATCH, DIFFERS, NOT_COMPARABLE, "missing")]
            lines.append(f"| [{item}](#{anchor(item)}) | " + " | ".join(map(str, counts)) + " |")
    return lines


def _section_head(item: str, heading: str, mine: Sequence[Row], link_prefix: str) -> list[str]:
    """An item's heading, title, commands, figures (linked, or named when absent) and ground truths."""
    lines = ["", f"## {item}", "", f"{heading[0].upper()}{heading[1:]}.", ""]
    commands = list(dict.fromkeys(r.claim.command for r in mine))
    lines.append("Regenerate: " + "; ".join(f"`{cmd}`" for cmd in commands) + ".")
    figures = list(dict.fromkeys(f for r in mine for f in r.figures))
    absent = list(dict.fromkeys(f for r in mine for f in r.claim.figures if f not in r.figures))
    if figures:
        lines.append("Figures: " + ", ".join(f"[{f}]({link_prefix}{f})" for f in figures) + ".")
    if absent:
        lines.append("Figures not found: " + ", ".join(f"`{f}`" for f in absent) + ".")
    truths = list(dict.fromkeys(r.claim.truth for r in mine if r.claim.truth))
    if truths:
        lines.append("Ground truth: " + "; ".join(truths) + ".")
    return lines


def _claim_row(r: Row) -> str:
    """One claim as a row of its item's table."""
    c = r.claim
    if r.verdict is None:
        ours, dev, status = f"missing: {r.missing}", "—", "missing"
    else:
        ours, dev, status = r.verdict.ours, r.verdict.deviation, f"**{r.verdict.status}**"
    cells = [c.quantity, c.thesis, c.where, ours, dev, status, c.rule, r.why or "—", _sources(r.read)]
    return "| " + " | ".join(_cell(x) for x in cells) + " |"


def _section(item: str, heading: str, mine: Sequence[Row], link_prefix: str) -> list[str]:
    """An item's section: its head, then its table of claims."""
    return [
        *_section_head(item, heading, mine, link_prefix),
        "",
        "| quantity | thesis (as printed) | where | ours | deviation | status | rule | why | read from |",
        "|---|---|---|---|---|---|---|---|---|",
        *(_claim_row(r) for r in mine),
    ]


def render_markdown(
    rows: Sequence[Row],
    *,
    link_prefix: str = "",
    title: str = "Thesis vs ours",
    inventory: Sequence[str] = (),
) -> str:
    """The report as Markdown: a count per item and status, the ``inventory`` lines (the table
    of every thesis table and figure, :func:`workbench.runner.report_inventory.render_inventory`),
    then one section per thesis item with a row per claim.  ``link_prefix`` is prepended to
    figure paths (relative to the results directory) so links work from where the report is
    written.  Pure: reads nothing."""
    lines = _preamble(title) + _count_rows(rows) + list(inventory)
    for item, heading in ITEMS.items():
        mine = [r for r in rows if r.claim.item == item]
        if mine:
            lines += _section(item, heading, mine, link_prefix)
    return "\n".join(lines) + "\n"


_MAKE_RESULTS = (
    "results are made by `make reproduce` (every experiment) or `workbench run NAME` (one; "
    "`workbench list` names them), written to results/NAME/summary.json"
)


def check_results_dir(results_dir: str | os.PathLike[str]) -> Path:
    """``results_dir`` as a Path if it is a directory holding at least one summary the report
    reads (``*/summary.json`` or ``benchmarks/*.json``), else ``ValueError`` naming the path and
    how results are made.  A partial directory passes (its absent keys become missing rows); a
    directory that does not exist or holds no summary at all would give a report of nothing but
    missing rows — almost always a mistyped path."""
    root = Path(results_dir)
    if not root.is_dir():
        what = "is a file, not a directory" if root.exists() else "does not exist"
        raise ValueError(f"results directory {str(root)!r} {what}; {_MAKE_RESULTS}")
    if not any(root.glob("*/summary.json")) and not any(root.glob("benchmarks/*.json")):
        raise ValueError(
            f"results directory {str(root)!r} holds no summary (no */summary.json, no benchmarks/*.json) "
            f"— nothing to report; {_MAKE_RESULTS}"
        )
    return root


def write_report(
    results_dir: str | os.PathLike[str] = "results", out: str | os.PathLike[str] | None = None
) -> Path:
    """Evaluate :data:`CLAIMS` on ``results_dir`` and write the Markdown atomically to ``out``
    (default ``results_dir/REPORT.md``).  Returns the path written.  Raises ``ValueError`` for
    a ``results_dir`` that does not exist or holds no summary (:func:`check_results_dir`)."""
    results_dir = check_results_dir(results_dir)
    out = Path(out) if out is not None else results_dir / "REPORT.md"
    from .report_inventory import render_inventory
    from .report_judge import render_judge_sections
    from .report_peers import render_peers_sections

    rows = evaluate(results_dir)
    prefix = os.path.relpath(results_dir.resolve(), out.resolve().parent).replace(os.sep, "/")
    link = "" if prefix == "." else prefix + "/"
    counts: dict[str, dict[str, int]] = {}
    for r in rows:
        by_status = counts.setdefault(r.claim.item, {})
        by_status[_status(r)] = by_status.get(_status(r), 0) + 1
    text = (
        render_markdown(rows, link_prefix=link, inventory=render_inventory(counts, results_dir, link))
        + render_judge_sections(results_dir, link)
        + render_peers_sections(Summaries(results_dir), link)
    )
    n_missing = sum(r.verdict is None for r in rows)
    if n_missing:
        log.warning("report: %d of %d rows missing their summary keys", n_missing, len(rows))
    return atomic_write_bytes(out, text.encode())


__all__ = [
    "CLAIMS",
    "DIFFERS",
    "ITEMS",
    "MATCH",
    "NOT_COMPARABLE",
    "RULE_NOT_COMPARABLE",
    "RULE_PM",
    "RULE_PRINTED",
    "TASKS",
    "Claim",
    "MissingKey",
    "Row",
    "Summaries",
    "Verdict",
    "below_percent",
    "check_results_dir",
    "evaluate",
    "not_comparable",
    "printed_half_unit",
    "printed_numbers",
    "render_markdown",
    "trend",
    "within_pm",
    "within_printed",
    "write_report",
]
