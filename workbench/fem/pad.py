"""A rigid jaw with a bonded compliant layer (thesis §3.5.2) and its face compliance.

The layer occupies ``[-w/2, w/2] × [-l/2, l/2] × [0, h]``; its back face ``z = 0``
is bonded to the jaw (all displacements fixed) and the contact face is ``z = h``.

:func:`condense_pad` condenses the linear-elastic layer once onto its contact
face: ``C = B K⁻¹ Bᵀ``, the inverse of the Schur complement of ``K`` onto the face dofs
(:func:`workbench.fem.sparse_factor.schur_compliance`: one Cholesky factorisation with the
face eliminated last), all three displacement components per face node, so tangential
coupling is kept.  ``C`` scales exactly with ``1/E``, so it is computed for ``E = 1`` and
cached on disk keyed by a content hash of the mesh, ``nu``, the scheme and the code that
computes it (:func:`workbench.code_key.code_digest` of this module: a comment edit keeps the
cache, a change of the condensation or of anything it imports rebuilds it).

Cache location (:func:`pad_cache_dir`): ``cache_dir=None`` (default) uses
``$WORKBENCH_CACHE_DIR`` if set, else the user cache directory
(``platformdirs.user_cache_dir("nonplanar-workbench")``), sub-folder ``pads``; a path uses that directory;
``cache_dir=False`` disables the cache (always condense, write nothing).
Cache files are written atomically (temp file + ``os.replace``) with the
usual permissions (``0o666 & ~umask``); an unreadable cache file is rebuilt and
an unwritable cache directory only costs the rebuild next time.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from skfem import MeshHex

from workbench.atomic_io import read_cache_npz, write_cache_npz
from workbench.cachedir import (
    CACHE_ENV,  # noqa: F401 - re-exported: the variable's name
    array_digest,
)
from workbench.cachedir import cache_dir as _cache_dir
from workbench.code_key import code_digest

from .elasticity import basis, stiffness
from .material import Material
from .sparse_factor import schur_compliance

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PadGeometry:
    """Layer size [m] and hex counts (default: 20 × 40 mm face, 5 mm silicone)."""

    width: float = 0.02  # x
    length: float = 0.04  # y
    thickness: float = 0.005  # z, the layer height h
    nx: int = 20
    ny: int = 40
    nz: int = 5
    # optional grading (fine_half_width, fine_size, growth): spacing fine_size within
    # |x|, |y| <= fine_half_width and within fine_half_width below the face, growing
    # geometrically by `growth` outside (nx, ny, nz are then ignored) — for Hertz
    grading: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        for name in ("width", "length", "thickness"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a positive length [m]; got {v}")
        for name in ("nx", "ny", "nz"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"{name} must be >= 1; got {getattr(self, name)}")

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Node coordinates along x, y, z."""
        if self.grading is None:
            return (
                np.linspace(-self.width / 2, self.width / 2, self.nx + 1),
                np.linspace(-self.length / 2, self.length / 2, self.ny + 1),
                np.linspace(0.0, self.thickness, self.nz + 1),
            )
        fine_half, size, growth = self.grading
        half_x = graded_half_axis(self.width / 2, fine_half, size, growth)
        half_y = graded_half_axis(self.length / 2, fine_half, size, growth)
        depth = graded_half_axis(self.thickness, fine_half, size, growth)
        return (
            np.concatenate([-half_x[::-1], half_x[1:]]),
            np.concatenate([-half_y[::-1], half_y[1:]]),
            self.thickness - depth[::-1],
        )

    def mesh(self) -> MeshHex:
        return MeshHex.init_tensor(*self.axes())


def graded_half_axis(length: float, fine: float, size: float, growth: float) -> np.ndarray:
    """Coordinates 0 .. length: spacing ``size`` up to ``fine``, then growing by ``growth``."""
    pts = [0.0]
    step = size
    # stop at the end of the pad, not one round-off step short of it
    while pts[-1] < length - 1e-12 * length:
        if pts[-1] >= fine - 1e-12 * length:
            step *= growth
        nxt = pts[-1] + step
        if length - nxt < 0.5 * step:  # avoid a sliver at the end
            nxt = length
        pts.append(min(nxt, length))
    return np.array(pts)


@dataclass(frozen=True)
class CondensedPad:
    """Compliance of the contact face.

    face_nodes : (n,) mesh node indices on ``z = h``; face_xy : (n, 2) [m];
    compliance_unit : (3n, 3n) [m/N] for ``E = 1 Pa``, dofs ordered
    ``[u_x, u_y, u_z]`` per face node; ``seconds`` : the build time (also when
    loaded from the disk cache, which ``from_cache`` says).
    """

    geometry: PadGeometry
    material: Material
    face_nodes: np.ndarray
    face_xy: np.ndarray
    compliance_unit: np.ndarray
    seconds: float
    from_cache: bool = False

    @property
    def compliance(self) -> np.ndarray:
        """(3n, 3n) face compliance [m/N] for the pad's material: ``C_1 / E``."""
        return self.compliance_unit / self.material.E


@dataclass(frozen=True)
class PadFace:
    """The contact face of a pad without its compliance: what
    :func:`workbench.fem.extract.extract_profile` needs of a full-mesh (``fidelity="linear"``)
    solution.  face_nodes : (n,) mesh node indices on ``z = h``; face_xy : (n, 2) [m]."""

    geometry: PadGeometry
    material: Material
    face_nodes: np.ndarray
    face_xy: np.ndarray

    @classmethod
    def of(cls, geometry: PadGeometry, material: Material) -> PadFace:
        """The face of the whole layer (the nodes and order of ``solve_contact_full``)."""
        p = geometry.mesh().p
        face = top_face_nodes(p, geometry.thickness)
        return cls(geometry, material, face, p[:2, face].T)


def top_face_nodes(points: np.ndarray, thickness: float) -> np.ndarray:
    """Indices of the nodes of a pad mesh (``points`` (3, N) [m]) on its free face
    ``z = thickness`` — the contact face every fidelity solves on."""
    return np.flatnonzero(np.isclose(points[2], thickness))


def pad_cache_dir(cache_dir: str | Path | bool | None = None) -> Path | None:
    """The directory pad compliances are cached in, or ``None`` when caching is off: the
    workbench's cache folder, :func:`workbench.cachedir.cache_dir` (its rules)."""
    return _cache_dir(cache_dir)


def _key(mesh: MeshHex, nu: float, scheme: str) -> str:
    arrays = (np.ascontiguousarray(mesh.p, dtype=np.float64), np.ascontiguousarray(mesh.t, dtype=np.int64))
    return array_digest(arrays, f"nu={nu!r};scheme={scheme};code={code_digest(__name__)}")


def condense_pad(
    geometry: PadGeometry,
    material: Material,
    *,
    scheme: str = "sri",
    cache_dir: str | Path | bool | None = None,
    patch_radius: float | None = None,
) -> CondensedPad:
    """Face compliance of the bonded layer (see module docstring).

    cache_dir : ``None`` (default): ``$WORKBENCH_CACHE_DIR`` or the user cache
        directory; a path: that directory; ``False``: no disk cache
        (:func:`pad_cache_dir`).  ``from_cache`` on the result says whether it was loaded.
    patch_radius : condense only the face nodes within this distance of the
        face center (the candidate contact zone of a large block, e.g. Hertz);
        contact outside it is then not represented.
    """
    from workbench.plausible import check

    check("pad_modulus", material.E, "material.E (the pad's Young's modulus [Pa])")
    # hard limits only: validation blocks (an 80 mm half-space) are condensed here too
    check("pad_size", geometry.width, "PadGeometry.width", warn=False)
    check("pad_size", geometry.length, "PadGeometry.length", warn=False)
    check("pad_thickness", geometry.thickness, "PadGeometry.thickness", warn=False)
    mesh = geometry.mesh()
    x, y, z = mesh.p
    face = top_face_nodes(mesh.p, geometry.thickness)
    if patch_radius is not None:
        check("pad_size", patch_radius, "patch_radius (the contact zone's radius [m])", warn=False)
        face = face[np.hypot(x[face], y[face]) <= patch_radius]
    tag = scheme if patch_radius is None else f"{scheme};patch={patch_radius!r}"
    folder = pad_cache_dir(cache_dir)
    path = None if folder is None else folder / f"pad-{_key(mesh, material.nu, tag)}.npz"
    n = 3 * face.size

    def check(d: dict) -> None:
        if d["compliance_unit"].shape != (n, n):
            raise ValueError(f"compliance of shape {d['compliance_unit'].shape}, expected {(n, n)}")
        if "seconds" in d:
            float(d["seconds"])  # the build time it records: a scalar

    cached = read_cache_npz(path, check, "pad cache", "condensing again")
    if cached is not None:
        log.info("pad compliance loaded from %s", path)
        C1 = cached["compliance_unit"]
        built = float(cached["seconds"]) if "seconds" in cached else float("nan")
        return CondensedPad(geometry, material, face, np.column_stack([x[face], y[face]]), C1, built, True)

    t0 = time.perf_counter()
    K = stiffness(mesh, Material(1.0, material.nu), scheme)  # E = 1: C scales with 1/E
    nodal = basis(mesh).nodal_dofs  # (3, N)
    fixed = np.zeros(K.shape[0], dtype=bool)
    fixed[nodal[:, np.isclose(z, 0.0)].ravel()] = True
    free = np.flatnonzero(~fixed)
    pos = np.full(K.shape[0], -1)
    pos[free] = np.arange(free.size)
    # the face compliance as the inverse of the Schur complement onto the face dofs (CHOLMOD, the
    # face eliminated last): two dense triangular solves instead of a sparse solve per face dof
    # (docs/decisions.md)
    face_dofs = nodal[:, face].T.ravel()  # node-major [ux, uy, uz]
    C1 = schur_compliance(K[free][:, free], pos[face_dofs])
    seconds = time.perf_counter() - t0
    if path is not None and write_cache_npz(path, compliance_unit=C1, seconds=np.float64(seconds)):
        log.info("pad compliance (%.1f s) cached in %s", seconds, path)
    return CondensedPad(geometry, material, face, np.column_stack([x[face], y[face]]), C1, seconds)
