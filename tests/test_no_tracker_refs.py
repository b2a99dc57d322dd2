"""No references to the team's own issue tracker in code, tests, benchmarks, docs or the build
files: a tracker number after the word "issue" means nothing to a reader of the code, so the text
says what the issue stood for instead.  Upstream projects' issues are fine (the line names the project or a
GitHub URL)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("workbench", "benchmarks", "tests")

#: the word "issue" or "issues", then a number ("#" before it allowed), also across a line end
TRACKER = re.compile(r"\bissues?\s+#?\d+", re.IGNORECASE)
#: a line naming one of these refers to that project's tracker, not ours
UPSTREAM = re.compile(r"HiGHS|MuJoCo|Drake|scikit-fem|skfem|numba|dask|cvxpy|github\.com/", re.IGNORECASE)


def _files(root: Path) -> list[Path]:
    files = [p for folder in FOLDERS for p in sorted((root / folder).rglob("*.py"))]
    top = [root / name for name in ("README.md", "pyproject.toml", "Makefile")]
    return files + [p for p in [*top, *sorted((root / "docs").glob("*.md"))] if p.is_file()]


def tracker_refs(root: Path = ROOT) -> list[str]:
    """``path:line: text`` of each line under ``root`` where a tracker reference starts and no
    upstream project is named (on the lines the reference spans)."""
    found = []
    for path in _files(root):
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        flagged = set()
        for m in TRACKER.finditer(text):
            first, last = text.count("\n", 0, m.start()), text.count("\n", 0, m.end())
            span = "\n".join(lines[first : last + 1])
            if first not in flagged and not UPSTREAM.search(span):
                flagged.add(first)
                found.append(f"{path.relative_to(root).as_posix()}:{first + 1}: {span.strip()}")
    return found


def test_no_tracker_issue_numbers():
    assert len(_files(ROOT)) > 100  # the scan reads the repository, not an empty list
    found = tracker_refs()
    why = "references to the team's tracker (say what the issue stood for instead):"
    assert not found, "\n".join([why, *found])


def test_the_scan_finds_references_and_allows_upstream_ones(tmp_path):
    # the references are assembled from parts so that this file itself stays clean
    issue, issues = "issue", "issues"
    (tmp_path / "workbench").mkdir()
    (tmp_path / "docs").mkdir()
    (tmp_path / "workbench" / "mod.py").write_text(
        f'"""A module ({issue} 12).\n\nSecond line, {issues} 11 and 13.\nSee the {issue}\n44."""\n'
        f"x = 1  # HiGHS {issues} 1702, 2749: upstream\n"
        f"y = 2  # https://github.com/org/repo/{issues}/3 and {issue} 3 there\n"
        f"z = 3  # an {issue} is not a number; {issue}s come and go\n",
        encoding="utf-8",
    )
    (tmp_path / "docs" / "notes.md").write_text(
        f"Fixed in {issue.title()} #5.\nMuJoCo's {issue} #3328.\n", encoding="utf-8"
    )
    (tmp_path / "README.md").write_text(f"closed by {issue.upper()} 7\n", encoding="utf-8")
    found = tracker_refs(tmp_path)
    assert [f.split(": ", 1)[0] for f in found] == [
        "workbench/mod.py:1",
        "workbench/mod.py:3",
        "workbench/mod.py:4",
        "README.md:1",
        "docs/notes.md:1",
    ], found
    # one entry per line however many references it holds; one broken over a line end is found
    assert found[1] == f"workbench/mod.py:3: Second line, {issues} 11 and 13."
    assert found[2] == f'workbench/mod.py:4: See the {issue}\n44."""'
