"""Atomic result writing and run metadata (CONVENTIONS.md "Experiments and results").

Every file is written to a temporary sibling and moved into place with
``os.replace``, so a killed run never leaves a half-written table.
"""

from __future__ import annotations

import csv
import io
import json
import logging
import os
import platform
from collections.abc import Iterable, Sequence
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic_io import atomic_write_bytes

log = logging.getLogger(__name__)

PACKAGES = (
    "numpy",
    "scipy",
    "numba",
    "scikit-fem",
    "meshio",
    "trimesh",
    "pyvista",
    "matplotlib",
    "cvxpy",
    "distributed",
    "pyarrow",
)


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, float) and not np.isfinite(obj):
        return None if np.isnan(obj) else ("inf" if obj > 0 else "-inf")
    return obj


def write_json(path: Path, obj: Any) -> Path:
    """Write ``obj`` as indented JSON atomically (NumPy types converted)."""
    text = json.dumps(_jsonable(obj), indent=2, sort_keys=False) + "\n"
    return atomic_write_bytes(path, text.encode())


def write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Path:
    """Write a CSV table atomically."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    for row in rows:
        writer.writerow([_jsonable(v) for v in row])
    return atomic_write_bytes(path, buf.getvalue().encode())


def write_parquet(path: Path, rows: Sequence[dict]) -> Path:
    """``rows`` (dicts; a key missing from a row is null there) as one Parquet table at ``path``,
    written atomically: a column of ints and floats is float, a column of mixed kinds JSON
    text, a column null in every row NaN (plottable)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns: dict[str, list] = {}
    for i, row in enumerate(rows):
        for k in row:
            columns.setdefault(k, [None] * i)
        for k, col in columns.items():
            col.append(row.get(k))
    arrays = {}
    for k, col in columns.items():
        kinds = {type(v) for v in col if v is not None}
        if not kinds:
            col = [float("nan")] * len(col)
        elif kinds <= {int, float} and float in kinds:
            col = [None if v is None else float(v) for v in col]
        elif len(kinds) > 1:
            col = [None if v is None else json.dumps(v) for v in col]
        arrays[k] = pa.array(col)
    sink = pa.BufferOutputStream()
    pq.write_table(pa.table(arrays), sink)
    return atomic_write_bytes(Path(path), sink.getvalue().to_pybytes())


def save_figure(fig: Any, path: Path, dpi: int = 130) -> Path:
    """Save a matplotlib figure atomically as PNG and close it."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def save_png(path: Path, data: bytes) -> Path:
    """Write the PNG image ``data`` (its bytes, e.g. a plotter's screenshot) to ``path``
    atomically."""
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise ValueError(f"data must be the PNG's bytes; got {type(data).__name__} {data!r:.40}")
    if not bytes(data[:4]) == b"\x89PNG":
        raise ValueError(f"data must be a PNG image (its bytes start with \\x89PNG); got {bytes(data[:8])!r}")
    return atomic_write_bytes(path, data)


def versions() -> dict[str, str]:
    """Python, platform and package versions for ``summary.json``."""
    out = {"python": platform.python_version(), "platform": platform.platform()}
    for pkg in PACKAGES:
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    try:
        out["workbench"] = metadata.version("nonplanar-workbench")
    except metadata.PackageNotFoundError:
        out["workbench"] = "source"
    return out


def content_hash(obj: Any, n: int = 16) -> str:
    """The first ``n`` hex digits of the SHA-256 of ``obj`` as sorted JSON (NumPy types
    converted): one key per content, for checkpoints, sweep points and caches."""
    import hashlib

    return hashlib.sha256(json.dumps(_jsonable(obj), sort_keys=True).encode()).hexdigest()[:n]


def code_hash(n: int = 16) -> str:
    """The first ``n`` hex digits of the SHA-256 of the running package's Python sources —
    ``workbench``, ``workbench.fem``, ``workbench.experiments``: each file's module path and
    normalised syntax (a comment, docstring or layout edit keeps it), the same in a checkout and
    in an installed wheel.  Keys checkpointed rows by default (:class:`Checkpoint`; experiments
    key theirs by :func:`workbench.code_key.code_digest` of what they import): rows computed by
    other code are recomputed, never reused."""
    return _sources_digest()[:n]


def _module_files(mod: str) -> list[tuple[str, Path]]:
    """``(name, path)`` of a module's Python sources, sorted by name: a package's every ``.py``
    under it (``mod:relative/path.py``), a plain module's own file (``mod``)."""
    from importlib.util import find_spec

    spec = find_spec(mod)
    if spec is None or not spec.submodule_search_locations and spec.origin is None:
        raise ValueError(f"sources_hash: no module {mod!r} to hash")
    if not spec.submodule_search_locations:
        return [(mod, Path(spec.origin))]
    root = Path(spec.submodule_search_locations[0])
    return sorted((f"{mod}:{f.relative_to(root).as_posix()}", f) for f in root.rglob("*.py"))


def _files_digest(files: list[tuple[str, Path]]) -> str:
    """SHA-256 hex digest of each file's name and the digest of its normalised syntax
    (:func:`workbench.code_key.normalized_digest`: comments, docstrings and layout left out), in
    the given order."""
    import hashlib

    from ..code_key import normalized_digest

    h = hashlib.sha256()
    for name, f in files:
        h.update(name.encode() + b"\0" + normalized_digest(f).encode() + b"\0")
    return h.hexdigest()


def sources_hash(*modules: str, n: int = 16) -> str:
    """The first ``n`` hex digits of the SHA-256 of the named modules' Python sources (a package:
    every ``.py`` file under it), each file's module path and normalised syntax: a narrower key than
    :func:`code_hash` for rows that only these modules can change (e.g. engine trials), so an
    edit elsewhere does not recompute them."""
    return _files_digest([f for mod in sorted(modules) for f in _module_files(mod)])[:n]


@lru_cache(maxsize=1)
def _sources_digest() -> str:
    """The full hex digest of :func:`code_hash`, read once per process."""
    return _files_digest(_module_files("workbench"))


#: the checkout's paths whose changes make a run's code differ from its revision (results/ does
#: not: a run writes its own tables there before its summary, which read "-dirty" for that)
CODE_PATHS = ("workbench", "benchmarks", "pyproject.toml")


#: the checkout the package runs from (an editable install: the repository, beside
#: ../shared/data; workbench/runner/ is two folders down)
CHECKOUT = Path(__file__).resolve().parents[2]


def code_revision(root: Path | None = None) -> str:
    """The code's revision: ``git describe --always --abbrev=12`` of the checkout the package
    runs from (``root``: another checkout), with ``-dirty`` when :data:`CODE_PATHS` hold
    uncommitted changes (results/ and the tests do not count), or, outside a git checkout,
    ``src-`` and :func:`code_hash`."""
    import subprocess

    root = CHECKOUT if root is None else Path(root)
    try:
        git = ["git", "-C", str(root)]
        res = subprocess.run(
            [*git, "describe", "--always", "--abbrev=12"], capture_output=True, text=True, timeout=10
        )
        if res.returncode == 0 and res.stdout.strip():
            st = subprocess.run(
                [*git, "status", "--porcelain", "--untracked-files=no", "--", *CODE_PATHS],
                capture_output=True,
                text=True,
                timeout=10,
            )
            dirty = st.returncode != 0 or bool(st.stdout.strip())
            return res.stdout.strip() + ("-dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        pass
    return "src-" + code_hash(12)


def write_summary(out: Path, experiment: str, config: dict, summary: dict, wall_time_s: float) -> dict:
    """Add the run's metadata (config, seed, the tolerances and defaults set away from their
    defaults — :func:`workbench.config.changed`, absent when none is —, versions, the code that
    ran: its git revision with a ``-dirty`` flag and :func:`code_hash`, wall time) and write
    ``out/summary.json`` atomically; returns the full summary."""
    from .. import config as _config

    full = {"experiment": experiment, **summary}
    full["config"] = config
    settings = _config.changed(numbers_only=True)
    if settings:
        full["settings"] = settings
    full["seed"] = config.get("seed")
    full["versions"] = versions()
    full["code"] = {"revision": code_revision(), "hash": code_hash()}
    full["wall_time_s"] = wall_time_s
    write_json(Path(out) / "summary.json", full)
    return full


def shared_cache_path(kind: str, inputs: Any) -> Path | None:
    """``<cache>/<kind>-<hash>.json`` for a result shared by runs on this machine (two
    experiments, every point of a sweep), keyed by the content hash of ``inputs`` (JSON-able:
    every input the result depends on) and of the code (:func:`code_hash`, so other code never
    reuses it); ``None`` when the cache is off.  ``<cache>`` is the pads' folder
    (``$WORKBENCH_CACHE_DIR``, :func:`workbench.cachedir.cache_dir`).  ``kind`` : lower-case
    letters, digits and dashes (it names the file)."""
    import re

    from workbench.cachedir import cache_dir

    if not (isinstance(kind, str) and re.fullmatch(r"[a-z0-9][a-z0-9-]*", kind)):
        raise ValueError(f"kind names the cache file: lower-case letters, digits and dashes; got {kind!r}")
    folder = cache_dir()
    if folder is None:
        return None
    return folder / f"{kind}-{content_hash({'inputs': inputs, 'code': code_hash()}, 24)}.json"


def read_shared(path: Path | None) -> Any:
    """What :func:`write_shared` stored at ``path`` as JSON reads it back (NaN as ``None``, ±inf
    as ``"inf"``/``"-inf"``, as in checkpoints), or ``None`` (no cache, no file, or an unreadable
    one: logged, the caller computes it again)."""
    if path is None or not path.is_file():
        return None
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        log.warning("shared result %s unreadable (%s); computing it again", path, exc)
        return None


def write_shared(path: Path | None, obj: Any) -> None:
    """Store ``obj`` at ``path`` atomically as JSON (NumPy types converted; anything else not
    JSON-able raises ``TypeError``) — concurrent writers of one key write the same content, the
    last rename wins; a cache that cannot be written (``OSError``) is logged and only costs the
    recomputation next time."""
    if path is None:
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(path, json.dumps(_jsonable(obj)).encode())
    except OSError as exc:
        log.warning("could not write the shared result %s (%s); continuing without it", path, exc)


class Checkpoint:
    """Append-only JSON-lines log of finished rows of a long sweep, for resuming.

    Each row carries a ``key``; a row is appended (flushed and fsynced) only
    when complete, so a killed run loses at most the row in progress and a
    torn last line is ignored on reload.  Rows are kept only if their
    ``config_hash`` matches — a hash of ``config`` and of the code (:func:`code_hash`, or
    ``code``: a narrower digest such as :func:`sources_hash` of what the rows depend on) — so
    changing the sweep's settings or the code that computes its rows starts afresh instead of
    mixing results.  Resuming never duplicates a key.  ``keep_other=True`` keeps the other
    rows in the file as history (a sweep's ``points.jsonl``: every point ever finished),
    never resumed; otherwise they are dropped.
    """

    def __init__(
        self, path: Path, config: dict, *, keep_other: bool = False, code: str | None = None
    ) -> None:
        self.path = Path(path)
        self.config_hash = Checkpoint._config_hash(config, code)
        self.rows: dict[str, dict] = Checkpoint.peek(self.path, config, code=code)
        if self.rows:
            log.info("%s: %d rows resumed (same config and code)", self.path, len(self.rows))
        # rewrite only the whole rows (all of them, or the valid ones), so a torn line never
        # precedes new ones
        kept = Checkpoint.history(self.path) if keep_other else list(self.rows.values())
        self.path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(self.path, "".join(json.dumps(r) + "\n" for r in kept).encode())

    @staticmethod
    def history(path: Path) -> list[dict]:
        """Every whole row of the file at ``path``, in order, whatever its config and code
        (a torn line is left out); ``[]`` for no file."""
        rows = []
        if Path(path).is_file():
            for line in Path(path).read_text().splitlines():
                try:
                    row = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if isinstance(row, dict) and "key" in row:
                    rows.append(row)
        return rows

    @staticmethod
    def _config_hash(config: dict, code: str | None) -> str:
        """The rows' key: ``config``, ``code`` (default: the whole package's :func:`code_hash`) and
        the tolerances and defaults set away from their defaults (:func:`workbench.config.changed`:
        a row computed under another ``resist_rtol`` is another row; the run settings, which change
        no number, are not in it)."""
        from .. import config as _config

        key = {"config": config, "code": code_hash() if code is None else code}
        settings = _config.changed(numbers_only=True)
        if settings:  # absent at the defaults: their rows keep the keys they had
            key["settings"] = settings
        return content_hash(key)

    @staticmethod
    def peek(path: Path, config: dict, *, code: str | None = None) -> dict[str, dict]:
        """The rows a ``Checkpoint(path, config, code=code)`` would resume, read without writing
        anything (no file or directory is created)."""
        config_hash = Checkpoint._config_hash(config, code)
        # a torn last line of a killed run is left out; the last row of a key wins
        return {r["key"]: r for r in Checkpoint.history(path) if r.get("config_hash") == config_hash}

    def __contains__(self, key: str) -> bool:
        return key in self.rows

    def add(self, key: str, row: dict) -> None:
        row = {"key": key, "config_hash": self.config_hash, **_jsonable(row)}
        with open(self.path, "a") as f:
            f.write(json.dumps(row) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.rows[key] = row
