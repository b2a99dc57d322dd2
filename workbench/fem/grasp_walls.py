"""The walls of the measured hollow objects at their grasps (thesis §4.3, §4.3.5).

The minimal-work experiment asks a measured object's thin wall three things, each here as a
function of plain arguments (a driver runs them as Dask tasks):

* :func:`wall_stiffness`: the linear wall's stiffness at a chunk of grasps
  (:func:`workbench.fem.wall_grasps.stiffness_at`), the wall assembled and factorised once per
  process (:func:`linear_wall`: the sparse factor does not pickle);
* :func:`calibrated_wall`: one scalar (an effective Young's modulus at fixed thickness: ``s ∝ E``
  exactly) calibrated on a random half of the measured grasps and scored on the other half
  (:func:`workbench.fem.calibration.one_factor_validation`), with what it leaves unexplained
  (:func:`workbench.fem.calibration.missing_physics`); :func:`series_compliance` bounds the
  gripper's own compliance over all objects;
* :func:`load_curve`: the geometrically nonlinear wall's force–closing curve at one grasp
  (:func:`workbench.fem.wall_nonlinear.squeeze_nonlinear`), and :func:`pose_work` the elastic
  work ``Σ_i ∫ f dΔ`` along it at a grasp's minimal jaw forces (Eq. 4.5 from a curve).

The objects' files are read by path (:func:`object_files`, :func:`load_mesh`, once per process).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from workbench import config as settings

log = logging.getLogger(__name__)

__all__ = [
    "NonlinearWallSettings",
    "WallSettings",
    "calibrated_stiffness",
    "calibrated_wall",
    "linear_wall",
    "load_curve",
    "load_mesh",
    "mesh_digest",
    "object_files",
    "pose_work",
    "series_compliance",
    "wall_geometry_of",
    "wall_stiffness",
]


@dataclass(frozen=True)
class WallSettings:
    """The linear wall of an object: Young's modulus ``E`` [Pa] before calibration, Poisson
    ratio ``nu``, ``thickness`` [m], ``mesh`` (hexes around, along the height) and the jaw pad
    ``jaw`` (width, length) [m] that squeezes it."""

    E: float
    nu: float
    thickness: float
    mesh: tuple[int, int]
    jaw: tuple[float, float]

    @classmethod
    def from_config(cls, config: Mapping) -> WallSettings:
        """From a run's settings of the same names (``E``, ``nu``, ``thickness``, ``mesh``, ``jaw``)."""
        nt, nz = config["mesh"]
        return cls(
            float(config["E"]),
            float(config["nu"]),
            float(config["thickness"]),
            (nt, nz),
            tuple(config["jaw"]),
        )


@dataclass(frozen=True)
class NonlinearWallSettings:
    """The St. Venant–Kirchhoff wall of :func:`load_curve`: ``E`` [Pa] before calibration,
    ``nu``, ``thickness`` [m], ``mesh`` (hexes around, along), the load stepping's closing
    increment ``step`` [m] and last closing ``max_closing`` [m], the jaw pad ``jaw`` [m]."""

    E: float
    nu: float
    thickness: float
    mesh: tuple[int, int]
    step: float
    max_closing: float
    jaw: tuple[float, float]

    @classmethod
    def from_config(cls, config: Mapping) -> NonlinearWallSettings:
        """From a run's settings (``E``, ``nu``, ``thickness``, ``nl_mesh``, ``nl_step_mm``,
        ``nl_max_closing_mm``, ``jaw``)."""
        return cls(
            config["E"],
            config["nu"],
            float(config["thickness"]),
            tuple(config["nl_mesh"]),
            config["nl_step_mm"] * 1e-3,
            config["nl_max_closing_mm"] * 1e-3,
            tuple(config["jaw"]),
        )


def object_files(data_dir: str | Path, name: str) -> tuple[Path, Path]:
    """(mesh ``meshes/<name>.obj``, measured map ``stiffness_maps/<name>.json``) of object
    ``name`` in the ``deformable_objects`` folder ``data_dir``; ``ValueError`` when either is missing."""
    d = Path(data_dir)
    mesh, smap = d / "meshes" / f"{name}.obj", d / "stiffness_maps" / f"{name}.json"
    if not mesh.exists() or not smap.exists():
        raise ValueError(
            f"{name}: {mesh} or {smap} not found — set data_dir to the deformable_objects folder "
            "(meshes/ and stiffness_maps/, CC BY-NC 4.0, read by path)"
        )
    return mesh, smap


@lru_cache(maxsize=8)
def load_mesh(path: str):
    """The object's mesh (``trimesh.Trimesh``), read once per process (driver and each worker)."""
    import trimesh

    return trimesh.load(path, force="mesh")


@lru_cache(maxsize=8)
def mesh_digest(path: str) -> str:
    """SHA-256 of the mesh file's bytes (the key of results computed from it)."""
    import hashlib

    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@lru_cache(maxsize=4)
def wall_geometry_of(path: str, thickness: float, n_z: int):
    """The wall geometry (ray casting, :func:`workbench.fem.object_wall.wall_geometry`) of the
    mesh at ``path``, once per process."""
    from .object_wall import wall_geometry

    return wall_geometry(load_mesh(path), thickness=thickness, n_z=n_z)


@lru_cache(maxsize=4)
def _object_wall(path: str, E: float, nu: float, thickness: float, n_theta: int, n_z: int):
    """The object's linear wall, assembled and factorised once per process (seconds; it
    cannot be sent to a worker: the sparse factor does not pickle)."""
    from .material import Material
    from .object_wall import object_wall

    return object_wall(load_mesh(path), Material(E, nu), thickness=thickness, n_theta=n_theta, n_z=n_z)


def linear_wall(path: str, wall: WallSettings):
    """(geometry, wall) of :func:`workbench.fem.object_wall.object_wall` for the mesh at
    ``path`` at the ``wall`` settings, once per process and settings."""
    nt, nz = wall.mesh
    return _object_wall(path, wall.E, wall.nu, wall.thickness, nt, nz)


def wall_stiffness(path: str, wall: WallSettings, P: np.ndarray, grasp_ids: list[int]) -> list[dict]:
    """The linear wall's stiffness at m grasps of the mesh at ``path``: ``P`` (2m, 3) [m] the
    first jaws' points, then the second jaws'; one row of
    :func:`workbench.fem.wall_grasps.stiffness_at` per grasp (numbered ``grasp_ids``)."""
    from .wall_grasps import stiffness_at

    geo, w = linear_wall(path, wall)
    return stiffness_at(w, geo, P, jaw=wall.jaw, grasp_ids=list(grasp_ids))


def calibrated_stiffness(row: Mapping, scale: float) -> float:
    """A grasp's calibrated wall stiffness [N/m] from its row of :func:`wall_stiffness` (before
    calibration) and the object's factor ``scale``: inf where the wall is rigid there or the
    squeeze failed."""
    return np.inf if row["rigid"] or row["failed"] else row["stiffness"] * scale


def _num(x) -> float:
    return float("nan") if x is None else float(x)


def calibrated_wall(
    fem_rows: list[dict],
    L: np.ndarray,
    measured: np.ndarray,
    rng: np.random.Generator,
    path: str,
    wall: WallSettings,
    force: float,
) -> tuple[dict, dict]:
    """One object's wall calibrated by one factor: from the FEM at its measured grasps
    (``fem_rows``, one per grasp, :func:`wall_stiffness`; the grasps ``L`` (2n, 3) [m] and
    their ``measured`` stiffness (n,) [N/m] of the map file), the factor calibrated on a random
    half (drawn from ``rng``) and scored on the other, and what the factor leaves (series
    compliance, large deflection, the clamps; ``force`` [N] the measurements' target force,
    §4.3.3.1).  ``path`` : the object's mesh file.  Returns the validation summary and the
    stiffness figures' data (``L``, ``measured``, ``predicted`` (n,), ``train``, ``test``)."""
    from .calibration import missing_physics, one_factor_validation

    fem = np.array([_num(r["stiffness"]) for r in fem_rows])
    n_g = len(fem)
    z_mid = 0.5 * (L[:n_g, 2] + L[n_g:, 2])
    validation, train, test = one_factor_validation(fem, measured, rng, heights=z_mid, E=wall.E)
    geo = wall_geometry_of(str(path), wall.thickness, wall.mesh[1])
    z_lo, z_hi = geo.z_range
    validation["missing_physics"] = missing_physics(
        fem,
        measured,
        width=np.linalg.norm(L[n_g:] - L[:n_g], axis=1),
        clamp_distance=np.minimum(z_mid - z_lo, z_hi - z_mid if geo.clamp_top else np.inf),
        force=force,
    )
    scale = validation["calibrated"]["scale"]
    rigid = settings.TOL.rigid_stiffness_threshold
    predicted = np.where(fem < rigid, fem * scale, np.inf)  # rigid stays rigid
    return validation, {"L": L, "measured": measured, "predicted": predicted, "train": train, "test": test}


def series_compliance(validation: Mapping, predicted: Mapping) -> dict:
    """One gripper measured every object: the tightest bound on its series compliance (pads,
    fingers) [m/N] holds for all, and the most it lowers each object's median calibrated
    stiffness.  ``validation`` {object: :func:`calibrated_wall` summary}, ``predicted``
    {object: (n,) calibrated stiffness [N/m]}."""
    key = "series_compliance_bound_m_per_N"
    tight = min(validation, key=lambda n: validation[n]["missing_physics"][key])
    c_max = validation[tight]["missing_physics"][key]
    series = {"bound_m_per_N": c_max, "from_object": tight, "effect_at_median": {}}
    for n in validation:
        p = np.asarray(predicted[n])
        series["effect_at_median"][n] = 1.0 - 1.0 / (1.0 + float(np.median(p[np.isfinite(p)])) * c_max)
    return series


def load_curve(
    path: str, g: Mapping, scale: float, force: float, nl: NonlinearWallSettings, label: str = ""
) -> dict:
    """The nonlinear wall's force–closing curve at grasp ``g`` (``p1``, ``p2`` [m]) of the mesh
    at ``path``, at the linear model's calibrated modulus ``nl.E * scale``, up to the jaw force
    ``force`` [N]: ``{"curve": {"closing": (k,) [m], "jaw_forces": (k, 2) [N]}, "on_clamp",
    "seconds"}``, or ``curve`` None with the ``error`` when the squeeze refuses the grasp
    (logged with ``label``)."""
    from .material import Material
    from .wall_nonlinear import grasp_frame_wall, squeeze_nonlinear

    geo = wall_geometry_of(str(path), nl.thickness, nl.mesh[1])
    mat = Material(nl.E * scale, nl.nu)  # the linear model's calibrated E
    t0 = time.perf_counter()
    try:
        wall, centre = grasp_frame_wall(geo, mat, g["p1"], g["p2"], n_theta=nl.mesh[0])
        res = squeeze_nonlinear(
            wall, centre, force=force, step=nl.step, max_closing=nl.max_closing, jaw=nl.jaw
        )
    except ValueError as e:  # e.g. no wall under a jaw: recorded, not hidden
        log.warning("nonlinear work %s: %s", label, e)
        return {"curve": None, "error": str(e)}
    return {
        "curve": {"closing": res.closing.tolist(), "jaw_forces": res.jaw_forces.tolist()},
        "on_clamp": res.on_clamp,
        "seconds": time.perf_counter() - t0,
    }


def pose_work(entry: Mapping, poses: list[np.ndarray]) -> float:
    """The work ``max over poses Σ_i ∫ f dΔ`` [J] along a :func:`load_curve` ``entry`` (with
    a ``curve``) at each pose's jaw forces (``poses``: (2,) [N] each, none NaN)
    (:func:`workbench.fem.wall_nonlinear.curve_work`); inf when a force lies past the curve's
    end (its largest closing: predicted to fail, like an unresisted pose)."""
    from .wall_nonlinear import curve_work

    cv = entry["curve"]
    w = [curve_work(cv["closing"], cv["jaw_forces"], p, rigid_beyond=entry["on_clamp"])[0] for p in poses]
    sums = np.array([x.sum() for x in w])
    return np.inf if np.isnan(sums).any() else float(sums.max())
