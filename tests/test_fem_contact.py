"""Condensed-pad contact: LCP correctness and the compressible thin-layer (Winkler) limit."""

import numpy as np
import pytest

from fem.contact import solve_contact, solve_lcp
from fem.material import Material
from fem.obstacles import Cylinder, Plane, Sphere
from fem.pad import PadGeometry, condense_pad


def test_lcp_solution_is_complementary():
    rng = np.random.default_rng(0)
    B = rng.standard_normal((40, 40))
    A = B @ B.T + 40 * np.eye(40)
    d = rng.standard_normal(40)
    lam, _, _ = solve_lcp(A, d)
    w = A @ lam + d
    assert (lam >= 0).all() and (w >= -1e-10).all()
    assert np.abs(lam * w).max() <= 1e-10


@pytest.fixture(scope="module")
def thin_pad():
    # h = 1 mm, 0.5 mm face spacing: a/h = 3.2 for the indentation below
    geom = PadGeometry(width=0.012, length=0.012, thickness=0.001, nx=24, ny=24, nz=2)
    return condense_pad(geom, Material(E=1.0e6, nu=0.0))


def test_sphere_on_thin_compressible_layer_matches_winkler(thin_pad):
    # Winkler: p = (M/h)(δ - r²/2R), a = sqrt(2Rδ), F = π R M δ² / h   (M = E at nu = 0)
    R, delta = 0.05, 0.1e-3
    h = thin_pad.geometry.thickness
    sol = solve_contact(thin_pad, Sphere((0, 0, h + R), R), delta)
    M = thin_pad.material.p_wave
    a = np.sqrt(2 * R * delta)
    assert a / h >= 3
    F_w = np.pi * R * M * delta**2 / h
    assert sol.force == pytest.approx(F_w, rel=0.05)
    assert sol.max_penetration <= 1e-6 * h
    r = np.hypot(*thin_pad.face_xy.T)
    assert (sol.lam[r > 1.3 * a] == 0).all()  # no force well outside the contact radius


def test_plane_and_no_contact(thin_pad):
    h = thin_pad.geometry.thickness
    far = solve_contact(thin_pad, Sphere((0, 0, h + 0.05 + 1e-3), 0.05), 0.0)
    assert not far.in_contact and far.force == 0.0
    flat = solve_contact(thin_pad, Plane((0, 0, h), (0, 0, -1)), 0.05e-3)
    assert flat.force > 0 and (flat.lam >= 0).all()
    with pytest.raises(ValueError, match="deeper than the layer"):
        solve_contact(thin_pad, Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 2 * h)
