"""The surface a Winkler pad can reach at one pose, pressed to a depth or to a force.

Where the pad lies fixes which sub-triangles it can touch (the front-most surface under its
footprint, :func:`~.reach.pad_patch`) and how far behind the first touch each one lies; how hard
it is pressed fixes only which of them are in contact and their pressure.  A :class:`PadPatch`
holds the first, so a pad pressed to several depths, or to the depth that gives its force,
is found once per pose.

A Winkler pad pressed ``d`` past first touch puts ``p_i = k (d − h_i)`` on each element at
``h_i = z_i − z_0`` behind it (``k`` the modulus over the layer's thickness, thesis §2.3.1.3); its
normal force along the closing axis is ``F(d) = k Σ_i a_i c_i (d − h_i)⁺`` (``c_i = −n_i·axis``,
each element's area seen along the axis), continuous, piecewise linear and increasing in ``d``:
:meth:`PadPatch.depth_for_force` inverts it exactly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..profile import ContactProfile

__all__ = ["PadPatch", "pressed_profile"]


def pressed_profile(centers, normals, areas, z, z0: float, stiffness: float, depth: float, among=None):
    """The :class:`~workbench.profile.ContactProfile` of a Winkler pad ``depth`` [m] past first
    touch ``z0`` [m] on elements ``centers``, ``normals`` (m, 3), ``areas``, ``z`` (m,) (as
    :class:`PadPatch` holds them; of those the ascending indices ``among`` only, None: all): each
    element ``z0 + depth − z`` deep carries ``stiffness`` [Pa/m] times that; None when none is
    in contact."""
    idx = np.arange(len(z)) if among is None else among
    d = z0 + depth - z[idx]
    sel = d > 0
    if not sel.any():
        return None
    keep = idx[sel]
    return ContactProfile(
        centers.take(keep, axis=0), normals.take(keep, axis=0), areas.take(keep), stiffness * d[sel]
    )


@dataclass(frozen=True)
class PadPatch:
    """The elements a pad at one pose can reach.

    centers, normals : (m, 3) [m], unit outward normals; areas : (m,) [m²]; z : (m,) [m] each
    centre's distance along ``axis`` from the jaw (so ``z − z0`` is how far behind the first
    touch ``z0`` [m] it lies); axis : (3,) the unit closing direction; stiffness : the pad's
    Winkler modulus [Pa/m].  Read-only arrays.
    """

    centers: np.ndarray = field(repr=False)
    normals: np.ndarray = field(repr=False)
    areas: np.ndarray = field(repr=False)
    z: np.ndarray = field(repr=False)
    z0: float
    axis: np.ndarray = field(repr=False)
    stiffness: float

    def __post_init__(self) -> None:
        for name in ("centers", "normals", "areas", "z", "axis"):
            a = np.array(getattr(self, name), dtype=float)
            a.flags.writeable = False
            object.__setattr__(self, name, a)

    def __len__(self) -> int:
        return len(self.areas)

    def pressures(self, depth: float) -> np.ndarray:
        """(m,) [Pa] each element's Winkler pressure with the pad ``depth`` [m] past first touch
        (0 where it does not reach)."""
        return self.stiffness * np.maximum(self.z0 + depth - self.z, 0.0)

    def depth_for_force(self, force: float) -> float:
        """The depth [m] past first touch at which the pad's normal force along its axis is
        ``force`` [N] (> 0): the root of the piecewise linear ``F(d)`` (module docstring)."""
        h = self.z - self.z0
        order = np.argsort(h, kind="stable")
        h = h[order]
        w = (self.areas * -(self.normals @ self.axis))[order]  # each element's area along the axis
        W, S = np.cumsum(w), np.cumsum(w * h)
        target = force / self.stiffness
        # with the first j + 1 elements in contact, F/k = d W_j − S_j, valid up to d = h_{j+1}
        reach = h[1:] * W[:-1] - S[:-1]
        j = int(np.searchsorted(reach, target, side="left"))
        return float((target + S[j]) / W[j])

    def axis_force(self, depth: float) -> float:
        """The pad's normal force [N] along its axis pressed ``depth`` [m] past first touch."""
        return float(self.pressures(depth) @ (self.areas * -(self.normals @ self.axis)))

    def torque(self, depth: float, point: np.ndarray) -> np.ndarray:
        """(3,) [N·m] the torque about ``point`` (3,) [m] of the normal forces on the object
        (``Σ (c − point) × (−p a n)``, outward normals) with the pad ``depth`` [m] past first touch."""
        f = -(self.pressures(depth) * self.areas)[:, None] * self.normals
        return np.cross(self.centers - np.asarray(point, float), f).sum(axis=0)

    def profile(self, depth: float) -> ContactProfile | None:
        """The :class:`~workbench.profile.ContactProfile` of the elements in contact with the pad
        ``depth`` [m] past first touch; None when none is."""
        return pressed_profile(self.centers, self.normals, self.areas, self.z, self.z0, self.stiffness, depth)
