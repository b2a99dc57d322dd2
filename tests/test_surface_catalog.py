"""workbench.sources.surface_catalog: the thesis's surfaces S1-S6 (Table 3.1) and
Example 3.2.5 — points on their implicit equations, analytic derivatives against central
differences, outward normals, the yz-plane symmetry, and areas against closed forms or
scipy's quad."""

import numpy as np
import pytest
from scipy import integrate

from workbench import surface_moments
from workbench.sources.surface_catalog import (
    PLANAR_NORMAL,
    S2,
    S4,
    S6,
    THESIS_SURFACES,
    example_3_2_5,
)

# implicit equation g(x) = 0 of each surface and the outward direction (the gradient of g
# or its opposite), from Table 3.1's parameters
CYL = {"S1": (1.0, 1.0), "S2": (1.0, 0.5)}
ELL = {"S3": (1.0, 1.0, 1.0), "S4": (1.0, 0.5, 0.6)}
PAR = {"S5": (1.0, 1.0), "S6": (1.0, 0.5)}


def _grid(surface, n=15):
    """Interior (u, v) points (the poles and apexes, where the normal is undefined, left out)."""
    (u0, u1), (v0, v1) = surface.u_range, surface.v_range
    u, v = np.meshgrid(np.linspace(u0, u1, n + 2)[1:-1], np.linspace(v0, v1, n + 2)[1:-1])
    return u.ravel(), v.ravel()


def _implicit(name, x):
    """(g, outward unit normal) at points x (P, 3)."""
    X, Y, Z = x.T
    if name in CYL:
        a, b = CYL[name]
        g, out = (X / a) ** 2 + (Y / b) ** 2 - 1, np.c_[X / a**2, Y / b**2, 0 * X]  # away from the axis
    elif name in ELL:
        a, b, c = ELL[name]
        g, out = (X / a) ** 2 + (Y / b) ** 2 + (Z / c) ** 2 - 1, np.c_[X / a**2, Y / b**2, Z / c**2]
    else:
        a, b = PAR[name]
        # the convex body z >= (x/a)² + (y/b)²: outward is −∇(z − (x/a)² − (y/b)²)
        g, out = Z - (X / a) ** 2 - (Y / b) ** 2, np.c_[2 * X / a**2, 2 * Y / b**2, -1 + 0 * X]
    return g, out / np.linalg.norm(out, axis=1, keepdims=True)


def test_table_3_1_in_order():
    assert list(THESIS_SURFACES) == ["S1", "S2", "S3", "S4", "S5", "S6"]
    assert all(
        THESIS_SURFACES[n].name == n and THESIS_SURFACES[n].analytic_derivatives for n in THESIS_SURFACES
    )
    np.testing.assert_array_equal(PLANAR_NORMAL, [0.0, 1.0, 0.0])


@pytest.mark.parametrize("name", list(THESIS_SURFACES))
def test_points_normals_and_derivatives(name):
    S = THESIS_SURFACES[name]
    u, v = _grid(S)
    x, n, jac, p = S.evaluate(u, v)
    g, outward = _implicit(name, x)
    np.testing.assert_allclose(g, 0.0, atol=1e-14)
    np.testing.assert_allclose(np.einsum("ij,ij->i", n, outward), 1.0, rtol=1e-12)
    np.testing.assert_array_equal(p, 1.0)  # uniform unit pressure
    # analytic derivatives against central differences (h = 1e-6: error ~h² + eps/h ~ 1e-10)
    h = 1e-6
    su, sv = S.derivatives(u, v)
    np.testing.assert_allclose(su, (S.sigma(u + h, v) - S.sigma(u - h, v)) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(sv, (S.sigma(u, v + h) - S.sigma(u, v - h)) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(jac, np.linalg.norm(np.cross(su, sv), axis=1), rtol=1e-14)


@pytest.mark.parametrize("name", list(THESIS_SURFACES))
def test_symmetric_about_the_yz_plane(name):
    """Every surface is mapped onto itself by x -> −x: each mirrored point satisfies the same
    equation and lies in the parameter domain (its mirror is a surface point too)."""
    S = THESIS_SURFACES[name]
    x = S.sigma(*_grid(S))
    mirrored = x * [-1, 1, 1]
    np.testing.assert_allclose(_implicit(name, mirrored)[0], 0.0, atol=1e-14)
    # the mirrored set is the set itself: every mirrored point has a twin at the grid
    # (the grids are symmetric about the middle of u, which maps x to −x)
    d = np.linalg.norm(mirrored[:, None] - x[None], axis=2).min(axis=1)
    np.testing.assert_allclose(d, 0.0, atol=1e-12)


def test_areas_against_closed_forms_and_quad():
    """S2: half an ellipse's perimeter × 1, ∫_0^π √(sin²u + 0.25 cos²u) du (quad); S6: the
    surface integral ∫∫ |σ_u × σ_v| du dv of [v cos u, 0.5 v sin u, v²] (dblquad of the
    hand-derived |σ_u × σ_v| = v √(0.25 + 4 v² (0.25 cos²u + sin²u)));  S4: the half
    ellipsoid's area ∫∫ cos u √(b²c² cos²u cos²v + a²c² cos²u sin²v + a²b² sin²u) (dblquad)."""
    s2, _ = integrate.quad(lambda u: np.sqrt(np.sin(u) ** 2 + 0.25 * np.cos(u) ** 2), 0, np.pi, epsabs=1e-13)
    assert surface_moments(S2).area == pytest.approx(s2, rel=1e-10)
    s6, _ = integrate.dblquad(
        lambda v, u: v * np.sqrt(0.25 + 4 * v**2 * (0.25 * np.cos(u) ** 2 + np.sin(u) ** 2)),
        0,
        np.pi,
        0,
        1,
        epsabs=1e-13,
    )
    assert surface_moments(S6).area == pytest.approx(s6, rel=1e-9)
    a, b, c = ELL["S4"]

    def s4_density(v, u):
        cu, su, cv, sv = np.cos(u), np.sin(u), np.cos(v), np.sin(v)
        return cu * np.sqrt((b * c * cu * cv) ** 2 + (a * c * cu * sv) ** 2 + (a * b * su) ** 2)

    s4, _ = integrate.dblquad(s4_density, -np.pi / 2, np.pi / 2, 0, np.pi, epsabs=1e-13)
    assert surface_moments(S4).area == pytest.approx(s4, rel=1e-9)


def test_example_3_2_5_is_the_printed_patch():
    """[0.02 cos u, 0.02 sin u, v], u ∈ [π/4, 3π/4], v ∈ [−0.05, −0.03] m, p = 10³ Pa:
    area R (π/2) × 0.02 = π × 2e-4 m², force 10³ × area (Σ p a)."""
    ex = example_3_2_5()
    assert ex.u_range == pytest.approx((np.pi / 4, 3 * np.pi / 4)) and ex.v_range == (-0.05, -0.03)
    u, v = _grid(ex)
    x, n, _, p = ex.evaluate(u, v)
    np.testing.assert_allclose(np.hypot(x[:, 0], x[:, 1]), 0.02, rtol=1e-14)
    np.testing.assert_allclose(n, x * [1, 1, 0] / 0.02, atol=1e-14)  # radial, outward
    np.testing.assert_allclose(p, 1e3, rtol=1e-15)
    m = surface_moments(ex)
    assert m.area == pytest.approx(0.02 * np.pi / 2 * 0.02, rel=1e-12)
    assert m.F == pytest.approx(1e3 * m.area, rel=1e-12)
