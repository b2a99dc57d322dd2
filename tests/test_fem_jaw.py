"""FEM pad profiles of a grasp on an object mesh (workbench.sources.fem_jaw) against analytic obstacles,
and through grasp analysis (evaluate_grasp) like REACH profiles."""

import numpy as np
import pytest
import trimesh
from scipy.optimize import brentq

from workbench import ContactProfile
from workbench.fem.bottle import Posed
from workbench.fem.contact import solve_contact
from workbench.fem.extract import extract_profile
from workbench.fem.material import Material
from workbench.fem.obstacles import Cylinder
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.plausible import ImplausibleWarning
from workbench.sources.fem_jaw import fem_jaw_profile, fem_jaw_profiles, jaw_rotation

GEOM = PadGeometry(width=0.016, length=0.024, thickness=0.004, nx=16, ny=24, nz=3)


@pytest.fixture(scope="module")
def pad():
    return condense_pad(GEOM, Material(), cache_dir=False)


def _analytic_cylinder_profile(pad, R, force):
    """The same pad on an exact cylinder (axis z, radius R), jaw at -x approaching +x."""
    rot = jaw_rotation([1.0, 0.0, 0.0])
    t = np.array([-R - pad.geometry.thickness, 0.0, 0.0])  # face z = h touches x = -R
    posed = Posed(Cylinder(axis=(0, 0, 1), radius=R), rot, t)
    d = brentq(
        lambda d: solve_contact(pad, posed, d).force_vector[2] - force, 0, 0.9 * GEOM.thickness, xtol=1e-15
    )
    return extract_profile(pad, solve_contact(pad, posed, d), posed).transformed(rot, t)


def test_jaw_rotation_frame():
    R = jaw_rotation([0.0, 2.0, 0.0], up=[0.0, 0.3, 1.0])
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-12) and np.linalg.det(R) == pytest.approx(1.0)
    assert np.allclose(R[:, 2], [0, 1, 0]) and np.allclose(R[:, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="parallel"):
        jaw_rotation([0, 0, 1.0], up=[0, 0, 2.0])
    with pytest.raises(ValueError, match="non-zero"):
        jaw_rotation([0, 0, 0.0])


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_cylinder_mesh_of_slivers_matches_the_analytic_cylinder(pad):
    R, F = 0.03, 8.0
    mesh = trimesh.creation.cylinder(radius=R, height=0.12, sections=256)  # 0.7 x 120 mm side faces
    prof = fem_jaw_profile(mesh, [-R, 0, 0], [1.0, 0, 0], F, pad=pad)
    ref = _analytic_cylinder_profile(pad, R, F)
    assert prof.normal_wrench[0] == pytest.approx(F, rel=1e-9)  # the reading, along the approach
    # facets (sag 2e-3 mm) against the exact surface: force and centre of pressure agree
    assert prof.F == pytest.approx(ref.F, rel=2e-3)
    assert np.abs(prof.pressure_center - ref.pressure_center).max() <= 5e-5
    assert prof.areas.sum() == pytest.approx(ref.areas.sum(), rel=0.05)
    # the pad pushes the object: normals outward (towards the jaw, -x)
    assert (prof.normals[:, 0] < 0).all()


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_flat_face_profile_is_centred_and_uniform(pad):
    box = trimesh.creation.box(extents=[0.06, 0.05, 0.1])
    p1, p2 = np.array([-0.03, 0.004, 0.01]), np.array([0.03, 0.004, 0.01])
    jaws = fem_jaw_profiles(box, {"p1": p1, "p2": p2, "axis": [1.0, 0, 0]}, 5.0, pad=pad)
    for prof, point, sign in zip(jaws, (p1, p2), (1, -1), strict=True):
        assert prof.F == pytest.approx(5.0, rel=1e-9)  # parallel normals: Σ p a is the axial force
        assert np.allclose(prof.normal_wrench[:3], [5.0 * sign, 0, 0], atol=1e-9)
        assert np.abs(prof.pressure_center - point).max() <= 1e-9  # symmetric pad on a flat face
        assert np.allclose(prof.normals, [-sign, 0, 0], atol=1e-12)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_bad_input(pad):
    cyl = trimesh.creation.cylinder(radius=0.03, height=0.12, sections=64)
    with pytest.raises(ValueError, match="force"):
        fem_jaw_profile(cyl, [-0.03, 0, 0], [1.0, 0, 0], 0.0, pad=pad)
    with pytest.raises(ValueError, match="force"):
        fem_jaw_profile(cyl, [-0.03, 0, 0], [1.0, 0, 0], float("nan"), pad=pad)
    with pytest.raises(ValueError, match="millimetres"):
        fem_jaw_profile(cyl.copy().apply_scale(1000), [-30, 0, 0], [1.0, 0, 0], 5.0, pad=pad)
    with pytest.raises(ValueError, match="point"):
        fem_jaw_profile(cyl, [-0.03, 0], [1.0, 0, 0], 5.0, pad=pad)
    with pytest.raises(ValueError, match=r"jaw force in \(0, 500\] N"):  # no gripper presses 1 kN a jaw
        fem_jaw_profile(cyl, [-0.03, 0, 0], [1.0, 0, 0], 1000.0, pad=pad)
    with pytest.warns(ImplausibleWarning), pytest.raises(ValueError, match="reaches only"):
        fem_jaw_profile(cyl, [-0.03, 0, 0], [1.0, 0, 0], 450.0, pad=pad)  # a 4 mm layer takes ~412 N
    with pytest.raises(ValueError, match="dict"):
        fem_jaw_profiles(cyl, [[-0.03, 0, 0], [0.03, 0, 0]], 5.0, pad=pad)


def test_an_fem_profile_enters_grasp_analysis_through_evaluate_grasp_like_a_reach_one(pad):
    """evaluate_grasp(profiles=...) takes the FEM pad's jaws as it takes REACH's: the verdict and
    the minimal force are those of the same steps done by hand on those profiles, and each
    jaw's normal force along its approach is the pad's reaction, the reading."""
    from workbench.grasp import (
        CutStore,
        Jaws,
        ModelOptions,
        Task,
        contact_sets,
        evaluate_grasp,
        min_grasp_force,
        resists,
    )
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.jaws import with_axis_force

    R, F, mu = 0.03, 6.0, 0.5
    cyl = trimesh.creation.cylinder(radius=R, height=0.12, sections=256)
    axis = np.array([1.0, 0.0, 0.0])
    grasp = {"p1": np.array([-R, 0.0, 0.0]), "p2": np.array([R, 0.0, 0.0]), "axis": axis}
    jaws = fem_jaw_profiles(cyl, grasp, F, pad=pad)
    w = np.array([0.0, 0.0, -4.0, 0.005, 0.0, 0.0])  # a 4 N weight hung slightly off the axis
    face = (GEOM.width, GEOM.length)
    task, at_face, opts = Task(w_ext=w), Jaws(force=F, pad=face), ModelOptions(mu=mu)
    ev = evaluate_grasp(None, grasp, task, jaws=at_face, options=opts, profiles=jaws)

    cache, cuts = LimitSurfaceCache(), CutStore()
    hand = [with_axis_force(p, a, F) for p, a in zip(jaws, (axis, -axis), strict=True)]
    contacts = [c for p in hand for c in contact_sets(p, "6dls", cache=cache, seed=0)]
    verdict = resists(contacts, w, mu, cuts=cuts)
    mf = min_grasp_force(contacts, w, mu, cuts=cuts)
    assert ev.resisted and bool(verdict)
    assert ev.min_force.scale == pytest.approx(mf.scale, rel=1e-9)
    assert 0.05 < ev.min_force.scale < 1.0  # 4 N held by two 6 N jaws at μ = 0.5 with room to spare
    for prof, ref, a in zip(ev.profiles, jaws, (axis, -axis), strict=True):
        np.testing.assert_allclose(prof.pressures, ref.pressures, rtol=1e-9)  # already at the reading
        assert prof.normal_wrench[:3] @ a == pytest.approx(F, rel=1e-9)  # the pad's reaction
        assert prof.F == pytest.approx(_analytic_cylinder_profile(pad, R, F).F, rel=2e-3)  # Σ λ, curved

    # the same checks as for REACH profiles, whatever the source
    with pytest.raises(ValueError, match="list of the two jaws"):
        evaluate_grasp(None, grasp, task, jaws=at_face, options=opts, profiles=jaws[0])
    with pytest.raises(ValueError, match="pad's diagonal"):
        evaluate_grasp(None, grasp, task, jaws=at_face, options=opts, profiles=jaws[::-1])
    flipped = ContactProfile(jaws[0].centers, -jaws[0].normals, jaws[0].areas, jaws[0].pressures)
    with pytest.raises(ValueError, match="would pull"):
        evaluate_grasp(None, grasp, task, jaws=at_face, options=opts, profiles=[flipped, jaws[1]])
    with pytest.raises(ValueError, match="pad must be"):
        evaluate_grasp(None, grasp, task, jaws=Jaws(force=F, pad=(0.0, 0.02)), options=opts, profiles=jaws)
    with pytest.raises(ValueError, match="give the object mesh"):
        evaluate_grasp(None, grasp, task, jaws=Jaws(force=F), options=opts)
