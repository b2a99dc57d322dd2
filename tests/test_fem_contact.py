"""Condensed-pad contact: LCP correctness and the compressible thin-layer (Winkler) limit."""

import numpy as np
import pytest

from workbench.fem.contact import solve_contact, solve_lcp
from workbench.fem.material import Material
from workbench.fem.obstacles import Cylinder, Plane, Sphere
from workbench.fem.pad import PadGeometry, condense_pad


def test_lcp_solution_is_complementary():
    rng = np.random.default_rng(0)
    B = rng.standard_normal((40, 40))
    A = B @ B.T + 40 * np.eye(40)
    d = rng.standard_normal(40)
    lam, _, _ = solve_lcp(A, d)
    w = A @ lam + d
    assert (lam >= 0).all() and (w >= -1e-10).all()
    assert np.abs(lam * w).max() <= 1e-10


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_sphere_on_thin_compressible_layer_matches_winkler(thin_pad):
    # Winkler: p = (M/h)(δ - r²/2R), a = sqrt(2Rδ), F = π R M δ² / h   (M = E at nu = 0)
    R, delta = 0.05, 0.1e-3
    h = thin_pad.geometry.thickness
    sol = solve_contact(thin_pad, Sphere((0, 0, h + R), R), delta)
    M = thin_pad.material.p_wave
    a = np.sqrt(2 * R * delta)
    assert a / h >= 3
    F_w = np.pi * R * M * delta**2 / h
    assert sol.force == pytest.approx(F_w, rel=0.05)
    assert sol.max_penetration <= 1e-6 * h
    r = np.hypot(*thin_pad.face_xy.T)
    assert (sol.lam[r > 1.3 * a] == 0).all()  # no force well outside the contact radius


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_plane_and_no_contact(thin_pad):
    h = thin_pad.geometry.thickness
    far = solve_contact(thin_pad, Sphere((0, 0, h + 0.05 + 1e-3), 0.05), 0.0)
    assert not far.in_contact and far.force == 0.0
    flat = solve_contact(thin_pad, Plane((0, 0, h), (0, 0, -1)), 0.05e-3)
    assert flat.force > 0 and (flat.lam >= 0).all()
    with pytest.raises(ValueError, match="deeper than the layer"):
        solve_contact(thin_pad, Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 2 * h)


CASES = {
    "sphere": (lambda h: Sphere((0, 0, h + 0.02), 0.02), 0.4e-3),
    "sphere off-center": (lambda h: Sphere((0.002, -0.0015, h + 0.015), 0.015), 0.3e-3),
    "cylinder": (lambda h: Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 0.3e-3),
    "tilted cylinder": (lambda h: Cylinder((0.001, 0, h + 0.012), (0.3, 1, 0), 0.012), 0.3e-3),
    "tilted plane": (lambda h: Plane((0, 0, h - 0.2e-3), (0.08, 0.05, -1)), 0.0),
}


@pytest.mark.parametrize("case", list(CASES))
def test_condensed_equals_full_mesh_linear_solve(case):
    from workbench.fem.contact import solve_contact_full

    geom = PadGeometry(width=0.008, length=0.01, thickness=0.002, nx=8, ny=10, nz=3)
    mat = Material(E=1.0e6, nu=0.45)
    make, delta = CASES[case]
    obs = make(geom.thickness)
    cond = solve_contact(condense_pad(geom, mat, cache_dir=False), obs, delta)
    full = solve_contact_full(geom, mat, obs, delta)
    assert cond.force > 0
    assert cond.force == pytest.approx(full.force, rel=1e-8)
    assert np.linalg.norm(cond.lam - full.lam) <= 1e-8 * np.linalg.norm(full.lam)
    assert full.max_penetration <= 1e-9 * geom.thickness


def _full_mesh_saddle_point(geom, mat, obs, delta, plane_strain=False):
    """The full-mesh Signorini solve by its saddle-point system ``[[K, Bᵀ], [B, 0]] [u; -λ] =
    [0; -d_S]`` and SuperLU (the slow reference of solve_contact_full's eliminated form)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from workbench.fem.contact import face_gaps
    from workbench.fem.elasticity import basis, stiffness
    from workbench.fem.pad import top_face_nodes

    mesh = geom.mesh()
    face = top_face_nodes(mesh.p, geom.thickness)
    _, d, nrm = face_gaps(geom, mesh.p[:2, face].T, obs, delta)
    K = stiffness(mesh, mat, "sri")
    nodal = basis(mesh).nodal_dofs
    free = np.ones(K.shape[0], dtype=bool)
    free[nodal[:, np.isclose(mesh.p[2], 0.0)].ravel()] = False
    if plane_strain:
        free[nodal[1]] = False
    fidx = np.flatnonzero(free)
    pos = np.full(K.shape[0], -1)
    pos[fidx] = np.arange(fidx.size)
    face_free = pos[nodal[:, face]].T
    active = d < 0
    for _ in range(30):
        S = np.flatnonzero(active)
        cols = face_free[S].ravel()
        keep = cols >= 0
        B = sp.csr_matrix(
            (nrm[S].ravel()[keep], (np.repeat(np.arange(S.size), 3)[keep], cols[keep])),
            shape=(S.size, fidx.size),
        )
        sol = spla.spsolve(
            sp.bmat([[K[fidx][:, fidx], B.T], [B, None]], format="csc"), np.r_[np.zeros(fidx.size), -d[S]]
        )
        lam = np.zeros(face.size)
        lam[S] = -sol[fidx.size :]
        u_face = np.where(face_free >= 0, sol[: fidx.size][face_free], 0.0)
        gap = d + np.einsum("ij,ij->i", nrm, u_face)
        new = (active & (lam > 0)) | (~active & (gap < -1e-12 * geom.thickness))
        if np.array_equal(new, active):
            return lam, u_face
        active = new
    raise AssertionError("the reference did not converge")


@pytest.mark.parametrize(
    "case, plane_strain",
    [("sphere", False), ("tilted cylinder", False), ("tilted plane", False), ("cylinder along y", True)],
)
def test_full_mesh_solve_equals_its_saddle_point_form(case, plane_strain):
    """Each active node's constraint eliminates one displacement (the SPD form, factored in
    nested-dissection order) — the same forces and face displacements as the saddle-point
    system with the multipliers, to rounding; with plane strain too (a fixed u_y component)."""
    from workbench.fem.contact import solve_contact_full
    from workbench.fem.obstacles import Cylinder

    geom = PadGeometry(width=0.008, length=0.01, thickness=0.002, nx=8, ny=10, nz=3)
    mat = Material(E=1.0e6, nu=0.45)
    if case == "cylinder along y":
        geom = PadGeometry(width=0.008, length=0.0005, thickness=0.002, nx=16, ny=1, nz=4)
        obs, delta = Cylinder((0, 0, 0.002 + 0.01), (0, 1, 0), 0.01), 0.1e-3
    else:
        make, delta = CASES[case]
        obs = make(geom.thickness)
    lam, u_face = _full_mesh_saddle_point(geom, mat, obs, delta, plane_strain)
    full = solve_contact_full(geom, mat, obs, delta, plane_strain=plane_strain)
    assert lam.sum() > 0
    assert np.linalg.norm(full.lam - lam) <= 1e-9 * np.linalg.norm(lam)
    assert np.abs(full.u - u_face).max() <= 1e-9 * np.abs(u_face).max()


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_pad_on_a_thesis_object_if_available(thin_pad):
    from pathlib import Path

    from workbench.fem.extract import extract_profile
    from workbench.fem.obstacles import MeshObstacle

    path = (
        Path(__file__).resolve().parents[2]
        / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
    )
    if not path.exists():
        pytest.skip("thesis objects not available")
    obs = MeshObstacle(path)
    # put the bottle's outermost side point (max x) onto the pad face center: x -> -z
    top = obs.mesh.vertices[np.argmax(obs.mesh.vertices[:, 0])]
    h = thin_pad.geometry.thickness
    T = np.eye(4)
    T[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # rotation taking +x to -z
    T[:3, 3] = [-top[2], -top[1], h + top[0]]
    placed = obs.transformed(T, facing=(0, 0, -1))  # the bottle's wall is 0.4 mm: one-sided
    sol = solve_contact(thin_pad, placed, 0.2e-3)
    prof = extract_profile(thin_pad, sol, placed)
    assert prof is not None and prof.F > 0
    assert (prof.normals[:, 2] < 0).all()  # outward from the bottle, towards the jaw


def test_normal_projection_kernels_match_numpy():
    from naive import normal_block, normal_rows

    from workbench.fem._kernels import _normal_block, _normal_rows

    rng = np.random.default_rng(4)
    n = 37
    C = rng.standard_normal((3 * n, 3 * n))
    nrm = rng.standard_normal((n, 3))
    nodes = np.sort(rng.choice(n, 20, replace=False))
    G = np.empty((nodes.size, 3 * n))
    _normal_rows(C, nodes, nrm, G)
    assert np.allclose(G, normal_rows(C, nodes, nrm), rtol=1e-13, atol=1e-13)
    A = np.empty((nodes.size, nodes.size))
    _normal_block(G, nodes, nrm, A)
    assert np.allclose(A, normal_block(G, nodes, nrm), rtol=1e-13, atol=1e-12)


@pytest.mark.parametrize("fraction", [0.0, 0.3, 1.0])
def test_lcp_active_set_variants_agree_with_nnls(fraction, monkeypatch):
    """Direct-Cholesky and factor-once (Schur) active-set steps give the NNLS optimum."""
    from scipy.optimize import nnls

    import workbench.fem.contact as fc

    monkeypatch.setattr(fc, "SCHUR_FRACTION", fraction)
    rng = np.random.default_rng(5)
    X = rng.standard_normal((60, 60))
    A = X @ X.T / 60 + np.eye(60)
    d = rng.standard_normal(60)
    lam, _, method = fc.solve_lcp(A, d)
    L = np.linalg.cholesky(A)
    ref, _ = nnls(L.T, -np.linalg.solve(L, d))
    assert method == "pdas"
    assert np.abs(lam - ref).max() < 1e-10
    w = A @ lam + d
    assert lam.min() >= 0 and w.min() > -1e-12 and abs(lam @ w) < 1e-10
