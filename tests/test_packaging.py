"""The installed names and the import graph: one top-level import name, ``workbench`` (fem/ and
experiments/ install as workbench.fem and workbench.experiments), every package folder listed
in pyproject.toml, and no import cycle among the workbench modules — deferred imports inside
functions included, since a cycle there is a layering knot even when it imports cleanly."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from workbench.results import code_hash

tomllib = pytest.importorskip("tomllib")  # Python >= 3.11
ROOT = Path(__file__).resolve().parents[1]


def _setuptools() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def _package_folders() -> dict[str, Path]:
    """{dotted package name: folder} of every folder with an ``__init__.py``, named as installed."""
    st = _setuptools()
    roots = {"workbench": ROOT / "workbench"}
    roots.update({name: ROOT / folder for name, folder in st["package-dir"].items()})
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
    for name in ("workbench", "fem", "experiments"):
        shutil.copytree(ROOT / name, src / name, ignore=skip)
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
        "import importlib.util as u, workbench.fem.pad, workbench.results as r;"
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
