"""workbench.grasp.contacts: point and soft-point contact wrenches (Eq. 4.1), the 6DLS contact's
inner vertices and outer half-spaces (Eqs. 3.27–3.28), REACH clusters."""

import numpy as np
import pytest
from grasp_helpers import MU, F, antipodal

from workbench import config
from workbench.grasp import (
    grasp_map,
    limit_surface_contact,
    point_contact,
    reach_contacts,
    resists_lp,
    wrench_resistance,
)


def test_contact_wrenches_are_forces_at_the_contact_point():
    """Independent reference for Eq. 4.1: a force f at p gives [f, p × f]."""
    p = np.array([0.01, -0.02, 0.03])
    c = point_contact(p, [0.0, 0.6, 0.8], F, n_edges=5)
    V = c.vertices(MU)
    np.testing.assert_allclose(V[:, 3:], np.cross(p, V[:, :3]), atol=1e-14)
    # every vertex on the cone's edge: normal part F, tangential part μF
    n_in = -np.array([0.0, 0.6, 0.8])
    fn = V[:, :3] @ n_in
    np.testing.assert_allclose(fn, F, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(V[:, :3] - fn[:, None] * n_in, axis=1), MU * F, rtol=1e-12)
    G = grasp_map([c, c])
    assert G.shape == (6, 12)


def test_soft_point_torsion_limit_is_gamma_F():
    ell = 0.004  # γ = μ ℓ
    grasp = antipodal(soft=ell, n=8)
    # one contact's largest torque about its normal
    tau_n = grasp[0].vertices(MU)[:, 3:] @ np.array([-1.0, 0, 0])
    assert tau_n.max() == pytest.approx(MU * ell * F, rel=1e-12)
    # one tolerance for both routes: a band of 10x config.TOL.resist_rtol
    band = 10 * config.TOL.resist_rtol
    for factor, expect in ((1 - band, True), (1 + band, False)):
        w = np.array([0, 0, 0, factor * 2 * MU * ell * F, 0, 0])  # torque about the grasp axis
        assert bool(resists_lp(grasp, w, MU)) == expect
        assert bool(wrench_resistance(grasp, w, MU)) == expect


@pytest.mark.jit_only("over 15 s as pure Python")
def test_six_dls_contact_vertices_lie_on_the_model():
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.surface_catalog import S2
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S2, 300, pressure_scale=1e4)
    model = LimitSurfaceCache().contact_model(prof, mu=1.0)
    c = limit_surface_contact(model, prof.pressure_center, prof.F, M=100)
    local = c.local_vertices(1.0)
    np.testing.assert_allclose(model.value(local, prof.F), 1.0, atol=1e-9)
    # object frame: the pressure centre is the torque reference
    V = c.vertices(1.0)
    np.testing.assert_allclose(
        V[:, 3:] - local[:, 3:], np.cross(prof.pressure_center, local[:, :3]), atol=1e-12
    )


@pytest.mark.jit_only("over 15 s as pure Python")
def test_six_dls_outer_qp_contains_the_inner_gws():
    """Outer half-spaces (Eq. 3.28) contain the inner vertices (Eq. 3.27): whatever the
    inner LP resists, the outer QP resists; the 6DFC (force up to F) contains the 6DLS."""
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.surface_catalog import S2
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S2, 300, pressure_scale=1e4)
    # the other jaw: a half-turn about an axis normal to the net contact force, through a
    # point beyond the pressure centre, so the two normal forces oppose (a parallel-jaw grasp)
    n = prof.normal_wrench[:3] / np.linalg.norm(prof.normal_wrench[:3])  # the force on the object
    axis = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    axis /= np.linalg.norm(axis)
    R = 2 * np.outer(axis, axis) - np.eye(3)
    # object centre inside: along the normal force, which points into the object (an
    # earlier version went the other way and built a pulling grasp; the check now warns)
    centre = prof.pressure_center + 0.5 * n
    mirror = prof.transformed(R, centre - R @ centre)
    cache = LimitSurfaceCache()
    grasp, cones = [], []
    for p in (prof, mirror):
        m = cache.contact_model(p, mu=1.0)
        grasp.append(limit_surface_contact(m, p.pressure_center, p.F, M=150))
        cones.append(limit_surface_contact(m, p.pressure_center, p.F, M=150, cone=True, name="6DFC"))
    rng = np.random.default_rng(1)
    Fs = grasp[0].force
    W = rng.normal(size=(60, 6)) * np.r_[np.full(3, 0.6 * Fs), np.full(3, 0.3 * Fs)]
    inner = np.array([bool(resists_lp(grasp, w, 1.0)) for w in W])
    outer = np.array([bool(wrench_resistance(grasp, w, 1.0)) for w in W])
    cone = np.array([bool(wrench_resistance(cones, w, 1.0)) for w in W])
    assert 0 < inner.sum() and not outer.all()
    assert (outer | ~inner).all() and (cone | ~outer).all()


def test_reach_clusters_keep_the_normal_wrench():
    """Merging a curved profile's elements keeps its normal wrench exactly (force and
    moment, reference: the profile's own Eq. 3.2 wrench moved to the origin); the
    scalar forces then sum to between |net force| and Σ p a (normals spread)."""
    from workbench.sources.surface_catalog import S3
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S3, 400, pressure_scale=1e4)
    subs = reach_contacts(prof, max_triangles=32)
    assert 1 <= len(subs) <= 32
    assert all(not s.cone for s in subs) and len({s.group for s in subs}) == 1
    wn = prof.normal_wrench
    ref = np.r_[wn[:3], wn[3:] + np.cross(prof.pressure_center, wn[:3])]  # about the origin
    got = sum(s.G @ (s.force * s.normal) for s in subs)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * prof.F)
    total = sum(s.force for s in subs)
    assert np.linalg.norm(wn[:3]) <= total <= prof.F
    assert total < 0.99 * prof.F  # S3 is curved: the scalar sum would overstate the force
    # a second call is a second jaw: its own force group
    assert reach_contacts(prof, max_triangles=32)[0].group != subs[0].group
