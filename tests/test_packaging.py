"""The installed names and the import graph: one top-level import name, ``workbench`` (every folder
installs where it lives, no package-dir mapping), every package folder listed in pyproject.toml,
and no import cycle among the workbench modules — deferred imports inside functions included,
since a cycle there is a layering knot even when it imports cleanly."""

from __future__ import annotations

import ast
import inspect
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from workbench.runner.results import code_hash

tomllib = pytest.importorskip("tomllib")  # Python >= 3.11
ROOT = Path(__file__).resolve().parents[1]


def _setuptools() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def _package_folders() -> dict[str, Path]:
    """{dotted package name: folder} of every folder with an ``__init__.py``, named as installed."""
    assert "package-dir" not in _setuptools(), "every folder installs where it lives"
    roots = {"workbench": ROOT / "workbench"}
    out = {}
    for name, folder in roots.items():
        for init in folder.rglob("__init__.py"):
            rel = init.parent.relative_to(folder).parts
            out[".".join((name, *rel))] = init.parent
    return out


def _modules() -> dict[str, Path]:
    """{dotted module name: file} of every module as installed (a package is its __init__)."""
    folders = _package_folders()
    out = {}
    for pkg, folder in folders.items():
        for f in folder.glob("*.py"):
            out[pkg if f.stem == "__init__" else f"{pkg}.{f.stem}"] = f
    return out


def _imports(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The workbench modules ``name`` imports anywhere in its file (``from pkg import mod`` counts
    as importing ``pkg.mod``, not the package)."""
    is_pkg = path.name == "__init__.py"
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = name.split(".") if is_pkg else name.split(".")[:-1]
                parts = parts[: len(parts) - (node.level - 1)]
                base = ".".join(parts + ([node.module] if node.module else []))
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names]
        else:
            continue
        out.update(t for t in targets if t in modules and t != name)
    return out


def test_the_install_lists_every_package_folder_under_the_one_name_workbench():
    st = _setuptools()
    assert sorted(st["packages"]) == sorted(_package_folders())
    assert {p.split(".")[0] for p in st["packages"]} == {"workbench"}


def test_no_import_cycle_among_workbench_modules():
    modules = _modules()
    assert len(modules) > 60
    assert "workbench.fem.pad" in modules and "workbench.experiments.fem_fitting" in modules
    names = sorted(modules)
    index = {n: i for i, n in enumerate(names)}
    edges = [(index[a], index[b]) for a in names for b in _imports(a, modules[a], modules)]
    assert len(edges) > 100  # the parser sees the imports
    rows, cols = np.array(edges).T
    graph = coo_matrix((np.ones(len(edges)), (rows, cols)), shape=(len(names), len(names)))
    _, label = connected_components(graph, directed=True, connection="strong")
    cycles = [sorted(names[i] for i in np.flatnonzero(label == c)) for c in np.unique(label)]
    cycles = [c for c in cycles if len(c) > 1]
    assert cycles == [], f"import cycles (strongly connected modules): {cycles}"


def test_cycle_finder_sees_a_deferred_cycle(tmp_path):
    # the check above must be able to fail: two modules importing each other inside functions
    a, b = tmp_path / "a.py", tmp_path / "b.py"
    a.write_text("def f():\n    from .b import g\n")
    b.write_text("def g():\n    from . import a\n")
    modules = {"pkg.a": a, "pkg.b": b}
    assert _imports("pkg.a", a, modules) == {"pkg.b"} and _imports("pkg.b", b, modules) == {"pkg.a"}


def test_a_built_wheel_holds_workbench_only_and_runs_with_the_checkouts_code_hash(tmp_path):
    # what `pip install .` puts into site-packages, built from a copy (no build/ in the checkout;
    # the build fetches setuptools from the package index)
    src = tmp_path / "src"
    skip = shutil.ignore_patterns("__pycache__", "*.pyc")
    shutil.copytree(ROOT / "workbench", src / "workbench", ignore=skip)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    res = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path / "dist"), str(src)],
        capture_output=True,
        text=True,
    )
    offline = "NewConnectionError" in res.stderr or "No matching distribution" in res.stderr
    if res.returncode != 0 and offline:
        pytest.skip(f"no package index to fetch the build backend from: {res.stderr[-300:]}")
    assert res.returncode == 0, res.stderr[-2000:]
    (wheel,) = (tmp_path / "dist").glob("*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert {n.split("/")[0] for n in names if ".dist-info/" not in n} == {"workbench"}
    assert "workbench/fem/pad.py" in names and "workbench/experiments/fem_fitting.py" in names
    # installed (unpacked) alone on the path: workbench.fem imports, fem does not, and the code
    # hash that keys checkpoints is the checkout's
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    probe = (
        "import importlib.util as u, workbench.fem.pad, workbench.runner.results as r;"
        "print(u.find_spec('fem') is None, u.find_spec('experiments') is None, r.code_hash(),"
        " workbench.fem.pad.__file__)"
    )
    path = [str(site), *_site_packages()]
    res = subprocess.run(
        [sys.executable, "-S", "-c", f"import sys; sys.path[:0] = {path!r}; {probe}"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert res.returncode == 0, res.stderr[-2000:]
    no_fem, no_experiments, digest, pad_file = res.stdout.split()
    assert (no_fem, no_experiments) == ("True", "True")
    assert digest == code_hash() and pad_file.startswith(str(site))


def _site_packages() -> list[str]:
    """The environment's site-packages without its .pth hooks (``-S``): the dependencies, and not
    the editable install of this checkout."""
    import site

    return site.getsitepackages()


# Where a module's tests live when not in tests/test_<module>.py (fem: or test_fem_<module>.py):
# {module or package: (test file or None, why)}.
_TESTED_ELSEWHERE = {
    "workbench._kernels": (
        None,
        "the kernels run through their wrappers, which are tested against tests/naive.py; "
        "--check-kernels (make test-nojit) fails unless each kernel ran as Python",
    ),
    "workbench.fem._kernels": (None, "as workbench._kernels"),
    "workbench.limit_surface._kernels": (
        None,
        "as workbench._kernels (the quartic's: tests/test_quartic.py)",
    ),
    "workbench._row_kernels": (
        "test_row_kernels.py",
        "each pass against the NumPy expression it redoes, to the last bit, and a profile built on them",
    ),
    "workbench.sources._kernels": (
        "test_reach_kernels.py",
        "the REACH press's passes, each against tests/naive.py and the press against its NumPy algorithm",
    ),
    "workbench.grasp.resistance": (
        "test_resistance.py",
        "one concept (the resistance QP) split by stage, tested through its entry point and per stage",
    ),
    "workbench.engine_trials": (
        "test_engine_trials.py",
        "one concept (a grasp trial on MuJoCo) split into settings, pad, trial and the probes that "
        "validate them, tested together against closed forms",
    ),
    "workbench.experiments": (
        "test_experiments.py",
        "every experiment runs in quick mode there and its headline numbers are asserted "
        "(scikit-fem's test_examples)",
    ),
}


def _mirror_files(module: str) -> list[str]:
    """The test files allowed to hold ``module``'s tests."""
    for prefix, (where, _why) in _TESTED_ELSEWHERE.items():
        if module == prefix or module.startswith(prefix + "."):
            return [where] if where else []
    stem = module.rsplit(".", 1)[1]
    return [f"test_{stem}.py"] + ([f"test_fem_{stem}.py"] if module.startswith("workbench.fem.") else [])


def _modules_used(test_file: Path) -> set[str]:
    """The workbench modules a test file imports, a name re-exported by a package counting as its
    defining module (``from workbench.grasp import q_robust`` uses ``workbench.grasp.robust``)."""
    import importlib

    out = set()
    for node in ast.walk(ast.parse(test_file.read_text())):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("workbench"))
        elif (
            isinstance(node, ast.ImportFrom)
            and not node.level
            and (node.module or "").startswith("workbench")
        ):
            base = importlib.import_module(node.module)
            out.add(node.module)
            for alias in node.names:
                obj = getattr(base, alias.name, None)
                name = (
                    getattr(obj, "__name__", None)
                    if inspect.ismodule(obj)
                    else getattr(obj, "__module__", None)
                )
                if name:
                    out.add(name)
    return out


def _tests_module(name: str, test_file: Path) -> bool:
    """Whether ``test_file`` uses ``name``; a module of a package listed in _TESTED_ELSEWHERE
    counts when the file uses the package through any of its modules (the resistance QP through
    its entry point) or, for an experiment, names it as the CLI does (``ls-fitting``)."""
    used = _modules_used(test_file)
    if name in used:
        return True
    package = next((p for p in _TESTED_ELSEWHERE if name.startswith(p + ".")), None)
    if package == "workbench.experiments":
        return f'"{name.rsplit(".", 1)[1].replace("_", "-")}"' in test_file.read_text()
    return package is not None and any(u.startswith(package + ".") for u in used)


def test_the_tests_mirror_the_modules():
    """Every library module has its own test file that uses it, or is listed above with
    the file that tests it and why."""
    modules = {n: p for n, p in _modules().items() if p.name != "__init__.py"}
    missing = []
    for name in sorted(modules):
        files = [f for f in _mirror_files(name) if (ROOT / "tests" / f).exists()]
        if not _mirror_files(name):
            continue
        if not any(_tests_module(name, ROOT / "tests" / f) for f in files):
            missing.append(f"{name} -> tests/{_mirror_files(name)[0]}")
    assert len(modules) > 60
    assert missing == [], "modules without a test file of their own that uses them: " + ", ".join(missing)


def test_mirror_rule_names_the_expected_files(tmp_path):
    assert _mirror_files("workbench.fem.pad") == ["test_pad.py", "test_fem_pad.py"]
    assert _mirror_files("workbench.grasp.margin") == ["test_margin.py"]
    assert _mirror_files("workbench.grasp.resistance.cuts") == ["test_resistance.py"]
    assert _mirror_files("workbench._kernels") == []
    probe = tmp_path / "test_probe.py"
    probe.write_text("from workbench.grasp import q_robust\nimport workbench.fem.pad\n")
    assert {"workbench.grasp.robust", "workbench.fem.pad"} <= _modules_used(probe)
