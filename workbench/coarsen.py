"""A contact profile seen at a coarser element size.

The thesis's FEM contacts have ~3 mm elements ("each contact surface consists of
3×3 rectangular elements", §3.5.2; ``ELEMENT_SZ_OBJECT = 3`` mm in the author's
ANSYS set-up), ours ~1 mm.  :func:`coarsen_profile` merges the elements of a
profile into square cells of a given size laid out in the contact's mean tangent
plane (⊥ the area-weighted mean normal, edges along the frame's x projected into
it), conserving each
cell's area and normal force:

* area ``A_c = Σ a_i``; pressure ``p_c = Σ p_i a_i / A_c`` (so ``F`` is exact);
* centre: the area-weighted centroid, as a coarser mesh's element centre would be
  (slightly inside a curved surface, by ~ cell² · curvature / 8: 0.02 mm for a
  3 mm cell on a 50 mm radius); the pressure variation inside a cell is lost, so the
  centre of pressure moves by a fraction of a cell.  With ``centre="pressure"`` it is
  the cell's own centre of pressure (``Σ p a c / Σ p a``) instead, so the contact's
  pressure centre — the reference point of its twists and wrenches — stays where it
  was, to round-off;
* normal: the area-weighted mean normal, renormalised.

Elements that face away from the mean normal (``n · n̄ < 0``: the far side of a contact
wrapping more than ±90° round a part, or the other face of a thin one) get cells of their
own: laid in one plane, the two sides would otherwise merge front to back (a trial saw a
±150° wrap of a 3 mm rod merged into cells 0.9 mm inside the rod).  A contact whose normals
cancel altogether has no tangent plane and is refused (:class:`NoTangentPlane`).

Cells that carry no force (all their elements at zero pressure) are dropped.  The
grid starts at the smallest element centre along each in-plane axis, so it is not
centred on the patch: on a symmetric 12 mm patch with 3 mm cells a trial measured
the centre of pressure moving by 0.09 mm (a fraction of a cell, as above), and the
partial cells at the far edges make a symmetric contact's coarse copy lopsided — under
a pure rotation about o a uniform 20 × 10 mm patch (μF = 8 N) gave a net force of 0.2 N
at 3 mm cells and 0.5 N at 6 mm, where the fine contact gives none, and 1.6 % / 5.5 %
less torsion (a new-user trial).  Centring the grid would put a cell's centre of pressure
on o, whose friction direction round-off then sets (an element on the rotation axis).
"""

from __future__ import annotations

import numbers

import numpy as np

from .profile import ContactProfile


class NoTangentPlane(ValueError):
    """The profile's area-weighted normals cancel: there is no plane to lay its cells in."""


def coarsen_profile(profile: ContactProfile, cell: float, *, centre: str = "area") -> ContactProfile:
    """Profile with elements merged into ``cell`` × ``cell`` squares [m] (module docstring).

    profile : any ContactProfile with at least two elements.
    cell : cell side [m], > 0; plausibly 1e-4 … 0.1 (a millimetre value is refused).
    centre : "area" (a coarser mesh's element centres) or "pressure" (each cell's centre of
        pressure: the contact's pressure centre kept).
    Returns a ContactProfile without a mesh (centres, normals, areas, pressures).
    """
    if isinstance(cell, bool) or not isinstance(cell, numbers.Real) or not (np.isfinite(cell) and cell > 0):
        raise ValueError(f"cell must be a positive length in metres (a number); got {cell!r}")
    if cell > 0.1:
        raise ValueError(
            f"cell = {cell:g} m is larger than any gripper contact — is it in millimetres? "
            f"pass {cell * 1e-3:g} for {cell:g} mm"
        )
    if len(profile.areas) < 2:
        raise ValueError(f"need a profile with >= 2 elements to coarsen; got {len(profile.areas)}")
    return _coarsen(profile, float(cell), centre)


def _coarsen(profile: ContactProfile, cell: float, centre: str) -> ContactProfile:
    """:func:`coarsen_profile` of a checked cell [m] (any size) and >= 2 elements."""
    if centre not in ("area", "pressure"):
        raise ValueError(f"centre must be 'area' or 'pressure'; got {centre!r}")
    c, a = profile.centers, profile.areas
    n_bar = a @ profile.normals
    # area-weighted normals cancelling to 1e-6 of the area: no side to face (a fold), not round-off
    if np.linalg.norm(n_bar) < 1e-6 * a.sum():
        raise NoTangentPlane(
            "the profile's area-weighted normals cancel (both sides of a thin part?): there is no "
            "tangent plane to lay the cells in — coarsen each side separately"
        )
    n_bar /= np.linalg.norm(n_bar)
    # in-plane axes from the frame's x (y if x is near the normal): deterministic, where
    # principal axes would spin freely on a square patch
    ref = np.eye(3)[0] if abs(n_bar[0]) < 0.9 else np.eye(3)[1]
    e1 = ref - (ref @ n_bar) * n_bar
    e1 /= np.linalg.norm(e1)
    uv = c @ np.column_stack([e1, np.cross(n_bar, e1)])
    span = (uv.max(axis=0) - uv.min(axis=0)) / cell
    if span.max() > 1e9:  # the cell indices must stay exact integers
        raise ValueError(
            f"cell = {cell:g} m is over 1e9 times smaller than the contact ({span.max() * cell:g} m): "
            "pass a cell of at least the elements' size"
        )
    # the snap keeps an element centred on a cell edge (rounding) in one cell consistently
    ij = np.floor((uv - uv.min(axis=0)) / cell + 1e-9).astype(np.int64)
    back = (profile.normals @ n_bar < 0).astype(np.int64)  # the far side: cells of its own
    # cells numbered in (side, i, j) order through one integer key a cell (the order
    # np.unique(ij, axis=0) gives a one-sided contact; sorting rows of pairs is the slower path)
    n_j = ij[:, 1].max() + 1
    key = (back * (ij[:, 0].max() + 1) + ij[:, 0]) * n_j + ij[:, 1]
    _, cell_of = np.unique(key, return_inverse=True)
    k = int(cell_of.max()) + 1
    area = np.bincount(cell_of, a, k)
    force = np.bincount(cell_of, a * profile.pressures, k)
    weight, total = (a, area) if centre == "area" else (a * profile.pressures, force)
    with np.errstate(invalid="ignore", divide="ignore"):  # cells of no force: dropped below
        sums = np.column_stack([np.bincount(cell_of, weight * c[:, d], k) for d in range(3)])
        centres = sums / total[:, None]
    normal = np.column_stack([np.bincount(cell_of, a * profile.normals[:, d], k) for d in range(3)])
    # a cell's elements all face one side of n̄, so their mean normal never cancels
    keep = force > 0
    return ContactProfile(
        centres[keep], normal[keep], area[keep], force[keep] / area[keep], normalize_normals=True
    )


__all__ = ["NoTangentPlane", "coarsen_profile"]
