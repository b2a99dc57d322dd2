"""Thin-layer limits (workbench.fem.thin_layer): the Winkler and thin-film formulas against
their derivations integrated numerically, and the finite element layers against them."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from workbench.fem.material import Material
from workbench.fem.thin_layer import (
    THIN_FILM_H,
    THIN_FILM_R,
    thin_film,
    thin_film_cylinder_force,
    thin_film_cylinder_half_width,
    thin_film_cylinder_indentation,
    thin_film_cylinder_pressure,
    thin_film_sphere_force,
    thin_film_sphere_indentation,
    thin_film_sphere_pressure,
    thin_film_sphere_radius,
    winkler_cases,
    winkler_contact_radius,
    winkler_cylinder_force,
    winkler_sphere_force,
)

M, H = 2.0e6, 1.5e-3  # a confined modulus [Pa] and a layer thickness [m]
G, R, A = 0.4e6, 0.08, 6e-3  # shear modulus [Pa], indenter radius, contact size [m]


@pytest.mark.parametrize("radius, delta", [(0.05, 0.1e-3), (0.1, 0.08e-3), (0.013, 0.37e-3)])
def test_winkler_forces_are_the_column_pressures_integrated(radius, delta):
    """Each column is compressed by δ − r²/(2R), so p = M (δ − r²/(2R)) / h over the disc or
    strip where that is positive, which ends at a = √(2Rδ)."""
    a = winkler_contact_radius(radius, delta)
    assert delta - a**2 / (2 * radius) == pytest.approx(0.0, abs=1e-15)

    def p(r):
        return M * (delta - r**2 / (2 * radius)) / H

    sphere, _ = quad(lambda r: 2 * np.pi * r * p(r), 0.0, a)
    cylinder, _ = quad(p, -a, a)
    assert winkler_sphere_force(radius, delta, M, H) == pytest.approx(sphere, rel=1e-12)
    assert winkler_cylinder_force(radius, delta, M, H) == pytest.approx(cylinder, rel=1e-12)


def _film_pressure(flux, a: float, x: float) -> float:
    """p(x) = ∫ₓᵃ 3G q(s)/h³ ds: the squeeze flux q = −h³ p'/(3G) integrated from the edge p(a) = 0."""
    return quad(lambda s: 3 * G * flux(s) / H**3, x, a)[0]


def test_thin_film_cylinder_from_the_squeeze_flux():
    """Plane strain: incompressibility dq/dx = δ − x²/(2R) with q(0) = 0 gives the flux
    q = δ x − x³/(6R); the edge condition p'(a) = 0 is q(a) = 0, so δ = a²/(6R), a = √(6Rδ);
    the pressure and the force per unit length are integrals of q."""
    delta = thin_film_cylinder_indentation(A, R)
    assert thin_film_cylinder_half_width(R, delta) == pytest.approx(A, rel=1e-14)

    def flux(s):
        return delta * s - s**3 / (6 * R)

    assert flux(A) == pytest.approx(0.0, abs=1e-15)
    xs = np.array([0.0, 0.3 * A, -0.7 * A, 0.95 * A])
    want = [_film_pressure(flux, A, abs(x)) for x in xs]
    np.testing.assert_allclose(thin_film_cylinder_pressure(xs, G, A, R, H), want, rtol=1e-10)
    assert thin_film_cylinder_pressure(np.array([1.01 * A]), G, A, R, H)[0] == 0.0
    force, _ = quad(lambda x: _film_pressure(flux, A, abs(x)), -A, A)
    assert thin_film_cylinder_force(G, A, R, H) == pytest.approx(force, rel=1e-10)


def test_thin_film_sphere_from_the_squeeze_flux():
    """Axisymmetric: (1/r) d(r q)/dr = δ − r²/(2R) gives q = δ r/2 − r³/(8R); q(a) = 0 gives
    δ = a²/(4R), a = 2√(Rδ); the force is ∫ 2π r p dr."""
    delta = thin_film_sphere_indentation(A, R)
    assert thin_film_sphere_radius(R, delta) == pytest.approx(A, rel=1e-14)

    def flux(s):
        return delta * s / 2 - s**3 / (8 * R)

    assert flux(A) == pytest.approx(0.0, abs=1e-15)
    rs = np.array([0.0, 0.4 * A, 0.9 * A])
    want = [_film_pressure(flux, A, r) for r in rs]
    np.testing.assert_allclose(thin_film_sphere_pressure(rs, G, A, R, H), want, rtol=1e-10)
    force, _ = quad(lambda r: 2 * np.pi * r * _film_pressure(flux, A, r), 0.0, A)
    assert thin_film_sphere_force(G, A, R, H) == pytest.approx(force, rel=1e-10)


def test_winkler_cases_are_within_5_percent_of_the_limits():
    """A 1 mm layer, nu = 0, 0.75 mm face cells: a/h = 2.8-4, where the Winkler limit holds to
    a few per cent (its neglected shear coupling between columns is O((h/a)²))."""
    rows = winkler_cases(0.001, 16)
    assert [r["shape"] for r in rows] == ["sphere", "sphere", "cylinder"]
    assert list(rows[0]) == ["shape", "R", "delta", "a_over_h", "F_fe", "F_limit", "rel_err"]
    e = 1.0e6  # M = E at nu = 0
    assert rows[0]["F_limit"] == pytest.approx(np.pi * 0.05 * e * 0.1e-3**2 / 0.001, rel=1e-14)
    assert rows[1]["a_over_h"] == pytest.approx(4.0, rel=1e-14)  # √(2 · 0.1 · 0.08e-3) / 1 mm
    for r in rows:
        assert abs(r["F_fe"] / r["F_limit"] - 1) < 0.05, r


def test_thin_film_cylinder_error_falls_as_h_over_a_squared():
    """Plane strain at nu = 0.49999: the thin-film limit drops corrections of order (h/a)², so
    doubling a/h from 10 to 20 divides the relative error by about 4, and it is within 5 % at
    a/h = 20; the column compressibility 3 (a/h)² G/K is the row's last column."""
    rows = thin_film(0.49999, [10, 20], [])
    mat = Material(1.0e6, 0.49999)
    assert [r["a_over_h"] for r in rows] == [10, 20]
    assert list(rows[0]) == [
        "shape",
        "a_over_h",
        "hex_mm",
        "F_fe",
        "F_limit",
        "seconds",
        "rel_err",
        "compressibility_3a2G_over_h2K",
    ]
    for r in rows:
        a, h = r["a_over_h"] * THIN_FILM_H, THIN_FILM_H
        assert r["F_limit"] == pytest.approx(2 * mat.mu * a**5 / (15 * THIN_FILM_R * h**3), rel=1e-14)
        assert r["compressibility_3a2G_over_h2K"] == pytest.approx(3 * r["a_over_h"] ** 2 * mat.mu / mat.bulk)
    e10, e20 = (r["rel_err"] for r in rows)
    assert 0 < e20 < 0.05 < e10
    assert 3.0 < e10 / e20 < 5.0


@pytest.mark.jit_only("a 3D layer of 1 x 1 x 0.25 mm hexes, 25 s as pure Python")
def test_thin_film_sphere_is_above_the_limit_by_the_h_over_a_correction():
    """The (h/a)² corrections stiffen a finite layer, as for the cylinder: at a/h = 10 the FE
    force is above the limit, by less than 20 %."""
    (row,) = thin_film(0.49999, [], [10])
    assert row["shape"] == "sphere" and row["hex_mm"] == "1x1x0.25"
    assert 0 < row["rel_err"] < 0.2
