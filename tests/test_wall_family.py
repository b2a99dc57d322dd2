"""Bottle-family walls (workbench.fem.wall_family): the grasp axis at the section's major axis
plus the angle, one cached wall per (bottle, mesh), and mesh convergence relative to the finest."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, bottle_family
from workbench.fem.material import Material
from workbench.fem.wall_family import bottle_wall, grasp_axis, mesh_convergence


def test_the_grasp_axis_turns_from_the_sections_major_axis():
    b = Bottle(bottle_family(seed=0)[16])  # an asymmetric bottle: its major axis turns with height
    z = 0.4 * b.params.height
    centre, A, B, phi = b.section(z)
    for angle in (0.0, 0.3, np.pi / 2):
        p, e = grasp_axis(b, z, angle)
        assert p == pytest.approx([centre[0], centre[1], z], abs=1e-15)
        assert np.linalg.norm(e) == pytest.approx(1.0, rel=1e-15) and e[2] == 0.0
        assert np.arctan2(e[1], e[0]) == pytest.approx(np.arctan2(np.sin(phi + angle), np.cos(phi + angle)))


@pytest.mark.jit_only("a wall's assembly and factorisation: over 10 s as pure Python")
def test_a_bottles_wall_is_built_once_and_the_finest_mesh_is_the_reference():
    bottle_wall.cache_clear()
    b1, w1 = bottle_wall(0, 0, 2.5e9, 0.4, 0.5e-3, 16, 8)
    b2, w2 = bottle_wall(0, 0, 2.5e9, 0.4, 0.5e-3, 16, 8)
    assert w1 is w2 and b1 is b2 and bottle_wall.cache_info().hits == 1
    assert b1.params.height == Bottle(bottle_family(seed=0)[0]).params.height
    conv = mesh_convergence(b1, Material(2.5e9, 0.4), 0.5e-3, [[16, 8], [24, 12]], 10.0, (0.02, 0.04))
    assert [(r["mesh"], r["angle"]) for r in conv] == [
        ("16x8", 0.0),
        ("16x8", np.pi / 2),
        ("24x12", 0.0),
        ("24x12", np.pi / 2),
    ]
    assert conv[2]["rel_to_finest"] == 0.0 and conv[3]["rel_to_finest"] == 0.0
    for coarse, fine in ((conv[0], conv[2]), (conv[1], conv[3])):
        k, k_ref = coarse["stiffness_N_per_m"], fine["stiffness_N_per_m"]
        assert coarse["rel_to_finest"] == pytest.approx(k / k_ref - 1, rel=1e-12)
        # conforming displacement elements are too stiff: the coarser wall the stiffer
        assert 0 < k_ref < k < 1e6
    bottle_wall.cache_clear()
