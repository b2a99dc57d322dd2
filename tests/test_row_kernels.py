"""The profile's row kernels (workbench/_row_kernels.py) against the NumPy expressions they
redo: equal to the last bit on rows of every scale, lengths across NumPy's summation blocks
(8, 128), read-only inputs and a single row — and a profile built on them against one built by
NumPy alone."""

import numpy as np
import pytest

from workbench import profile as profile_module
from workbench._row_kernels import (
    _column_ranges,
    _column_sums,
    _row_norms,
    _rows_minus,
    _rows_over,
    _weighted_column_sums,
)
from workbench.profile import ContactProfile

SIZES = [1, 2, 3, 7, 8, 9, 127, 128, 129, 1000, 4099]


def _rows(rng, n):
    # columns of different scales and offsets, as centres [m] far from the origin are
    x = rng.normal(size=(n, 3)) * rng.uniform(1e-4, 1.0, 3) + rng.normal(0, 10, 3)
    x.flags.writeable = bool(rng.integers(2))
    return x


@pytest.mark.parametrize("n", SIZES)
def test_each_kernel_is_its_numpy_expression_to_the_last_bit(n):
    rng = np.random.default_rng(n)
    for _ in range(5):
        x, w, c = _rows(rng, n), rng.uniform(0, 1e4, n), rng.normal(size=3)
        d = rng.uniform(0.5, 2.0, n)
        np.testing.assert_array_equal(_row_norms(x), np.linalg.norm(x, axis=1))
        np.testing.assert_array_equal(_rows_over(x, d), x / d[:, None])
        np.testing.assert_array_equal(_rows_minus(x, c), x - c)
        np.testing.assert_array_equal(_column_sums(x), x.sum(axis=0))
        np.testing.assert_array_equal(_weighted_column_sums(w, x), (w[:, None] * x).sum(axis=0))
        for k in (1, 2, 3):
            np.testing.assert_array_equal(_column_ranges(x[:, :k].copy()), np.ptp(x[:, :k], axis=0))


def test_the_sums_are_not_pairwise():
    # a sum where the order shows: 1 then 2**-53 many times (each lost when added to 1 alone),
    # NumPy's first-axis reduction adds row after row, as the kernel does
    x = np.full((64, 3), 2.0**-53)
    x[0] = 1.0
    assert _column_sums(x)[0] == x.sum(axis=0)[0] == 1.0
    assert x[:, 0].sum() > 1.0  # a contiguous 1-D sum is pairwise: what the kernel must not be


def _numpy_profile(c, n, a, p):
    """The profile's derived numbers as NumPy computed them before the kernels."""
    nn = n / np.linalg.norm(n, axis=1)[:, None]
    f = p * a
    o = (f[:, None] * c).sum(axis=0) / f.sum()
    centered = c - c.mean(axis=0)
    _, _, axes = np.linalg.svd(centered, full_matrices=False)
    extent = centered @ axes.T
    return nn, o, extent.max(axis=0) - extent.min(axis=0)


def test_a_profile_is_the_numpy_one_bit_for_bit():
    rng = np.random.default_rng(7)
    for n in (3, 50, 2000):
        c = rng.uniform(-0.01, 0.01, (n, 3)) * [1, 2, 0.1] + [0.3, -0.2, 0.9]
        nrm = np.column_stack([rng.normal(0, 0.1, (n, 2)), np.ones(n)])
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        a, p = rng.uniform(1e-7, 1e-6, n), rng.uniform(0, 1e5, n)
        prof = ContactProfile(c, nrm, a, p)
        nn, o, sides = _numpy_profile(c, nrm, a, p)
        np.testing.assert_array_equal(prof.normals, nn)
        np.testing.assert_array_equal(prof.pressure_center, o)
        np.testing.assert_array_equal(profile_module._pca_box(c)[3], sides)
        # the columns the wrench kernels read: the torque arms about o, as NumPy subtracts them
        np.testing.assert_array_equal(np.column_stack(prof._soa[:3]), c - o)


def test_a_fortran_ordered_input_is_stored_c_ordered():
    rng = np.random.default_rng(8)
    c = np.asfortranarray(rng.uniform(-0.01, 0.01, (40, 3)))
    nrm = np.asfortranarray(np.tile([0.0, 0.0, 1.0], (40, 1)))
    prof = ContactProfile(c, nrm, np.full(40, 1e-6), np.ones(40))
    assert prof.centers.flags.c_contiguous and prof.normals.flags.c_contiguous
    np.testing.assert_array_equal(prof.centers, c)
