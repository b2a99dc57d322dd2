"""Geometrically nonlinear wall (workbench.fem.wall_nonlinear): its small-closing limit against the
linear squeeze, and the load-curve reading (the St. Venant–Kirchhoff assembly: tests/test_fem_svk.py)."""

import numpy as np
import pytest

from workbench.fem.material import Material
from workbench.fem.wall import build_wall, circle_surface, squeeze
from workbench.fem.wall_nonlinear import curve_stiffness, curve_work, squeeze_nonlinear


@pytest.mark.jit_only("over 15 s as pure Python")
def test_small_closing_is_the_linear_squeeze():
    """At a closing of 1/50 of the wall thickness rotations are negligible: the nonlinear
    wall's secant stiffness is the linear squeeze's (same mesh, clamps, jaws)."""
    wall = build_wall(circle_surface(0.03), Material(2.5e9, 0.4), n_theta=16, n_z=6, z_range=(0.0, 0.06))
    c = np.array([0.0, 0.0, 0.03])
    lin = squeeze(wall, c, np.array([1.0, 0.0, 0.0]), force=1.0)
    f_small = 0.02 * lin.stiffness * 1e-5  # the force at a closing of 0.01 mm
    nl = squeeze_nonlinear(wall, c, force=f_small, step=0.5e-5, max_closing=1e-4)
    assert nl.stiffness == pytest.approx(lin.stiffness, rel=0.01)
    np.testing.assert_allclose(nl.jaw_forces[-1, 0], nl.jaw_forces[-1, 1], rtol=1e-3)
    # the answer says why the curve stopped; its arrays cannot be written
    assert nl.status == "reached" and nl.reason is None and not nl.on_clamp
    assert nl.closing.shape == (nl.jaw_forces.shape[0],) and nl.closing[0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        nl.closing[0] = 1.0
    # a curve stopped by max_closing below the force (about 1/20 of it there): no stiffness, and
    # the status says why
    short = squeeze_nonlinear(wall, c, force=1e3 * f_small, step=0.5e-5, max_closing=1e-5)
    assert short.status == "max_closing" and "max_closing" in short.reason and np.isnan(short.stiffness)
    with pytest.raises(ValueError, match="positive jaw force"):
        squeeze_nonlinear(wall, c, force=0.0)
    with pytest.raises(ValueError, match="misses the object"):
        squeeze_nonlinear(wall, np.array([0.0, 0.0, 0.5]), force=1.0)


def test_curve_stiffness_on_a_linear_spring():
    closing = np.array([0.0, 1e-3, 2e-3, 3e-3])
    forces = np.column_stack([5000.0 * closing] * 2)  # s = 5000 N/m
    s, w = curve_stiffness(closing, forces, 10.0)
    assert s == pytest.approx(5000.0) and w == pytest.approx(0.5 * 10.0 * 2e-3)
    # the same wall twice as stiff (E x 2): same closings, twice the force
    s2, w2 = curve_stiffness(closing, forces, 10.0, e_scale=2.0)
    assert s2 == pytest.approx(10000.0) and w2 == pytest.approx(0.5 * 10.0 * 1e-3)
    assert np.isnan(curve_stiffness(closing, forces, 100.0)[0])  # not reached
    with pytest.raises(ValueError, match="closing"):
        curve_stiffness(closing[1:], forces[1:], 10.0)


def test_curve_work_against_closed_forms():
    """∫ f dΔ on a load curve: exact for a linear spring (f² / 2s), to the trapezoid's
    error on a stiffening f = c Δ² (c Δ³ / 3); past the curve NaN, or its end when the
    jaw rests on a clamped base."""
    closing = np.linspace(0.0, 4e-3, 9)
    lin = np.column_stack([5000.0 * closing] * 2)
    f = np.array([0.0, 1.0, 7.5, 20.0])
    w, d = curve_work(closing, lin, f)
    assert np.allclose(w, f**2 / (2 * 5000.0), rtol=1e-12, atol=0) and np.allclose(d, f / 5000.0)
    assert np.allclose(w, [curve_stiffness(closing, lin, x)[1] if x > 0 else 0.0 for x in f])
    c = 1e6  # N/m²
    fine = np.linspace(0.0, 4e-3, 4001)
    quad = np.column_stack([c * fine**2, c * fine**2])
    w, d = curve_work(fine, quad, [4.0, 9.0])
    assert np.allclose(d, np.sqrt([4.0, 9.0] / np.array(c)), rtol=1e-6)
    assert np.allclose(w, c * d**3 / 3, rtol=1e-6)
    (w_past,), _ = curve_work(closing, lin, [25.0])
    assert np.isnan(w_past)  # 20 N is the curve's end
    (w_rest,), (d_rest,) = curve_work(closing, lin, [25.0], rigid_beyond=True)
    assert w_rest == pytest.approx(20.0**2 / (2 * 5000.0)) and d_rest == 4e-3
    with pytest.raises(ValueError, match="NaN"):
        curve_work(closing, lin, [np.nan])
