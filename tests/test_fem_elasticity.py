"""SRI linear elasticity against the Lamé thick-walled cylinder (plane strain),
the classic volumetric-locking benchmark."""

import numpy as np
import pytest

from workbench.fem.material import Material
from workbench.fem.validation import lame_cylinder_fe


def lame_inner_displacement(material, p=1.0, a=1.0, b=2.0):  # independent reference
    E, nu = material.E, material.nu
    return (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * a + b**2 / a)


def solve_cylinder(material, scheme):
    return lame_cylinder_fe(material, scheme)


@pytest.mark.parametrize("nu", [0.3, 0.45, 0.499, 0.4999])
def test_sri_matches_lame_solution(nu):
    mat = Material(E=1.0e6, nu=nu)
    exact = lame_inner_displacement(mat)
    assert solve_cylinder(mat, "sri") == pytest.approx(exact, rel=0.02)


def test_full_integration_locks_and_sri_does_not():
    mat = Material(E=1.0e6, nu=0.4999)
    exact = lame_inner_displacement(mat)
    full = solve_cylinder(mat, "full")
    sri = solve_cylinder(mat, "sri")
    assert full < 0.8 * exact  # locked: too stiff by > 25%
    assert abs(sri / exact - 1) < 0.02


@pytest.mark.parametrize(
    "E, nu", [(0.0, 0.3), (-1.0, 0.3), (1e6, 0.5), (1e6, -1.0), (1e6, 0.7), (np.nan, 0.3)]
)
def test_bad_material(E, nu):
    with pytest.raises(ValueError, match="E must be|nu must be"):
        Material(E=E, nu=nu)
