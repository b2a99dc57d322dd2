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
