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


def test_array_digest_is_the_sha256_of_shapes_bytes_and_tag():
    import hashlib

    import numpy as np

    from workbench.cachedir import array_digest

    a, b = np.arange(6.0).reshape(2, 3), np.arange(4)
    h = hashlib.sha256(b"(2, 3)" + a.tobytes() + b"(4,)" + b.tobytes() + b"v=1")
    assert array_digest((a, b), "v=1") == h.hexdigest()
    assert array_digest((a.reshape(3, 2), b), "v=1") != h.hexdigest()  # same bytes, other shape
    assert array_digest((a, b), "v=2") != h.hexdigest()
