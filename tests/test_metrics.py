"""workbench.peers.metrics against closed forms: interpolation of linear fields, Hertz's and a
uniform disc's torsion lengths, a flat patch's sliding support, MuJoCo's cone supports, the
balanced two-jaw grasp."""

import numpy as np
import pytest

from workbench.peers import metrics
from workbench.peers.hertz import hertz_profile
from workbench.profile import ContactProfile


def _disc(a=0.004, n=40, p=1.0e4, z=0.005):
    """A flat uniform disc of radius a on the pad face z, normals -z (out of the object above)."""
    x = (np.arange(n) + 0.5) / n * 2 * a - a
    X, Y = np.meshgrid(x, x, indexing="ij")
    keep = X**2 + Y**2 <= a * a
    c = np.column_stack([X[keep], Y[keep], np.full(keep.sum(), z)])
    m = len(c)
    return ContactProfile(c, np.tile([0.0, 0.0, -1.0], (m, 1)), np.full(m, (2 * a / n) ** 2), np.full(m, p))


def test_grid_covers_the_face():
    g, cell = metrics.face_grid_points(0.016, 0.02, 0.001)
    assert g.shape == (16 * 20, 2)
    assert cell * len(g) == pytest.approx(0.016 * 0.02, rel=1e-12)
    assert np.abs(g[:, 0]).max() == pytest.approx(0.0075) and np.abs(g[:, 1]).max() == pytest.approx(0.0095)


def test_fields_reproduce_linear_and_bilinear_fields_exactly():
    prof = _disc()
    lin = prof.with_pressures(1.0e4 + 1.0e6 * prof.centers[:, 0])
    g = np.array([[0.0, 0.0], [0.001, -0.002], [0.01, 0.0]])  # the last outside the hull: 0
    p = metrics.field_from_elements(lin, g)
    assert p[:2] == pytest.approx(1.0e4 + 1.0e6 * g[:2, 0], rel=1e-10) and p[2] == 0.0
    xs, ys = np.linspace(-0.008, 0.008, 9), np.linspace(-0.01, 0.01, 11)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    f = 3.0 + 100 * nodes[:, 0] - 50 * nodes[:, 1] + 1e4 * nodes[:, 0] * nodes[:, 1]
    q = np.array([[0.0013, -0.0042], [-0.007, 0.009]])
    want = 3.0 + 100 * q[:, 0] - 50 * q[:, 1] + 1e4 * q[:, 0] * q[:, 1]
    assert metrics.field_from_nodes(nodes, f, q) == pytest.approx(want, rel=1e-12)
    assert metrics.field_from_elements(None, g).tolist() == [0.0, 0.0, 0.0]


def test_rel_l2():
    assert metrics.rel_l2([3.0, 4.0], [0.0, 5.0]) == pytest.approx(np.hypot(3, 1) / 5)
    with pytest.raises(ValueError, match="zero"):
        metrics.rel_l2([1.0], [0.0])
    with pytest.raises(ValueError, match="share"):
        metrics.rel_l2([1.0, 2.0], [1.0])


def test_torsion_lengths_of_hertz_and_a_uniform_disc():
    R, d = 0.015, 1e-3
    a = np.sqrt(R * d)
    prof = hertz_profile(R, d, 1e6, 0.45, center=np.array([0.0, 0.0, 0.005 + R]))
    # w_max about z over the *jaw* force: F's share along z is 1 - O(a²/R²), so compare to 1e-2
    assert metrics.torsion_length(prof, 0.5) == pytest.approx(3 * np.pi * a / 16, rel=a * a / R / R)
    disc = _disc(a=0.004, n=200)
    assert metrics.torsion_length(disc, 0.5) == pytest.approx(2 * 0.004 / 3, rel=5e-3)  # grid of 200²


def test_flat_patch_supports_and_the_cone():
    mu = 0.4
    s = metrics.supports(_disc(), mu)
    assert s[:2] == pytest.approx([mu, mu], rel=1e-12)  # sliding: μ per unit normal force
    assert s[2] == pytest.approx(0.0, abs=1e-12)  # no friction along the normal of a flat patch
    assert s[3:5] == pytest.approx([0.0, 0.0], abs=1e-12)  # nor against rolling (slip normal to the patch)
    c = metrics.cone_supports([mu, mu, 0.003, 0.0, 0.0])
    assert c == pytest.approx([mu, mu, 0.0, 0.0, 0.0, 0.003], abs=1e-15)
    c = metrics.cone_supports([mu, 0.5 * mu, 0.003, 0.001, 0.002])
    assert sorted(c[:2]) == pytest.approx([0.5 * mu, mu]) and sorted(c[3:5]) == pytest.approx([0.001, 0.002])


def test_opposed_jaws_balance_and_push_along_x():
    prof = _disc()
    jaws = metrics.opposed_jaws(prof, [0.0, 0.0, 0.02])
    n1, n2 = (j.normal_wrench for j in jaws)
    assert n1[0] == pytest.approx(prof.F) and n1[1:3] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert n1 + n2 == pytest.approx(np.zeros(6), abs=1e-12)  # the squeeze balances
    assert jaws[0].pressure_center == pytest.approx([-0.015, 0.0, 0.0], abs=1e-15)
    with pytest.raises(ValueError, match="center"):
        metrics.opposed_jaws(prof, [0.0, 0.0])


def _shrunk(profile, s):
    """``profile`` scaled by ``s`` about its pressure centre at the same element forces (areas s²,
    pressures / s²): its 6DFW set is exactly ``diag(1, 1, 1, s, s, s)`` times the original's (the
    slip of twist (v, ω) on the copy is that of (v, s ω) on the original; Eq. 3.6)."""
    o = profile.pressure_center
    return ContactProfile(
        o + s * (profile.centers - o),
        profile.normals,
        profile.areas * s * s,
        profile.pressures / (s * s),
    )


def test_fitted_ls_error_is_the_shrunk_contact_s_ellipsoid_at_the_reference_s_surface():
    """A contact scaled by s about its centre, sampled at its own length scale, gives S times the
    original's wrenches and S times its w_max: the same normalised data, so the same A_e, with
    scale S w_max.  Its score is then recomputed here in NumPy at the reference's exact surface
    points (normals d uniform in the fit's coordinates, twists -d ⊘ scale)."""
    from workbench.wrench import frictional_wrenches, w_max

    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    s, mu = 0.8, 0.5
    kw = {"model": "ellipsoid_lsq", "n_twists": 60, "n_directions": 400, "seed": 3}
    own = metrics.fitted_ls_error(ref, ref, mu, **kw)
    peer = metrics.fitted_ls_error(_shrunk(ref, s), ref, mu, **kw)
    scale = w_max(ref, mu) * np.array([1, 1, 1, s, s, s])
    np.testing.assert_allclose(peer.model.scale, scale, rtol=1e-12)
    np.testing.assert_allclose(peer.model.A_e, own.model.A_e, rtol=1e-7, atol=1e-9)
    d = np.random.default_rng(3).standard_normal((400, 6))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    x = frictional_wrenches(ref, -d / scale, mu) / scale
    radial = np.abs(np.sqrt(np.einsum("ni,ij,nj->n", x, peer.model.A_e, x)) - 1)
    assert peer.radial_mean == pytest.approx(radial.mean(), rel=1e-9)
    # measured: 5.4 % (the ellipsoid's own error) and 21.7 % for the copy with 20 % shorter torque axes
    assert peer.radial_mean > own.radial_mean + 0.1


def test_fitted_ls_error_compares_at_equal_jaw_force_and_refuses_a_bad_model():
    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    a = metrics.fitted_ls_error(ref, ref, 0.5, n_twists=40, n_directions=200)
    b = metrics.fitted_ls_error(
        ref.with_pressures(3.0 * ref.pressures), ref, 0.5, n_twists=40, n_directions=200
    )
    assert b.radial_mean == pytest.approx(a.radial_mean, rel=1e-6)  # the sensor reads one force
    assert set(a.as_dict()) == {"radial_mean", "radial_p95", "fit_s"}
    with pytest.raises(ValueError, match="ellipsoid_sdp"):
        metrics.fitted_ls_error(ref, ref, 0.5, model="ellipsoid")
