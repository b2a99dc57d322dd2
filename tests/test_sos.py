"""workbench.limit_surface.sos: the swap-invariant split of the Gram products and the symmetric
Hessian biform it rests on."""

import naive
import numpy as np

from workbench.limit_surface.sos import exponents


def test_swap_blocks_split_the_products_orthonormally():
    from workbench.limit_surface.sos import swap_blocks

    for n in (1, 3, 6):
        T_s, T_a = swap_blocks(n)
        assert T_s.shape == (n * (n + 1) // 2, n * n) and T_a.shape == (n * (n - 1) // 2, n * n)
        T = np.vstack([T_s, T_a])
        np.testing.assert_allclose(T @ T.T, np.eye(n * n), atol=1e-15)  # a complete orthonormal basis
        swap = np.arange(n * n).reshape(n, n).T.ravel()  # x_i z_j -> x_j z_i
        np.testing.assert_array_equal(T_s[:, swap], T_s)
        np.testing.assert_array_equal(T_a[:, swap], -T_a)


def test_hessian_biform_is_symmetric_in_its_arguments(rng):
    """zᵀ∇²f(x) z = xᵀ∇²f(z) x for any quartic: the fact the reduced Gram basis rests on
    (checked on the slow per-monomial Hessians of tests/naive.py)."""
    expo = exponents(6, 4)
    a = rng.standard_normal(len(expo))
    x, z = rng.standard_normal((2, 20, 6))
    H = [np.einsum("njkl,l->njk", naive.monomial_hessians(p, expo), a) for p in (x, z)]
    zHz = np.einsum("nj,njk,nk->n", z, H[0], z)
    xHx = np.einsum("nj,njk,nk->n", x, H[1], x)
    np.testing.assert_allclose(zHz, xHx, rtol=1e-11, atol=1e-11 * np.abs(zHz).max())
