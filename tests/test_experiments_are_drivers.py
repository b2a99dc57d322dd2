"""The experiments are drivers: what the tests exercise of them is their public face (``run``,
``DEFAULT_CONFIG``, ``check_config``, ...); the logic they compose lives in the library under
public names and is tested there.  A test reaching for an experiment's ``_private`` name is a
sign that library logic has crept back into a driver."""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parent
PREFIX = "workbench.experiments"


def _experiment_imports(tree: ast.AST) -> tuple[dict[str, str], list[str]]:
    """(``{alias: experiment module}`` of the modules imported whole, ``module:name`` of the
    private names imported from one)."""
    aliases: dict[str, str] = {}
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(PREFIX):
            for a in node.names:
                if node.module == PREFIX:
                    aliases[a.asname or a.name] = f"{PREFIX}.{a.name}"
                elif a.name.startswith("_"):
                    found.append(f"{node.module}:{a.name}")
        elif isinstance(node, ast.Import):
            whole = [a for a in node.names if a.name.startswith(PREFIX + ".") and a.asname]
            aliases.update({a.asname: a.name for a in whole})
    return aliases, found


def private_uses(source: str) -> list[str]:
    """``module:name`` of every ``_private`` name of an experiment module that ``source``
    imports (``from workbench.experiments.X import _y``) or reads off an imported experiment
    module (``import workbench.experiments.X as m`` / ``from workbench.experiments import X as m``,
    then ``m._y``)."""
    tree = ast.parse(source)
    aliases, found = _experiment_imports(tree)
    found += [
        f"{aliases[node.value.id]}:{node.attr}"
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id in aliases
        and node.attr.startswith("_")
        and not node.attr.startswith("__")
    ]
    return sorted(set(found))


def test_the_scan_finds_both_kinds_of_private_use():
    src = (
        "from workbench.experiments.sensitivity import _row, run\n"
        "from workbench.experiments import minimal_work as mw\n"
        "import workbench.experiments.peers as p\n"
        "mw._wall_rows(); mw.run(); p._compare; p.__name__\n"
    )
    assert private_uses(src) == [
        "workbench.experiments.minimal_work:_wall_rows",
        "workbench.experiments.peers:_compare",
        "workbench.experiments.sensitivity:_row",
    ]


def test_no_test_uses_a_private_name_of_an_experiment():
    here = Path(__file__).resolve()
    uses = {
        p.name: private_uses(p.read_text(encoding="utf-8"))
        for p in sorted(TESTS.glob("*.py"))
        if p.resolve() != here
    }
    assert {k: v for k, v in uses.items() if v} == {}
