"""workbench.atomic_io: the process umask (also without /proc) and the .npz cache files of the
pads and ray casts."""

import os

import numpy as np

from workbench import atomic_io


def test_umask_fallback_without_proc_restores_the_mask(monkeypatch):
    old = os.umask(0o027)
    try:

        def no_proc(*args, **kwargs):
            raise OSError("no /proc")

        monkeypatch.setattr(atomic_io, "open", no_proc, raising=False)  # shadows the builtin
        assert atomic_io.current_umask() == 0o027
        assert os.umask(0o027) == 0o027  # restored, not left at the probe value
    finally:
        os.umask(old)


def test_cache_npz_round_trip_and_an_unreadable_file_is_none(tmp_path, caplog):
    """write_cache_npz / read_cache_npz (the pad and ray caches' files): the arrays come back
    bit for bit; no cache, no file, a truncated file or one failing the caller's check read as
    None (the caller recomputes), the last two with one warning naming the file."""
    path = tmp_path / "x.npz"
    a = np.random.default_rng(0).standard_normal((3, 4))
    assert atomic_io.write_cache_npz(path, a=a, n=np.int64(7))
    got = atomic_io.read_cache_npz(path, lambda d: None, "test cache", "again")
    np.testing.assert_array_equal(got["a"], a)
    assert int(got["n"]) == 7
    assert atomic_io.read_cache_npz(None, lambda d: None, "test cache", "again") is None
    assert atomic_io.read_cache_npz(tmp_path / "none.npz", lambda d: None, "test cache", "again") is None

    def wrong_shape(d):
        raise ValueError(f"shape {d['a'].shape}")

    with caplog.at_level("WARNING"):
        assert atomic_io.read_cache_npz(path, wrong_shape, "test cache", "again") is None
        path.write_bytes(path.read_bytes()[:40])
        assert atomic_io.read_cache_npz(path, lambda d: None, "test cache", "again") is None
    assert caplog.text.count("test cache") == 2 and "shape (3, 4)" in caplog.text
