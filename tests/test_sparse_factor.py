"""workbench.fem.sparse_factor: the nested-dissection factor and its blocked solves of many right-hand
sides (workbench.fem._kernels) against slow references and SuperLU."""

from __future__ import annotations

import dataclasses

import naive
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from workbench import config
from workbench.fem._kernels import _lower_unit_rows, _upper_rows
from workbench.fem.sparse_factor import factor_spd


def _random_triangular(rng, n, density, lower):
    M = sp.random(n, n, density=density, random_state=rng, format="csr")
    M = sp.tril(M, -1) if lower else sp.triu(M, 1)
    diag = rng.uniform(1.0, 2.0, n) if not lower else rng.uniform(5.0, 9.0, n)  # L's is ignored
    return (M + sp.diags(diag)).tocsr()


@pytest.mark.parametrize("k", [1, 3, 17])
def test_triangular_row_kernels_match_the_slow_substitution(k):
    rng = np.random.default_rng(k)
    n = 40
    B = rng.standard_normal((n, k))
    L = _random_triangular(rng, n, 0.2, lower=True)
    U = _random_triangular(rng, n, 0.2, lower=False)
    for M in (L, U):
        M.sort_indices()
    X = B.copy()
    _lower_unit_rows(L.indptr, L.indices, L.data, X)
    np.testing.assert_allclose(X, naive.lower_unit_solve(L.toarray(), B), rtol=1e-12, atol=1e-12)
    X = B.copy()
    _upper_rows(U.indptr, U.indices, U.data, X)
    np.testing.assert_allclose(X, naive.upper_solve(U.toarray(), B), rtol=1e-12, atol=1e-12)


def _spd(n_side):
    """A 2D Laplacian plus a diagonal shift: sparse, symmetric positive definite."""
    T = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n_side, n_side))
    eye = sp.identity(n_side)
    return (sp.kron(T, eye) + sp.kron(eye, T) + 0.1 * sp.identity(n_side**2)).tocsr()


@pytest.mark.parametrize("k", [1, 8, 40])
def test_blocked_and_superlu_solves_agree_with_spsolve(k, monkeypatch):
    K = _spd(15)
    B = np.random.default_rng(0).standard_normal((K.shape[0], k))
    ref = spla.spsolve(K.tocsc(), B).reshape(B.shape)
    f = factor_spd(K, blocked=True)
    assert f.rows is not None and factor_spd(K).rows is None
    for least in (1, 10**6):  # the blocked kernels for every k, then SuperLU for every k
        monkeypatch.setattr(
            config, "DEFAULTS", dataclasses.replace(config.DEFAULTS, blocked_solve_min_rhs=least)
        )
        got = f.solve(B)
        np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(f.solve(B[:, 0]), ref[:, 0], rtol=1e-10)  # one vector: SuperLU


def test_a_wall_compliance_is_the_same_by_either_solve(monkeypatch):
    from workbench.fem.wall import build_wall, circle_surface

    wall = build_wall(circle_surface(0.03), thickness=1e-3, n_theta=16, n_z=4, z_range=(0.0, 0.04))
    assert wall.lu.rows is not None  # walls keep the row copies
    free = np.flatnonzero((wall.free_position[wall.outer_dofs] >= 0).all(axis=1))  # off the clamped rim
    nodes = free[::5]
    dirs = np.tile([1.0, 0.0, 0.0], (nodes.size, 1))
    out = {}
    for least in (1, 10**6):
        monkeypatch.setattr(
            config, "DEFAULTS", dataclasses.replace(config.DEFAULTS, blocked_solve_min_rhs=least)
        )
        out[least] = wall.compliance(nodes, dirs)
    assert nodes.size > 16
    np.testing.assert_allclose(out[1], out[10**6], rtol=1e-9, atol=1e-12 * np.abs(out[1]).max())


def test_one_order_restricted_to_each_dirichlet_set_solves_exactly():
    """squeeze_nonlinear orders the whole mesh once and factors every free set in that order."""
    from workbench.fem.sparse_factor import nested_dissection, restrict_order

    K = _spd(20)
    perm = nested_dissection(K)
    assert np.array_equal(np.sort(perm), np.arange(K.shape[0]))
    rng = np.random.default_rng(3)
    for _ in range(3):
        keep = np.flatnonzero(rng.random(K.shape[0]) > 0.2)  # ~20 % of the dofs prescribed
        order = restrict_order(perm, keep)
        # the kept dofs in exactly the order the full ordering eliminates them
        in_perm = [p for p in perm if p in set(keep.tolist())]
        assert keep[order].tolist() == in_perm
        Kk = K[keep][:, keep]
        b = rng.standard_normal(keep.size)
        ref = spla.spsolve(Kk.tocsc(), b)
        np.testing.assert_allclose(factor_spd(Kk, perm=order).solve(b), ref, rtol=1e-10, atol=1e-12)
        # an induced subgraph eliminated in the restricted order fills no more than the whole
        # graph in the full order (restrict_order's docstring)
        assert factor_spd(Kk, perm=order).lu.L.nnz <= factor_spd(K, perm=perm).lu.L.nnz


@pytest.mark.parametrize("perm", [[0, 1], [0, 0, 1, 2], [3, 2, 1, 0, 4]])
def test_factor_refuses_an_order_that_is_not_a_permutation(perm):
    K = sp.identity(4, format="csr") * 2.0
    with pytest.raises(ValueError, match="permutation of 0..3"):
        factor_spd(K, perm=np.array(perm))


def _refactor_case(seed):
    """A sparse SPD K (the 2D Laplacian with random symmetric values on its pattern), a kept set
    (the unclamped dofs) and, inside it, a pinned set (the contact nodes of one Newton step)."""
    rng = np.random.default_rng(seed)
    K = _spd(14)
    K = K + sp.diags(rng.uniform(0.0, 1.0, K.shape[0]))  # same pattern, other values
    K.sort_indices()
    keep = np.flatnonzero(rng.random(K.shape[0]) > 0.15)
    pinned = rng.random(keep.size) < 0.1
    return rng, K, keep, pinned


def test_refactor_solves_the_kept_block_with_pinned_rows_as_dirichlet_values():
    """The Newton step's linear system both ways: CHOLMOD on the pinned-as-identity matrix (the
    pinned values moved to the right-hand side first, as the caller does), and the textbook
    elimination of the pinned rows and columns solved densely."""
    from workbench.fem.sparse_factor import Refactor, nested_dissection, restrict_order

    rng, K, keep, pinned = _refactor_case(0)
    chol = Refactor(K, keep, restrict_order(nested_dissection(K), keep))
    Kk = K[keep][:, keep].toarray()
    for scale in (1.0, 3.0):  # a second matrix of the same pattern: numeric factor only
        Ks = K.copy()
        Ks.data *= scale
        b = rng.standard_normal(keep.size)
        f = ~pinned
        A = scale * Kk
        rhs = b.copy()
        rhs[f] -= A[np.ix_(f, pinned)] @ b[pinned]
        x = chol.factor(Ks, pinned).solve(rhs)
        np.testing.assert_array_equal(x[pinned], b[pinned])
        ref = np.linalg.solve(A[np.ix_(f, f)], b[f] - A[np.ix_(f, pinned)] @ b[pinned])
        np.testing.assert_allclose(x[f], ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())
        # without pins: the kept block itself, several right-hand sides at once
        B = rng.standard_normal((keep.size, 3))
        np.testing.assert_allclose(chol.factor(Ks).solve(B), np.linalg.solve(A, B), rtol=1e-10, atol=1e-12)
    assert chol.fallbacks == 0


def test_refactor_falls_back_to_lu_on_an_indefinite_matrix_and_counts_it(caplog):
    from workbench.fem.sparse_factor import Refactor, nested_dissection

    rng, K, _, _ = _refactor_case(1)
    keep = np.arange(K.shape[0])
    chol = Refactor(K, keep, nested_dissection(K))
    Kin = K.copy()
    on_diagonal = Kin.indices == np.repeat(np.arange(K.shape[0]), np.diff(K.indptr))
    Kin.data[on_diagonal] -= 2.5  # some negative pivots
    assert np.linalg.eigvalsh(Kin.toarray()).min() < 0
    b = rng.standard_normal(keep.size)
    with caplog.at_level("INFO"):
        x = chol.factor(Kin).solve(b)
    assert chol.fallbacks == 1 and "not positive definite" in caplog.text
    np.testing.assert_allclose(x, np.linalg.solve(Kin.toarray(), b), rtol=1e-8, atol=1e-10)
    # and back to Cholesky for the next positive definite one
    np.testing.assert_allclose(chol.factor(K).solve(b), np.linalg.solve(K.toarray(), b), rtol=1e-10)
    assert chol.fallbacks == 1


def test_refactor_refuses_another_pattern_and_bad_masks():
    from workbench.fem.sparse_factor import Refactor, nested_dissection

    _, K, keep, pinned = _refactor_case(2)
    chol = Refactor(K, np.arange(K.shape[0]), nested_dissection(K))
    other = (K + sp.random(*K.shape, density=0.01, random_state=0)).tocsr()
    with pytest.raises(ValueError, match="pattern differs"):
        chol.factor(other)
    with pytest.raises(ValueError, match="pinned must be a"):
        chol.factor(K, pinned[:5])
    with pytest.raises(ValueError, match="keep must be sorted unique"):
        Refactor(K, keep[::-1], np.arange(keep.size))
    with pytest.raises(ValueError, match="order must be an elimination order"):
        Refactor(K, keep, np.arange(keep.size - 1))


def test_one_shot_cholesky_solves_like_dense_in_its_own_and_a_given_order():
    """``cholesky`` (the full-mesh contact reference's factor) against dense solves: an SPD matrix
    with unsorted CSR indices (as ``Tᵀ K T`` comes out of a sparse product), in METIS's order
    and in a given one; an indefinite matrix goes to SuperLU and is counted."""
    from workbench.fem.sparse_factor import cholesky

    rng, K, _, _ = _refactor_case(2)
    shuffled = K.copy()
    for i in range(K.shape[0]):  # reverse each row's column indices: unsorted CSR
        lo, hi = shuffled.indptr[i], shuffled.indptr[i + 1]
        shuffled.indices[lo:hi] = shuffled.indices[lo:hi][::-1].copy()
        shuffled.data[lo:hi] = shuffled.data[lo:hi][::-1].copy()
    shuffled.has_sorted_indices = False
    b = rng.standard_normal((K.shape[0], 2))
    ref = np.linalg.solve(K.toarray(), b)
    for perm in (None, rng.permutation(K.shape[0])):
        chol = cholesky(shuffled, perm)
        np.testing.assert_allclose(chol.solve(b), ref, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(chol.solve(b[:, 0]), ref[:, 0], rtol=1e-10, atol=1e-12)
        assert chol.fallbacks == 0
    Kin = (K - 2.5 * sp.identity(K.shape[0])).tocsr()
    assert np.linalg.eigvalsh(Kin.toarray()).min() < 0
    chol = cholesky(Kin)
    assert chol.fallbacks == 1
    np.testing.assert_allclose(chol.solve(b), np.linalg.solve(Kin.toarray(), b), rtol=1e-8, atol=1e-10)
    with pytest.raises(ValueError, match="square"):
        cholesky(sp.random(4, 5, density=0.5, format="csr"))


def test_schur_compliance_is_the_block_of_the_dense_inverse(caplog):
    """``(K⁻¹)[rows][:, rows]`` by the Schur complement's Cholesky block against the dense
    inverse: rows scattered in any order (a pad's face dofs, node-major), all rows, one row;
    an indefinite K goes to SuperLU's unit-load solves (logged) with the same answer."""
    from workbench.fem.sparse_factor import schur_compliance

    rng, K, _, _ = _refactor_case(3)
    Kinv = np.linalg.inv(K.toarray())
    for rows in (rng.choice(K.shape[0], 23, replace=False), np.arange(K.shape[0])[::-1], np.array([7])):
        C = schur_compliance(K, rows)
        assert C.shape == (rows.size, rows.size)
        np.testing.assert_allclose(C, Kinv[np.ix_(rows, rows)], rtol=1e-10, atol=1e-12 * np.abs(Kinv).max())
        assert np.array_equal(C, C.T)
    Kin = (K - 2.5 * sp.identity(K.shape[0])).tocsr()
    rows = rng.choice(K.shape[0], 9, replace=False)
    with caplog.at_level("INFO"):
        C = schur_compliance(Kin, rows)
    assert "not positive definite" in caplog.text
    np.testing.assert_allclose(C, np.linalg.inv(Kin.toarray())[np.ix_(rows, rows)], rtol=1e-8, atol=1e-10)
    with pytest.raises(ValueError, match="unique"):
        schur_compliance(K, np.array([1, 1]))
    with pytest.raises(ValueError, match="index"):
        schur_compliance(K, np.array([0, K.shape[0]]))
