"""workbench.pressure: the power-law pressure of thesis Eqs. 2.14, 4.3 against its closed
forms (Hertz k = 2, linear k = 1, uniform k -> inf), its total force on a disc, and bad
parameters."""

import numpy as np
import pytest
from scipy import integrate

from workbench.pressure import fit_power_law, power_law


def test_hertz_linear_and_uniform_closed_forms():
    """k = 2: p0 √(1 − s²) (Hertz); k = 1: p0 (1 − s); s = r / r_max; zero at and beyond
    r_max; a large k tends to the uniform p0 inside."""
    r_max, p0 = 0.004, 2.5e5
    r = np.array([0.0, 0.001, 0.002, 0.003, 0.0039, 0.004, 0.005])
    s = np.minimum(r / r_max, 1.0)
    np.testing.assert_allclose(power_law(r, r_max, 2.0, p0), p0 * np.sqrt(1 - s**2), rtol=1e-14, atol=0)
    np.testing.assert_allclose(power_law(r, r_max, 1.0, p0), p0 * (1 - s), rtol=1e-14, atol=1e-9)
    assert power_law(r, r_max, 2.0, p0)[-2:].tolist() == [0.0, 0.0]
    np.testing.assert_allclose(power_law(r[:4], r_max, np.inf, p0), p0, rtol=0)
    # k = 200 at s = 3/4: (1 − 0.75^200)^(1/200) = 1 − 1.6e-28 / 200 ≈ 1
    assert power_law([0.003], r_max, 200.0, p0)[0] == pytest.approx(p0, rel=1e-15)
    # the default p0 is 1 (a shape to scale), and lists are accepted
    assert power_law([0.0, 0.002], r_max, 2.0).tolist() == pytest.approx([1.0, np.sqrt(0.75)], rel=1e-15)


def test_hertz_force_on_a_disc():
    """∫ p 2π r dr over the disc for k = 2 is (2/3) π r_max² p0 (the Hertz load); for k = 1 it
    is (1/3) π r_max² p0 (a cone).  Reference: the closed forms; power_law under scipy's quad."""
    r_max, p0 = 0.004, 2.5e5
    for k, factor in ((2.0, 2 / 3), (1.0, 1 / 3)):
        got, _ = integrate.quad(
            lambda r, k=k: power_law(np.array([r]), r_max, k, p0)[0] * 2 * np.pi * r, 0, r_max
        )
        assert got == pytest.approx(factor * np.pi * r_max**2 * p0, rel=1e-9)


def test_uniform_pressure_is_zero_from_the_rim_on():
    # the k -> inf limit of [1 - s^k]^(1/k): 1 for s < 1, 0 for s >= 1 (k = 1e6 at s = 0.5 is 1 - 1e-301...)
    r = np.array([0.0, 0.002, 0.004, 0.006])
    assert power_law(r, 0.004, np.inf, 3.0).tolist() == [3.0, 3.0, 0.0, 0.0]
    assert np.allclose(power_law(r, 0.004, 1e4, 3.0), [3.0, 3.0, 0.0, 0.0], rtol=1e-3)


@pytest.mark.parametrize(
    "r_max, k, match",
    [
        (0.0, 2.0, "r_max must be > 0; got 0.0"),
        (-0.004, 2.0, "r_max must be > 0"),
        (np.nan, 2.0, "r_max must be > 0; got nan"),
        (np.inf, 2.0, "r_max must be > 0; got inf"),
        (0.004, 0.0, "k must be > 0; got 0.0"),
        (0.004, -2.0, "k must be > 0"),
        (0.004, np.nan, "k must be > 0; got nan"),
    ],
)
def test_bad_parameters_are_refused(r_max, k, match):
    with pytest.raises(ValueError, match=match):
        power_law(np.array([0.0, 0.001]), r_max, k)


def test_the_fit_recovers_the_exponent_and_scale_of_exact_power_laws():
    """Pressures made by Eq. 4.3 itself (k = 2.4, the thesis's Fig 4.2(d) value, and 5.5, its
    range's end) give back k and p0; r_max defaults to the largest r, where p is 0."""
    r = np.linspace(0.0, 0.012, 41)
    for k, p0 in ((2.4, 3.0e4), (5.5, 1.7)):
        fit = fit_power_law(r, power_law(r, 0.012, k, p0))
        assert fit.k == pytest.approx(k, rel=1e-5) and fit.p0 == pytest.approx(p0, rel=1e-6)
        assert fit.r_max == 0.012 and fit.rms_rel < 1e-6 and not fit.at_bound
    # Hertz with 5 % multiplicative noise (seeded): k within 10 %, the residual about the noise
    rng = np.random.default_rng(7)
    p = power_law(r, 0.012, 2.0, 1.0) * (1 + 0.05 * rng.standard_normal(r.size))
    fit = fit_power_law(r, np.clip(p, 0, None))
    assert fit.k == pytest.approx(2.0, rel=0.1) and 0.02 < fit.rms_rel < 0.06


def test_the_fit_flags_data_outside_its_k_range_and_refuses_bad_input():
    r = np.linspace(0.0, 0.01, 20)
    flat = fit_power_law(r[:-1], np.ones(19), r_max=0.01)  # uniform inside: k wants infinity
    assert flat.at_bound and flat.k == pytest.approx(1000.0, rel=1e-3)
    with pytest.raises(ValueError, match="n >= 3"):
        fit_power_law(r[:2], r[:2])
    with pytest.raises(ValueError, match="one length"):
        fit_power_law(r, r[:-1])
    with pytest.raises(ValueError, match="finite and >= 0"):
        fit_power_law(-r, np.ones(20))
    with pytest.raises(ValueError, match="no positive pressure"):
        fit_power_law(r, np.zeros(20))
    with pytest.raises(ValueError, match=r"r_max must be > 0 and >= max\(r\)"):
        fit_power_law(r, np.ones(20), r_max=0.005)
    with pytest.raises(ValueError, match="k_range"):
        fit_power_law(r, np.ones(20), k_range=(2.0, 1.0))
