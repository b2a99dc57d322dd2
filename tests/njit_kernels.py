"""The library's Numba kernels, found in the source: every function decorated with a Numba
compiler (``@njit``, ``@jit``, ``@vectorize``, ...) in workbench/ (its subpackages included).
The no-JIT run (``make test-nojit``, tests/conftest.py) checks each one runs as Python;
tests/test_nojit.py checks this list against the compiled dispatchers."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: source folder -> import name (every folder installs where it lives)
PACKAGES = {"workbench": "workbench"}
COMPILERS = {"njit", "jit", "vectorize", "guvectorize", "cfunc", "stencil", "generated_jit"}


def _decorator_name(node: ast.expr) -> str:
    """``njit`` for ``@njit``, ``@njit(...)``, ``@numba.njit`` and ``@numba.njit(...)``."""
    if isinstance(node, ast.Call):
        node = node.func
    if isinstance(node, ast.Attribute):
        return node.attr
    return node.id if isinstance(node, ast.Name) else ""


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = [PACKAGES[rel.parts[0]], *rel.parts[1:]]
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def njit_functions() -> list[tuple[str, str]]:
    """``(module, function)`` of every module-level Numba-compiled function, sorted."""
    found = []
    for folder in PACKAGES:
        for path in sorted((ROOT / folder).rglob("*.py")):
            source = path.read_text(encoding="utf-8")
            if "numba" not in source:
                continue
            for node in ast.parse(source).body:
                if isinstance(node, ast.FunctionDef) and any(
                    _decorator_name(d) in COMPILERS for d in node.decorator_list
                ):
                    found.append((module_name(path), node.name))
    return sorted(found)
