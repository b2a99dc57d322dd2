"""Atomic result writing: a failed write leaves the previous file intact and no debris."""

import json
import os

import numpy as np
import pytest

from workbench import results


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


def test_umask_fallback_without_proc_restores_the_mask(monkeypatch):
    old = os.umask(0o027)
    try:

        def no_proc(*args, **kwargs):
            raise OSError("no /proc")

        monkeypatch.setattr(results, "open", no_proc, raising=False)  # shadows the builtin
        assert results.current_umask() == 0o027
        assert os.umask(0o027) == 0o027  # restored, not left at the probe value
    finally:
        os.umask(old)
