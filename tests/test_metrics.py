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
    points."""
    from workbench.wrench import frictional_wrenches, w_max

    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    s, mu = 0.8, 0.5
    kw = {"model": "ellipsoid_lsq", "n_twists": 60, "n_directions": 400, "seed": 3}
    own = metrics.fitted_ls_error(ref, ref, mu, **kw)
    peer = metrics.fitted_ls_error(_shrunk(ref, s), ref, mu, **kw)
    scale = w_max(ref, mu) * np.array([1, 1, 1, s, s, s])
    np.testing.assert_allclose(peer.model.scale, scale, rtol=1e-12)
    np.testing.assert_allclose(peer.model.A_e, own.model.A_e, rtol=1e-7, atol=1e-9)
    # the truth's surface points: normals d uniform in the reference's coordinates, twists -d ⊘ w_max
    d = np.random.default_rng(3).standard_normal((400, 6))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    x = frictional_wrenches(ref, -d / w_max(ref, mu), mu) / scale  # in the peer fit's coordinates
    g = np.sqrt(np.einsum("ni,ij,nj->n", x, peer.model.A_e, x))  # truth's radius / the fit's
    assert peer.radial_mean == pytest.approx(np.abs(g - 1).mean(), rel=1e-9)
    assert peer.rel_err == pytest.approx(np.exp(np.abs(np.log(g)).mean()) - 1, rel=1e-9)
    assert peer.bias == pytest.approx(np.exp(np.median(-np.log(g))) - 1, rel=1e-9)
    # the copy's torques are 20 % short: its fitted surface lies inside the truth (bias < 0);
    # measured 5.3 % (the ellipsoid's own error) and 21.2 % for the copy
    assert peer.bias < 0 and peer.rel_err > own.rel_err + 0.1


def test_fitted_ls_error_compares_at_equal_jaw_force_and_refuses_a_bad_model():
    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    a = metrics.fitted_ls_error(ref, ref, 0.5, n_twists=40, n_directions=200)
    b = metrics.fitted_ls_error(
        ref.with_pressures(3.0 * ref.pressures), ref, 0.5, n_twists=40, n_directions=200
    )
    assert b.rel_err == pytest.approx(a.rel_err, rel=1e-6)  # the sensor reads one force
    assert set(a.as_dict()) == {"rel_err", "bias", "radial_mean", "fit_s"}
    # every model, the twists-as-normals quartic too (it is given the twists)
    q = metrics.fitted_ls_error(ref, ref, 0.5, model="quartic_normals", n_twists=100, n_directions=200)
    assert 0 <= q.rel_err < 0.2
    with pytest.raises(ValueError, match="ellipsoid_sdp"):
        metrics.fitted_ls_error(ref, ref, 0.5, model="ellipsoid")
    with pytest.raises(ValueError, match=r"n_twists must be an integer >= 11"):
        metrics.fitted_ls_error(ref, ref, 0.5, n_twists=3)


def test_fitted_ls_error_refuses_a_flat_peer_and_a_profile_in_another_frame():
    """A planar patch's 6DFW set spans 3 dimensions: no 6DLS of the curved truth to score (it read
    1260, i.e. +126,000 %); flipped normals push the object the other way: refused, not negative."""
    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    flat = _disc(a=0.004, z=0.005)
    with pytest.raises(ValueError, match="no 6DLS of the curved contact"):
        metrics.fitted_ls_error(flat, ref, 0.5, n_twists=40)
    # nearly flat (normals tilted by 1e-6): it read 816,571 (+8e7 %), at 1e-12 a w_max error
    rng = np.random.default_rng(0)
    for eps in (1e-12, 1e-6):
        n = flat.normals + eps * rng.standard_normal(flat.normals.shape)
        near = ContactProfile(flat.centers, n, flat.areas, flat.pressures, normalize_normals=True)
        with pytest.raises(ValueError, match=r"almost\) no (force|torque) capacity"):
            metrics.fitted_ls_error(near, ref, 0.5, n_twists=40)
    with pytest.raises(ValueError, match="seed must be an integer >= 0"):
        metrics.fitted_ls_error(ref, ref, 0.5, n_twists=40, seed=1.5)
    flip = ContactProfile(ref.centers, -ref.normals, ref.areas, ref.pressures)
    # turned by 90° about x: jaw force ~1e-16 N of 3.5 N (a sign test let it through: 5e12 m torsion)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    turned = ref.transformed(Rx, np.zeros(3))
    for bad in (flip, turned):
        for call, args in (
            (metrics.fitted_ls_error, (bad, ref, 0.5)),
            (metrics.torsion_length, (bad, 0.5)),
            (metrics.supports, (bad, 0.5)),
        ):
            with pytest.raises(ValueError, match="not a contact of the pad frame"):
                call(*args)


def test_group_max_and_min_twists():
    """Each axis is measured against its own unit's largest support; min_twists covers the unknowns
    (21 of a 6D ellipsoid, 126 of a quartic) with 2 n wrenches."""
    w = np.array([2.0, 1.0, 0.5, 1e-4, 3e-4, 2e-4])
    np.testing.assert_array_equal(metrics.group_max(w), [2.0, 2.0, 2.0, 3e-4, 3e-4, 3e-4])
    assert metrics.min_twists("ellipsoid_sdp") == 11 and metrics.min_twists("quartic_values") == 63
    with pytest.raises(ValueError, match="ellipsoid_sdp"):
        metrics.min_twists("ellipsoid")
