"""Contact solution -> ``workbench.ContactProfile`` on the object surface.

Nodal pressures are ``λ_i / A_i`` (tributary face areas).  Each face quad with
a loaded node becomes one element: pressure = mean of its nodal pressures,
center = its deformed center projected onto the obstacle, normal = the
obstacle's outward normal there (outward from the object, into the jaw),
area = the deformed quad's vector-area magnitude.
"""

from __future__ import annotations

import numpy as np

from workbench import ContactProfile

from .contact import ContactSolution
from .pad import CondensedPad


def face_grid(face_xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quads (m, 4) of face-node indices (counter-clockwise seen from +z) and
    tributary nodal areas (n,) of the undeformed face with nodes ``face_xy`` (n, 2)."""
    xs, ix = np.unique(np.round(face_xy[:, 0], 12), return_inverse=True)
    ys, iy = np.unique(np.round(face_xy[:, 1], 12), return_inverse=True)
    grid = np.full((xs.size, ys.size), -1)
    grid[ix, iy] = np.arange(face_xy.shape[0])
    quads = np.column_stack(
        [grid[:-1, :-1].ravel(), grid[1:, :-1].ravel(), grid[1:, 1:].ravel(), grid[:-1, 1:].ravel()]
    )
    cell_area = np.outer(np.diff(xs), np.diff(ys)).ravel()
    whole = (quads >= 0).all(axis=1)  # a condensed patch need not fill the grid
    quads, cell_area = quads[whole], cell_area[whole]
    return quads, tributary_areas(quads, cell_area, face_xy.shape[0])


def tributary_areas(quads: np.ndarray, quad_area: np.ndarray, n: int) -> np.ndarray:
    """(n,) nodal areas: a quarter of each quad's area (m,) to each of its corners."""
    area = np.zeros(n)
    np.add.at(area, quads.ravel(), np.repeat(quad_area / 4.0, 4))
    return area


def quad_vector_areas(corners: np.ndarray) -> np.ndarray:
    """(m, 3) vector areas of quads with corners (m, 4, 3) (half the diagonals' cross product)."""
    return 0.5 * np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])


def nodal_pressures(pad: CondensedPad, lam: np.ndarray) -> np.ndarray:
    """(n,) nodal pressures ``λ_i / A_i`` [Pa]; nodes on the rim of a condensed
    patch belong to no whole quad (area 0, λ = 0) and get 0."""
    _, area = face_grid(pad.face_xy)
    return np.divide(lam, area, out=np.zeros_like(lam, dtype=float), where=area > 0)


def extract_profile(pad: CondensedPad, sol: ContactSolution, obstacle) -> ContactProfile | None:
    """The contact profile on the object, or ``None`` if nothing touches."""
    if not sol.in_contact:
        return None
    quads, _ = face_grid(pad.face_xy)
    p_node = nodal_pressures(pad, sol.lam)
    loaded = (sol.lam[quads] > 0).any(axis=1)
    q = quads[loaded]
    corners = sol.x[q]  # (m, 4, 3) deformed
    center = corners.mean(axis=1)
    d, n = obstacle.signed_distance(center)
    on_surface = center - d[:, None] * n
    vec = quad_vector_areas(corners)
    # mesh for export/plots: the used deformed nodes projected onto the obstacle
    used, faces = np.unique(q, return_inverse=True)
    dv, nv = obstacle.signed_distance(sol.x[used])
    verts = sol.x[used] - dv[:, None] * nv
    return ContactProfile(
        on_surface,
        n,
        np.linalg.norm(vec, axis=1),
        p_node[q].mean(axis=1),
        vertices=verts,
        faces=faces.reshape(-1, 4)[:, ::-1],  # wound so the face normal points out of the object
    )
