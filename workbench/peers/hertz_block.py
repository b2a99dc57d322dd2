"""Our condensed FEM pad against Hertz where Hertz applies: a rigid sphere on thick blocks.

The half-space of :mod:`workbench.peers.hertz` is approached by blocks ``2H × 2H × H`` and
``4H × 4H × 2H`` graded to a fine mesh under the contact; the layer adds stiffness at first order
in ``a/H``, so the half-space force is read off the two depths by Richardson extrapolation,
``F_∞ = 2 F_2H − F_H``.
"""

from __future__ import annotations

from ..fem.contact import solve_contact
from ..fem.material import Material
from ..fem.obstacles import Sphere
from ..fem.pad import PadGeometry, condense_pad
from .hertz import hertz_force

__all__ = ["hertz_half_space"]


def hertz_half_space(block: dict, E: float) -> dict:
    """Force at ``δ = a²/R`` on each block depth and the extrapolated force, each relative to
    Hertz's ``(4/3) E* √R δ^1.5`` (:func:`workbench.peers.hertz.hertz_force`).

    block : ``{"R_mm", "a_mm", "nu", "fine_mm", "depths_mm": [H, 2H]}`` — sphere radius, contact
        radius, the block's Poisson ratio, finest hex and the two depths, lengths in mm.
    E : the block's Young's modulus [Pa].

    Returns ``{"delta_mm", "a_over_H" (2,), "hertz_force_N", "force_N" (2,), "force_rel_err" (2,),
    "extrapolated_force_rel_err"}``.
    """
    R, a, fine = (block[k] * 1e-3 for k in ("R_mm", "a_mm", "fine_mm"))
    d = a * a / R
    mat = Material(E, block["nu"])
    f_h = hertz_force(R, d, E, block["nu"])
    depths = [H * 1e-3 for H in block["depths_mm"]]
    if len(depths) != 2 or not depths[1] == 2 * depths[0]:
        raise ValueError(f"hertz_block.depths_mm must be two depths H, 2H; got {block['depths_mm']!r}")
    forces = []
    for H in depths:
        geom = PadGeometry(2 * H, 2 * H, H, grading=(1.6 * a, fine, 1.35))
        pad = condense_pad(geom, mat, patch_radius=1.5 * a)
        forces.append(solve_contact(pad, Sphere((0.0, 0.0, H + R), R), d).force)
    f_inf = 2 * forces[1] - forces[0]
    return {
        "delta_mm": d * 1e3,
        "a_over_H": [a / H for H in depths],
        "hertz_force_N": f_h,
        "force_N": forces,
        "force_rel_err": [f / f_h - 1 for f in forces],
        "extrapolated_force_rel_err": f_inf / f_h - 1,
    }
