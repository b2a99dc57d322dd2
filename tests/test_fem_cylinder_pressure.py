"""workbench.fem.cylinder_pressure: the pad pressed on an elliptic cylinder, Eq. 4.3 fitted to
its pressures against r = |y| — checked in the Winkler limit (a thin layer with ν = 0: each
column in uniaxial strain, ``p = E (δ − z(y)) / h``, z the cylinder's rise above its apex),
where the pressures and the fitted k have a closed form to compare with."""

import numpy as np
import pytest

from workbench.fem.cylinder_pressure import cylinder_pressure_laws
from workbench.fem.material import Material
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.pressure import fit_power_law

E, H = 1.0e6, 0.001


@pytest.fixture(scope="module")
def thin_pad():
    # 20 x 40 x 1 mm, 2 x 0.5 x 0.5 mm hexes: the contact (half-width 8.5 mm) is 8.5 h wide
    return condense_pad(PadGeometry(0.02, 0.04, H, nx=10, ny=80, nz=2), Material(E, 0.0), cache_dir=False)


def _rise(y: np.ndarray, a: float, b: float) -> np.ndarray:
    """The ellipse's rise above its apex at y: a (1 − √(1 − y²/b²))."""
    return a * (1.0 - np.sqrt(1.0 - (y / b) ** 2))


def test_in_the_winkler_limit_the_pressures_and_k_are_the_closed_forms(thin_pad):
    a, b, delta = 0.03, 0.06, 0.3e-3
    (law,) = cylinder_pressure_laws(thin_pad, [(a, b)], [delta])
    winkler = E * (delta - _rise(law.r, a, b)) / H  # ν = 0: the oedometric modulus is E
    inner = law.r < 0.7 * law.fit.r_max  # the rim is smoothed over about one thickness
    assert np.abs(law.p[inner] / winkler[inner] - 1).max() < 0.05
    # the contact's half-width: where the rise reaches δ, b √(1 − (1 − δ/a)²) = 8.46 mm
    half = b * np.sqrt(1 - (1 - delta / a) ** 2)
    assert law.fit.r_max == pytest.approx(half, abs=0.6e-3)  # within one element (0.5 mm)
    # the law fitted to the FEM and to the closed form at the same r: one k
    closed = fit_power_law(law.r, np.clip(winkler, 0, None), r_max=law.fit.r_max)
    assert law.fit.k == pytest.approx(closed.k, rel=0.1)
    # the force: Σ p A over the contact against the closed form's ∫ p dy times the pad's width
    y = np.linspace(-half, half, 20001)
    force = 0.02 * np.trapezoid(E * (delta - _rise(y, a, b)) / H, y)
    assert law.force == pytest.approx(force, rel=0.05)


def test_displacements_must_be_positive_and_increasing(thin_pad):
    for deltas in ([0.2e-3, 0.1e-3], [0.0, 0.1e-3], []):
        with pytest.raises(ValueError, match="increasing jaw displacements > 0"):
            cylinder_pressure_laws(thin_pad, [(0.03, 0.06)], deltas)
