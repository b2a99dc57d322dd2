"""Validation item (a) of the engines (workbench.engine_trials.indentation): a pad indented by a
sphere and a flat, the engine's force against our neo-Hookean pad FEM (fem.press, nonlinear) —
MuJoCo on small meshes (a sphere within 10 % at δ = 0.25 mm; the flat's St Venant–Kirchhoff
softening at 1 mm, stated as what it is and checked against our FEM with the SVK law), Drake on a
small mesh (skipped without pydrake), the tet mesh of a PadGeometry, careless input."""

import json
from dataclasses import asdict

import numpy as np
import pytest
import scipy.sparse as sp

from workbench.engine_trials.indentation import (
    STIFF_CONTACT,
    DrakeSettings,
    IndentProtocol,
    indent_pad,
    indenter_pad_mesh,
    pad_tets,
)
from workbench.fem.material import Material
from workbench.fem.pad import PadGeometry

# the reference is our nonlinear pad FEM: minutes as pure Python
SLOW_FEM = (
    "the nonlinear pad FEM reference runs minutes as pure Python; its kernels run in test_fem_nonlinear.py"
)
#: the acceptance criterion: force within 10 % of our pad's
WITHIN = 0.10
# graded pad nodes for spheres: 1 mm spacing within 4 mm of the contact, growing by 1.5 outside
# (1,710 vertices); the trials' 5 mm grid has one vertex or none inside a 1.6 mm contact
SPHERE_MESH = PadGeometry(grading=(0.004, 0.001, 1.5))


def test_pad_tets_fill_the_pad_and_pin_its_back():
    g = PadGeometry(nx=4, ny=6, nz=2)
    points, tets, back = pad_tets(g)
    assert points.shape == (5 * 7 * 3, 3) and tets.shape == (6 * 4 * 6 * 2, 4)
    v = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0]) / 6
    assert (vol > 0).all()
    assert vol.sum() == pytest.approx(g.width * g.length * g.thickness, rel=1e-12)
    assert np.array_equal(back, np.flatnonzero(points[:, 2] == 0.0)) and back.size == 5 * 7
    # a graded geometry keeps its axes: every node of PadGeometry.axes() is a vertex
    x, y, z = SPHERE_MESH.axes()
    assert len(pad_tets(SPHERE_MESH)[0]) == len(x) * len(y) * len(z) == 1710


def test_the_indenters_pad_meshes_resolve_their_contact_on_the_trials_pad():
    """The probe's pads are the trials' 20 x 40 x 5 mm pad (indent_pad's reference): under the
    flat a uniform 2 x 2 x 1 mm hex mesh; under a sphere 1 mm spacing within 4 mm of the face's
    centre (and through the layer), so the contact radius sqrt(R d) = 1.58 mm (R 10 mm,
    d 0.25 mm) spans at least three nodes across, coarser (growth 1.5) away from it."""
    ref = PadGeometry()
    for radius in (None, 0.01, 0.025):
        g = indenter_pad_mesh(radius)
        assert (g.width, g.length, g.thickness) == (ref.width, ref.length, ref.thickness)
    x, y, z = indenter_pad_mesh(None).axes()
    for axis, step, extent in ((x, 0.002, 0.02), (y, 0.002, 0.04), (z, 0.001, 0.005)):
        np.testing.assert_allclose(np.diff(axis), step, rtol=1e-12)
        assert axis[-1] - axis[0] == pytest.approx(extent, rel=1e-12)
    x, y, z = indenter_pad_mesh(0.01).axes()
    assert len(x) * len(y) * len(z) == 1710  # the graded pad of SPHERE_MESH
    for axis in (x, y):
        near = np.abs(axis) <= 0.004 + 1e-12
        np.testing.assert_allclose(np.diff(axis[near]), 0.001, rtol=1e-9)
        # growing by 1.5 away from the contact: 1.5, 2.25 mm, ... (the last step fits the edge)
        np.testing.assert_allclose(np.diff(axis[axis >= 0.004 - 1e-12])[:2], [0.0015, 0.00225], rtol=1e-9)
    np.testing.assert_allclose(np.diff(z), 0.001, rtol=1e-9)  # 1 mm through the 5 mm layer
    a = np.sqrt(0.01 * 0.25e-3)
    assert np.sum(np.abs(x) <= a) >= 3 and np.sum(np.abs(y) <= a) >= 3
    assert indenter_pad_mesh(0.025) == indenter_pad_mesh(0.01) == SPHERE_MESH


@pytest.mark.jit_only(SLOW_FEM)
def test_the_trials_pad_is_the_tet_pad_on_its_grid_and_its_contacts_sink():
    # the default is the trials' pad (pad.flexcomp_xml on EngineSettings().pad_grid, 5 x 9 x 3):
    # the same pad built from a PadGeometry's nodes gives the same force (the probe's finer pads
    # are that pad, finer); with the trials' contact impedance the tips sink 0.055 mm into the
    # flat at δ = 0.25 mm (a fifth of δ), with STIFF_CONTACT 0.3 µm
    trials = indent_pad("flat", depths=(0.25e-3,))
    same = indent_pad("flat", depths=(0.25e-3,), mesh=PadGeometry(nx=4, ny=8, nz=2))
    assert trials.vertices == same.vertices == 5 * 9 * 3
    assert same.force[0] == pytest.approx(trials.force[0], rel=1e-9)
    assert trials.penetration[0] > 0.1 * 0.25e-3
    stiff = indent_pad("flat", depths=(0.25e-3,), settings=STIFF_CONTACT)
    assert stiff.penetration[0] < 0.01 * 0.25e-3
    assert trials.reference[0] == pytest.approx(stiff.reference[0], rel=1e-12)
    assert trials.spread[0] < 1e-3 and trials.engine_warnings == {}
    record = json.loads(json.dumps(stiff.as_dict()))  # JSON as it is, for summary.json
    assert record["settings"]["engine"]["pad_mass"] == STIFF_CONTACT.pad_mass
    assert record["depths"][0]["reference"] == pytest.approx(stiff.reference[0])


@pytest.mark.jit_only(SLOW_FEM)
@pytest.mark.parametrize("radius", [0.01, 0.025])
def test_mujoco_sphere_at_a_quarter_millimetre_is_within_ten_percent_of_our_pad(radius):
    # measured +5.4 % (R 10 mm: 1.008 N against 0.957 N) and -0.6 % (R 25 mm: 2.045 against
    # 2.058 N); +1.0 / -1.8 % on 4,725 vertices.  A pass by cancellation, not agreement: these
    # linear tets are 22 / 12 % stiffer than MuJoCo's law (SVK) in our FEM, itself 14 / 11 % below
    # our neo-Hookean pad.  Beyond 0.25 mm item (a) fails: -10 / -12 % at 0.5 mm, -32 % at 1 mm
    r = indent_pad("sphere", radius, depths=(0.25e-3,), settings=STIFF_CONTACT, mesh=SPHERE_MESH)
    assert r.engine == "mujoco" and r.vertices == 1710
    assert abs(r.error[0]) < WITHIN
    assert r.penetration[0] < 0.01 * 0.25e-3 and r.spread[0] < 1e-3
    assert r.engine_warnings == {}
    assert r.as_dict()["depths"][0]["error"] == pytest.approx(r.error[0])


def _svk_press_force(geometry, depth: float) -> float:
    """Our pad FEM (fem.nonlinear's hexes, contact and load stepping) with MuJoCo's material law,
    St Venant–Kirchhoff (fem.svk), pressed by the flat: the force on the flat [N]."""
    from workbench.fem.material import Material
    from workbench.fem.nonlinear import NonlinearPad
    from workbench.fem.obstacles import Plane
    from workbench.fem.svk import svk_tangent

    class SVKPad(NonlinearPad):
        def _internal(self, u):
            self.__dict__.setdefault("_svk_cache", {})
            K, r = svk_tangent(self.b2, u, self.material.mu, self.material.lam, self._svk_cache)
            # the same 2x2x2 hex quadrature, so the same sparsity pattern as the neo-Hookean tangent
            assert np.array_equal(K.indptr, self._indptr) and np.array_equal(K.indices, self._indices)
            return r, sp.csr_matrix((K.data, self._indices, self._indptr), shape=K.shape)

    plane = Plane(point=(0.0, 0.0, geometry.thickness), normal=(0.0, 0.0, -1.0))
    return float(SVKPad(geometry, Material()).solve(plane, [depth])[depth].force_vector[2])


@pytest.mark.slow
@pytest.mark.jit_only(SLOW_FEM)
def test_mujoco_flat_at_one_millimetre_is_softer_than_our_pad_by_its_material_law():
    # Item (a) fails in MuJoCo on the flat: its 3D flex is St Venant–Kirchhoff, softer than our
    # neo-Hookean pad in compression — at δ = 1 mm 141 N against 375 N (-62 %) on an 11 x 21 x 6
    # grid (-19 / -37 / -62 % at 0.25 / 0.5 / 1 mm in the study, the same on 21 x 41 x 6).  Our
    # FEM with the SVK law instead gives 137.5 N: MuJoCo is within 5 % of it (+2.5 %; +2.9 % at
    # 0.25 and 0.5 mm), so the gap is the law, not the contact or the mesh.
    fast = IndentProtocol(speed=0.02, hold=0.02)
    r = indent_pad("flat", depths=(1e-3,), settings=STIFF_CONTACT, mesh=PadGeometry(nx=10, ny=20, nz=5),
                   protocol=fast)  # fmt: skip
    assert r.vertices == 11 * 21 * 6 and r.engine_warnings == {}
    assert r.error[0] < -WITHIN  # the failing item, as measured
    svk = _svk_press_force(PadGeometry(), 1e-3)
    assert abs(r.force[0] / svk - 1.0) < 0.05
    assert svk < (1.0 - WITHIN) * r.reference[0]  # the law alone is that soft in our own FEM


@pytest.mark.jit_only(SLOW_FEM)
def test_drake_flat_at_a_quarter_millimetre_is_within_ten_percent_of_our_pad():
    pytest.importorskip("pydrake")
    # Drake's stable neo-Hookean pad on 9 x 17 x 3 vertices (459): +2.3 % at δ = 0.25 mm (-5.8 %
    # on 11 x 21 x 6).  Not asserted at 1 mm: there the coarse mesh's stiffness hides the law's
    # softness (-8.3 % here, -13.8 % on 11 x 21 x 6; Drake's law in our own solver is -14 %)
    r = indent_pad("flat", depths=(0.25e-3,), engine="drake", mesh=PadGeometry(nx=8, ny=16, nz=2))
    assert r.engine == "drake" and r.vertices == 459 and r.elements == 6 * 8 * 16 * 2
    assert abs(r.error[0]) < WITHIN
    assert r.travel[0] == pytest.approx(0.25e-3, rel=2e-3)  # the drive follows its path
    # the hydroelastic contact's own compliance (pressure / DrakeSettings.pressure_gradient) is
    # small against δ: 11 µm
    assert r.penetration[0] < 0.1 * 0.25e-3
    assert r.as_dict()["settings"]["engine"] == asdict(DrakeSettings())


def test_careless_indentation_input_is_refused():
    cases = (
        ({"depths": (0.25, 0.5)}, r"probably in millimetres — pass 0.00025"),
        ({"depths": (5e-3,)}, r"not below the layer thickness"),
        ({"depths": (0.0, 1e-3)}, r"distinct indentations > 0"),
        ({"depths": (1e-3, 1e-3)}, r"distinct indentations > 0"),
        ({"depths": ()}, r"distinct indentations > 0"),
        ({"indenter": "sphere", "radius": 10}, r"diameter .*20 mm = 0.02"),
        ({"indenter": "sphere"}, r"needs its radius \[m\]"),
        ({"radius": 0.01}, r"flat indenter takes no radius"),
        ({"indenter": "cylinder"}, r"indenter must be one of \('flat', 'sphere'\)"),
        ({"engine": "bullet"}, r"engine must be one of \('mujoco', 'drake'\)"),
        ({"mesh": PadGeometry(width=0.03)}, r"must be the same pad"),
        ({"mesh": (5, 9, 3)}, r"mesh must be a PadGeometry"),
        ({"settings": DrakeSettings()}, r"settings must be an EngineSettings"),
        ({"indenter": "sphere", "radius": "10 mm"}, r"radius must be > 0, a length in metres"),
        ({"material": Material(E=1.0)}, r"probably in MPa — pass 1e\+06"),
        ({"reference": PadGeometry(thickness=5.0)}, r"millimetres — pass 0.005"),
    )
    for kwargs, match in cases:
        kw = {"indenter": "flat", **kwargs}
        with pytest.raises(ValueError, match=match):
            indent_pad(**kw)
    with pytest.raises(ValueError, match=r"a speed in mm/s\? 10 mm/s = 0.01"):
        IndentProtocol(speed=10)
    with pytest.raises(ValueError, match=r"time_step must be in \(0, 2e-3\] s"):
        DrakeSettings(time_step=0.01)
    with pytest.raises(ValueError, match="material must be one of"):
        DrakeSettings(material="svk")
    with pytest.raises(ValueError, match=r"pressure_gradient must be a number > 0"):
        DrakeSettings(pressure_gradient=0.0)
