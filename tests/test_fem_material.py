"""Isotropic linear-elastic material (workbench.fem.material): the derived moduli against
the textbook conversion formulas, and careless input."""

import dataclasses

import numpy as np
import pytest

from workbench.fem.material import Material


@pytest.mark.parametrize(
    "E, nu", [(0.0, 0.3), (-1.0, 0.3), (1e6, 0.5), (1e6, -1.0), (1e6, 0.7), (np.nan, 0.3)]
)
def test_bad_material(E, nu):
    with pytest.raises(ValueError, match="E must be|nu must be"):
        Material(E=E, nu=nu)


def test_derived_moduli_at_nu_one_quarter_by_hand():
    """E = 1 MPa, nu = 1/4: G = E / 2.5 = 0.4 MPa; lambda = E nu / ((1 + nu)(1 - 2 nu))
    = 0.25 / 0.625 MPa = 0.4 MPa (= G at nu = 1/4, the Poisson solid); K = E / (3 (1 - 2 nu))
    = 2/3 MPa; M = lambda + 2 G = 1.2 MPa."""
    m = Material(E=1.0e6, nu=0.25)
    assert m.mu == pytest.approx(4.0e5, rel=1e-14)
    assert m.lam == pytest.approx(4.0e5, rel=1e-14)
    assert m.bulk == pytest.approx(2.0e6 / 3.0, rel=1e-14)
    assert m.p_wave == pytest.approx(1.2e6, rel=1e-14)


@pytest.mark.parametrize("E, nu", [(2.5e9, 0.4), (1.0e6, 0.0), (3.0e5, 0.499), (7.0e4, -0.3)])
def test_derived_moduli_match_the_conversion_formulas(E, nu):
    """K = E / (3 (1 - 2 nu)), M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), and back from (lambda, G):
    E = G (3 lambda + 2 G) / (lambda + G), nu = lambda / (2 (lambda + G)) — the standard table
    of elastic-moduli conversions, other formulas than the module's."""
    m = Material(E=E, nu=nu)
    assert m.bulk == pytest.approx(E / (3.0 * (1.0 - 2.0 * nu)), rel=1e-12)
    assert m.p_wave == pytest.approx(E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)), rel=1e-12)
    lam, G = m.lam, m.mu
    assert G * (3.0 * lam + 2.0 * G) / (lam + G) == pytest.approx(E, rel=1e-12)
    assert lam / (2.0 * (lam + G)) == pytest.approx(nu, rel=1e-12, abs=1e-15)
    # nearly incompressible silicone: K / G = 2 (1 + nu) / (3 (1 - 2 nu)) = 499.67 at 0.499
    assert m.bulk / m.mu == pytest.approx(2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)), rel=1e-12)


@pytest.mark.parametrize(
    "E, nu, match",
    [
        (np.inf, 0.3, "E must be a positive Young's modulus"),
        (-np.inf, 0.3, "E must be a positive Young's modulus"),
        (1e6, np.nan, r"nu must be a Poisson ratio in \(-1, 0.5\)"),
        (1e6, 0.5, "for incompressible silicone use e.g. 0.499"),
    ],
)
def test_bad_material_messages(E, nu, match):
    with pytest.raises(ValueError, match=match):
        Material(E=E, nu=nu)


def test_material_is_immutable():
    m = Material(E=1.0e6, nu=0.45)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.E = 2.0e6
    assert m.E == 1.0e6
