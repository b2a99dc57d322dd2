"""Files written whole or not at all: a temporary sibling renamed over the target, with the
mode a plain ``open`` would give; and the ``.npz`` cache files of the pads and the ray casts,
whose loss or corruption only costs the recomputation.  No science and no run machinery: the
FEM, the limit-surface cache and the run machinery all write through here."""

from __future__ import annotations

import io
import logging
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

log = logging.getLogger(__name__)

__all__ = ["atomic_write_bytes", "current_umask", "read_cache_npz", "write_cache_npz"]


def current_umask() -> int:
    """The process umask, read afresh on every call (a program may change it).

    Linux reports it in ``/proc/self/status`` (a read, safe with threads).  POSIX
    has no other query than setting it and restoring it at once: a file another
    thread creates between the two calls gets the temporary mask, so it is
    0o077 (owner only — too strict at worst, never too open).
    """
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o077)
    os.umask(mask)
    return mask


def atomic_write_bytes(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary sibling and ``os.replace``.

    The file gets the mode a plain ``open(path, "wb")`` would give (0o666 minus
    the umask: 0o644 under umask 022), not mkstemp's owner-only 0o600, which
    ``os.replace`` would carry over and leave results unreadable to others.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~current_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def write_cache_npz(path: Path, **arrays: np.ndarray) -> bool:
    """Write ``arrays`` to the cache file ``path`` (``.npz``) atomically; ``False`` (logged) when
    the cache cannot be written — that only costs the recomputation next time."""
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    try:
        atomic_write_bytes(path, buf.getvalue())  # temp file + os.replace, 0o666 & ~umask
    except OSError as exc:
        log.warning("could not write the cache file %s (%s); continuing without it", path, exc)
        return False
    return True


def read_cache_npz(path: Path | None, check: Any, what: str, redo: str) -> dict[str, np.ndarray] | None:
    """The arrays of the cache file ``path`` (``.npz``, :func:`write_cache_npz`), or ``None`` when
    there is none — or when it cannot be read or ``check(arrays)`` raises (a truncated or foreign
    file): logged as "``what`` <path> unreadable (<why>); ``redo``", and the caller computes the
    result again and overwrites the file."""
    if path is None or not path.exists():
        return None
    try:
        with np.load(path) as d:
            arrays = {k: d[k] for k in d.files}
        check(arrays)
    except Exception as exc:  # noqa: BLE001 - any unreadable file only costs the recomputation
        log.warning("%s %s unreadable (%s); %s", what, path, exc, redo)
        return None
    return arrays
