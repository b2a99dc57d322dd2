"""Drake hydroelastic pad (workbench.peers.drake_hydro): the force law and modulus mapping in closed
form, Drake's contact surface as a profile against the elastic-foundation law (skipped without
``pydrake``), careless input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from workbench.fem.obstacles import Cylinder, Sphere
from workbench.peers.drake_hydro import (
    DrakeHydroPad,
    foundation_depth,
    hydroelastic_modulus,
    sphere_force_law,
)
from workbench.wrench import normal_wrench

R, H_LAYER, E_HYDRO = 0.02, 0.01, 1.0e6  # a 20 mm sphere on a 40 x 40 x 10 mm pad, E_hydro = 1 MPa
OBSTACLE = Sphere((0.0, 0.0, H_LAYER + R), R)
DELTAS = (0.5e-3, 1e-3, 2e-3)


def test_force_law_against_quadrature():
    # p = E u / H with u(r) = δ - R + √(R² - r²) on the overlap r < r0 = √(2Rδ - δ²):
    # net normal force ∫ p dA_xy = (E/H) V, V = π δ² (3R - δ) / 3; the pressure integral over the
    # curved cap, dA = 2π R dz with u = z - (R - δ) for the height z above the centre, is
    # (E/H) 2π R ∫_{R-δ}^R (z - R + δ) dz = π R δ² E / H
    H = 0.01
    for d in DELTAS:
        r0 = np.sqrt(2 * R * d - d * d)
        fz, _ = quad(lambda r, d=d: E_HYDRO / H * (d - R + np.sqrt(R * R - r * r)) * 2 * np.pi * r, 0, r0)
        fm, _ = quad(lambda z, d=d: E_HYDRO / H * (z - R + d) * 2 * np.pi * R, R - d, R)
        law_z, law_m = sphere_force_law(R, d, E_HYDRO, H)
        assert law_z == pytest.approx(fz, rel=1e-10) and law_m == pytest.approx(fm, rel=1e-10)


def test_modulus_mapping():
    # box="doubled": H = h, so E_hydro = (E/h) h = E; box="layer": H = h/2, E_hydro = E/2
    assert foundation_depth(H_LAYER, 0.04, 0.04) == H_LAYER
    assert foundation_depth(H_LAYER, 0.04, 0.04, box="layer") == H_LAYER / 2
    assert hydroelastic_modulus(1e6, H_LAYER, 0.04, 0.04) == pytest.approx(1e6, rel=1e-15)
    assert hydroelastic_modulus(1e6, H_LAYER, 0.04, 0.04, box="layer") == pytest.approx(5e5, rel=1e-15)
    confined = hydroelastic_modulus(1e6, H_LAYER, 0.04, 0.04, nu=0.45, kind="confined")
    assert confined == pytest.approx(0.55e6 / (1.45 * 0.1), rel=1e-12)
    with pytest.raises(ValueError, match="box='layer'"):
        foundation_depth(0.03, 0.04, 0.04)  # a 60 mm box on a 40 mm pad: the sides set its field


@pytest.fixture(scope="module")
def pad():
    pytest.importorskip("pydrake.geometry")
    return DrakeHydroPad(OBSTACLE, H_LAYER, E_HYDRO)


def test_drake_force_follows_the_elastic_foundation_law(pad):
    # the sphere's tessellation (R/80 = 0.25 mm) is an inscribed polyhedron, shallower by ~res²/(8R)
    # = 0.4 µm: the force is low by ~2 × 0.4 µm / δ (measured 0.20, 0.10, 0.05 %)
    assert pad.H == H_LAYER
    for d in DELTAS:
        prof = pad.profile(d)
        law_z, law_m = sphere_force_law(R, d, E_HYDRO, pad.H)
        sag = 2 * pad.resolution**2 / (8 * R) / d
        assert normal_wrench(prof)[2] == pytest.approx(law_z, rel=1.5 * sag)
        assert prof.F == pytest.approx(law_m, rel=1.5 * sag)
        assert normal_wrench(prof)[2] < law_z
        # on the sphere (within its tessellation), normals out of it (into the pad), centred
        dist = np.linalg.norm(prof.centers - OBSTACLE.center, axis=1)
        assert (dist <= R + 1e-12).all() and (dist > R - pad.resolution**2 / R).all()
        assert (prof.normals[:, 2] < 0).all()
        assert np.abs(prof.pressure_center[:2]).max() < 0.02 * np.sqrt(2 * R * d)
        assert prof.pressures.max() == pytest.approx(E_HYDRO * d / pad.H, rel=1e-2)
    assert len(pad.query_seconds) >= len(DELTAS) and max(pad.query_seconds) < 1.0


def test_triangles_and_layer_box():
    pytest.importorskip("pydrake.geometry")
    d = 1e-3
    coarse = dict(resolution=R / 20)
    poly = DrakeHydroPad(OBSTACLE, H_LAYER, E_HYDRO, **coarse).profile(d)
    tri_pad = DrakeHydroPad(OBSTACLE, H_LAYER, E_HYDRO, representation="triangle", **coarse)
    tri = tri_pad.profile(d)
    # both integrate the same linear pressure field over the same surface exactly (the torques
    # about o differ: a centroid's pressure times area is not the element's exact first moment)
    assert tri.F == pytest.approx(poly.F, rel=1e-9)
    assert np.allclose(normal_wrench(tri)[:3], normal_wrench(poly)[:3], rtol=1e-9, atol=1e-12)
    assert np.abs(normal_wrench(tri)[3:] - normal_wrench(poly)[3:]).max() < 1e-6 * poly.F * R
    assert len(tri) > len(poly) and tri.faces is not None and tri.faces.shape[1] == 3
    # a box of the layer's own thickness has H = h/2: twice the force
    layer = DrakeHydroPad(OBSTACLE, H_LAYER, E_HYDRO, box="layer", **coarse)
    assert layer.H == H_LAYER / 2
    assert layer.profile(d).F == pytest.approx(2 * poly.F, rel=1e-9)


def test_no_contact_gives_none(pad):
    above = DrakeHydroPad(Sphere((0.0, 0.0, H_LAYER + R + 2e-3), R), H_LAYER, E_HYDRO, resolution=R / 10)
    assert above.profile(1e-3) is None


@pytest.mark.parametrize(
    ("delta", "match"),
    [(0.01, "1 mm = 1e-3"), (-1e-3, "jaw displacement"), (float("nan"), "finite"), (1.0, "1 mm")],
)
def test_careless_delta_raises(pad, delta, match):
    with pytest.raises(ValueError, match=match):
        pad.profile(delta)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"E_hydro": 1.0}, "1 MPa = 1e6"),  # modulus in MPa
        ({"h": 10.0}, "millimetres"),  # thickness in mm
        ({"obstacle": Cylinder()}, "sphere"),
        ({"representation": "quad"}, "representation"),
        ({"box": "thick"}, "box"),
    ],
)
def test_careless_construction_raises(kwargs, match):
    # the checks run before Drake is touched: no pydrake needed to see them
    args = {"obstacle": OBSTACLE, "h": H_LAYER, "E_hydro": E_HYDRO} | kwargs
    with pytest.raises(ValueError, match=match):
        DrakeHydroPad(**args)


def test_closed_forms_validate_too():
    with pytest.raises(ValueError, match="millimetres"):
        sphere_force_law(20.0, 1.0, E_HYDRO, 0.01)
    with pytest.raises(ValueError, match="positive depth"):
        sphere_force_law(R, -1e-3, E_HYDRO, 0.01)
    with pytest.raises(ValueError, match="1 MPa"):
        sphere_force_law(R, 1e-3, 1.0, 0.01)


def test_without_drake_the_error_names_the_install(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pydrake.geometry", None)
    with pytest.raises(ImportError, match="pip install"):
        DrakeHydroPad(OBSTACLE, H_LAYER, E_HYDRO)
