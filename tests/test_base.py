"""workbench.limit_surface.base: the fitting error (Eq. 3.18 and radial) of either model."""

import pytest

from workbench import fit_ellipsoid
from workbench.limit_surface.base import LimitSurfaceModel


@pytest.mark.jit_only("over 15 s as pure Python")
def test_radial_error_is_the_geometric_distance(s4_data, s4_quartic):
    # points at radius rho times the surface: radial error |rho - 1| for both degrees,
    # Eq. 3.18 |rho^d - 1|
    e = fit_ellipsoid(s4_data[1])
    for model in (e, s4_quartic):
        assert isinstance(model, LimitSurfaceModel)  # the error is the base class's, for either degree
        on = model.linearize(200, "inner", directions="sphere").vertices
        for rho in (0.9, 1.05):
            assert model.fitting_error(rho * on, "radial") == pytest.approx(abs(rho - 1), rel=1e-9)
            assert model.fitting_error(rho * on) == pytest.approx(abs(rho**model.degree - 1), rel=1e-9)
    with pytest.raises(ValueError, match="kind must be"):
        e.fitting_error(on, "nope")
    with pytest.raises(ValueError, match="at least one wrench"):  # not numpy's nan of an empty mean
        e.fitting_error(on[:0])
