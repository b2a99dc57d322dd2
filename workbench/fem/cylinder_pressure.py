"""The power law of Eq. 4.3 fitted to the FEM pad's pressure on an elliptic cylinder (thesis
§4.1.3.2, Fig 4.2(d)): the thesis fitted it to a fin-ray jaw's ANSYS solution on its type I
objects and found k = 2.4, "from 2.4 to 5.5 … under different loads"; here the pad is ours (a
bonded silicone layer, :mod:`workbench.fem.pad`) and so is the cylinder's size.

In the pad's frame (face at z = h, x across its 20 mm width, y along its 40 mm length) the
cylinder's axis runs along x, its semi-axis ``a`` along the closing direction z (the grasp
axis) and ``b`` along y, so the pressure varies along the pad's length.  The thesis's r is the
y component of a point's distance to the object's centre o_g in its frame, y across both the
grasp axis and the cylinder axis: here |y| too.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..pressure import PowerLawFit, fit_power_law
from .contact import solve_contact
from .extract import extract_profile
from .obstacles import EllipticCylinder

__all__ = ["CylinderLaw", "cylinder_pressure_laws"]


@dataclass(frozen=True)
class CylinderLaw:
    """The pad pressed ``delta`` [m] onto the cylinder of semi-axes ``a`` (along the grasp
    axis) and ``b`` (across) [m]: its total normal force ``force`` [N], contact elements
    ``n_elements``, the fitted law ``fit`` (:class:`workbench.pressure.PowerLawFit`) and the
    points it was fitted to — ``r`` (n,) [m] and ``p`` (n,) [Pa], read-only."""

    a: float
    b: float
    delta: float
    force: float
    n_elements: int
    fit: PowerLawFit
    r: np.ndarray
    p: np.ndarray

    def __post_init__(self) -> None:
        for name in ("r", "p"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)


def cylinder_pressure_laws(
    pad, semi_axes: Sequence[tuple[float, float]], deltas: Sequence[float]
) -> list[CylinderLaw]:
    """For each ``(a, b)`` of ``semi_axes`` [m] and each jaw displacement of ``deltas`` [m]
    (increasing; each solve warm-starts the next), the pad (a
    :class:`workbench.fem.pad.CondensedPad`) pressed onto the cylinder and Eq. 4.3 fitted to
    its contact's element pressures against r = |y| (:func:`workbench.pressure.fit_power_law`,
    r_max the largest r in contact).  Returns the laws in that order; a displacement that
    leaves fewer than 3 elements in contact raises ``ValueError`` (press further)."""
    deltas = [float(d) for d in deltas]
    if not deltas or any(d <= 0 for d in deltas) or deltas != sorted(deltas):
        raise ValueError(f"deltas must be increasing jaw displacements > 0 [m]; got {deltas}")
    h = pad.geometry.thickness
    out = []
    for a, b in semi_axes:
        cyl = EllipticCylinder(point=(0.0, 0.0, h + a), axis=(1.0, 0.0, 0.0), major=(0.0, 0.0, 1.0), a=a, b=b)
        sol = None
        for d in deltas:
            sol = solve_contact(pad, cyl, d, warm=sol)
            prof = extract_profile(pad, sol, cyl)
            loaded = None if prof is None else prof.pressures > 0
            if prof is None or loaded.sum() < 3:
                raise ValueError(
                    f"the cylinder a = {a} m, b = {b} m touches fewer than 3 elements at {d} m: "
                    "press further (a larger delta)"
                )
            r, p = np.abs(prof.centers[loaded, 1]), prof.pressures[loaded]
            out.append(CylinderLaw(a, b, d, float(sol.force), int(loaded.sum()), fit_power_law(r, p), r, p))
    return out
