"""workbench.grasp.models: every contact model of a profile by name."""

import numpy as np
import pytest

from workbench.grasp import resists


@pytest.mark.jit_only("over 15 s as pure Python")
def test_every_model_on_the_elliptic_cylinder_grasp():
    from workbench.grasp.models import MODELS, ModelParameters, contact_sets, planar_profile
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.scenes import elliptic_cylinder_grasp

    profiles = elliptic_cylinder_grasp(force=25.0, n_elements=200)
    # the force-sensor convention: the grasp-axis normal force of each jaw is F
    assert -profiles[0].normal_wrench[0] == pytest.approx(25.0, rel=1e-12)
    flat = planar_profile(profiles[0])
    assert flat.F == pytest.approx(profiles[0].F, rel=1e-12)
    assert np.allclose(np.abs(flat.normals[:, 0]), 1.0)  # projected onto the yz-plane
    cache = LimitSurfaceCache()
    mu = 0.3
    lift = np.array([0, -0.9 * 2 * mu * 25.0, 0, 0, 0, 0])  # a weight along -y
    twist = np.array([0, 0, 0, 0.02, 0, 0])  # torque about the grasp axis
    for name in MODELS:
        params = ModelParameters(M=100, n_wrenches=400)
        sets = [c for p in profiles for c in contact_sets(p, name, params, cache=cache)]
        # outer QP where the model has half-spaces (the thesis's QP), else the exact LP
        assert resists(sets, lift, mu), name  # friction force ~2μF > 0.9·2μF
        assert resists(sets, np.zeros(6), mu), name
        if name == "point":
            assert not resists(sets, twist, mu)  # no torsional friction
        else:
            assert resists(sets, twist, mu), name
    with pytest.raises(ValueError, match="model must be one of"):
        contact_sets(profiles[0], "ellipsoid")


def test_planar_profile_of_a_strip_one_element_wide():
    """Centres on one line leave the PCA plane undetermined (the zero-normal crash of a 1 mm
    strip in the physical trials): the plane through the line closest to normal to the net
    normal — for a flat strip, the strip's own plane; a single element keeps its normal."""
    from workbench.grasp.models import planar_profile
    from workbench.profile import ContactProfile

    n = np.array([0.0, 0.6, -0.8])
    x = np.linspace(-2e-3, 2e-3, 5)
    centers = np.column_stack([x, np.zeros(5), np.zeros(5)])
    strip = ContactProfile(centers, np.tile(n, (5, 1)), np.full(5, 1e-7), np.full(5, 1e5))
    flat = planar_profile(strip)
    np.testing.assert_allclose(flat.normals, np.tile(n, (5, 1)), atol=1e-12)
    np.testing.assert_allclose(flat.centers, centers, atol=1e-15)
    assert flat.F == pytest.approx(strip.F, rel=1e-12)
    one = planar_profile(ContactProfile(centers[:1], n[None], [1e-7], [1e5]))
    np.testing.assert_allclose(one.normals[0], n, atol=1e-12)


def test_planar_profile_of_a_spread_patch_is_the_pca_plane():
    """Away from the collinear case the plane is the least-variance PCA axis, as before (by hand:
    the SVD of the area-weighted centres, oriented like the net normal)."""
    from workbench.grasp.models import net_normal, planar_profile
    from workbench.profile import ContactProfile

    rng = np.random.default_rng(3)
    c = rng.normal(size=(40, 3)) * [3e-3, 2e-3, 2e-4]
    normals = np.tile([0.0, 0.0, 1.0], (40, 1)) + rng.normal(scale=0.05, size=(40, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    prof = ContactProfile(c, normals, rng.uniform(1e-7, 2e-7, 40), rng.uniform(1e4, 2e4, 40))
    w = (prof.centers - prof.pressure_center) * np.sqrt(prof.areas)[:, None]
    v = np.linalg.svd(w)[2][-1]
    v = v * np.sign(v @ net_normal(prof))
    np.testing.assert_allclose(planar_profile(prof).normals[0], v, atol=1e-12)


def test_a_one_element_contact_is_a_point_under_every_model():
    """A pad catching a cube's corner touches one element: its exact 6DFW set is the friction
    disc (no torsion), so the limit-surface models reduce to the hard point contact instead of
    failing to fit a surface to a contact with no extent (a sweep point of the physical trials)."""
    from workbench.grasp.models import MODELS, contact_sets
    from workbench.grasp.resistance import resists
    from workbench.profile import ContactProfile

    one = ContactProfile([[0.01, 0.0, 0.0]], [[1.0, 0.0, 0.0]], [1e-7], [2e8])  # 20 N along −x
    for name in MODELS:
        sets = contact_sets(one, name)
        assert sum(abs(s.force) for s in sets) == pytest.approx(20.0, rel=1e-9), name
        # 5 N of tangential load (below mu F = 10 N at mu = 0.5) balanced by the contact with a
        # normal push; a torque about the contact normal is not (no torsion)
        w_ok = [20.0, 0.0, 5.0, 0.0, -0.05, 0.0]
        w_torsion = [20.0, 0.0, 0.0, 0.01, 0.0, 0.0]
        assert resists(sets, w_ok, 0.5), name
        assert not resists(sets, w_torsion, 0.5), name


@pytest.mark.parametrize(
    "given, meant",
    [("6DLS", "6dls"), ("softpoint", "soft_point"), ("soft-point", "soft_point"), ("6DFC", "6dfc")],
)
def test_a_misspelt_model_name_is_refused_with_the_name_meant(given, meant):
    from workbench.grasp.models import check_model

    with pytest.raises(ValueError, match=rf"got '{given}' — did you mean '{meant}'\?$"):
        check_model(given)
    with pytest.raises(ValueError, match=r"got 'xyz'$"):  # nothing close: no guess
        check_model("xyz")
