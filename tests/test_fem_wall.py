"""Thin-walled objects (workbench.fem.wall): the triquadratic shell-solid against the thin-ring
formulas (Roark), the mesh, and the squeeze contact."""

import math

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, bottle_family
from workbench.fem.material import Material
from workbench.fem.wall import (
    PET,
    SqueezeControls,
    build_wall,
    circle_surface,
    ring_pinch,
    ring_wall,
    squeeze,
    wall_mesh,
)

R, T = 0.035, 0.5e-3


def _ring(n_theta, material=PET):
    return ring_wall(R, T, material, n_theta)


def test_wall_mesh_closes_the_tube():
    mesh, outer, bottom, _ = wall_mesh(circle_surface(0.03), 1e-3, 16, 3, (0.0, 0.05))
    assert mesh.p.shape[1] == 16 * 4 * 2  # θ = 2π merged onto θ = 0
    assert mesh.t.shape[1] == 16 * 3
    r = np.hypot(*mesh.p[:2])
    np.testing.assert_allclose(r[outer], 0.03, rtol=1e-12)
    np.testing.assert_allclose(r[~outer], 0.029, rtol=1e-12)
    assert bottom.sum() == 32 and np.allclose(mesh.p[2, bottom], 0.0)
    # wall volume: exact annulus up to the polygon's cos/sin factor
    from skfem import Functional

    from workbench.fem.wall import GAUSS_3, Basis, ElementHex2, ElementVector

    vol = Functional(lambda w: 1.0 + 0 * w.x[0]).assemble(
        Basis(mesh, ElementVector(ElementHex2()), quadrature=GAUSS_3)
    )
    poly = 0.5 * 16 * np.sin(2 * np.pi / 16) * (0.03**2 - 0.029**2) * 0.05
    assert vol == pytest.approx(poly, rel=1e-12)


def test_ring_pinch_converges_to_roark():
    errs = [ring_pinch(R, T, PET, n_theta=n)["rel_err"] for n in (32, 64, 128)]
    # perpendicular diameter (4 − π)/(2π) P'R³/D: second-order convergence, 3e-4 at 128
    assert abs(errs[2]) < 1e-3 < abs(errs[1]) < abs(errs[0]) < 0.03


def test_squeeze_ring_load_line():
    """Two rigid jaws closing on a plane-strain ring: closing = (π/4 − 2/π) P'R³/D."""
    D = PET.E * T**3 / (12 * (1 - PET.nu**2))
    P = 1e-3
    r = squeeze(_ring(64), np.array([0, 0, T / 2]), np.array([1.0, 0, 0]), force=P)
    exact = (np.pi / 4 - 2 / np.pi) * (P / T) * R**3 / D
    assert r.delta / exact - 1 == pytest.approx(0.0, abs=0.006)
    np.testing.assert_allclose(r.jaw_forces, [P, P], rtol=1e-8)
    # linear wall, line contact that cannot grow: stiffness independent of the force
    r2 = squeeze(_ring(64), np.array([0, 0, T / 2]), np.array([1.0, 0, 0]), force=10 * P)
    assert r2.stiffness == pytest.approx(r.stiffness, rel=1e-8)
    # stiffness scales with E (linear elasticity)
    r3 = squeeze(
        _ring(64, Material(2 * PET.E, PET.nu)), np.array([0, 0, T / 2]), np.array([1.0, 0, 0]), force=P
    )
    assert r3.stiffness == pytest.approx(2 * r.stiffness, rel=1e-8)


@pytest.fixture(scope="module")
def bottle_wall():
    b = Bottle(bottle_family()[0])
    return b, build_wall(b.points_normals, n_theta=24, n_z=12, z_range=(0.0, b.params.height))


def test_squeeze_bottle_contact(bottle_wall):
    b, wall = bottle_wall
    H = b.params.height
    c, _, _, phi = b.section(0.5 * H)
    axis = np.array([np.cos(phi), np.sin(phi), 0.0])
    r = squeeze(wall, np.r_[c, 0.5 * H], axis, force=10.0)
    np.testing.assert_allclose(r.jaw_forces, [10.0, 10.0], rtol=1e-6)
    # the first-touch points lie on the wall (outer nodes of the quadratic mesh: sag only)
    d, _ = b.signed_distance(r.contact_points)
    assert np.abs(d).max() < 0.2e-3
    # after the solve no footprint node is pushed through a jaw: re-solving from the
    # converged candidate set changes nothing (the growth loop terminated cleanly)
    assert r.candidate_rounds <= 3 and r.contact_nodes >= 2


def _square_surface(half: float):
    """Outer surface of a square tube (a box's flat faces), rounded corners of 5 mm."""
    r = 5e-3

    def surface(th, z):
        d = np.column_stack([np.cos(th), np.sin(th)])
        # superellipse-like square: radius along d to the rounded square |x|, |y| <= half
        p = np.empty_like(d)
        n = np.empty_like(d)
        for k, (c, s) in enumerate(d):
            t = half / max(abs(c), abs(s))
            q = t * np.array([c, s])
            core = np.clip(q, -(half - r), half - r)
            if np.all(np.abs(q) > half - r):  # on a rounded corner
                u = (q - core) / np.linalg.norm(q - core)
                p[k], n[k] = core + r * u, u
            else:
                p[k] = q
                n[k] = [np.sign(c), 0.0] if abs(c) >= abs(s) else [0.0, np.sign(s)]
        return np.column_stack([p, z]), np.column_stack([n, np.zeros_like(z)])

    return surface


@pytest.mark.jit_only("over 15 s as pure Python")
def test_squeeze_flat_face_grows_few_nodes_to_the_full_answer():
    """A flat jaw on a flat face: the whole footprint starts in contact range, the contact
    gathers at the jaw's edges; growing the contact set from a spread start gives the
    footprint-wide LCP's answer with far fewer compliance solves."""
    wall = build_wall(_square_surface(0.03), thickness=0.5e-3, n_theta=32, n_z=12, z_range=(0.0, 0.08))
    c, ax = np.array([0.0, 0.0, 0.04]), np.array([1.0, 0.0, 0.0])
    grown = squeeze(wall, c, ax)
    full = squeeze(wall, c, ax, controls=SqueezeControls(margin=math.inf, max_start=10**6, max_add=10**6))
    assert grown.converged and full.converged
    assert grown.stiffness == pytest.approx(full.stiffness, rel=1e-9)
    assert grown.compliance_solves < 0.6 * full.compliance_solves


def test_squeeze_equal_jaw_forces_off_centre(bottle_wall):
    """Low on the clamped wall, off the section's centre: each jaw travels its own
    distance so both press with the target force (the clamps carry no net force)."""
    b, wall = bottle_wall
    H = b.params.height
    c, _, _, phi = b.section(0.3 * H)
    axis = np.array([np.cos(phi + 0.3), np.sin(phi + 0.3), 0.0])
    side = np.cross([0.0, 0.0, 1.0], axis)
    r = squeeze(wall, np.r_[c, 0.3 * H] + 0.01 * side, axis, force=10.0)
    assert r.converged
    np.testing.assert_allclose(r.jaw_forces, [10.0, 10.0], rtol=1e-8)
    assert r.delta == pytest.approx(r.jaw_travel.sum(), rel=1e-12)
    assert r.jaw_travel.min() > 0


def test_squeeze_bad_input(bottle_wall):
    b, wall = bottle_wall
    H = b.params.height
    with pytest.raises(ValueError, match=r"jaw force in \(0, 500\] N"):
        squeeze(wall, np.array([0, 0, 0.5 * H]), np.array([1.0, 0, 0]), force=0.0)
    with pytest.raises(ValueError, match="misses the object"):
        squeeze(wall, np.array([0, 0, 2 * H]), np.array([1.0, 0, 0]))
    # the footprint reaches the clamped base: the jaws rest on it (rigid), not an error
    low = squeeze(wall, np.array([0, 0, 0.05 * H]), np.array([1.0, 0, 0]))
    assert low.on_clamp and low.delta <= 2 * low.clamp_gap + 1e-12
    assert not squeeze(wall, np.array([0, 0, 0.5 * H]), np.array([1.0, 0, 0])).on_clamp
    with pytest.raises(ValueError, match="positive wall thickness"):
        wall_mesh(circle_surface(0.03), 0.0, 16, 3, (0.0, 0.05))


def test_squeeze_answers_one_set_of_fields_on_every_path():
    """A jaw starting on the clamped base rim (no solve) and a solved squeeze give the same
    frozen answer: the clamped one with inf stiffness, no closing, NaN jaw forces and the width
    between the first touches (the tube's outer diameter); the arrays cannot be written."""
    import dataclasses

    wall = build_wall(circle_surface(0.03), n_theta=16, n_z=4, z_range=(0.0, 0.04))
    ax = np.array([1.0, 0.0, 0.0])
    clamped = squeeze(wall, np.array([0.0, 0.0, 0.0]), ax)  # the footprint's outermost nodes: the rim
    assert clamped.status == "clamped" and "clamped" in clamped.reason
    assert clamped.stiffness == np.inf and clamped.delta == 0.0 and clamped.on_clamp
    assert clamped.width == pytest.approx(0.06, rel=1e-12) and not clamped.implausible
    assert np.isnan(clamped.jaw_forces).all() and (clamped.jaw_travel == 0).all()
    assert clamped.contact_points.shape == (2, 3) and clamped.lcp_solves == 0
    solved = squeeze(wall, np.array([0.0, 0.0, 0.03]), ax)
    assert solved.status == "solved" and solved.converged and solved.reason is None
    assert solved.delta == pytest.approx(solved.jaw_travel.sum(), rel=1e-12)
    assert solved.width == pytest.approx(0.06, rel=1e-12)
    assert [f.name for f in dataclasses.fields(clamped)] == [f.name for f in dataclasses.fields(solved)]
    for arr in (solved.jaw_travel, solved.jaw_forces, solved.contact_points, clamped.jaw_forces):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        solved.stiffness = 1.0


def test_squeeze_controls_refuse_a_bad_setting():
    with pytest.raises(ValueError, match="margin must be a distance >= 0"):
        SqueezeControls(margin=-1.0)
    with pytest.raises(ValueError, match="max_rounds must be an integer >= 1; got 0"):
        SqueezeControls(max_rounds=0)
    wall = build_wall(circle_surface(0.03), n_theta=16, n_z=4, z_range=(0.0, 0.04))
    with pytest.raises(
        ValueError,
        match=r"controls must be a workbench\.fem\.wall\.SqueezeControls"
        r" \(or None: its defaults\); got dict",
    ):
        squeeze(wall, np.array([0.0, 0.0, 0.03]), np.array([1.0, 0.0, 0.0]), controls={"margin": 1.0})


def test_every_dof_has_its_component():
    """Interior facet and bubble dofs of the triquadratic basis included (get_dofs sees only
    boundary facets: building the table from it left them unassigned)."""
    from workbench.fem.wall import components

    b = _ring(16).basis
    comp = components(b)
    assert np.bincount(comp).tolist() == [b.N // 3] * 3
    for c in range(3):
        assert (comp[b.get_dofs(lambda x: np.ones(x.shape[1], dtype=bool)).all(f"u^{c + 1}")] == c).all()
    assert (comp[b.interior_dofs[1]] == 1).all()


def test_nested_dissection_factor_solves_like_superlu():
    """workbench.fem.sparse_factor against SuperLU's default ordering on a small wall's stiffness."""
    import scipy.sparse.linalg as spla
    from skfem import asm
    from skfem.models.elasticity import linear_elasticity

    from workbench.fem.sparse_factor import factor_spd
    from workbench.fem.wall import build_wall

    wall = build_wall(circle_surface(0.03), thickness=1e-3, n_theta=16, n_z=4, z_range=(0.0, 0.04))
    K = asm(linear_elasticity(wall.material.lam, wall.material.mu), wall.basis).tocsr()
    Kff = K[wall.free][:, wall.free]
    b = np.random.default_rng(0).normal(size=(Kff.shape[0], 3))
    ref = spla.splu(Kff.tocsc()).solve(b)
    np.testing.assert_allclose(factor_spd(Kff).solve(b), ref, rtol=1e-7, atol=1e-9 * np.abs(ref).max())
    with pytest.raises(ValueError, match="square"):
        factor_spd(Kff[:, :-1])


def test_wall_stiffness_is_the_isotropic_form_written_out():
    # workbench/fem/wall.py assembles scikit-fem's linear_elasticity(λ, μ); the form written out term by
    # term (tests/naive.py) gives the same matrix to round-off
    from naive import isotropic_elasticity_form
    from skfem import Basis, ElementHex2, ElementVector, asm
    from skfem.models.elasticity import linear_elasticity

    mesh = wall_mesh(circle_surface(0.03), 0.001, 8, 2, (0.0, 0.02))[0]
    basis = Basis(mesh, ElementVector(ElementHex2()))
    K = asm(linear_elasticity(PET.lam, PET.mu), basis)
    K_ref = asm(isotropic_elasticity_form(), basis, mu=PET.mu, lam=PET.lam)
    assert K.shape == K_ref.shape == (basis.N, basis.N) and K.nnz > 0
    assert abs(K - K_ref).max() <= 1e-12 * abs(K_ref).max()


@pytest.mark.jit_only(
    "five ring solves: over a minute as pure Python; their kernels run as Python in "
    "test_ring_pinch_converges_to_roark and test_squeeze_ring_load_line"
)
def test_ring_validation_against_roark_both_ways():
    """workbench.fem.wall.ring_validation: the perpendicular diameter (ring_pinch's) and the
    jaws' load-line closing, (π/4 − 2/π) P'R³/D, both within 0.5 % at 64 elements and closer
    than at 32; one plane-strain slab of 2n × 3 × 3 triquadratic nodes, 3 dofs each; the probe
    load far below a gripper's is not warned about."""
    import warnings

    from workbench.fem.wall import ring_validation
    from workbench.plausible import ImplausibleWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        rows = ring_validation(PET, T, [32, 64], radius=R)
    assert [r["n_theta"] for r in rows] == [32, 64]
    assert [r["dofs"] for r in rows] == [54 * 32, 54 * 64]
    coarse, fine = rows
    assert fine["perpendicular_rel_err"] == ring_pinch(R, T, PET, n_theta=64)["rel_err"]
    assert abs(fine["perpendicular_rel_err"]) < 0.005 and abs(fine["load_line_rel_err"]) < 0.005
    assert abs(coarse["load_line_rel_err"]) > abs(fine["load_line_rel_err"])
    assert abs(coarse["perpendicular_rel_err"]) > abs(fine["perpendicular_rel_err"])
    # the load line by hand: Roark's closing against the squeeze's on the same slab
    D = PET.E * T**3 / (12 * (1 - PET.nu**2))
    exact = (np.pi / 4 - 2 / np.pi) * (1e-3 / T) * R**3 / D
    delta = squeeze(_ring(64), np.array([0, 0, T / 2]), np.array([1.0, 0, 0]), force=1e-3).delta
    assert fine["load_line_rel_err"] == pytest.approx(delta / exact - 1, rel=1e-9)
