"""Neo-Hookean pad (workbench/fem/nonlinear.py): element-batched assembly against scikit-fem
forms, small-strain consistency with the linear pad, finite-difference tangent."""

import numpy as np
import pytest
from skfem import BilinearForm, LinearForm, asm
from skfem.helpers import ddot, det, grad, inv, mul, transpose

from workbench.fem.contact import solve_contact
from workbench.fem.elasticity import GAUSS_1, GAUSS_2, basis, stiffness
from workbench.fem.material import Material
from workbench.fem.nonlinear import NonlinearControls, NonlinearPad
from workbench.fem.obstacles import Sphere
from workbench.fem.pad import PadGeometry, condense_pad

GEOM = PadGeometry(0.008, 0.008, 0.003, 4, 4, 2)
MAT = Material(1.0e6, 0.45)


def _kin(w):
    F = grad(w["prev"]) + np.eye(3)[:, :, None, None]
    Fi = inv(F)
    J = det(F)
    return F, Fi, transpose(Fi), J, ddot(F, F)


@LinearForm
def _res_iso(v, w):
    F, _, FiT, J, I1 = _kin(w)
    return ddot(w["mu"] * J ** (-2 / 3) * (F - I1 / 3 * FiT), grad(v))


@LinearForm
def _res_vol(v, w):
    _, _, FiT, J, _ = _kin(w)
    return ddot(w["kappa"] * np.log(J) * FiT, grad(v))


@BilinearForm
def _tan_iso(u, v, w):
    F, Fi, FiT, J, I1 = _kin(w)
    dF = grad(u)
    dP = (
        dF
        - 2 / 3 * ddot(FiT, dF) * (F - I1 / 3 * FiT)
        - 2 / 3 * ddot(F, dF) * FiT
        + I1 / 3 * transpose(mul(mul(Fi, dF), Fi))
    )
    return w["mu"] * J ** (-2 / 3) * ddot(dP, grad(v))


@BilinearForm
def _tan_vol(u, v, w):
    _, Fi, FiT, J, _ = _kin(w)
    dF = grad(u)
    return w["kappa"] * ddot(ddot(FiT, dF) * FiT - np.log(J) * transpose(mul(mul(Fi, dF), Fi)), grad(v))


@pytest.mark.parametrize("beta", [0.0, 0.3, 1.0])
def test_batched_assembly_matches_skfem_forms(beta):
    """Residual and tangent at a finite deformation against scikit-fem forms
    written directly from the formulas in the module docstring."""
    nl = NonlinearPad(GEOM, MAT, stabilization=beta)
    u = 2e-4 * np.random.default_rng(0).standard_normal(nl.b2.N)
    r, K = nl._internal(u)
    b2, b1 = basis(nl.mesh, GAUSS_2), basis(nl.mesh, GAUSS_1)
    p2, p1 = b2.interpolate(u), b1.interpolate(u)
    kap = MAT.bulk
    r_ref = asm(_res_iso, b2, prev=p2, mu=MAT.mu) + (1 - beta) * asm(_res_vol, b1, prev=p1, kappa=kap)
    K_ref = asm(_tan_iso, b2, prev=p2, mu=MAT.mu) + (1 - beta) * asm(_tan_vol, b1, prev=p1, kappa=kap)
    if beta:
        r_ref = r_ref + beta * asm(_res_vol, b2, prev=p2, kappa=kap)
        K_ref = K_ref + beta * asm(_tan_vol, b2, prev=p2, kappa=kap)
    assert np.abs(r - r_ref).max() <= 1e-10 * np.abs(r_ref).max()
    assert abs(K - K_ref).max() <= 1e-10 * abs(K_ref).max()


def test_tangent_is_the_residual_derivative_and_linear_at_rest():
    nl = NonlinearPad(GEOM, MAT, stabilization=0.0)
    r0, K0 = nl._internal(np.zeros(nl.b2.N))
    assert np.abs(r0).max() == 0.0
    K_lin = stiffness(nl.mesh, MAT, "sri")
    assert abs(K0 - K_lin).max() <= 1e-12 * abs(K_lin).max()  # small-strain limit = linear SRI
    rng = np.random.default_rng(1)
    u, du = 3e-4 * rng.standard_normal(nl.b2.N), rng.standard_normal(nl.b2.N)
    _, K = nl._internal(u)
    eps = 1e-9
    fd = (nl._internal(u + eps * du)[0] - nl._internal(u - eps * du)[0]) / (2 * eps)
    assert np.abs(fd - K @ du).max() <= 1e-6 * np.abs(K @ du).max()


@pytest.mark.jit_only("22 s as pure Python; the element kernel runs as Python in the assembly tests above")
def test_small_indentation_matches_the_linear_pad():
    """At δ/h = 1% the neo-Hookean contact equals the linear condensed contact
    (same discretization: full integration) to ~δ/h."""
    geom = PadGeometry(0.01, 0.01, 0.003, 8, 8, 3)
    h = geom.thickness
    obs = Sphere((0, 0, h + 0.008), 0.008)
    d = 0.01 * h
    nl = NonlinearPad(geom, MAT, stabilization=1.0).solve(obs, [d], step=d)[d]
    lin = solve_contact(condense_pad(geom, MAT, scheme="full", cache_dir=False), obs, d)
    assert abs(nl.force / lin.force - 1) < 0.02
    assert np.array_equal(nl.lam > 0, lin.lam > 0)
    assert nl.max_penetration <= 1e-3 * h


@pytest.mark.jit_only("28 s as pure Python; the element kernel runs as Python in the assembly tests above")
def test_force_grows_and_stiffens_with_compression():
    geom = PadGeometry(0.01, 0.01, 0.003, 6, 6, 2)
    h = geom.thickness
    obs = Sphere((0, 0, h + 0.008), 0.008)
    ds = [0.1 * h, 0.2 * h, 0.3 * h]
    sols = NonlinearPad(geom, MAT).solve(obs, ds)
    F = [sols[d].force for d in ds]
    assert F[0] < F[1] < F[2]
    lin = condense_pad(geom, MAT, scheme="full", cache_dir=False)
    assert sols[ds[-1]].force > solve_contact(lin, obs, ds[-1]).force  # geometric stiffening


def test_bad_inputs():
    with pytest.raises(ValueError, match="stabilization"):
        NonlinearPad(GEOM, MAT, stabilization=2.0)
    nl = NonlinearPad(GEOM, MAT)
    with pytest.raises(ValueError, match="deeper than the layer"):
        nl.solve(Sphere((0, 0, GEOM.thickness + 0.01), 0.01), [2 * GEOM.thickness])


def test_zero_displacement_and_preloaded_start():
    """δ = 0 in the sequence: stress-free when the obstacle only touches, a real solve
    when it already overlaps the face (then equal to the small linear contact)."""
    nl = NonlinearPad(GEOM, MAT, stabilization=1.0)
    h = GEOM.thickness
    touch = nl.solve(Sphere((0, 0, h + 0.01), 0.01), [0.0, 0.01 * h], step=0.01 * h)
    assert touch[0.0].force == 0.0 and touch[0.0].iterations == 0
    assert touch[0.01 * h].force > 0
    pre = Sphere((0, 0, h + 0.01 - 0.01 * h), 0.01)  # overlaps by 1% of h at δ = 0
    sol = nl.solve(pre, [0.0], step=0.01 * h)[0.0]
    lin = solve_contact(condense_pad(GEOM, MAT, scheme="full", cache_dir=False), pre, 0.0)
    assert sol.force == pytest.approx(lin.force, rel=0.02)


def test_a_vertex_touching_the_face_to_round_off_is_not_a_load():
    """An obstacle vertex on the face, 2e-17 m 'inside' by round-off (a faceted cylinder placed to
    touch at δ = 0), used to make the δ = 0 step fail ('Newton did not converge at delta = 0 m');
    the solve now starts stress-free and matches the same cylinder lifted clear by 1 nm."""
    import trimesh

    from workbench.fem.obstacles import MeshObstacle

    h = 0.003
    geom = PadGeometry(0.008, 0.01, h, 4, 5, 2)
    forces = []
    for lift in (-2e-17, 1e-9):
        cyl = trimesh.creation.cylinder(radius=0.01, height=0.03, sections=16)
        turn = np.eye(4)
        turn[:3, :3] = [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]  # axis along y, a vertex line at the bottom
        cyl.apply_transform(turn)
        cyl.apply_translation([0, 0, h + 0.01 + lift])
        assert (cyl.vertices[:, 2].min() - h) * lift > 0  # really inside / outside
        forces.append(NonlinearPad(geom, Material(1e6, 0.45)).solve(MeshObstacle(cyl), [3e-4])[3e-4].force)
    # 1 nm less approach out of 0.3 mm: the force changes by ~1.5 x 1e-9/3e-4 (F ~ δ^1.5 or less)
    assert forces[0] == pytest.approx(forces[1], rel=1.5 * 1e-9 / 3e-4 + 1e-9)


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"penalty": 0.0}, r"penalty must be a finite number > 0; got 0.0"),
        ({"gap_tol": float("nan")}, r"gap_tol must be a finite number > 0; got nan"),
        ({"newton_rtol": "1e-7"}, r"newton_rtol must be a finite number > 0; got '1e-7'"),
        ({"max_newton": 0}, r"max_newton must be an integer >= 1; got 0"),
        ({"max_uzawa": 2.0}, r"max_uzawa must be an integer >= 1; got 2.0"),
        ({"max_bisections": True}, r"max_bisections must be an integer >= 0; got True"),
    ],
)
def test_nonlinear_controls_refuse_what_the_solver_cannot_use(bad, message):
    with pytest.raises(ValueError, match=message):
        NonlinearControls(**bad)
    assert NonlinearControls(max_bisections=0).max_bisections == 0  # 0: no halving, allowed


def test_solve_takes_its_controls_as_one_object_only():
    nl = NonlinearPad(GEOM, MAT)
    with pytest.raises(
        ValueError,
        match=r"controls must be a workbench\.fem\.nonlinear\.NonlinearControls"
        r" .*got dict — pass Nonl",
    ):
        nl.solve(Sphere((0, 0, GEOM.thickness + 0.01), 0.01), [1e-4], controls={"penalty": 5.0})
