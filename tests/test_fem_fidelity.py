"""One interface to the three fidelities of the pad contact (workbench.fem.fidelity):
``press`` returns a ``Pressed`` dict of solutions with the pad and obstacle, one call
away from a profile; a case with an exact answer; careless input.  ``sphere_press`` and
``pad_cache`` are in tests/conftest.py."""

import numpy as np
import pytest

from workbench.fem import press
from workbench.fem.contact import ContactSolution
from workbench.fem.extract import extract_profile
from workbench.fem.material import Material
from workbench.fem.obstacles import Plane, Sphere
from workbench.fem.pad import PadFace, PadGeometry

DELTAS_MM = [0.1, 0.25, 0.5, 1.0, 2.0, 3.0]  # conftest.SPHERE_PRESS_DELTAS_MM
MAT = Material(E=1.0e6, nu=0.45)  # as fem-fitting


def test_one_interface_for_three_fidelities():
    from workbench.fem.fidelity import press

    geom = PadGeometry(0.01, 0.01, 0.003, 6, 6, 2)
    h = geom.thickness
    obs = Sphere((0, 0, h + 0.008), 0.008)
    ds = [0.005 * h, 0.01 * h]
    res = {
        f: press(geom, MAT, obs, ds, fidelity=f, scheme="full", cache_dir=False)
        for f in ("condensed", "linear")
    }
    res["nonlinear"] = press(geom, MAT, obs, ds, fidelity="nonlinear", step=ds[0])
    for d in ds:
        f_c, f_l, f_n = (res[k][d].force for k in ("condensed", "linear", "nonlinear"))
        assert abs(f_c / f_l - 1) < 1e-9  # condensation is exact
        assert abs(f_n / f_l - 1) < 0.02  # small strain: the neo-Hookean pad is the linear one
        for r in res.values():  # every level carries its pad: press, then extract the profile
            prof = r.profile(d)
            assert prof.F == pytest.approx(r[d].force, rel=1e-12)
            assert prof.normal_wrench[2] > 0  # pushes the object away from the jaw (+z)
    assert type(res["linear"].pad).__name__ == "PadFace"
    assert res["nonlinear"].pad.face_xy.shape == res["condensed"].pad.face_xy.shape
    with pytest.raises(ValueError, match="fidelity must be one of"):
        press(geom, MAT, obs, ds, fidelity="exact")
    with pytest.raises(ValueError, match="unknown options"):
        press(geom, MAT, obs, ds, fidelity="linear", step=1.0)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_press_result_is_the_solutions_plus_pad(sphere_press):
    res = sphere_press
    assert sorted(res) == [d * 1e-3 for d in DELTAS_MM]  # still the {delta: solution} dict
    assert all(isinstance(s, ContactSolution) for s in res.values())
    assert res.fidelity == "condensed" and res.pad.face_xy.shape[0] == res[1e-3].lam.size
    profs = res.profiles()
    assert [p.F for p in profs.values()] == pytest.approx([s.force for s in res.values()], rel=1e-12)
    with pytest.raises(ValueError, match="no solution at delta"):
        res.profile(4e-3)
    with pytest.raises(ValueError, match="face_xy"):
        extract_profile(object(), res[1e-3], res.obstacle)
    small = PadFace.of(PadGeometry(0.01, 0.01, 0.003, 4, 4, 2), MAT)
    with pytest.raises(ValueError, match="face nodes but the solution has"):
        extract_profile(small, res[1e-3], res.obstacle)


def test_millimetre_inputs_raise_instead_of_pressing_nothing(pad_cache):
    """A new-user trial: δ = 1.0 meant as 1 mm moved the jaw through a 40 mm sphere and
    returned zero force; a sphere given in millimetres did the same."""
    h = PadGeometry().thickness
    with pytest.raises(ValueError, match="metres"):
        press(PadGeometry(), MAT, Sphere((0.0, 0.0, h + 0.02), 0.02), [0.25, 1.0], cache_dir=pad_cache)
    with pytest.raises(
        ValueError, match=r"radius 20.0\) .*probably in millimetres: give the radius and the center"
    ):
        Sphere((0.0, 0.0, 25.0), 20.0)
    assert Sphere((0.0, 0.0, 50.0), 50.0, allow_scale=True).radius == 50.0  # a deliberate giant


@pytest.mark.parametrize("fidelity", ["condensed", "linear"])
def test_linear_levels_press_a_layer_uniaxially_at_nu_0(fidelity):
    """nu = 0, a rigid plane pressed δ into a 6 x 8 mm layer of h = 2 mm bonded at its back:
    the exact solution is uniaxial, u_z = -δ z / h (no lateral coupling at nu = 0, the free
    sides traction-free, the frictionless face free to slide), and trilinear hexes hold it
    exactly.  So the force is E δ W L / h, node i carries E δ / h times its tributary area
    (a quarter, half or whole 2 x 2 mm cell: 1, 2, 4 mm² at corners, edges, inside), and the
    profile's pressure is E δ / h everywhere.  The displacements come back sorted."""
    geom = PadGeometry(width=0.006, length=0.008, thickness=0.002, nx=3, ny=4, nz=2)
    mat = Material(E=2.0e6, nu=0.0)
    h = geom.thickness
    plane = Plane((0.0, 0.0, h), (0.0, 0.0, -1.0))
    deltas = [4e-5, 1e-5, 2e-5]
    res = press(geom, mat, plane, deltas, fidelity=fidelity, cache_dir=False)
    assert list(res) == sorted(deltas) and res.fidelity == fidelity and res.obstacle is plane
    dx = 0.002
    xy = res.pad.face_xy
    on_x_edge = np.isclose(np.abs(xy[:, 0]), geom.width / 2)
    on_y_edge = np.isclose(np.abs(xy[:, 1]), geom.length / 2)
    tributary = dx * dx / 2.0 ** (on_x_edge.astype(int) + on_y_edge.astype(int))
    assert tributary.sum() == pytest.approx(geom.width * geom.length, rel=1e-12)
    for d in deltas:
        p = mat.E * d / h
        assert res[d].force == pytest.approx(p * geom.width * geom.length, rel=1e-9)
        np.testing.assert_allclose(res[d].lam, p * tributary, rtol=1e-9)
        prof = res.profile(d)
        np.testing.assert_allclose(prof.pressures, p, rtol=1e-9)
        assert prof.F == pytest.approx(res[d].force, rel=1e-12)
    assert set(res.profiles()) == set(deltas)
    with pytest.raises(ValueError, match=r"no solution at delta = 3e-05 m; solved displacements are"):
        res.profile(3e-5)


@pytest.mark.parametrize(
    "deltas, kw, match",
    [
        ([], {}, "deltas is empty"),
        ([1e-4, 0.002], {}, "not below the layer thickness h = 0.002 m"),  # the back would hit
        ([0.5], {"fidelity": "nonlinear"}, "probably in millimetres — pass 0.0005"),  # 0.5 mm meant
        ([1e-4], {"fidelity": "Condensed"}, "fidelity must be one of"),
        ([1e-4], {"fidelity": "condensed", "step": 1e-5}, "unknown options"),
        ([-1e-5], {"fidelity": "linear"}, r"pad compression in \[0, 0.02\] m; got -1e-05"),
        ([np.nan], {"fidelity": "linear"}, r"pad compression in \[0, 0.02\] m; got nan"),
    ],
)
def test_press_rejects_careless_input(deltas, kw, match):
    geom = PadGeometry(width=0.004, length=0.004, thickness=0.002, nx=2, ny=2, nz=1)
    plane = Plane((0.0, 0.0, geom.thickness), (0.0, 0.0, -1.0))
    with pytest.raises(ValueError, match=match):
        press(geom, MAT, plane, deltas, cache_dir=False, **kw)
