"""Contact solution -> ``workbench.ContactProfile`` on the object surface.

Each face quad with a loaded corner becomes one element.  Node i carries the
contact force ``λ_i`` along the obstacle normal ``n_i`` the solver used
(:class:`workbench.fem.contact.ContactSolution`: ``λ_i ≥ 0`` is the magnitude of the
nodal force along the obstacle's outward normal, *not* along the press axis;
the pad receives ``λ_i n_i``, the object ``−λ_i n_i``).  The force is split
among the quads around the node in proportion to their share of the node's
*deformed* tributary area (a quarter of each deformed quad's area), so

* element force ``f_e = Σ_corners λ_i (a_e / 4) / A_i`` and pressure
  ``p_e = f_e / a_e`` = the mean of the corners' Cauchy nodal pressures
  ``λ_i / A_i`` (``a_e``: deformed quad area, ``A_i``: deformed tributary area);
* ``Σ p_e a_e = Σ λ_i`` exactly (``profile.F == sol.force`` to round-off);
* the element normal is the force-weighted mean direction of its corners' solver
  normals, ``n_e ∝ Σ_corners λ_i (a_e / 4) / A_i · n_i``, so the profile's normal
  wrench force ``−Σ p_e a_e n_e`` equals the solution's force on the object
  ``−Σ λ_i n_i`` (:attr:`workbench.fem.contact.ContactSolution.force_vector`) up to the spread
  of the normals inside an element: ``‖Δ‖ ≤ (1 − cos θ) Σ λ_i`` with θ the largest
  angle between two corner normals of a loaded quad (~(spacing / curvature radius)²;
  measured 4–7e-4 of Σ λ on the default pad against a R 20 mm sphere, 1.0–1.6e-3 on
  the faceted thesis bottle 0006, δ = 0.1–3 mm);
* the element center is the deformed quad's center projected onto the obstacle.

An earlier version divided λ by the *undeformed* tributary area and multiplied
by the deformed quad area: ``F`` exceeded ``Σ λ`` by 0.3% at δ = 0.1 mm and 12%
at δ = 1 mm (default pad, R 20 mm sphere).
"""

from __future__ import annotations

import logging

import numpy as np

from workbench.profile import ContactProfile

from .contact import ContactSolution
from .pad import CondensedPad

log = logging.getLogger(__name__)


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
    """(n,) nodal pressures ``λ_i / A_i`` [Pa] on the *undeformed* tributary areas
    (the small-strain reference pressure of the validation tables; profiles use the
    deformed areas, see :func:`extract_profile`); nodes on the rim of a condensed
    patch belong to no whole quad (area 0, λ = 0) and get 0."""
    _, area = face_grid(pad.face_xy)
    return np.divide(lam, area, out=np.zeros_like(lam, dtype=float), where=area > 0)


def extract_profile(pad, sol: ContactSolution, obstacle) -> ContactProfile | None:
    """The contact profile on the object (see the module docstring), or ``None`` if
    nothing touches.

    pad : the pad the solution belongs to — anything with the face-node
        coordinates ``face_xy`` (n, 2) of ``sol``'s nodes: a
        :class:`workbench.fem.pad.CondensedPad`, :class:`workbench.fem.nonlinear.NonlinearPad` or
        :class:`workbench.fem.pad.PadFace`; ``workbench.fem.press(...)`` returns it as ``.pad``.
    sol : :class:`workbench.fem.contact.ContactSolution` of any fidelity.
    obstacle : the obstacle the solution was computed against (``signed_distance``).

    Conserved exactly: ``profile.F == sol.force`` (Σ p a = Σ λ).  Conserved up to
    the normals' spread within an element: ``profile.normal_wrench[:3] ≈
    sol.force_vector``.
    """
    face_xy = getattr(pad, "face_xy", None)
    if face_xy is None:
        raise ValueError(
            f"pad must have the face-node coordinates face_xy (n, 2); got {type(pad).__name__} "
            "— pass the CondensedPad/NonlinearPad the solution came from (workbench.fem.press(...).pad)"
        )
    lam = np.asarray(sol.lam, dtype=float)
    if face_xy.shape[0] != lam.size:
        raise ValueError(
            f"the pad has {face_xy.shape[0]} face nodes but the solution has {lam.size} forces; "
            "pass the pad the solution was computed on"
        )
    if not sol.in_contact:
        return None
    quads, _ = face_grid(face_xy)
    quad_area = np.linalg.norm(quad_vector_areas(sol.x[quads]), axis=1)  # deformed
    node_area = tributary_areas(quads, quad_area, lam.size)  # deformed tributary areas
    orphan = (lam > 0) & (node_area <= 0)
    if orphan.any():  # a loaded node on the rim of a condensed patch: no quad to carry it
        log.warning(
            "%d loaded nodes belong to no whole face quad; their %.3g N (of %.3g N) are not in the "
            "profile — condense a larger patch",
            int(orphan.sum()),
            float(lam[orphan].sum()),
            float(lam.sum()),
        )
    p_node = np.divide(lam, node_area, out=np.zeros_like(lam), where=node_area > 0)
    loaded = (lam[quads] > 0).any(axis=1) & (quad_area > 0)
    q, a = quads[loaded], quad_area[loaded]
    share = p_node[q] * (a[:, None] / 4.0)  # (m, 4) force of each corner on this quad [N]
    m = np.einsum("ek,ekj->ej", share, np.asarray(sol.normals, dtype=float)[q])
    n = m / np.linalg.norm(m, axis=1, keepdims=True)
    corners = sol.x[q]  # (m, 4, 3) deformed
    center = corners.mean(axis=1)
    d, n_obs = obstacle.signed_distance(center)
    on_surface = center - d[:, None] * n_obs
    # mesh for export/plots: the used deformed nodes projected onto the obstacle
    used, faces = np.unique(q, return_inverse=True)
    dv, nv = obstacle.signed_distance(sol.x[used])
    verts = sol.x[used] - dv[:, None] * nv
    return ContactProfile(
        on_surface,
        n,
        a,
        share.sum(axis=1) / a,
        vertices=verts,
        faces=faces.reshape(-1, 4)[:, ::-1],  # wound so the face normal points out of the object
    )
