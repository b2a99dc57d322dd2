"""Every contact model (workbench.grasp.models.MODELS) on the profiles of every profile source,
through evaluate_grasp: the FEM pad (sources.fem_jaw), REACH (sources.reach), a
parametric surface (sources.surfaces via sources.scenes) and a measured-style mesh with
pressures (ContactProfile.from_trimesh).  Each cell holds a weight two jaws clearly carry and
drops one they clearly cannot; the models whose friction never exceeds Coulomb's (point, soft
point, REACH, the sampled 6DFWs) also keep their minimal force above the Coulomb bound.

Also here: the round-off of the wrench kernel that crashed the planar model on FEM pad profiles
(a w_max entry of -3.98e-10 refused as negative) — w_max's one rule
(limit_surface.normalize.check_w_max), a given exact w_max's degenerate components, and the
planar model fitted in its plane's frame.
"""

import numpy as np
import pytest
import trimesh

from workbench import ContactProfile, config
from workbench.grasp import CutStore, Jaws, ModelOptions, Task, contact_sets, evaluate_grasp, resists
from workbench.grasp.models import MODELS, planar_profile, plane_frame_profile
from workbench.limit_surface import LimitSurfaceCache, fit_ellipsoid
from workbench.limit_surface.normalize import check_w_max, prepare
from workbench.wrench import frictional_wrenches, w_max

MU = 0.5
FORCE = 20.0  # each jaw's reading [N]
#: models whose friction at a contact never exceeds μ Σ p a (inner polygons, sampled hulls):
#: their minimal force is bounded below by Coulomb's; the fitted limit surfaces may overshoot
#: it by their fitting error
INNER = ("point", "soft_point", "reach", "6dfw")
#: the test pad of tests/test_fem_jaw.py, coarser (8 x 12 face elements): profiles in a fraction of a second
FEM_FACE = (0.016, 0.024)
SLOW = pytest.mark.jit_only(
    "the limit-surface fits sample 48,483 twists per profile, 6DFW 600 on REACH's 1,900 elements: "
    "10 s to minutes as pure Python"
)


def _fem_pad_source():
    """The FEM pad on a 128-gon cylinder (R 30 mm) grasped along y, the axis as an angle gives
    it (x = 6e-17): curved contacts whose PCA plane lies a round-off off the xz-plane — where the
    planar model used to crash (a w_max entry of -2.4e-11 refused as negative)."""
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.sources.fem_jaw import fem_jaw_profiles

    geom = PadGeometry(width=FEM_FACE[0], length=FEM_FACE[1], thickness=0.004, nx=8, ny=12, nz=2)
    pad = condense_pad(geom, Material(), cache_dir=False)
    cyl = trimesh.creation.cylinder(radius=0.03, height=0.12, sections=128)
    axis = np.array([np.cos(np.pi / 2), np.sin(np.pi / 2), 0.0])
    grasp = {"p1": -0.03 * axis, "p2": 0.03 * axis, "axis": axis}
    return grasp, fem_jaw_profiles(cyl, grasp, FORCE, pad=pad), FEM_FACE


def _reach_source():
    """REACH's Winkler pad (8 x 12 mm) on a 64-gon cylinder grasped along x (the planar model
    crashed on it too: a w_max entry of -7.4e-10)."""
    from workbench.sources.reach import jaw_profiles

    cyl = trimesh.creation.cylinder(radius=0.03, height=0.12, sections=64)
    grasp = {
        "p1": np.array([-0.03, 0.0, 0.0]),
        "p2": np.array([0.03, 0.0, 0.0]),
        "axis": np.array([1.0, 0, 0]),
    }
    face = (0.008, 0.012)
    return grasp, jaw_profiles(cyl, grasp, FORCE, pad=face), face


def _surface_source():
    """Elliptic-cylinder patches (a ParametricSurface meshed with the power-law pressure of
    Eq. 4.3), jaw 1 at +x pushing along −x."""
    from workbench.sources.scenes import elliptic_cylinder_grasp

    grasp = {
        "p1": np.array([0.03, 0.0, 0.0]),
        "p2": np.array([-0.03, 0.0, 0.0]),
        "axis": np.array([-1.0, 0, 0]),
    }
    return grasp, elliptic_cylinder_grasp(force=FORCE, n_elements=150), (0.02, 0.04)


def _mesh_source():
    """A sphere's (R 25 mm) triangles within 6 mm of the grasp axis with Hertz pressure
    p0 √(1 − r²/a²), read as a measured mesh would be (face winding gives the normals); jaw 2
    is jaw 1 turned by π about z."""
    R, a = 0.025, 0.006
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=R)
    c = sphere.triangles_center
    cap = sphere.submesh(
        [np.flatnonzero((c[:, 0] < 0) & (np.linalg.norm(c[:, 1:], axis=1) < a))], append=True
    )
    r = np.linalg.norm(cap.triangles_center[:, 1:], axis=1)
    left = ContactProfile.from_trimesh(cap, 1e5 * np.sqrt(1.0 - (r / a) ** 2))
    right = left.transformed(np.diag([-1.0, -1.0, 1.0]))
    grasp = {"p1": np.array([-R, 0.0, 0.0]), "p2": np.array([R, 0.0, 0.0]), "axis": np.array([1.0, 0, 0])}
    return grasp, [left, right], (0.02, 0.04)


SOURCES = {
    "fem_pad": _fem_pad_source,
    "reach": _reach_source,
    "surface": _surface_source,
    "mesh": _mesh_source,
}


@pytest.fixture(scope="module")
def made():
    """Each source's grasp, profiles and pad face, made once (lazily, per source)."""
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = SOURCES[name]()
        return cache[name]

    return get


@pytest.fixture(scope="module")
def ls_cache():
    return LimitSurfaceCache()


def _weight(profiles, magnitude):
    """A downward force ``magnitude`` [N] acting at the midpoint of the two pressure centres
    (6,): no torque about the line through the contacts, which two point contacts cannot
    resist at any force (every grasp axis here is horizontal)."""
    m = 0.5 * (profiles[0].pressure_center + profiles[1].pressure_center)
    f = np.array([0.0, 0.0, -magnitude])
    return np.r_[f, np.cross(m, f)]


CELLS = [
    pytest.param(s, m, marks=SLOW) if (m not in INNER or (s, m) == ("reach", "6dfw")) else (s, m)
    for s in SOURCES
    for m in MODELS
]


@pytest.mark.parametrize("source, model", CELLS)
def test_every_model_on_every_profile_source(made, ls_cache, source, model):
    """Two jaws each carrying up to μ Σ p a of friction (Σ p a >= the reading on curved
    contacts) hold 0.8 × 2 μ × the reading — inner 8-gons keep cos(π/8) = 0.92 of a circle, the
    fitted surfaces are within a few % of the exact set — and drop 1.2 × 2 μ × the larger Σ p a,
    beyond what any model credits; the minimal force converges (the planar model on FEM pad
    profiles crashed, and on REACH ones was refused as exceeding its w_max)."""
    grasp, profiles, face = made(source)
    w_in = _weight(profiles, 0.8 * 2 * MU * FORCE)
    ev = evaluate_grasp(
        None,
        grasp,
        Task(w_ext=w_in),
        jaws=Jaws(force=FORCE, pad=face),
        options=ModelOptions(model=model, mu=MU),
        profiles=profiles,
        cache=ls_cache,
        cuts=CutStore(),
    )
    assert ev.resisted, (source, model, ev.resistance.residual)
    f_jaws = np.array([p.F for p in ev.profiles])  # Σ p a of each jaw at the reading
    assert not resists(ev.contacts, _weight(profiles, 1.2 * 2 * MU * f_jaws.max()), MU)
    mf = ev.min_force
    assert mf.feasible and mf.converged and 0 < mf.scale < 1, (source, model, mf)
    if model in INNER:  # Coulomb: W <= μ Σ_j s Σ p a_j, up to the residual band of "resisted"
        band = 2 * config.TOL.resist_rtol * f_jaws.max() * (1 + MU)
        assert mf.scale * f_jaws.sum() * MU >= 0.8 * 2 * MU * FORCE - band
    if model == "planar":  # fitted in its plane's frame: exactly a 3D set
        assert [c.model.dim for c in ev.contacts] == [3, 3]


# --- the round-off that crashed the planar model -------------------------------------------


def _flat_patch(normal, n=9, seed=0):
    """n × n elements of a 12 × 20 mm patch through the origin with one outward ``normal``
    (3,), random pressures."""
    nrm = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross(nrm, [0.0, 0.0, 1.0])
    u /= np.linalg.norm(u)
    v = np.cross(nrm, u)
    g = np.linspace(-0.5, 0.5, n)
    A, B = np.meshgrid(g, g)
    centers = 0.012 * A.reshape(-1, 1) * u + 0.020 * B.reshape(-1, 1) * v
    p = np.random.default_rng(seed).uniform(0.5, 1.5, n * n) * 1e4
    return ContactProfile(centers, np.tile(nrm, (n * n, 1)), np.full(n * n, 3e-6), p)


def test_check_w_max_sets_round_off_negatives_to_zero_and_refuses_more():
    reported = np.array([1.0, 2.88e-07, 1.0, 2.77e-09, 9.6e-03, -3.98e-10])  # the crash's w_max
    out = check_w_max(reported)
    np.testing.assert_array_equal(out, np.r_[reported[:5], 0.0])
    rtol = config.TOL.wrench_roundoff_rtol
    with pytest.raises(ValueError, match=r"w_max component 5 is -0.0011, below 0 by more than round-off"):
        check_w_max(np.r_[reported[:5], -1.1 * rtol])
    with config.override(wrench_roundoff_rtol=0.0):  # read at call time
        with pytest.raises(ValueError, match="below 0 by more than round-off"):
            check_w_max(reported)
    with pytest.raises(ValueError, match="positive entry"):
        check_w_max(-np.abs(reported))  # the author's +ξ: every maximum negative
    with pytest.raises(ValueError, match=r"finite \(6,\) array"):
        check_w_max(reported[:5])


def test_given_w_max_round_off_is_tolerated_and_its_degenerate_components_are_zero():
    """A flat patch normal to x: f_x, τ_y, τ_z are 0 on it.  A round-off negative in w_max's
    f_x and a round-off of the samples there fit the same ellipsoid as the exact zeros do (the
    fit of the crash); a sample 1 % of the largest past its exact w_max is another contact's."""
    prof = _flat_patch([-1.0, 0.0, 0.0]).normalized()
    xi = np.random.default_rng(1).normal(size=(200, 6))
    W = frictional_wrenches(prof, xi, 1.0)
    wm = w_max(prof, 1.0)
    assert wm[0] == 0.0 and wm[4] == 0.0 and wm[5] == 0.0
    exact = fit_ellipsoid(W, w_max=wm)
    noisy_wm = wm.copy()
    noisy_wm[0] = -1e-10 * wm.max()
    noisy_W = W.copy()
    noisy_W[:, 0] = 1e-6 * wm.max() * np.sin(np.arange(len(W)))  # the kernel's round-off size
    fit = fit_ellipsoid(noisy_W, w_max=noisy_wm)
    assert fit.w_max[0] == 0.0 and fit.dim == exact.dim == 3
    np.testing.assert_allclose(fit.A_e, exact.A_e, rtol=1e-12, atol=1e-12 * np.abs(exact.A_e).max())
    Wz = prepare(noisy_W, noisy_wm)[0]
    np.testing.assert_array_equal(Wz[:, 0], 0.0)
    noisy_W[0, 0] = 0.01 * wm.max()
    with pytest.raises(ValueError, match="exceed the given w_max in component 0"):
        fit_ellipsoid(noisy_W, w_max=noisy_wm)


@SLOW
def test_planar_model_is_fitted_in_the_plane_frame():
    """A patch whose plane is 1e-10 rad off the yz-plane (as an SVD normal of a symmetric
    contact): in its frame the planar contact's normal force and tilting torques are exactly 0
    (object = R local, R the smallest turn from −x to the normal), so its model is exactly 3D;
    its verdicts and minimal force are those of the same patch exactly in the yz-plane, where R
    is the identity."""
    tilt = 1e-10  # below the downsampling's tie tolerance: the same training wrenches
    n = np.array([-np.cos(tilt), 0.0, np.sin(tilt)])
    prof = _flat_patch(n)
    straight = _flat_patch([-1.0, 0.0, 0.0])
    local, R = plane_frame_profile(planar_profile(prof))
    np.testing.assert_allclose(R @ [-1.0, 0, 0], planar_profile(prof).normals[0], atol=1e-15)
    assert (local.normals == [-1.0, 0.0, 0.0]).all() and (local.centers[:, 0] == 0.0).all()
    np.testing.assert_array_equal(plane_frame_profile(planar_profile(straight))[1], np.eye(3))
    cache = LimitSurfaceCache()
    tilted = contact_sets(prof, "planar", cache=cache)[0]
    ref = contact_sets(straight, "planar", cache=cache)[0]
    assert tilted.model.dim == 3
    np.testing.assert_array_equal(tilted.model.w_max[[0, 4, 5]], 0.0)
    np.testing.assert_allclose(tilted.R, R, atol=0)
    # the same contact: its wrench vertices in the object frame agree to the tilt
    np.testing.assert_allclose(tilted.vertices(MU), ref.vertices(MU), atol=1e-6 * prof.F)
