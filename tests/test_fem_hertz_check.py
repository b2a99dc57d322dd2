"""The condensed pad against Hertz (workbench.fem.hertz_check): the Hertz formulas against
their derivation, the profile fit on an exact profile, and a graded block against Hertz."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from workbench.fem.hertz_check import (
    fit_hertz_pressure,
    hertz_block_case,
    hertz_contact_radius,
    hertz_peak_pressure,
)


@pytest.mark.parametrize("R, a, e_star", [(0.02, 1.5e-3, 1.0e6 / 0.91), (0.005, 0.4e-3, 3.3e6)])
def test_hertz_radius_and_peak_pressure_invert_the_force(R, a, e_star):
    """Hertz: δ = a²/R and F = (4/3) E* √R δ^(3/2) = 4 E* a³ / (3R); the pressure
    p₀ √(1 − r²/a²) integrates over the disc to (2/3) π a² p₀ = F."""
    force = 4 * e_star * a**3 / (3 * R)
    assert force == pytest.approx(4 / 3 * e_star * np.sqrt(R) * (a * a / R) ** 1.5, rel=1e-12)
    assert hertz_contact_radius(force, R, e_star) == pytest.approx(a, rel=1e-12)
    p0 = hertz_peak_pressure(force, a)
    total, _ = quad(lambda r: 2 * np.pi * r * p0 * np.sqrt(1 - (r / a) ** 2), 0.0, a)
    assert total == pytest.approx(force, rel=1e-9)


def test_the_fit_recovers_an_exact_hertz_profile():
    a, p0 = 1.5e-3, 5.3e4
    r = np.linspace(0.0, 0.8 * a, 9)
    got_a, got_p0 = fit_hertz_pressure(r, p0 * np.sqrt(1 - (r / a) ** 2))
    assert got_a == pytest.approx(a, rel=1e-10)
    assert got_p0 == pytest.approx(p0, rel=1e-10)


def test_growth_must_coarsen_the_mesh():
    with pytest.raises(ValueError, match="growth must be > 1"):
        hertz_block_case(0.6e-3, 0.9)


@pytest.mark.jit_only("a graded 40 mm block (19k dofs) condensed: over a minute as pure Python")
def test_coarse_block_is_near_hertz():
    """At a/h = 2.5 (0.6 mm hexes under a = 1.5 mm): a from the fit within 10 % and p₀ within
    3 % of Hertz at the FE force, the patch holds the whole contact, and the force is above
    Hertz's at δ = a²/R (a block 13 a deep and trilinear hexes both stiffen) by under 10 %."""
    R, a, e_star = 0.02, 1.5e-3, 1.0e6 / (1 - 0.3**2)
    row = hertz_block_case(0.6e-3, 1.35)
    assert row["a_over_h"] == pytest.approx(2.5, rel=1e-12)
    assert row["a_hertz_mm"] == pytest.approx(1e3 * (3 * row["F_N"] * R / (4 * e_star)) ** (1 / 3), rel=1e-12)
    assert abs(row["a_rel_err"]) < 0.1
    assert abs(row["p0_rel_err"]) < 0.03 and abs(row["p0_fit_rel_err"]) < 0.03
    assert row["patch_edge_force_N"] == 0.0
    f_hertz = 4 * e_star * a**3 / (3 * R)
    assert 1.0 < row["F_N"] / f_hertz < 1.1
