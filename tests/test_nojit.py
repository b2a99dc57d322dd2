"""The no-JIT run cannot drift: `make test-nojit` runs the whole suite with NUMBA_DISABLE_JIT=1
except the tests marked ``jit_only`` (each with its reason), and --check-kernels fails it unless
every kernel found by tests/njit_kernels.py ran as Python; here, that the Makefile keeps that
rule and that the source scan finds every compiled function the library defines."""

import importlib
import re
import shlex
from pathlib import Path

import pytest
from njit_kernels import PACKAGES, module_name, njit_functions

ROOT = Path(__file__).resolve().parents[1]


def _recipe(target: str) -> str:
    """The Makefile target's recipe, continuation lines joined."""
    text = (ROOT / "Makefile").read_text().replace("\\\n", " ")
    m = re.search(rf"^{re.escape(target)}:[^\n]*\n((?:\t[^\n]*\n)+)", text, re.M)
    assert m, f"no {target} target in the Makefile"
    return m.group(1)


def test_the_nojit_target_runs_the_whole_suite_but_jit_only():
    (line,) = _recipe("test-nojit").strip().splitlines()
    args = shlex.split(line)
    assert args[0] == "NUMBA_DISABLE_JIT=1" and args[1:4] == ["$(BIN)/python", "-m", "pytest"]
    assert args[args.index("-m", 4) + 1] == "not jit_only" and "--check-kernels" in args
    # no hand-picked files, tests or keyword filters: the suite is collected from testpaths
    picked = [a for a in args if a.startswith("tests") or ".py" in a or a in ("-k", "--deselect")]
    assert not picked, f"make test-nojit must not list tests; found {picked}"


def test_jit_only_is_a_registered_strict_marker():
    tomllib = pytest.importorskip("tomllib")  # Python >= 3.11
    ini = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    assert "--strict-markers" in ini["addopts"].split()  # a misspelt jit_only is an error, not a no-op
    assert any(m.startswith("jit_only(reason):") for m in ini["markers"])
    assert ini["testpaths"] == ["tests"]


def test_the_source_scan_finds_every_compiled_function():
    """Against Numba itself: each module that mentions numba, imported with JIT on, holds a
    Dispatcher exactly for the functions the AST scan lists (none missed, none extra)."""
    numba = pytest.importorskip("numba")
    if numba.config.DISABLE_JIT:
        pytest.skip("with NUMBA_DISABLE_JIT=1 the kernels are plain functions")
    from numba.core.dispatcher import Dispatcher

    found = njit_functions()
    assert {("workbench._kernels", "_fw_segments"), ("workbench.fem._kernels", "_upper_rows")} <= set(found)
    dispatchers = set()
    for folder in PACKAGES:
        for path in (ROOT / folder).rglob("*.py"):
            if "numba" in path.read_text(encoding="utf-8"):
                mod = importlib.import_module(module_name(path))
                dispatchers |= {
                    (mod.__name__, name)
                    for name, obj in vars(mod).items()
                    if isinstance(obj, Dispatcher) and getattr(obj, "__module__", None) == mod.__name__
                }
    assert set(found) == dispatchers
