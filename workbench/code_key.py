"""What a cached result's code is: the syntax of the modules that can run to compute it.

A cache or checkpoint keyed by every source byte of the package recomputes everything after a
comment edit.  Here a module's key is its *normalised syntax* — the parsed tree with docstrings
dropped (comments and layout never reach the tree), dumped without line numbers — so an edit
of a comment, a docstring or the layout keeps every key, and a change of a statement, a
constant or a message changes the key of every module that imports it, directly or not.

:func:`module_closure` follows the package's own imports statically (every ``import`` and
``from … import`` of a module, function-level ones included, resolved inside the package
``workbench``), so a module that the computation cannot import does not change its key.
A change of meaning that the code does not show (a data file's format, an external tool's
behaviour) is the caller's to add to its key.
"""

from __future__ import annotations

import ast
import hashlib
from collections.abc import Iterable, Mapping
from functools import lru_cache
from pathlib import Path

__all__ = [
    "code_digest",
    "module_closure",
    "module_imports",
    "normalized_function",
    "normalized_source",
    "package_roots",
]


@lru_cache(maxsize=1)
def _package_folder() -> Path:
    from importlib.util import find_spec

    return Path(find_spec("workbench").submodule_search_locations[0])


def package_roots() -> dict[str, Path]:
    """``{package: folder}`` of the installed package's root (``workbench``; its subpackages
    ``workbench.fem``, ``workbench.experiments``, ``workbench.runner`` live in its folder)."""
    return {"workbench": _package_folder()}


def _stamp(path: Path) -> tuple[str, str]:
    """A file's cache key: its path and the SHA-256 of its bytes (an edited file reparses)."""
    return str(path), hashlib.sha256(path.read_bytes()).hexdigest()


def normalized_source(path: str | Path) -> bytes:
    """The file's syntax tree without docstrings (module, class and function), dumped without
    positions: the same for two files that differ only in comments, docstrings or layout.
    Raises ``SyntaxError`` for a file that does not parse."""
    return _normalized(_stamp(Path(path)))


@lru_cache(maxsize=1024)
def _normalized(stamp: tuple[str, str]) -> bytes:
    path = stamp[0]
    return _strip_docstrings(ast.parse(Path(path).read_bytes(), filename=path))


def _file(name: str, roots: Mapping[str, Path]) -> Path | None:
    """The source file of dotted module ``name`` under the longest matching root, or ``None``."""
    for pkg in sorted(roots, key=len, reverse=True):
        if name == pkg or name.startswith(pkg + "."):
            rel = name[len(pkg) :].lstrip(".").split(".") if name != pkg else []
            base = roots[pkg].joinpath(*rel)
            for candidate in (base / "__init__.py", base.with_suffix(".py") if rel else None):
                if candidate is not None and candidate.is_file():
                    return candidate
            return None
    return None


def normalized_function(fn) -> str:
    """The SHA-256 hex digest of one function's (or class's) own source, normalised as
    :func:`normalized_source` does: for a key narrower than its module's."""
    import inspect
    import textwrap

    tree = ast.parse(textwrap.dedent(inspect.getsource(fn)))
    return hashlib.sha256(_strip_docstrings(tree)).hexdigest()


def _strip_docstrings(tree: ast.AST) -> bytes:
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                if isinstance(body[0].value.value, str):
                    # a body of only a docstring keeps a placeholder: the tree must stay valid
                    node.body = body[1:] or [ast.Pass()]
    return ast.dump(tree, include_attributes=False).encode()


def _is_main_guard(node: ast.AST) -> bool:
    """``if __name__ == "__main__":`` — what runs only as a script, never in a computation."""
    test = getattr(node, "test", None)
    return (
        isinstance(node, ast.If)
        and isinstance(test, ast.Compare)
        and isinstance(test.left, ast.Name)
        and test.left.id == "__name__"
        and len(test.comparators) == 1
        and isinstance(test.comparators[0], ast.Constant)
        and test.comparators[0].value == "__main__"
    )


def _walk(node: ast.AST):
    """``ast.walk`` without the bodies of ``__main__`` guards."""
    yield node
    for child in ast.iter_child_nodes(node):
        if not _is_main_guard(child):
            yield from _walk(child)


def _imports(name: str, path: Path, roots: Mapping[str, Path]) -> set[str]:
    """The package modules whose code module ``name`` (file ``path``) uses (a ``__main__``
    guard's imports excepted): ``import a.b`` uses ``a.b``; ``from a import b`` uses the module
    ``a.b`` if there is one, else what package ``a`` (its ``__init__``) makes ``b``."""
    used: set[str] = set()
    for target, names in _imported_names(name, _stamp(path)):
        if names is None:
            used.add(target)
            continue
        submodules = [f"{target}.{n}" for n in names if _file(f"{target}.{n}", roots) is not None]
        used.update(submodules)
        if len(submodules) < len(names):  # a name the package itself defines or re-exports
            used.add(target)
    return {m for m in used if _file(m, roots) is not None}


def module_imports(name: str, roots: Mapping[str, Path] | None = None) -> set[str]:
    """The package modules whose code module ``name`` uses directly (:func:`_imports`: function-
    level imports included, a ``__main__`` guard's not; ``from a import b`` is the module ``a.b``
    when there is one).  Raises ``ValueError`` for a name that is no module under ``roots``."""
    roots = package_roots() if roots is None else dict(roots)
    path = _file(name, roots)
    if path is None:
        raise ValueError(f"module_imports: {name!r} is no module of {sorted(roots)}")
    return _imports(name, path, roots)


@lru_cache(maxsize=1024)
def _imported_names(name: str, stamp: tuple[str, str]) -> tuple[tuple[str, tuple[str, ...] | None], ...]:
    """``(module, names)`` of each ``from module import names``, ``(module, None)`` of each
    ``import module``, relative imports resolved."""
    path = Path(stamp[0])
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: list[tuple[str, tuple[str, ...] | None]] = []
    for node in _walk(ast.parse(path.read_bytes(), filename=str(path))):
        if isinstance(node, ast.Import):
            found += [(alias.name, None) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1])
                target = f"{base}.{node.module}" if node.module else base
            else:
                target = node.module or ""
            found.append((target, tuple(alias.name for alias in node.names)))
    return tuple(found)


def _parents(name: str, roots: Mapping[str, Path]) -> list[str]:
    """The packages above ``name`` (importing ``a.b.c`` runs ``a`` and ``a.b`` first)."""
    parts = name.split(".")
    return [p for p in (".".join(parts[:i]) for i in range(1, len(parts))) if _file(p, roots)]


def module_closure(*modules: str, roots: Mapping[str, Path] | None = None) -> list[str]:
    """Sorted dotted names of ``modules``, every package module whose code they use, directly
    or through others (:func:`_imports`), and the packages above each.  A package's
    ``__init__`` that is only passed through on the way to a submodule is in the list (its own
    code runs) but what it imports is followed only where a module takes a name from it.
    Raises ``ValueError`` for a name that is no module under ``roots`` (default:
    :func:`package_roots`)."""
    roots = package_roots() if roots is None else dict(roots)
    for m in modules:
        if _file(m, roots) is None:
            raise ValueError(
                f"module_closure: {m!r} is no module of {sorted(roots)}; pass a dotted module name "
                "such as 'workbench.wrench' or 'workbench.experiments.sensitivity'"
            )
    todo, used = list(modules), set()
    while todo:
        m = todo.pop()
        if m not in used:
            used.add(m)
            todo += [d for d in _imports(m, _file(m, roots), roots) if d not in used]
    return sorted(used.union(*(_parents(m, roots) for m in used)))


def _digest(names: Iterable[str], roots: Mapping[str, Path]) -> str:
    h = hashlib.sha256()
    for name in names:
        h.update(name.encode() + b"\0" + normalized_source(_file(name, roots)) + b"\0")
    return h.hexdigest()


@lru_cache(maxsize=64)
def _cached_digest(modules: tuple[str, ...]) -> str:
    roots = package_roots()
    return _digest(module_closure(*modules, roots=roots), roots)


def code_digest(*modules: str, n: int = 16, roots: Mapping[str, Path] | None = None) -> str:
    """The first ``n`` hex digits of the SHA-256 of the normalised syntax
    (:func:`normalized_source`) of ``modules`` and everything they import in the package
    (:func:`module_closure`), each with its dotted name.  With the default ``roots`` it is
    computed once per process and set of modules (the running code does not change under it)."""
    if roots is None:
        return _cached_digest(tuple(sorted(modules)))[:n]
    return _digest(module_closure(*modules, roots=roots), roots)[:n]
