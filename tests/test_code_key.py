"""workbench.code_key: caches and checkpoints keyed by the code that can change their numbers —
a comment edit reuses, a changed constant of a used module recomputes, an unused module's edit
reuses — on a toy package and on a copy of the real one."""

import shutil
from pathlib import Path

import pytest

from workbench.code_key import code_digest, module_closure, module_imports, normalized_source, package_roots
from workbench.runner.results import Checkpoint


def _toy(tmp_path: Path) -> dict[str, Path]:
    pkg = tmp_path / "ckpkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from . import c\n")  # passed through, not followed
    (pkg / "a.py").write_text(
        '"""Uses b."""\n'
        "from . import b\n"
        "from .sub import d\n\n"
        "def f(x):\n"
        '    """Doc."""\n'
        "    from .sub.e import g  # a function-level import counts\n"
        "    return b.K * x + g(d.L)\n\n"
        'if __name__ == "__main__":\n'
        "    from . import c  # a script's import does not\n"
    )
    (pkg / "b.py").write_text("K = 2  # the constant\n")
    (pkg / "c.py").write_text("UNUSED = 0\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "d.py").write_text("L = 1\n")
    (pkg / "sub" / "e.py").write_text("def g(y):\n    return y\n")
    return {"ckpkg": pkg}


def test_the_closure_follows_used_imports_only(tmp_path):
    roots = _toy(tmp_path)
    # a, what it imports at module and function level, and the packages it passes through
    assert module_closure("ckpkg.a", roots=roots) == [
        "ckpkg",
        "ckpkg.a",
        "ckpkg.b",
        "ckpkg.sub",
        "ckpkg.sub.d",
        "ckpkg.sub.e",
    ]
    with pytest.raises(ValueError, match="'ckpkg.nope' is no module"):
        module_closure("ckpkg.nope", roots=roots)
    # a's direct imports: `from .sub import d` is the module d, not the package; no script imports
    assert module_imports("ckpkg.a", roots=roots) == {"ckpkg.b", "ckpkg.sub.d", "ckpkg.sub.e"}
    assert module_imports("ckpkg", roots=roots) == {"ckpkg.c"}
    with pytest.raises(ValueError, match="'ckpkg.nope' is no module"):
        module_imports("ckpkg.nope", roots=roots)


def test_a_comment_reuses_a_used_constant_recomputes_an_unused_module_reuses(tmp_path):
    roots = _toy(tmp_path)
    pkg = roots["ckpkg"]
    key = code_digest("ckpkg.a", roots=roots)
    # comments, docstrings and layout are not code
    (pkg / "b.py").write_text('"""The constant."""\n\nK = 2    # still the constant\n')
    (pkg / "a.py").write_text((pkg / "a.py").read_text().replace('"""Doc."""', '"""Other words."""'))
    assert code_digest("ckpkg.a", roots=roots) == key
    # a module a cannot run: not part of its key (c is imported by the package, a script, nobody else)
    (pkg / "c.py").write_text("UNUSED = 1\n")
    assert code_digest("ckpkg.a", roots=roots) == key
    # a constant of a module a uses through a function-level import
    (pkg / "sub" / "e.py").write_text("def g(y):\n    return 2 * y\n")
    changed = code_digest("ckpkg.a", roots=roots)
    assert changed != key
    (pkg / "b.py").write_text("K = 3\n")
    assert code_digest("ckpkg.a", roots=roots) not in (key, changed)


def test_on_a_copy_of_the_package_rows_survive_a_comment_and_follow_a_kernel_constant(tmp_path):
    roots = {}
    for pkg, src in package_roots().items():
        roots[pkg] = shutil.copytree(src, tmp_path / pkg, ignore=shutil.ignore_patterns("__pycache__"))
    experiment = "workbench.experiments.sensitivity"
    closure = module_closure(experiment, roots=roots)
    assert {"workbench.wrench", "workbench._kernels", "workbench.limit_surface.ellipsoid"} <= set(closure)
    assert "workbench.runner.report" not in closure and "workbench.fem.wall" not in closure

    def rows_kept() -> int:
        ck = Checkpoint.peek(tmp_path / "rows.jsonl", {"n": 1}, code=code_digest(experiment, roots=roots))
        return len(ck)

    ckpt = Checkpoint(tmp_path / "rows.jsonl", {"n": 1}, code=code_digest(experiment, roots=roots))
    ckpt.add("r", {"x": 1})
    wrench = roots["workbench"] / "wrench.py"
    wrench.write_text(wrench.read_text() + "\n# a comment-only edit\n")
    assert rows_kept() == 1
    report = roots["workbench"] / "runner" / "report.py"
    report.write_text(report.read_text() + "\n_NOT_USED_BY_SENSITIVITY = 1\n")
    assert rows_kept() == 1
    kernels = roots["workbench"] / "_kernels.py"
    text = kernels.read_text()
    # the 6DFW kernel's slip test: an element slips when |v_t|² > rtol² |v|²
    assert text.count("t2 > rtol2 * u2") == 1
    kernels.write_text(text.replace("t2 > rtol2 * u2", "t2 >= rtol2 * u2"))
    assert rows_kept() == 0


def test_normalized_source_ignores_layout_and_refuses_broken_files(tmp_path):
    one, two = tmp_path / "one.py", tmp_path / "two.py"
    one.write_text("def f(a, b):\n    return a + b\n")
    two.write_text('def f(a,\n      b):  # sum\n    """Adds."""\n    return (a + b)\n')
    assert normalized_source(one) == normalized_source(two)
    two.write_text("def f(a, b):\n    return b + a\n")
    assert normalized_source(one) != normalized_source(two)
    two.write_text("def f(:\n")
    with pytest.raises(SyntaxError):
        normalized_source(two)


def _fresh_process(monkeypatch, cache):
    """What a new process sees: the memo in ``cache`` (or none), empty in-memory caches."""
    import workbench.code_key as ck

    if cache is None:
        monkeypatch.setenv("WORKBENCH_CACHE_DIR", "off")
    else:
        monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(cache))
    ck._facts.cache_clear()
    ck._cached_digest.cache_clear()
    return ck


def test_a_file_seen_before_is_read_from_the_memo_not_parsed(tmp_path, monkeypatch):
    roots = _toy(tmp_path / "src")
    ck = _fresh_process(monkeypatch, tmp_path / "cache")
    key = code_digest("ckpkg.a", roots=roots)
    closure = module_closure("ckpkg.a", roots=roots)
    # one memo per file of the closure (c, imported only by the package's __init__, is not read)
    memos = sorted((tmp_path / "cache" / "code_key").rglob("*.json"))
    assert len(memos) == len(closure) == 6

    # a new process: nothing may be parsed, and the key and the closure come out the same
    ck = _fresh_process(monkeypatch, tmp_path / "cache")

    def no_parse(*args, **kwargs):
        raise AssertionError("parsed a file whose memo is on disk")

    monkeypatch.setattr(ck.ast, "parse", no_parse)
    assert code_digest("ckpkg.a", roots=roots) == key
    assert module_closure("ckpkg.a", roots=roots) == closure
    # an edited file is a different file: parsed (here: refused by the patch), never the old memo
    (roots["ckpkg"] / "b.py").write_text("K = 3\n")
    with pytest.raises(AssertionError, match="parsed a file"):
        code_digest("ckpkg.a", roots=roots)


def test_a_broken_memo_is_reparsed_and_the_cache_off_gives_the_same_key(tmp_path, monkeypatch, caplog):
    roots = _toy(tmp_path / "src")
    _fresh_process(monkeypatch, None)
    key = code_digest("ckpkg.a", roots=roots)  # the cache off: parsed, nothing written
    assert not (tmp_path / "cache").exists()
    _fresh_process(monkeypatch, tmp_path / "cache")
    assert code_digest("ckpkg.a", roots=roots) == key
    for memo in (tmp_path / "cache" / "code_key").rglob("*.json"):
        memo.write_text('{"digest": "abc", "imports": []}')  # a foreign file: a short digest
    _fresh_process(monkeypatch, tmp_path / "cache")
    with caplog.at_level("WARNING", logger="workbench.code_key"):
        assert code_digest("ckpkg.a", roots=roots) == key
    assert "unreadable (a digest of 3 characters); parsing the file again" in caplog.text
    # and the memos were written afresh
    _fresh_process(monkeypatch, tmp_path / "cache")
    caplog.clear()
    with caplog.at_level("WARNING", logger="workbench.code_key"):
        assert code_digest("ckpkg.a", roots=roots) == key
    assert caplog.text == ""


def test_the_digest_of_a_file_is_the_sha256_of_its_normalised_syntax(tmp_path, monkeypatch):
    import hashlib

    from workbench.code_key import normalized_digest

    _fresh_process(monkeypatch, tmp_path / "cache")
    f = tmp_path / "m.py"
    f.write_text('"""Doc."""\nimport os  # a comment\nX = 1\n')
    want = hashlib.sha256(normalized_source(f)).hexdigest()
    assert normalized_digest(f) == want
    _fresh_process(monkeypatch, tmp_path / "cache")
    assert normalized_digest(f) == want  # from the memo
