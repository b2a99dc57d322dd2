"""workbench.cachedir: where the pads, ray hits and shared results live, and how to turn it off."""

from pathlib import Path

import pytest

from workbench.cachedir import cache_dir


def test_the_environment_chooses_the_folder_or_turns_it_off(tmp_path, monkeypatch):
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "c"))
    assert cache_dir() == tmp_path / "c" and cache_dir(True) == tmp_path / "c"
    for off in ("0", "off", "OFF", "False", "no"):
        monkeypatch.setenv("WORKBENCH_CACHE_DIR", off)
        assert cache_dir() is None
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", "  ")  # empty: the user cache folder's pads/
    default = cache_dir()
    assert default.name == "pads" and "nonplanar-workbench" in str(default)
    assert cache_dir(tmp_path / "x") == tmp_path / "x" and cache_dir(False) is None
    assert cache_dir("~/y") == Path.home() / "y"
    with pytest.raises(ValueError, match="cache_dir must be None"):
        cache_dir(3)
