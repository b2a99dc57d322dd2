"""workbench.limit_surface.contact_wrench: the contact-wrench model c = w + F ŵ⊥ (thesis
Eqs. 3.25–3.28) on an axis-aligned ellipsoidal limit surface, whose value, surface points
and support function are known in closed form."""

import numpy as np
import pytest

from workbench.limit_surface.contact_wrench import ContactWrenchModel
from workbench.limit_surface.ellipsoid import EllipsoidLS
from workbench.limit_surface.normalize import Subspace

# semi-axes of the normalised (F = 1) limit surface: Σ (w_i / s_i)² = 1 [N, N, N, Nm, Nm, Nm]
SEMI = np.array([0.5, 0.4, 0.3, 0.02, 0.015, 0.01])
NORMAL = np.array([0.0, 0.0, 1.0, 0.001, -0.002, 0.0])  # ŵ⊥ for F = 1


def _model():
    """f(w) = Σ (w_i / s_i)²: A_e = I in coordinates normalised by scale = SEMI, full 6D."""
    ls = EllipsoidLS(SEMI, SEMI, Subspace(np.eye(6), np.zeros((6, 0)), np.ones(6)), A_e=np.eye(6))
    return ContactWrenchModel(ls, NORMAL)


def test_value_is_the_shifted_scaled_ellipsoid(rng):
    """Eq. 3.26: f((c − F ŵ⊥) / F) = Σ ((c_i − F n_i) / (F s_i))²; 1 on the surface, < 1 inside."""
    model = _model()
    c = rng.normal(size=(50, 6)) * SEMI * 3
    for F in (1.0, 2.5, 40.0):
        ref = (((c * F - F * NORMAL) / (F * SEMI)) ** 2).sum(axis=1)
        np.testing.assert_allclose(model.value(c * F, F), ref, rtol=1e-12)
    assert model.value(7.0 * NORMAL, 7.0) == 0.0  # the normal wrench alone: the centre
    tip = 3.0 * (NORMAL + SEMI * np.eye(6)[4])  # one semi-axis from the centre at F = 3
    assert model.value(tip, 3.0) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("F", [1.0, 12.0])
def test_inner_vertices_lie_on_the_surface(F):
    """Eq. 3.27: every vertex F (ŝ + ŵ⊥) satisfies Σ ((v/F − n_i) / s_i)² = 1, and the
    vertices spread over the surface (both signs of every component)."""
    V = _model().inner_vertices(300, F)
    assert V.shape == (300, 6)
    np.testing.assert_allclose((((V / F - NORMAL) / SEMI) ** 2).sum(axis=1), 1.0, rtol=1e-12)
    d = V / F - NORMAL
    assert (d.max(axis=0) > 0.5 * SEMI).all() and (d.min(axis=0) < -0.5 * SEMI).all()


@pytest.mark.parametrize("F", [1.0, 12.0])
def test_outer_half_spaces_are_tangent_planes(rng, F):
    """Eq. 3.28: A c <= b.  The ellipsoid Σ (x_i / s_i)² <= 1 has support function
    h(a) = √(Σ a_i² s_i²); a tangent half-space with unit normal a is a·x <= h(a), so
    shifted by F ŵ⊥ and scaled by F:  b = F (h(a) + a·ŵ⊥).  Every point of the scaled
    ellipsoid then satisfies A c <= b."""
    A, b = _model().outer(200, F)
    assert A.shape == (200, 6) and b.shape == (200,)
    np.testing.assert_allclose(np.linalg.norm(A, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(b, F * (np.sqrt((A**2 * SEMI**2).sum(axis=1)) + A @ NORMAL), rtol=1e-12)
    u = rng.normal(size=(2000, 6))
    inside = F * (NORMAL + SEMI * u / np.linalg.norm(u, axis=1, keepdims=True))  # on the surface
    assert (inside @ A.T <= b + 1e-12 * np.abs(b).max()).all()
    # the polytope is outside: its tangent points (the inner vertices of the same directions)
    # lie on its planes
    V = _model().inner_vertices(200, F)
    np.testing.assert_allclose(np.einsum("ij,ij->i", A, V), b, rtol=1e-12)


def test_a_force_that_is_not_positive_is_refused():
    model = _model()
    for F in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="scale factor must be > 0"):
            model.value(NORMAL, F)
