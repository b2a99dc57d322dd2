"""The workbench's on-machine cache folder: condensed pads (:mod:`workbench.fem.pad`), an object
mesh's ray hits (:mod:`workbench.fem.mesh_wall`) and results shared by runs
(:func:`workbench.runner.results.shared_cache_path`).  A module of its own so that the results module and
the FEM modules can both reach it without importing each other."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

#: environment variable overriding the default cache directory
CACHE_ENV = "WORKBENCH_CACHE_DIR"
_APP = "nonplanar-workbench"
#: values of ``$WORKBENCH_CACHE_DIR`` (any case) that turn the cache off
OFF = frozenset({"0", "off", "false", "no"})


def cache_dir(cache_dir: str | Path | bool | None = None) -> Path | None:
    """The cache directory, or ``None`` when caching is off.

    cache_dir : ``None`` (or ``True``) -> ``$WORKBENCH_CACHE_DIR`` if set and non-empty
        (``0``/``off``/``false``/``no``, any case, disable the cache), else
        ``<user cache dir>/pads`` (the pads' folder, where it began); a path -> that directory;
        ``False`` -> no cache.
    """
    if cache_dir is False:
        return None
    if cache_dir is True or cache_dir is None:
        env = os.environ.get(CACHE_ENV, "").strip()
        if env:
            if env.lower() in OFF:
                return None
            return Path(env).expanduser()
        return _user_cache_root() / "pads"
    if isinstance(cache_dir, (str, os.PathLike)):
        return Path(cache_dir).expanduser()
    raise ValueError(
        f"cache_dir must be None (default location), a directory path or False (no cache); got {cache_dir!r}"
    )


def _user_cache_root() -> Path:
    import platformdirs

    return Path(platformdirs.user_cache_dir(_APP, appauthor=False))


def array_digest(arrays: Iterable[np.ndarray], tag: str) -> str:
    """SHA-256 hex digest of arrays (each's shape, then its bytes as given: the caller fixes the
    dtype and C order) and a ``tag`` of the settings: the content key of a cache file."""
    h = hashlib.sha256()
    for arr in arrays:
        h.update(str(arr.shape).encode())
        h.update(arr.tobytes())
    h.update(tag.encode())
    return h.hexdigest()
