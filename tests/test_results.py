"""Atomic result writing: a failed write leaves the previous file intact and no debris."""

import json
import os
from pathlib import Path

import numpy as np
import pytest

from workbench.runner import results


def test_write_json_roundtrip_and_types(tmp_path):
    data = {"x": np.float64(1.5), "v": np.arange(3), "n": np.nan}
    path = results.write_json(tmp_path / "a" / "s.json", data)
    assert json.loads(path.read_text()) == {"x": 1.5, "v": [0, 1, 2], "n": None}


def test_failed_write_keeps_old_file(tmp_path, monkeypatch):
    path = tmp_path / "s.json"
    results.write_json(path, {"old": 1})

    def boom(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        results.write_json(path, {"new": 2})
    assert json.loads(path.read_text()) == {"old": 1}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]  # no temp leftovers


def test_checkpoint_resumes_without_loss_or_duplicates(tmp_path):
    path = tmp_path / "rows.jsonl"
    ck = results.Checkpoint(path, {"a": 1})
    ck.add("k1", {"x": 1.0})
    ck.add("k2", {"x": np.float64(2.0)})
    with open(path, "a") as f:
        f.write('{"key": "k3", "config_hash": "')  # a run killed mid-write
    ck2 = results.Checkpoint(path, {"a": 1})
    assert sorted(ck2.rows) == ["k1", "k2"] and "k3" not in ck2 and ck2.rows["k2"]["x"] == 2.0
    ck2.add("k3", {"x": 3.0})
    lines = path.read_text().splitlines()
    assert [json.loads(line)["key"] for line in lines] == ["k1", "k2", "k3"]  # torn line dropped
    # other settings: nothing is reused
    assert results.Checkpoint(path, {"a": 2}).rows == {}


def test_checkpoint_rows_of_other_code_are_recomputed_and_summaries_name_the_code(tmp_path, monkeypatch):
    path = tmp_path / "rows.jsonl"
    results.Checkpoint(path, {"a": 1}).add("k", {"x": 1})
    assert "k" in results.Checkpoint(path, {"a": 1})
    real = results.code_hash()
    assert len(real) == 16 and int(real, 16) >= 0
    monkeypatch.setattr(results, "code_hash", lambda n=16: "0" * n)  # the sources changed
    assert results.Checkpoint(path, {"a": 1}).rows == {}
    monkeypatch.undo()
    full = results.write_summary(tmp_path, "toy", {"seed": 3}, {"x": 1.0}, 0.5)
    assert full["code"]["hash"] == real and full["code"]["revision"]
    assert json.loads((tmp_path / "summary.json").read_text())["code"] == full["code"]


def test_code_hash_follows_the_sources(tmp_path, monkeypatch):
    # a copy of the package with one byte changed hashes differently; the same copy, the same
    import shutil
    from importlib.util import find_spec

    src = Path(find_spec("workbench").submodule_search_locations[0])
    skip = shutil.ignore_patterns("__pycache__")
    roots = {"workbench": shutil.copytree(src, tmp_path / "workbench", ignore=skip)}

    class _Spec:
        def __init__(self, root):
            self.submodule_search_locations = [str(root)]

    monkeypatch.setattr("importlib.util.find_spec", lambda name: _Spec(roots[name]))
    digest = results._sources_digest.__wrapped__()[:16]
    assert digest == results.code_hash()  # the copy is the running code
    f = roots["workbench"] / "fem" / "pad.py"
    text = f.read_text()
    # a comment, a blank line and a docstring edit are not code: the same digest
    f.write_text(text.replace('"""', '""" (edited)', 1) + "\n# a comment\n")
    assert results._sources_digest.__wrapped__()[:16] == digest
    f.write_text(text + "\n_A_NEW_CONSTANT = 1\n")  # a statement is
    assert results._sources_digest.__wrapped__()[:16] != digest


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o027, 0o640), (0o077, 0o600)])
def test_written_files_get_the_umask_mode(tmp_path, umask, mode):
    # mkstemp creates 0o600 and os.replace keeps it: results were unreadable to others
    old = os.umask(umask)
    try:
        paths = [
            results.write_json(tmp_path / "s.json", {"a": 1}),
            results.write_csv(tmp_path / "t.csv", ["x"], [[1]]),
            results.save_png(tmp_path / "f.png", b"\x89PNG"),
        ]
        results.Checkpoint(tmp_path / "rows.jsonl", {"a": 1}).add("k", {"x": 1})
        paths.append(tmp_path / "rows.jsonl")
    finally:
        os.umask(old)
    assert [p.stat().st_mode & 0o777 for p in paths] == [mode] * 4


def test_code_revision_is_dirty_for_code_changes_not_for_results(tmp_path):
    """A run writes its own tables into results/ before its summary: that read "-dirty" (the full
    fem-fitting summary of a clean checkout said so); only the code's paths count."""
    import shutil
    import subprocess

    if shutil.which("git") is None:
        pytest.skip("git not installed")
    git = ["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t"]
    (tmp_path / "workbench").mkdir()
    (tmp_path / "results").mkdir()
    (tmp_path / "workbench" / "x.py").write_text("a = 1\n")
    (tmp_path / "results" / "r.csv").write_text("1\n")
    subprocess.run([*git, "init", "-q"], check=True)
    subprocess.run([*git, "add", "-A"], check=True)
    subprocess.run([*git, "commit", "-qm", "c"], check=True)
    clean = results.code_revision(tmp_path)
    assert len(clean) == 12 and not clean.endswith("-dirty")
    (tmp_path / "results" / "r.csv").write_text("2\n")
    assert results.code_revision(tmp_path) == clean
    (tmp_path / "workbench" / "x.py").write_text("a = 2\n")
    assert results.code_revision(tmp_path) == clean + "-dirty"


def test_shared_cache_path_names_files_inside_the_cache_only(tmp_path, monkeypatch):
    """``kind`` names the file: anything but lower-case letters, digits and dashes is refused
    (``../x`` would have written outside the cache); the key is the content's, not its order's."""
    from workbench.runner.results import read_shared, shared_cache_path, write_shared

    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path))
    for bad in ("../evil", "a/b", "", "Rows", None):
        with pytest.raises(ValueError, match="lower-case letters, digits and dashes"):
            shared_cache_path(bad, {})
    p = shared_cache_path("wall-fem-rows", {"b": 1, "a": [1.0, 2.0]})
    assert p.parent == tmp_path and p == shared_cache_path("wall-fem-rows", {"a": [1.0, 2.0], "b": 1})
    write_shared(p, [{"k": 1.5}])
    assert read_shared(p) == [{"k": 1.5}]
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", "OFF")
    assert shared_cache_path("wall-fem-rows", {}) is None and read_shared(None) is None


def test_a_checkpoint_keyed_by_its_own_code_resumes_under_that_code_only(tmp_path):
    from workbench.runner.results import Checkpoint

    path = tmp_path / "rows.jsonl"
    ck = Checkpoint(path, {"a": 1}, code="engine-v1")
    ck.add("r1", {"x": 1.5})
    assert Checkpoint(path, {"a": 1}, code="engine-v1").rows["r1"]["x"] == 1.5
    assert Checkpoint.peek(path, {"a": 1}, code="engine-v2") == {}
    assert Checkpoint.peek(path, {"a": 1}) == {}  # the whole package's hash is another key


def test_sources_hash_follows_the_named_modules_code(tmp_path, monkeypatch):
    import importlib
    import sys

    from workbench.runner.results import sources_hash

    pkg = tmp_path / "hashme_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("X = 1\n")
    (tmp_path / "hashme_mod.py").write_text("Y = 2\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    importlib.invalidate_caches()
    h1 = sources_hash("hashme_pkg", "hashme_mod")
    assert h1 == sources_hash("hashme_mod", "hashme_pkg")  # order-free
    (pkg / "a.py").write_text('"""A docstring."""\n\nX = 1  # a comment\n')
    assert sources_hash("hashme_pkg", "hashme_mod") == h1  # not code
    (pkg / "a.py").write_text("X = 2\n")
    assert sources_hash("hashme_pkg", "hashme_mod") != h1
    assert sources_hash("hashme_mod") != sources_hash("hashme_pkg")
    with pytest.raises(ValueError, match="no module 'no_such_module_here'"):
        sources_hash("no_such_module_here")
    sys.modules.pop("hashme_pkg", None)


def test_checkpoint_rows_are_keyed_by_the_settings_in_force(tmp_path):
    # a row computed under another tolerance is another row; at the defaults the key is unchanged
    from workbench import config
    from workbench.runner.results import Checkpoint

    path = tmp_path / "rows.jsonl"
    Checkpoint(path, {"a": 1}, code="c").add("r", {"x": 1})
    with config.override(resist_rtol=config.TOL.resist_rtol / 10):
        assert Checkpoint.peek(path, {"a": 1}, code="c") == {}
        Checkpoint(path, {"a": 1}, code="c").add("r", {"x": 2})
        assert Checkpoint.peek(path, {"a": 1}, code="c")["r"]["x"] == 2


def test_write_parquet_keeps_each_columns_kind_and_nulls(tmp_path):
    import pandas as pd

    rows = [
        {"name": "a", "n": 1, "x": 1, "held": True, "p": [0.1, 0.2]},
        {"name": "b", "n": 2, "x": 2.5, "held": False, "p": [0.3, 0.4], "late": "z"},
        {"name": "c", "n": 3, "x": None, "held": True, "p": [0.5, 0.6], "mixed": 1},
    ]
    rows[0]["mixed"] = "one"
    path = results.write_parquet(tmp_path / "t.parquet", rows)
    t = pd.read_parquet(path)
    assert t["name"].tolist() == ["a", "b", "c"] and t["n"].tolist() == [1, 2, 3]
    assert str(t["n"].dtype) == "int64" and str(t["x"].dtype) == "float64"  # ints beside floats: float
    assert t["x"].tolist()[:2] == [1.0, 2.5] and np.isnan(t["x"].iloc[2])
    assert t["held"].tolist() == [True, False, True]
    assert [list(v) for v in t["p"]] == [[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]
    assert t["late"].isna().tolist() == [True, False, True] and t["late"][1] == "z"  # missing: null
    assert t["mixed"].isna().tolist() == [False, True, False]
    assert (t["mixed"][0], t["mixed"][2]) == ('"one"', "1")  # mixed kinds: JSON text
    assert [p.name for p in tmp_path.iterdir()] == ["t.parquet"]  # no temporary left
