"""workbench.limit_surface.sos_ipm: the quartic fit's own interior point (Eq. 3.17) against its
definition (the svec Kronecker kernel against a column-by-column reference) and against Clarabel
on the same program (the same optimum), and fit_quartic(solver="IPM") against Clarabel's fit."""

import naive
import numpy as np
import pytest

import workbench.limit_surface.sos_ipm as sos_ipm
from workbench import config, fit_quartic
from workbench.limit_surface import quartic as quart_mod
from workbench.limit_surface._kernels import (
    _add_svec,
    _cho_solve_upper,
    _schur,
    _smallest_eigenvalue,
    _smat,
    _svec_kron,
)
from workbench.limit_surface.sdp_solver import check_fit_solver
from workbench.limit_surface.sos import exponents, monomials, sos_convexity_maps, svec_index, swap_blocks


@pytest.mark.parametrize("n", [1, 2, 5, 15])
def test_svec_kron_is_the_operator_it_names(n, rng):
    A, B = rng.standard_normal((2, n, n))
    Z, Y = A @ A.T + np.eye(n), B + B.T
    i, j = svec_index(n)
    out = np.empty((len(i), len(i)))
    _svec_kron(Z, Y, i, j, out)
    np.testing.assert_allclose(out, naive.svec_kron(Z, Y), rtol=1e-13, atol=1e-13)
    # the kernels' smat / svec adjoint are the dense maps' (svec: upper triangle by columns,
    # off-diagonals times √2), and isometries: <U, V> = svec(U)·svec(V)
    to_vec, from_vec = naive._svec_maps(n)
    U, V = (lambda M: M + M.T)(rng.standard_normal((n, n))), (lambda M: M + M.T)(rng.standard_normal((n, n)))
    u = np.zeros(len(i))
    _add_svec(U, i, j, u, 0)
    np.testing.assert_allclose(u, from_vec @ U.ravel(), rtol=1e-14)
    assert u @ (from_vec @ V.ravel()) == pytest.approx(np.sum(U * V), rel=1e-12)
    np.testing.assert_allclose(_smat(u, i, j, n), U, rtol=1e-14)
    np.testing.assert_allclose(_smat(u, i, j, n).ravel(), to_vec @ u, rtol=1e-14)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 7, 8, 9, 246])
def test_the_cholesky_solve_is_the_substitutions_one_unknown_at_a_time(n, rng):
    """The Schur system's solve (four rows at a time) against the one-at-a-time substitutions
    bit for bit (the same sums in the same order), for a row-major factor (sos_ipm's) and a
    column-major one, and against np.linalg.solve to round-off."""
    from scipy.linalg.lapack import dpotrf

    B = rng.standard_normal((n, n))
    M = B @ B.T + n * np.eye(n)
    U = dpotrf(M, lower=False, clean=False)[0]
    b = rng.standard_normal(n)
    ref = naive.cho_solve_upper(U, b)
    for factor in (U, np.ascontiguousarray(U)):
        assert np.array_equal(_cho_solve_upper(factor, b), ref)
    np.testing.assert_allclose(ref, np.linalg.solve(M, b), rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("r", [1, 3, 6])
def test_the_schur_matrix_is_its_definition_and_its_triangle_the_full_ones(r, rng):
    """The Schur matrix ``H + Σ_b G_bᵀ (Z_b ⊛ X_b⁻¹) G_b`` against the dense one (naive.svec_kron),
    and the upper triangle the factorisation reads against the full matrix's, bit for bit; at
    r = 1 there is no antisymmetric block."""
    prog = quart_mod._ipm_program(r)
    n_x, L = prog.n_x, prog.L

    def spd(n):
        B = rng.standard_normal((n, n))
        return B @ B.T + np.eye(n)

    Zs, Xi = (spd(prog.n_S), spd(prog.n_A)), (spd(prog.n_S), spd(prog.n_A))
    B = rng.standard_normal((L, L))
    H = np.zeros((n_x, n_x))
    H[:L, :L] = B.T @ B
    M = _schur(Zs, Xi, H, prog.layout, True)
    GA = np.hstack([np.zeros((n_x - L, L)), np.eye(n_x - L)])
    G = prog.G.toarray()
    ref = H + G.T @ naive.svec_kron(Zs[0], Xi[0]) @ G
    if prog.n_A:
        ref += GA.T @ naive.svec_kron(Zs[1], Xi[1]) @ GA
    np.testing.assert_allclose(M, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    upper = np.triu_indices(n_x)
    assert np.array_equal(_schur(Zs, Xi, H, prog.layout, False)[upper], M[upper])


@pytest.mark.parametrize("n", [1, 2, 3, 15, 21])
def test_the_smallest_eigenvalue_by_sturm_bisection_is_lapacks(n, rng):
    """The step length's eigenvalue (Householder tridiagonal + Sturm bisection) against LAPACK's
    (np.linalg.eigvalsh) on indefinite, diagonal, rank-2 and nearly scalar matrices."""
    for trial in range(40):
        B = rng.standard_normal((n, n))
        C = [
            B + B.T,
            np.diag(rng.standard_normal(n)),
            B[:, :2] @ B[:, :2].T,
            1e-9 * (B + B.T) + 5 * np.eye(n),
        ][trial % 4]
        lam = np.linalg.eigvalsh(C)
        scale = max(np.abs(lam).max(), 1e-300)
        assert abs(_smallest_eigenvalue(C) - lam[0]) <= 1e-13 * scale


def _program(r, rng, n_points=300):
    """(Rm, c) of a fit to points near a skewed ellipsoid (the convexity constraint binds)."""
    z = rng.standard_normal((n_points, r)) * np.linspace(0.5, 1.3, r)
    z /= np.linalg.norm(z, axis=1, keepdims=True) ** rng.uniform(0.8, 1.2, (n_points, 1))
    Q, Rm = np.linalg.qr(monomials(z, exponents(r, 4)))
    return Rm, Q.T @ np.ones(n_points)


@pytest.mark.parametrize("r", [1, 2, 3, 4, 6])
def test_the_interior_point_finds_clarabels_optimum(r, rng):
    """The same convex program (the reduced Gram form) solved by Clarabel and by the interior
    point: the same optimal objective (to the stopping rule's 1e-8), the same coefficients, and a Gram
    matrix that certifies them (PSD, Eq. 3.16)."""
    Rm, c = _program(r, rng)
    ok, a_clar, _, _ = quart_mod._solve(r, "CLARABEL", Rm, c, warm_start=False)
    ok_i, a_ipm, M, status = quart_mod._solve(r, "IPM", Rm, c, warm_start=False)
    assert ok and ok_i and status == "optimal"
    obj_c, obj_i = (0.5 * np.sum((Rm @ a - c) ** 2) for a in (a_clar, a_ipm))
    # at least as good as Clarabel's to the stopping rule's gap (1e-8 of the objective, at least
    # 1), and not below the optimum Clarabel brackets to its own tolerances (1e-8, on ‖·‖)
    scale = max(1.0, obj_c)
    assert obj_c - 1e-6 * scale <= obj_i <= obj_c + 1e-8 * scale
    np.testing.assert_allclose(a_ipm, a_clar, atol=1e-4 * np.abs(a_clar).max())
    V1, V2 = sos_convexity_maps(r)
    assert np.linalg.eigvalsh(M).min() >= -1e-12 * np.abs(M).max()
    assert np.abs(V1 @ M.ravel(order="F") - V2 @ a_ipm).max() <= 1e-10 * np.abs(a_ipm).max()


@pytest.mark.parametrize("r", [2, 4, 6])
def test_the_compiled_iteration_is_the_dense_reference_step_by_step(r, rng):
    """The kernels' iteration against naive.hkm_reference, the same method in dense NumPy (Schur
    matrix column by column, np.linalg.solve): the same iteration count and the same optimum."""
    Rm, c = _program(r, rng)
    prog = quart_mod._ipm_program(r)
    res = sos_ipm.solve(Rm, c, prog)
    x, grams, its = naive.hkm_reference(Rm, c, prog.G.toarray(), prog.n_S, prog.n_A, prog.start[0])
    assert res.ok and res.iterations == its
    np.testing.assert_allclose(res.a, x[: prog.L], rtol=0, atol=1e-7 * np.abs(x).max())
    np.testing.assert_allclose(res.grams[0], grams[0], rtol=0, atol=1e-7 * np.abs(grams[0]).max())


def test_an_unconstrained_optimum_is_the_least_squares_solution(rng):
    """Points on a known SOS-convex quartic: the least-squares solution is convex, so the
    constraint is inactive and the interior point must return it (Rm a = c to ~the gap)."""
    z = rng.standard_normal((400, 6))
    f = (z**4).sum(axis=1) + (z**2).sum(axis=1) ** 2
    z = z * f[:, None] ** -0.25
    Q, Rm = np.linalg.qr(monomials(z, exponents(6, 4)))
    c = Q.T @ np.ones(len(z))
    ok, a, _, _ = quart_mod._solve(6, "IPM", Rm, c, warm_start=False)
    np.testing.assert_allclose(a, np.linalg.solve(Rm, c), atol=1e-5 * np.abs(a).max())


def test_fit_quartic_by_the_interior_point_is_clarabels_fit(rng):
    """fit_quartic end to end (whitening, QR, certificate): the IPM's model predicts what
    Clarabel's does on held-out wrenches, to far below the fit's own error."""
    s = np.array([1.0, 0.8, 0.6, 0.3, 0.1, 0.05])
    u = rng.standard_normal((900, 6)) * s
    W = u * (((u / s) ** 2).sum(axis=1) + 0.3 * (u[:, 0] / s[0]) ** 2)[:, None] ** -0.25  # not a quartic
    train, test = W[:600], W[600:]
    wm = np.abs(W).max(axis=0)
    q_c = fit_quartic(train, w_max=wm, fallback_solver=None)
    q_i = fit_quartic(train, w_max=wm, solver="ipm", fallback_solver=None)
    assert q_i.info["solver"] == "IPM" and q_i.info["fallback"] is None  # recorded in upper case
    # an interior point is strictly feasible: the certificate adds round-off only
    assert 0.0 <= q_i.info["certificate_delta"] <= 1e-12 * np.abs(q_i.A_q).max()
    np.testing.assert_allclose(q_i.value(test), q_c.value(test), rtol=1e-5)
    assert q_c.fitting_error(test) > 1e-3  # the agreement is not that of two exact fits


def test_no_convergence_is_a_recorded_fallback(rng, monkeypatch):
    """An IPM that stops short falls back (by default to Clarabel, not the slow SCS), recorded;
    with no fallback the error names what failed and what to try, not a missing install."""
    from dataclasses import replace

    from workbench import config

    monkeypatch.setattr(config, "TOL", replace(config.TOL, sos_ipm_max_iter=2))
    Rm, c = _program(6, rng)
    ok, *_, status = quart_mod._solve(6, "IPM", Rm, c, warm_start=False)
    assert not ok and "2 iterations" in status
    z = rng.standard_normal((300, 6))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    q = fit_quartic(z, solver="ipm")
    assert q.info["solver"] == "CLARABEL" and "IPM: no convergence in 2 iterations" in q.info["fallback"]
    failed = r"IPM: no convergence in 2 iterations\); try another solver"
    with pytest.raises(RuntimeError, match=failed) as exc:
        fit_quartic(z, solver="IPM", fallback_solver=None)
    assert "installed" not in str(exc.value)


def test_a_fit_near_the_coefficient_count_reaches_clarabels_optimum():
    """K = 128 wrenches of S4 for 126 coefficients: the fit nearly interpolates them, so the
    objective is ~1e-7; a gap absolute in it (the first stopping rule) stopped 0.6 % above the
    optimum (a new-user trial).  The IPM's objective is now Clarabel's or lower."""
    from workbench import frictional_wrenches, mesh_profile, sample_twists_thesis, w_max
    from workbench.sources.surface_catalog import THESIS_SURFACES

    prof = mesh_profile(THESIS_SURFACES["S4"], 1000).normalized()
    W = frictional_wrenches(prof, sample_twists_thesis(64, prof, seed=1), 0.5)
    seen = {}
    solve = quart_mod._solve

    def spy(r, solver, Rm, c, warm_start=True):
        seen[solver] = (Rm, c)
        return solve(r, solver, Rm, c, warm_start)

    quart_mod._solve = spy
    try:
        fit_quartic(W, w_max=w_max(prof), solver="CLARABEL", fallback_solver=None)
    finally:
        quart_mod._solve = solve
    Rm, c = seen["CLARABEL"]
    obj = {}
    for name in ("CLARABEL", "IPM"):
        ok, a, _, _ = solve(6, name, Rm, c)
        obj[name] = 0.5 * np.sum((Rm @ a - c) ** 2)
    assert obj["CLARABEL"] < 1e-6  # the regime the trial found
    assert obj["IPM"] <= obj["CLARABEL"] * (1 + 1e-6)


def test_solver_names():
    assert check_fit_solver("ipm") == "IPM"
    assert check_fit_solver("clarabel") == "CLARABEL"
    refused = r"fallback_solver must name a conic .*, or 'IPM' .* got 'IPOPT'"
    with pytest.raises(ValueError, match=refused) as exc:
        check_fit_solver("IPOPT", "fallback_solver")
    assert "(the default)" not in str(exc.value)
    assert quart_mod._fallback_for("IPM", "auto") == "CLARABEL"
    assert quart_mod._fallback_for("CLARABEL", "auto") == "SCS"
    assert len(swap_blocks(6)[0]) == 21  # the blocks the module notes name


@pytest.mark.jit_only(
    "~30 iterations of the Schur kernels as Python take ~10 s; the reference test runs them"
)
@pytest.mark.parametrize("K", [130, 600])
def test_exact_data_of_a_badly_scaled_quartic_is_fitted_as_well_as_by_clarabel(K):
    """Wrenches exactly on f(w) = Σ(w_i/s_i)⁴ + (Σ(w_i/s_i)²)², s spanning 1,500×, drawn as raw
    Gaussian directions (they crowd the thin axes): the fit through its data has an objective
    ~0, where a gap floor of 1e-16 × ½‖c‖² stopped with held-out errors 10-100× Clarabel's (a
    new-user trial; the floor was chosen on seeds 10-13 and 100-102, these are others).  Now the
    IPM's held-out Eq. 3.18 error is within 3x of the better of Clarabel's and the IPM's own
    round-off limit (its fit with a floor no double reaches, 1e-30: what its Schur solves can give
    on this host), and the fit has the quartic's value at a point worked by hand on a thin axis,
    where the samples crowd (along the thick axes there are none: both solvers extrapolate there,
    differently).  Where BLAS rounds otherwise the limit moves: on an AMD EPYC host (OpenBLAS's
    Haswell kernels) K = 130 gave the IPM 1.1e-6 at the default floor and 1.5e-6 at the limit,
    Clarabel 7.2e-8; a floor of 1e-16 gave 8.3e-6 there, and fails this test on every host seen."""
    s = np.array([1.0, 0.05, 3.0, 0.002, 0.4, 0.01])

    def f(W):
        X = W / s
        return (X**4).sum(axis=1) + ((X**2).sum(axis=1)) ** 2

    rng = np.random.default_rng(7000 + K)
    U = rng.standard_normal((K + 3000, 6))
    W = U / f(U)[:, None] ** 0.25
    train, test = W[:K], W[K:]
    fits = {name: fit_quartic(train, solver=name, fallback_solver=None) for name in ("IPM", "CLARABEL")}
    with config.override(sos_ipm_gap_floor=1e-30):
        fits["limit"] = fit_quartic(train, solver="IPM", fallback_solver=None)
    errs = {name: np.mean(np.abs(q.value(test) - 1)) for name, q in fits.items()}
    assert errs["IPM"] <= 3.0 * max(errs["CLARABEL"], errs["limit"])
    # at w = ½ s_3 e_3: (½)⁴ + ((½)²)² = 0.125
    assert fits["IPM"].value(0.5 * s[3] * np.eye(6)[3]) == pytest.approx(0.125, rel=1e-4)


@pytest.mark.jit_only(
    "~30 iterations of the Schur kernels as Python take ~10 s; the reference test runs them"
)
def test_a_gap_stalled_in_round_off_returns_clarabels_accuracy_marked_inaccurate(monkeypatch):
    """Exact wrenches of a badly scaled quartic (a fit through its data, objective ~0) with a
    floor no double reaches: the gap stops halving, and the iterate within Clarabel's own
    accuracy is returned as "optimal_inaccurate" (recorded in info["status"]), not a failure."""
    from dataclasses import replace

    from workbench import config

    monkeypatch.setattr(config, "TOL", replace(config.TOL, sos_ipm_gap_floor=1e-40))
    s = np.array([1.0, 0.05, 3.0, 0.002, 0.4, 0.01])
    U = np.random.default_rng(2154).standard_normal((130, 6))  # its gap stalls at ~1e-20 (traced)
    W = U / (((U / s) ** 4).sum(axis=1) + ((U / s) ** 2).sum(axis=1) ** 2)[:, None] ** 0.25
    q = fit_quartic(W, fallback_solver=None)
    assert q.info["solver"] == "IPM" and q.info["status"] == "optimal_inaccurate"
    assert q.info["train_error"] < 1e-6
    assert q.value(0.5 * s[3] * np.eye(6)[3]) == pytest.approx(0.125, rel=1e-4)


@pytest.mark.slow
def test_a_fit_is_the_same_whether_its_kernels_were_compiled_or_loaded_from_the_cache(tmp_path):
    """Two fresh processes sharing an empty Numba cache: the first compiles the kernels, the
    second loads them.  A fit through its data (K = 130, objective ~0) amplifies round-off, and
    with fastmath the two processes' coefficients differed by 2e-8 (a fresh-clone test caught
    it: a row's numbers depended on which process ran it); they must be equal bit for bit."""
    import os
    import subprocess
    import sys

    script = (
        "import hashlib, logging; logging.disable(logging.WARNING)\n"
        "from workbench import fit_quartic, frictional_wrenches, mesh_profile, sample_twists_thesis, w_max\n"
        "from workbench.sources.surface_catalog import THESIS_SURFACES\n"
        "prof = mesh_profile(THESIS_SURFACES['S4'], 1000).normalized()\n"
        "W = frictional_wrenches(prof, sample_twists_thesis(65, prof, seed=1), 0.5)\n"
        "print(hashlib.sha256(fit_quartic(W, w_max=w_max(prof)).A_q.tobytes()).hexdigest())\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_DISABLE_JIT": "0"}
    runs = [
        subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
        ).stdout
        for _ in range(2)
    ]
    assert runs[0] == runs[1] and len(runs[0].strip()) == 64
