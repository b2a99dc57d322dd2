"""Physical grasp trials in the REACH format (Danielczuk et al., ISRR 2019; packaged: the 3 cm cube).

A trial file is a JSON list of dicts, one per physical trial, with keys ``obj`` (object name),
``attempt`` (the grasp index), ``trial`` (the repeat), ``pose`` (4×4, the object in the world),
``grasp`` (4×4, the gripper base frame in the world: x the jaw axis, z the approach),
``result`` (bool, the grasp held) and ``stable_pose`` (the object's resting-pose index); ``tf``
and the ``qs_*`` columns are ignored (README of the data: ``qs_*`` copy ``result``).

What was checked on the data: ``attempt`` is the grasp index and ``trial`` the repeat (the
publishing code reads trial ``5 · grasp``; the five trials of one attempt share one gripper pose
in the object frame, to 0.0); the world's z is up (every ``down`` lies along a cube axis).  Every
``pose`` rotation of the cube file has one entry 0.01 where a rotation has 0 (``max |RᵀR − I|``
= 0.010): such rotations, off by at most ``repair_atol``, are made orthonormal with a logged warning,
keeping their world-z row (the object's up, which sets its resting face and ``down``) and
orthogonalising the y and x rows — for the cube this sets the stray 0.01 to 0 — which moves the
tooltips in the object frame by < 0.3 mm against the inverse of the sheared pose.
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..units import check_rigid
from .gripper import DATA_DIR

__all__ = [
    "REACH_MASS_KG",
    "TrialGrasp",
    "Trials",
    "default_mesh_path",
    "default_trials_path",
    "read_trials",
]

log = logging.getLogger(__name__)

#: files whose repaired rotations this process has warned about
_REPAIRED_WARNED: set[str] = set()

#: object masses [kg] of the REACH trials (the table of ``tools/grasping/phys_grasp_ipc.py`` in
#: BerkeleyAutomation/ipc-graspsim, grams there)
REACH_MASS_KG = {
    name: grams / 1000
    for name, grams in {
        "bar_clamp": 18.5, "book": 34.8, "bowl": 15.7, "cat": 9.9, "cube_3cm": 3.0, "endstop_holder": 16.3,
        "engine_part": 28.6, "fan_extruder": 7.4, "gearbox": 7.4, "large_marker": 3.2, "mount1": 10.4,
        "mug": 20.2, "nozzle": 6.3, "part1": 6.8, "part3": 13.6, "pawn": 18.6, "pear": 6.5,
        "pipe_connector": 23.5, "sardines": 11.2, "sulfur_neutron": 7.0, "vase": 13.1, "yoda": 20.4,
    }.items()
}  # fmt: skip

_KEYS = ("obj", "attempt", "trial", "pose", "grasp", "result", "stable_pose")
# the trials of one grasp must share one gripper pose to this (metres, and rotation entries)
_SAME_POSE_ATOL = 1e-6


def default_trials_path() -> Path:
    """The packaged trials of the 3 cm cube (``cube_3cm.json``, 125 trials, MIT)."""
    return DATA_DIR / "cube_3cm.json"


def default_mesh_path() -> Path:
    """The packaged 3 cm cube (``cube_3cm.obj``, metres, ±0.015)."""
    return DATA_DIR / "cube_3cm.obj"


@dataclass(frozen=True)
class TrialGrasp:
    """One grasp of a trial file and its outcomes.

    index : the grasp index (``attempt``).
    pose : (4, 4) the gripper frame in the object frame [m].
    down : (3,) unit, gravity's direction in the object frame.
    outcomes : one bool per repeat, in repeat order (True: the grasp held).
    """

    index: int
    pose: np.ndarray
    down: np.ndarray
    outcomes: tuple[bool, ...]

    @property
    def success_rate(self) -> float:
        """Fraction of the repeats that held."""
        return sum(self.outcomes) / len(self.outcomes)


@dataclass(frozen=True)
class Trials:
    """Physical grasp trials of one object (arrays read-only; n trials).

    obj : the object's name.
    grasp_index : (n,) int, the grasp (``attempt``).
    repeat : (n,) int, the repeat of that grasp (``trial``).
    gripper_pose : (n, 4, 4) the gripper frame in the object frame, ``inv(pose) @ grasp`` [m].
    down : (n, 3) unit, gravity (the world's −z) in the object frame.
    success : (n,) bool, the outcome.
    stable_pose : (n,) int, the object's resting-pose index.
    object_pose : (n, 4, 4) the object in the world as used (rotation made orthonormal) [m].
    pose_spread : the largest difference between the gripper poses of one grasp's trials.
    """

    obj: str
    grasp_index: np.ndarray
    repeat: np.ndarray
    gripper_pose: np.ndarray
    down: np.ndarray
    success: np.ndarray
    stable_pose: np.ndarray
    object_pose: np.ndarray
    pose_spread: float

    def __post_init__(self):
        for name in (
            "grasp_index",
            "repeat",
            "gripper_pose",
            "down",
            "success",
            "stable_pose",
            "object_pose",
        ):
            arr = np.array(getattr(self, name))
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return len(self.success)

    @property
    def mass(self) -> float | None:
        """The object's mass [kg] if it is one of REACH's objects (:data:`REACH_MASS_KG`), else None."""
        return REACH_MASS_KG.get(self.obj)

    def grasps(self) -> dict[int, TrialGrasp]:
        """{grasp index: :class:`TrialGrasp`} in index order; the pose and ``down`` are those of the
        grasp's first trial (its trials share them to :attr:`pose_spread`)."""
        out = {}
        for g in np.unique(self.grasp_index):
            rows = np.flatnonzero(self.grasp_index == g)
            rows = rows[np.argsort(self.repeat[rows], kind="stable")]
            out[int(g)] = TrialGrasp(
                int(g),
                self.gripper_pose[rows[0]],
                self.down[rows[0]],
                tuple(bool(s) for s in self.success[rows]),
            )
        return out


def _rigid(T, what: str, repair_atol: float, repaired: list[float]) -> np.ndarray:
    """``T`` checked rigid; a rotation off by at most ``repair_atol`` made orthonormal (module docstring)."""
    try:
        return check_rigid(T, what)
    except ValueError as err:
        T = np.array(T, dtype=float)
        if T.shape != (4, 4) or not np.isfinite(T).all() or not np.allclose(T[3], [0, 0, 0, 1]):
            raise
        R = T[:3, :3]
        off = float(np.abs(R.T @ R - np.eye(3)).max())
        if "not rigid" not in str(err) or off > repair_atol:
            raise
        # rows from the last: the world's z row (the object's up, its resting face) is kept
        z = R[2] / np.linalg.norm(R[2])
        y = R[1] - (R[1] @ z) * z
        y /= np.linalg.norm(y)
        T[:3, :3] = np.array([np.cross(y, z), y, z])  # a rotation unless R was a reflection (checked)
        repaired.append(off)
        return check_rigid(T, what)


def _as_int(value, key: str, i: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"trial {i}: '{key}' must be an integer; got {value!r}")
    return value


def read_trials(path, *, repair_atol: float = 0.02) -> Trials:
    """The trials of a REACH-format JSON file (module docstring), e.g. :func:`default_trials_path`.

    repair_atol : a ``pose`` or ``grasp`` rotation with ``max |RᵀR − I|`` up to this is made
        orthonormal keeping its world-z row (logged as a warning); beyond it, ValueError.

    Raises ValueError for a missing file, one that is not JSON text (a mesh given by mistake), a
    missing key, a pose that is not 4×4 or not rigid, a non-boolean ``result`` or several objects
    in one file.  Logs a warning if the trials are not listed in blocks of one grasp's repeats or
    one grasp's gripper poses differ.
    """
    path = Path(path)
    rows = _load_rows(path)
    objs, grasp, rep, success, stable, P, G = [], [], [], [], [], [], []
    repaired: list[float] = []
    for i, row in enumerate(rows):
        _check_row(row, i, path)
        objs.append(str(row["obj"]))
        grasp.append(_as_int(row["attempt"], "attempt", i))
        rep.append(_as_int(row["trial"], "trial", i))
        stable.append(_as_int(row["stable_pose"], "stable_pose", i))
        success.append(row["result"])
        P.append(_rigid(row["pose"], f"trial {i}: 'pose' (the object in the world)", repair_atol, repaired))
        G.append(
            _rigid(row["grasp"], f"trial {i}: 'grasp' (the gripper in the world)", repair_atol, repaired)
        )
    if len(set(objs)) != 1:
        raise ValueError(f"{path}: one object per trial file; got {sorted(set(objs))}")
    if repaired:
        _log_repaired(path, repaired)
    P, G = np.array(P), np.array(G)
    grasp_index, repeat = np.array(grasp), np.array(rep)
    _check_blocks(grasp_index, repeat, path)
    gripper_pose = np.linalg.inv(P) @ G
    down = -P[:, 2, :3]  # R.T @ (0, 0, -1)
    spread = 0.0
    for g in np.unique(grasp_index):
        blk = gripper_pose[grasp_index == g]
        spread = max(spread, float(np.abs(blk - blk[0]).max()))
    if spread > _SAME_POSE_ATOL:
        log.warning(
            "%s: the trials of one grasp have gripper poses differing by up to %.3g: is 'attempt' the grasp "
            "index here? grasps() uses each grasp's first trial",
            path.name,
            spread,
        )
    return Trials(
        objs[0], grasp_index, repeat, gripper_pose, down, np.array(success, bool), np.array(stable), P, spread
    )


def _load_rows(path: Path) -> list:
    """The non-empty JSON list of a trial file, or ValueError (no file, not JSON text)."""
    if not path.is_file():
        raise ValueError(f"no such trial file: {path}")
    try:
        with path.open(encoding="utf-8") as f:
            rows = json.load(f)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        got = (
            "a binary file (not UTF-8 text: a mesh or an archive?)"
            if isinstance(exc, UnicodeDecodeError)
            else f"text that is not JSON ({exc.msg} at line {exc.lineno}, column {exc.colno}; truncated?)"
        )
        raise ValueError(
            f"{path} is not a trial file: expected the REACH format, a JSON list of trials (dicts with "
            f"keys {list(_KEYS)}; e.g. default_trials_path()); got {got} — pass the trials' .json file "
            "(the object's mesh goes to trimesh.load)"
        ) from None
    if not isinstance(rows, list) or not rows:
        raise ValueError(f"{path}: expected a non-empty JSON list of trials (dicts with keys {list(_KEYS)})")
    return rows


def _check_row(row, i: int, path: Path) -> None:
    """ValueError unless trial ``i`` is a dict with the REACH format's keys and a boolean result."""
    if not isinstance(row, dict):
        raise ValueError(f"{path}: trial {i} is a {type(row).__name__}, not a dict with keys {list(_KEYS)}")
    missing = [k for k in _KEYS if k not in row]
    if missing:
        raise ValueError(
            f"{path}: trial {i} lacks {missing} (it has {sorted(row)}); the REACH format needs {list(_KEYS)}"
        )
    if not isinstance(row["result"], bool):
        raise ValueError(f"trial {i}: 'result' must be true or false; got {row['result']!r}")


def _log_repaired(path: Path, repaired: list[float]) -> None:
    """Log the rotations made orthonormal (their ``max |RᵀR − I|`` in ``repaired``): a warning the
    first time a process reads the file (a sweep's every point reads it again), else info."""
    level = logging.INFO if str(path.resolve()) in _REPAIRED_WARNED else logging.WARNING
    _REPAIRED_WARNED.add(str(path.resolve()))
    log.log(
        level,
        "%s: %d pose/grasp rotations were not orthonormal (max |RᵀR − I| up to %.3g) and were made "
        "orthonormal keeping their world-z rows",
        path.name,
        len(repaired),
        max(repaired),
    )


def _check_blocks(grasp_index: np.ndarray, repeat: np.ndarray, path: Path) -> None:
    """Warn unless the rows are grasp 0's repeats 0..r-1, then grasp 1's, … (REACH's reader takes
    trial ``r · grasp`` as the grasp's), and unless each (grasp, repeat) occurs once."""
    n = len(grasp_index)
    r = int(repeat.max()) + 1
    i = np.arange(n)
    if n % r or not (np.array_equal(grasp_index, i // r) and np.array_equal(repeat, i % r)):
        log.warning(
            "%s: the trials are not listed in blocks of %d repeats per grasp ('attempt' 0, 0, …, 1, …; "
            "'trial' 0..%d): REACH's code reads trial %d·grasp as the grasp; 'attempt' is used as the "
            "grasp index",
            path.name,
            r,
            r - 1,
            r,
        )
    pairs = grasp_index * (r + 1) + repeat
    if len(np.unique(pairs)) != n:
        log.warning("%s: some (attempt, trial) pairs occur more than once", path.name)
