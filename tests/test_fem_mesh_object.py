"""workbench.fem.mesh_object: a closed mesh as a graspable object — the equivalent ellipse of a
polygon against an ellipse's own numbers, the section of a meshed elliptic cylinder, the
mirror test, a pad placed at first touch by grasp_pose, and the thesis's 24 meshes (when beside
the repository: 8 asymmetric, as Fig 3.11(b) says)."""

from pathlib import Path

import numpy as np
import pytest
import trimesh

from workbench.fem.bottle import grasp_pose
from workbench.fem.mesh_object import MeshObject, polygon_ellipse

THESIS_OBJECTS = Path(__file__).resolve().parents[2] / "shared" / "data" / "thesis_objects"


def _ellipse(A, B, phi, centre, n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    u = np.c_[A * np.cos(t), B * np.sin(t)]
    R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    return u @ R.T + centre


def test_the_equivalent_ellipse_of_an_ellipse_is_itself():
    # a 4,000-gon: its moments are the ellipse's to (π/n)² ~ 1e-6
    for phi, sense in ((0.3, 1), (-1.2, -1), (1.5, 1)):
        xy = _ellipse(0.04, 0.024, phi, np.array([0.01, -0.005]), 4000)[::sense]
        centre, A, B, got = polygon_ellipse(xy)
        np.testing.assert_allclose(centre, [0.01, -0.005], atol=1e-9)
        assert A == pytest.approx(0.04, rel=1e-5) and B == pytest.approx(0.024, rel=1e-5)
        assert got == pytest.approx(phi, abs=1e-6)
    # a square 2 × 2 cm: ∫ u² dA / area = 1/3 cm² along any axis, so A = B = 2/√3 cm
    centre, A, B, _ = polygon_ellipse(np.array([[0, 0], [0.02, 0], [0.02, 0.02], [0, 0.02]]))
    np.testing.assert_allclose(centre, [0.01, 0.01], atol=1e-15)
    assert A == pytest.approx(0.02 / np.sqrt(3), rel=1e-12) and B == pytest.approx(A, rel=1e-12)
    with pytest.raises(ValueError, match="no area"):
        polygon_ellipse(np.array([[0, 0], [1, 0], [2, 0]]))


def _elliptic_cylinder(A=0.04, B=0.024, phi=0.3, centre=(0.01, -0.005), height=0.1):
    cyl = trimesh.creation.cylinder(radius=1.0, height=height, sections=512)
    cyl.apply_transform(np.diag([A, B, 1.0, 1.0]))
    cyl.apply_transform(trimesh.transformations.rotation_matrix(phi, [0, 0, 1]))
    cyl.apply_translation([centre[0], centre[1], height / 2])
    return cyl


def test_a_meshed_elliptic_cylinder_gives_its_section_and_is_symmetric():
    obj = MeshObject(_elliptic_cylinder(), name="ell")
    centre, A, B, phi = obj.section(0.05)
    np.testing.assert_allclose(centre, [0.01, -0.005], atol=1e-7)
    # the 512-gon inscribed in the ellipse: its moments fall short by O((π/512)²)
    assert A == pytest.approx(0.04, rel=1e-4) and B == pytest.approx(0.024, rel=1e-4)
    assert phi == pytest.approx(0.3, abs=1e-4)
    assert obj.params.height == pytest.approx(0.1, rel=1e-12) and not obj.params.asymmetric
    with pytest.raises(ValueError, match="misses the object"):
        obj.section(0.2)


def test_a_leaning_object_is_asymmetric():
    # a cylinder sheared along x with the height: its sections' centres move off the x midpoint
    mesh = _elliptic_cylinder(phi=0.0, centre=(0.0, 0.0))
    shear = np.eye(4)
    shear[0, 2] = 0.2
    mesh.apply_transform(shear)
    assert MeshObject(mesh).params.asymmetric


def test_grasp_pose_places_the_pad_at_first_touch_on_a_mesh():
    obj = MeshObject(_elliptic_cylinder())
    x, y = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.02, 0.02, 9))
    face = np.c_[x.ravel(), y.ravel()]
    pose = grasp_pose(obj, 0.05, 0.0, face, 0.005)
    d, _ = pose.signed_distance(np.c_[face, np.full(len(face), 0.005)])
    assert abs(d.min()) < 1e-9  # touching, not pressed
    # along the major axis from the section's centre: the face's centre sits at A from it
    centre, A, _, phi = obj.section(0.05)
    face_centre = pose.to_object(np.array([[0.0, 0.0, 0.005]]))[0]
    assert np.hypot(*(face_centre[:2] - centre)) == pytest.approx(A, rel=2e-3)


@pytest.mark.skipif(not THESIS_OBJECTS.is_dir(), reason="the thesis's meshes are not beside the repository")
def test_the_thesis_meshes_read_as_objects_eight_asymmetric():
    paths = sorted(THESIS_OBJECTS.glob("*.obj"))
    assert len(paths) == 24
    objs = [MeshObject(p) for p in paths]
    asym = [o.name[:4] for o in objs if o.params.asymmetric]
    assert asym == [f"{i:04d}" for i in range(17, 25)]  # the "cien" family, 0017–0024
    # heights as the file names print them (mm), to the mesh's tessellation
    for o in objs:
        printed = float(o.name.split("_")[-1].split("x")[0]) * 1e-3
        assert o.params.height == pytest.approx(printed, rel=0.02), o.name


def test_a_thin_shell_is_pressed_on_its_near_side_only():
    """A 0.5 mm shell (the thesis's meshes are such shells) pressed 3 mm: the one-sided view
    grasp_pose gives a mesh keeps every contact normal facing the jaw; against the whole mesh the
    nodes pressed past the wall are nearer its inner side and drop out of the contact."""
    import warnings

    from workbench.fem.contact import solve_contact
    from workbench.fem.extract import extract_profile
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.plausible import ImplausibleWarning

    shell = trimesh.creation.annulus(r_min=0.0295, r_max=0.03, height=0.1, sections=256)
    shell.apply_translation([0.0, 0.0, 0.05])
    obj = MeshObject(shell, name="shell")
    pad = condense_pad(PadGeometry(nx=10, ny=20, nz=3), Material(1e6, 0.45), cache_dir=False)
    pose = grasp_pose(obj, 0.05, 0.0, pad.face_xy, pad.geometry.thickness)
    assert pose.obstacle is obj.one_sided(pose.R[:, 2] * -1) and pose.obstacle.facing is not None
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)  # a flipped normal would raise here
        prof = extract_profile(pad, solve_contact(pad, pose, 3e-3), pose)
    n_mean = (prof.normals * (prof.pressures * prof.areas)[:, None]).sum(0)
    assert (prof.normals @ n_mean > 0).all()
    # two-sided, the nodes pressed past the wall find its inner side nearer and read as outside:
    # the contact falls away where it should be deepest
    two_sided = type(pose)(obj.obstacle, pose.R, pose.t)
    one, two = solve_contact(pad, pose, 3e-3), solve_contact(pad, two_sided, 3e-3)
    assert two.force < 0.5 * one.force
