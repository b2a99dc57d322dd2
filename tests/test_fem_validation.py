"""Validation problems with closed-form answers (workbench.fem.validation): the Lamé
thick cylinder's formula, its finite-element counterpart (convergence order, linearity),
the locking table, and the condensed-versus-full exactness check on a case with an exact
answer and on the ten comparison cases.  The SRI scheme against Lamé (volumetric locking)
is tested in tests/test_fem_elasticity.py."""

import numpy as np
import pytest

from workbench.fem.material import Material
from workbench.fem.validation import (
    compare_condensed_vs_full,
    comparison_cases,
    condensed_vs_full,
    lame_cylinder_fe,
    lame_inner_displacement,
    locking_rows,
)


@pytest.mark.parametrize("E, nu, p, a, b", [(1e6, 0.3, 1.0, 1.0, 2.0), (2.5e9, 0.45, 3e5, 0.01, 0.013)])
def test_lame_formula_solves_the_plane_strain_boundary_value_problem(E, nu, p, a, b):
    """Plane strain, u_r = A r + B / r (the general axisymmetric solution), so
    σ_rr = (λ + 2G) u_r' + λ u_r / r = 2 (λ + G) A - 2 G B / r²; σ_rr(a) = -p, σ_rr(b) = 0 is a
    2 x 2 system for A and B (λ, G from E and nu by hand), and u_r(a) = A a + B / a."""
    G = E / (2 * (1 + nu))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    M = np.array([[2 * (lam + G), -2 * G / a**2], [2 * (lam + G), -2 * G / b**2]])
    A, B = np.linalg.solve(M, [-p, 0.0])
    got = lame_inner_displacement(Material(E=E, nu=nu), p=p, a=a, b=b)
    assert got == pytest.approx(A * a + B / a, rel=1e-12)


def test_lame_cylinder_fe_converges_at_second_order():
    """Trilinear hexes (and the flat facets of the inner circle) err by O(h²) in displacement:
    halving the element size divides the error against the Lamé formula by 2² = 4, i.e. an
    observed order log2(e_h / e_h/2) of 2 on each refinement."""
    mat = Material(E=1.0e6, nu=0.3)
    exact = lame_inner_displacement(mat)
    err = [
        abs(lame_cylinder_fe(mat, "sri", nr=nr, nt=nt) / exact - 1) for nr, nt in ((4, 6), (8, 12), (16, 24))
    ]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    np.testing.assert_allclose(orders, 2.0, atol=0.1)


def test_lame_cylinder_fe_is_linear_in_pressure_and_compliance():
    """Linear elasticity: the displacement is proportional to p / E, exactly (one linear solve)."""
    u1 = lame_cylinder_fe(Material(E=1.0e6, nu=0.45), "sri", nr=4, nt=6)
    u2 = lame_cylinder_fe(Material(E=4.0e6, nu=0.45), "sri", nr=4, nt=6, p=6.0)
    assert u2 == pytest.approx(1.5 * u1, rel=1e-10)
    with pytest.raises(ValueError, match="scheme must be 'sri' or 'full'"):
        lame_cylinder_fe(Material(), "reduced", nr=2, nt=3)


def test_condensed_vs_full_on_a_uniaxially_compressed_layer():
    """nu = 0 and a rigid plane pressed δ into the face of a layer bonded at its back: the
    exact solution is u_z = -δ z / h (uniaxial strain = uniaxial stress at nu = 0, free sides
    traction-free, frictionless face), which trilinear hexes represent exactly.  So both
    levels give the uniform pressure E δ / h on every node (λ_i / A_i on the undeformed
    tributary areas) and the force E δ W L / h, and they agree to round-off."""
    from workbench.fem.obstacles import Plane
    from workbench.fem.pad import PadGeometry, condense_pad

    geom = PadGeometry(width=0.006, length=0.008, thickness=0.002, nx=3, ny=4, nz=2)
    mat = Material(E=1.0e6, nu=0.0)
    h, delta = geom.thickness, 1e-5
    pad = condense_pad(geom, mat, cache_dir=False)
    row = condensed_vs_full(pad, Plane((0.0, 0.0, h), (0.0, 0.0, -1.0)), delta, "uniaxial")
    p = mat.E * delta / h
    assert row["case"] == "uniaxial"
    assert row["force_N"] == pytest.approx(p * geom.width * geom.length, rel=1e-9)
    assert row["force_rel_err"] < 1e-9 and row["pressure_rel_l2"] < 1e-9
    assert row["min_pressure"] == pytest.approx(p, rel=1e-9)
    assert row["active_nodes"] == (geom.nx + 1) * (geom.ny + 1)
    assert row["max_penetration_m"] <= 1e-9 * h
    assert row["condensed_ms"] > 0 and row["full_s"] > 0
    assert row["speed_ratio"] == pytest.approx(row["full_s"] / (row["condensed_ms"] * 1e-3), rel=1e-12)


def test_locking_rows_sri_stays_near_lame_where_full_integration_locks():
    """On 4 x 6 hexes: SRI within 1 % of Lamé (its O(h²) discretization error) at nu = 0.3 and
    at nu = 0.4999 alike; full integration within 2 % at 0.3 but locked far below Lamé at
    0.4999 (K/G = 5000), the first Poisson ratio's row first."""
    rows = locking_rows([0.3, 0.4999], 4, 6)
    assert [list(r) for r in rows] == [["nu", "sri_over_exact", "full_over_exact"]] * 2
    assert [r["nu"] for r in rows] == [0.3, 0.4999]
    assert all(abs(r["sri_over_exact"] - 1) < 0.01 for r in rows)
    assert abs(rows[0]["full_over_exact"] - 1) < 0.02
    assert rows[1]["full_over_exact"] < 0.2


def test_the_ten_comparison_cases_are_exact_on_a_coarse_pad():
    """Condensation is the exact Schur complement of the same stiffness: on a 4 x 6 x 1 pad
    every case's force and pressure field equal the full-mesh solve to round-off, pressures
    are >= 0 without penetration, and the sphere R20 sweep rises with δ, its 0.6 mm entry
    being the case's own solve."""
    res = compare_condensed_vs_full([4, 6, 1], 0.499, [0.1e-3, 0.3e-3, 0.6e-3])
    cases = comparison_cases(res.pad.geometry.thickness)
    assert len(cases) == 10
    assert [r["case"] for r in res.rows] == list(cases) == list(res.cases)
    assert res.pad.geometry.thickness == 0.004 and res.pad.material.nu == 0.499
    for r in res.rows:
        assert r["force_N"] > 0 and r["active_nodes"] > 0, r["case"]
        assert r["force_rel_err"] < 1e-10 and r["pressure_rel_l2"] < 1e-10, r["case"]
        assert r["min_pressure"] >= 0 and r["max_penetration_m"] <= 1e-12, r["case"]
    assert res.monotone and all(np.diff(res.sweep_forces) > 0)
    assert res.sweep_forces[-1] == res.rows[0]["force_N"]
    assert res.precompute_s > 0
