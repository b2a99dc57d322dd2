"""The design docs stay true to the code: docs/equations.md is what docs/generate_equations.py
writes now, every citation of an equation is in the one house format, every module
docs/architecture.md names exists, and its table of core modules importing the run machinery
is the list the import graph gives."""

from __future__ import annotations

import ast
import difflib
import importlib.util
import re
import sys
from pathlib import Path

import pytest

from workbench.code_key import module_imports

ROOT = Path(__file__).resolve().parents[1]
ARCHITECTURE = ROOT / "docs" / "architecture.md"


def _generator():
    path = ROOT / "docs" / "generate_equations.py"
    spec = importlib.util.spec_from_file_location("generate_equations", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


gen = _generator()


def test_equations_md_is_current():
    want = gen.render()
    have = gen.OUT.read_text(encoding="utf-8") if gen.OUT.exists() else ""
    diff = difflib.unified_diff(have.splitlines(True), want.splitlines(True), "docs/equations.md", "now")
    diff = "".join(list(diff)[:40])
    assert have == want, f"docs/equations.md is stale: run `{gen.COMMAND}` and commit it\n{diff}"


def test_every_cited_equation_has_a_meaning_or_is_marked_missing():
    found, _ = gen.index()
    thesis = {n for n in found if not n.startswith("6DFC ")}
    paper = {n[5:] for n in found if n.startswith("6DFC ")}
    assert thesis - set(gen.MEANINGS) - gen.NOT_IN_THESIS == set()
    assert paper - set(gen.PAPER_MEANINGS) == set()
    assert len(found) > 40 and "3.8" in found and "6DFC IV.2" in found  # the scan sees the code


_SOURCE = '''"""Module docstring (Eq. 3.1)."""
# a module-level comment, Eqs. 3.2, 3.5

# the comment right above a function belongs to it: Eq. 4.4
@decorator
def f():
    """Eqs. 3.10–3.12."""
    x = 1  # a body comment, Eq. 3.18
    def inner():
        # Eq. 2.100
        pass


class C:
    """6DFC Eq. IV.2."""

    # Eq. 3.29 in the class body
    y = 2

    def method(self):
        return 1  # Eqs. 3.6, 3.8


def g():
    """no citation; eq3.18 is a name, Eq. 4.3.3 a section"""
'''


def test_citations_go_to_the_innermost_definition():
    by_name = {}
    for d in gen.definitions("pkg.mod", _SOURCE):
        by_name[d.name] = gen.cited(d.text)
    assert by_name == {
        "pkg.mod": ["3.1", "3.2", "3.5"],
        "pkg.mod:f": ["3.10", "3.11", "3.12", "4.4", "3.18"],  # docstring first, then comments
        "pkg.mod:f.inner": ["2.100"],
        "pkg.mod:C": ["6DFC IV.2", "3.29"],
        "pkg.mod:C.method": ["3.6", "3.8"],
        "pkg.mod:g": [],
    }


def test_a_renamed_cited_function_changes_the_index(tmp_path):
    # the staleness check must be able to fail: the same citation under another name
    for folder in gen.PACKAGES:
        (tmp_path / folder).mkdir()
    module = tmp_path / "workbench" / "wrench.py"
    module.write_text('def frictional_wrenches():\n    """Eq. 3.8."""\n')
    before = gen.render(tmp_path)
    assert "| Eq. 3.8 | discrete frictional wrench" in before
    assert "`workbench.wrench:frictional_wrenches`" in before
    module.write_text('def wrenches():\n    """Eq. 3.8."""\n')
    after = gen.render(tmp_path)
    assert after != before and "`workbench.wrench:wrenches`" in after
    (tmp_path / "workbench" / "fem").mkdir()
    (tmp_path / "workbench" / "fem" / "pad.py").write_text("# Eq. 5.99\n")
    assert "`workbench.fem.pad`" in gen.render(tmp_path)
    assert "no meaning written yet" in gen.render(tmp_path)


@pytest.mark.parametrize(
    ("text", "numbers"),
    [
        ("Eq. 3.6", ["3.6"]),
        ("(Eq. 4.5).", ["4.5"]),
        ("Eq. 3.18's", ["3.18"]),
        ("Eqs. 3.10–3.12", ["3.10", "3.11", "3.12"]),
        ("Eqs. 3.22–3.24, 3.28, 3.30", ["3.22", "3.23", "3.24", "3.28", "3.30"]),
        ("Eqs. 3.20,\n  3.25–3.27", ["3.20", "3.25", "3.26", "3.27"]),
        ("Eqs. 2.100–2.101, 4.4", ["2.100", "2.101", "4.4"]),
        ("thesis Eq. 2.100; 6DFC Eq. IV.3", ["2.100", "6DFC IV.3"]),
        ("Eq. 4.6 / §4.3.3.2", ["4.6"]),
        ("kind='eq3.18', §3.3.4", []),
    ],
)
def test_cited_reads_the_house_format(text, numbers):
    assert gen.cited(text) == numbers
    assert gen.old_format_citations(text) == []


@pytest.mark.parametrize(
    "text",
    [
        "Eq. (3.6)",
        "Eqs. (3.10)-(3.12)",
        "Eq. 3.6-3.8",
        "Eq. 2.44/2.47",
        "Eq. 3.1, 3.2",
        "Eq. 3.10–3.12",
        "Eqs. 3.6 alone",
        "Eq.3.6",
        "Eq 3.6",
        "6DFC paper Eq. IV.2",
    ],
)
def test_old_formats_are_found(text):
    assert gen.old_format_citations(text) != []


def _cited_files() -> list[Path]:
    folders = ("workbench", "tests", "benchmarks")
    files = [p for d in folders for p in sorted((ROOT / d).rglob("*.py"))]
    files += [
        ROOT / "README.md",
        *sorted((ROOT / "docs").glob("*.md")),
        ROOT / "docs" / "generate_equations.py",
    ]
    here = Path(__file__).resolve()
    return [p for p in files if "__pycache__" not in p.parts and p.resolve() != here]


def test_every_citation_is_in_the_house_format():
    bad = [
        f"{p.relative_to(ROOT)}:{line}: {excerpt!r} ({why})"
        for p in _cited_files()
        for line, excerpt, why in gen.old_format_citations(p.read_text(encoding="utf-8"))
    ]
    assert bad == [], (
        "write thesis equations as 'Eq. 3.6', 'Eqs. 3.10–3.12' or 'Eqs. 3.10, 3.12', the 6DFC "
        "paper's as '6DFC Eq. IV.2':\n" + "\n".join(bad)
    )


# ---- docs/architecture.md

_PATH = re.compile(r"(?<![\w./-])((?:workbench|fem|experiments|tests|benchmarks|docs)/[\w./-]*[\w/])")
_DOTTED = re.compile(r"(?<![\w./])(workbench(?:\.\w+)+)(?::([\w.]+))?")


def _module_file(dotted: str) -> Path | None:
    """The file of an installed module name (``workbench.fem.pad`` -> workbench/fem/pad.py), or None."""
    parts = dotted.split(".")[1:]
    path = (ROOT / "workbench").joinpath(*parts)
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _top_level_names(path: Path) -> set[str]:
    """Names a module binds at its top level (defs, classes, imports, assignments) and
    ``Class.method`` for the methods of its classes."""
    names = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
            if isinstance(node, ast.ClassDef):
                names.update(
                    f"{node.name}.{m.name}"
                    for m in node.body
                    if isinstance(m, (ast.FunctionDef, ast.AsyncFunctionDef))
                )
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def missing_names(text: str) -> list[str]:
    """Every repository path and ``workbench.x.y`` (or ``workbench.x.y:name``) in ``text``
    that does not exist."""
    out = []
    for m in _PATH.finditer(text):
        if not (ROOT / m.group(1)).exists():
            out.append(m.group(1))
    for m in _DOTTED.finditer(text):
        dotted, attr = m.group(1), m.group(2)
        path = _module_file(dotted)
        if path is None:
            out.append(dotted)
        elif attr and attr not in _top_level_names(path):
            out.append(f"{dotted}:{attr}")
    return out


def test_every_module_architecture_md_names_exists():
    text = ARCHITECTURE.read_text(encoding="utf-8")
    assert len(_PATH.findall(text)) > 80 and len(_DOTTED.findall(text)) > 5  # it reads the names
    assert missing_names(text) == []


def test_the_name_check_can_fail():
    text = (
        "`workbench/wrench.py` `workbench/nothing.py` `workbench/fem/pad.py` `workbench/experiments/none/` "
        "`workbench.fem.pad` `workbench.fem.nothing` `workbench.fem:press` `workbench.fem:nothing` "
        "`workbench.fem.pad:PadGeometry` `workbench.grasp.contacts:ContactSet.vertices`."
    )
    assert missing_names(text) == [
        "workbench/nothing.py",
        "workbench/experiments/none/",
        "workbench.fem.nothing",
        "workbench.fem:nothing",
    ]


#: the layers of docs/architecture.md in order, core first, by module (a package stands for its
#: modules); a module of none of them fails the test below until it is given one
_LAYERS = {
    "base": (
        "config units plausible seeds groups kernel_launch blas_threads cachedir atomic_io stats timing "
        "quiet_log"
    ),
    "code keys": "code_key",
    "core math": "profile twists twists_author _kernels _row_kernels wrench pressure coarsen",
    "fem": "fem",
    "sources": "sources",
    "limit surfaces": "limit_surface",
    "grasp": "grasp",
    "peers": "peers",
    "engine judge": "engine_trials",
    "facade": "",  # workbench/__init__.py: re-exports the public API of the layers above
    "run machinery": "runner",
    "experiments": "experiments",
}
_ORDER = list(_LAYERS)
_CORE = _ORDER[: _ORDER.index("run machinery")]


def _layer(dotted: str) -> str:
    """The layer of a module (``workbench`` itself: the facade, workbench/__init__.py)."""
    parts = dotted.split(".")
    if len(parts) == 1:
        return "facade"
    for layer, names in _LAYERS.items():
        if parts[1] in names.split():
            return layer
    raise AssertionError(f"{dotted} is in no layer: add it to docs/architecture.md and _LAYERS here")


def _modules() -> dict[str, Path]:
    return dict(gen.source_files())


def _table(text: str, heading: str) -> set[tuple[str, str]]:
    """(importer path, imported module) of the table right after the paragraph ``heading``
    starts."""
    section = text.split(heading, 1)[1].split("\n\n", 2)[1]
    return set(re.findall(r"^\| `([\w/.]+)` \| `(workbench[\w.]*)`", section, re.M))


def test_architecture_md_lists_every_import_against_the_layers():
    modules = _modules()
    into_run, upward = set(), set()
    for name, path in modules.items():
        layer = _layer(name)
        if layer not in _CORE:
            continue
        for imported in module_imports(name) & set(modules):
            other = _layer(imported)
            row = (str(path.relative_to(ROOT)), imported)
            if other not in _CORE:
                into_run.add(row)
            elif _ORDER.index(other) > _ORDER.index(layer):
                upward.add(row)
    assert upward, "the import scan sees nothing"
    # the contract: the core never imports the run machinery
    assert into_run == set(), f"the core imports the run machinery: {sorted(into_run)}"
    text = ARCHITECTURE.read_text(encoding="utf-8")
    for found, heading in [(upward, "Where a core layer imports one listed after it")]:
        listed = _table(text, heading)
        assert listed == found, (
            f"docs/architecture.md's table under {heading!r} is out of date: listed but not "
            f"imported {sorted(listed - found)}, imported but not listed {sorted(found - listed)}"
        )


# ---- the import contract of make lint (pyproject.toml [tool.importlinter])


def _contract_layers() -> list[set[str]]:
    """The layers of the import-linter contract, top first, each a set of module names."""
    tomllib = pytest.importorskip("tomllib")  # Python >= 3.11
    tool = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    (contract,) = tool["contracts"]
    return [{m.strip() for m in re.split(r"[:|]", layer)} for layer in contract["layers"]]


def test_the_import_contract_has_every_module_in_the_layers_of_architecture_md():
    # a module missing from the contract would be free to import anything: each must be in the
    # layer _LAYERS gives it, in the same order (the contract lists the top first)
    contract = _contract_layers()
    where = {m: i for i, layer in enumerate(contract) for m in layer}
    seen = []
    for name in _modules():
        parts = name.split(".")
        if len(parts) == 1:
            continue  # the facade, workbench/__init__.py
        top = ".".join(parts[:2])
        assert top in where, f"{top} is in no layer of pyproject.toml [tool.importlinter]"
        seen.append((_ORDER.index(_layer(name)), len(contract) - where[top]))
    # one contract layer per architecture layer, in the same order
    by_arch = {}
    for arch, rank in seen:
        by_arch.setdefault(arch, set()).add(rank)
    assert all(len(r) == 1 for r in by_arch.values()), by_arch
    ranks = [by_arch[a].pop() for a in sorted(by_arch)]
    assert ranks == sorted(ranks), "pyproject.toml's layers are not in docs/architecture.md's order"


def test_the_import_contract_fails_on_a_core_module_importing_the_run_machinery(tmp_path):
    # lint-imports on a copy of the package where wrench.py imports the results module: refused
    import shutil
    import subprocess

    exe = Path(sys.executable).with_name("lint-imports")
    if not exe.is_file():
        pytest.skip("import-linter is not installed (the dev extra)")
    skip = shutil.ignore_patterns("__pycache__", "data")
    shutil.copytree(ROOT / "workbench", tmp_path / "workbench", ignore=skip)
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    wrench = tmp_path / "workbench" / "wrench.py"
    wrench.write_text(wrench.read_text() + "\n\ndef _f():\n    from workbench.runner import results\n")
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(tmp_path)}
    res = subprocess.run([str(exe), "--no-cache"], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert res.returncode == 1, res.stdout[-2000:] + res.stderr[-2000:]
    assert "workbench.wrench is not allowed to import workbench.runner" in res.stdout
