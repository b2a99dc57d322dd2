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

Parsing every module a run imports costs about a second per process, and each Dask worker
and each experiment is a process.  So what one file contributes (the digest of its normalised
syntax and its import statements) is kept in the cache folder (:func:`workbench.cachedir.cache_dir`,
``code_key/``) under the SHA-256 of the file's bytes, of this module's own bytes and of the Python
version (whose parser writes the tree): an unchanged file is read, not parsed, and any change
of the three parses afresh.  With the cache off it is kept in memory only.
"""

from __future__ import annotations

import ast
import hashlib
import json
import logging
import sys
from collections.abc import Iterable, Mapping
from functools import lru_cache
from pathlib import Path
from typing import NamedTuple

from .atomic_io import atomic_write_bytes
from .cachedir import cache_dir

log = logging.getLogger(__name__)

__all__ = [
    "code_digest",
    "module_closure",
    "module_imports",
    "normalized_digest",
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
    path = Path(path)
    return _strip_docstrings(ast.parse(path.read_bytes(), filename=str(path)))


def normalized_digest(path: str | Path) -> str:
    """The SHA-256 hex digest of :func:`normalized_source` of the file, read from the cache
    folder when the file's bytes were seen before (the module docstring says how it is keyed).
    Raises ``SyntaxError`` for a file that does not parse."""
    return _facts(_stamp(Path(path))).digest


class _Facts(NamedTuple):
    """What one file contributes to a key: the digest of its normalised syntax, and its import
    statements as written, ``(level, module, names)`` (``names`` ``None`` for ``import module``;
    a ``__main__`` guard's left out)."""

    digest: str
    imports: tuple[tuple[int, str, tuple[str, ...] | None], ...]


@lru_cache(maxsize=1)
def _memo_salt() -> str:
    """What the memo of a file's facts depends on besides the file: this module's code and the
    Python version (its parser writes the tree that is dumped)."""
    own = hashlib.sha256(Path(__file__).read_bytes()).hexdigest()
    return f"{own}:{sys.version_info.major}.{sys.version_info.minor}:{sys.implementation.name}"


def _memo_path(file_sha: str) -> Path | None:
    folder = cache_dir()
    if folder is None:
        return None
    name = hashlib.sha256(f"{file_sha}:{_memo_salt()}".encode()).hexdigest()
    return folder / "code_key" / name[:2] / f"{name}.json"


def _read_memo(path: Path | None) -> _Facts | None:
    if path is None or not path.is_file():
        return None
    try:
        raw = json.loads(path.read_bytes())
        imports = tuple(
            (int(level), str(module), None if names is None else tuple(str(n) for n in names))
            for level, module, names in raw["imports"]
        )
        digest = str(raw["digest"])
        if len(digest) != 64:
            raise ValueError(f"a digest of {len(digest)} characters")
    except Exception as exc:  # noqa: BLE001 - a foreign or truncated memo only costs a parse
        log.warning("code-key memo %s unreadable (%s); parsing the file again", path, exc)
        return None
    return _Facts(digest, imports)


@lru_cache(maxsize=4096)
def _facts(stamp: tuple[str, str]) -> _Facts:
    """The file's :class:`_Facts`: from the memo in the cache folder, else parsed once (and
    written there; a folder that cannot be written only costs the parse next time)."""
    memo = _memo_path(stamp[1])
    found = _read_memo(memo)
    if found is not None:
        return found
    path = stamp[0]
    tree = ast.parse(Path(path).read_bytes(), filename=path)
    imports: list[tuple[int, str, tuple[str, ...] | None]] = []
    for node in _walk(tree):
        if isinstance(node, ast.Import):
            imports += [(0, alias.name, None) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            imports.append((node.level, node.module or "", tuple(alias.name for alias in node.names)))
    facts = _Facts(hashlib.sha256(_strip_docstrings(tree)).hexdigest(), tuple(imports))
    if memo is not None:
        try:
            atomic_write_bytes(memo, json.dumps({"digest": facts.digest, "imports": facts.imports}).encode())
        except OSError as exc:
            log.warning("could not write the code-key memo %s (%s); continuing without it", memo, exc)
    return facts


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


def _imported_names(name: str, stamp: tuple[str, str]) -> tuple[tuple[str, tuple[str, ...] | None], ...]:
    """``(module, names)`` of each ``from module import names``, ``(module, None)`` of each
    ``import module``, relative imports resolved."""
    path = Path(stamp[0])
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: list[tuple[str, tuple[str, ...] | None]] = []
    for level, module, names in _facts(stamp).imports:
        if level:
            parts = package.split(".")
            base = ".".join(parts[: len(parts) - level + 1])
            target = f"{base}.{module}" if module else base
        else:
            target = module
        found.append((target, names))
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
        h.update(name.encode() + b"\0" + normalized_digest(_file(name, roots)).encode() + b"\0")
    return h.hexdigest()


@lru_cache(maxsize=64)
def _cached_digest(modules: tuple[str, ...]) -> str:
    roots = package_roots()
    return _digest(module_closure(*modules, roots=roots), roots)


def code_digest(*modules: str, n: int = 16, roots: Mapping[str, Path] | None = None) -> str:
    """The first ``n`` hex digits of the SHA-256 of the digests of the normalised syntax
    (:func:`normalized_digest`) of ``modules`` and everything they import in the package
    (:func:`module_closure`), each with its dotted name.  With the default ``roots`` it is
    computed once per process and set of modules (the running code does not change under it)."""
    if roots is None:
        return _cached_digest(tuple(sorted(modules)))[:n]
    return _digest(module_closure(*modules, roots=roots), roots)[:n]
