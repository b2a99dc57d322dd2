"""workbench.limit_surface.downsample: grid downsampling of wrench samples (the author's
``downsamplewrench.m``, the "thesis-code" protocol) against a brute-force loop over
the cells, hand-counted cells, and bad input."""

import itertools

import numpy as np
import pytest

from workbench.limit_surface.downsample import grid_downsample


def _reference_downsample(W, steps):
    """Slow reference: loop over every grid cell like the author's code (closed cells); of
    members within 1e-9 of the nearest to the mean the first is kept (a two-member cell is
    always such a tie: both are half their gap from the mean)."""
    lo, hi = W.min(0), W.max(0)
    width = (hi - lo) / steps
    starts = [np.arange(lo[j], hi[j] + 1e-15, width[j]) if width[j] > 0 else [lo[j]] for j in range(6)]
    keep = set()
    for cell in itertools.product(*starts):
        inside = np.ones(len(W), dtype=bool)
        for j, x in enumerate(cell):
            if width[j] > 0:
                inside &= (W[:, j] >= x) & (W[:, j] <= x + width[j])
        idx = np.flatnonzero(inside)
        if idx.size:
            d = np.linalg.norm(W[idx] - W[idx].mean(0), axis=1)
            keep.add(int(idx[np.flatnonzero(d <= d.min() + 1e-9)[0]]))
    return np.array(sorted(keep))


def _per_cell_loop(W, steps, tie):
    """The cells of grid_downsample (same keys, flat ranges, tie rule) one at a time, as the
    module did before its single pass: the mean, distances and choice of each cell alone."""
    from workbench import config

    lo, hi = W.min(0), W.max(0)
    width = (hi - lo) / steps
    n_cells = int(np.floor(steps)) + 1
    flat = width <= config.TOL.subspace_rtol * width.max()
    idx = np.where(flat, 0, np.floor((W - lo) / np.where(flat, 1.0, width) + tie)).astype(np.int64)
    key = np.ravel_multi_index(np.clip(idx, 0, n_cells - 1).T, (n_cells,) * 6)
    keep = []
    for k in np.unique(key):
        members = np.flatnonzero(key == k)
        d = np.linalg.norm(W[members] - W[members].mean(axis=0), axis=1)
        keep.append(members[np.flatnonzero(d <= d.min() + tie)[0]])
    return np.array(sorted(keep))


@pytest.mark.parametrize("kind", ["normal", "quantised", "large"])
def test_single_pass_is_the_per_cell_loop_to_the_last_bit(kind, rng):
    """The vectorised cells (np.add.reduceat sums rows in the order the per-cell mean does)
    keep exactly the indices of a loop over the cells, also with many exact ties (values on a
    coarse lattice: equidistant members, members on cell boundaries) and at the thesis-code
    protocol's size (48,483 wrenches)."""
    from workbench import config

    n = 48_483 if kind == "large" else 2_000
    W = rng.standard_normal((n, 6))
    if kind == "quantised":
        W = np.round(W * 2) / 2
    tie = config.TOL.downsample_tie_atol
    for steps in (2.5, 4.0):
        np.testing.assert_array_equal(grid_downsample(W, steps), _per_cell_loop(W, steps, tie))


def test_grid_downsample_keeps_one_wrench_per_occupied_cell(rng):
    W = rng.standard_normal((400, 6))
    W[:, 5] = 0.0  # a flat dimension is one cell
    got = grid_downsample(W, 2.5)
    np.testing.assert_array_equal(got, _reference_downsample(W, 2.5))
    assert 50 < len(got) < 3**5  # 3 cells per non-flat dimension, many occupied
    with pytest.raises(ValueError, match="steps"):
        grid_downsample(W, 0)


def test_a_range_at_rounding_noise_is_one_cell(rng):
    """A flat contact tilted by 1e-9 rad has components at noise level: one cell, as zero is."""
    W = rng.standard_normal((500, 6))
    flat, noisy = W.copy(), W.copy()
    flat[:, 3:5] = 0.0
    noisy[:, 3:5] = 1e-11 * rng.standard_normal((500, 2))
    np.testing.assert_array_equal(grid_downsample(noisy), grid_downsample(flat))


# --- added ---------------------------------------------------------------------------------


def _on_axis(values):
    """(n, 6) wrenches with ``values`` in component 0 and the other five zero (flat: one cell)."""
    W = np.zeros((len(values), 6))
    W[:, 0] = values
    return W


def test_cells_counted_by_hand():
    """Component 0 spans [0, 1]; steps 2.5 cuts it at 0, 0.4, 0.8 (three cells, the last
    past the maximum): {0, 0.1, 0.3} (mean 0.133: keeps 0.1), {0.5}, {0.85, 0.9, 1.0}
    (mean 0.917: keeps 0.9).  Steps 1 gives two cells, [0, 1) and [1, 2): the maximum alone
    in the second, and 0.5 nearest the mean 0.442 of the others."""
    W = _on_axis([0.0, 0.1, 0.3, 0.5, 0.85, 0.9, 1.0])
    np.testing.assert_array_equal(grid_downsample(W, 2.5), [1, 3, 5])
    np.testing.assert_array_equal(grid_downsample(W, 1.0), [3, 6])
    # one cell per sample once the cells are finer than the gaps (0.05 apart, width 0.02)
    np.testing.assert_array_equal(grid_downsample(W, 50.0), np.arange(7))
    # the same counts in any component, and under a positive scale of it
    np.testing.assert_array_equal(grid_downsample(np.roll(W, 4, axis=1) * 3e-3), [1, 3, 5])


def test_one_index_per_occupied_cell_sorted(rng):
    """Sorted unique int64 indices, as many as occupied cells (cells counted as tuples of
    ``min(floor((w - lo) / width), 2)``), each kept wrench in a cell of its own."""
    W = rng.standard_normal((300, 6))
    keep = grid_downsample(W)
    assert keep.dtype == np.int64 and np.all(np.diff(keep) > 0)
    assert 0 <= keep.min() and keep.max() < len(W)
    lo, width = W.min(0), np.ptp(W, axis=0) / 2.5
    cell = [tuple(np.minimum(np.floor((w - lo) / width), 2).astype(int)) for w in W]
    assert len(keep) == len(set(cell)) == len({cell[k] for k in keep})


@pytest.mark.parametrize(
    "wrenches, steps, match",
    [
        (np.ones((5, 3)), 2.5, r"wrenches must have shape \(K, 6\); got \(5, 3\)"),
        (np.ones(6), 2.5, r"shape \(K, 6\); got \(6,\)"),
        (np.where(np.eye(6, dtype=bool), np.nan, 1.0), 2.5, "wrenches must be finite; row 0 has NaN/inf"),
        (np.r_[np.ones((2, 6)), np.full((1, 6), np.inf)], 2.5, "row 2 has NaN/inf"),
        (np.zeros((4, 6)), 2.5, "all zero"),
        ([["a"] * 6], 2.5, "numeric"),
        (np.ones((4, 6)), 0.0, "steps must be a positive number"),
        (np.ones((4, 6)), -2.5, "steps must be a positive number"),
        (np.ones((4, 6)), np.nan, "steps must be a positive number"),
        (np.ones((4, 6)), np.inf, "steps must be a positive number"),
        (np.ones((4, 6)), "2", "steps must be a positive number.*got '2'"),
        (np.ones((4, 6)), True, "steps must be a positive number.*got True"),
        (np.ones((4, 6)), 1e6, "at most 1000"),
        (np.ones((0, 6)), 2.5, "wrenches has no rows"),
    ],
)
def test_careless_input_is_refused(wrenches, steps, match):
    with pytest.raises(ValueError, match=match):
        grid_downsample(wrenches, steps)


# --- stability in round-off ------------------------------------------------------------------


def test_mirror_ties_keep_the_first_whatever_the_round_off():
    """Cell [0, 0.4) holds 0.1 and 0.3, equally near their mean 0.2: the first (index 0) is
    kept, and still is when either moves by 1e-13 — where ``argmin`` followed the noise."""
    base = np.array([0.1, 0.3, 0.5, 1.0])
    assert grid_downsample(_on_axis(base))[0] == 0
    for k in (0, 1):
        for eps in (-1e-13, 1e-13):
            values = base.copy()
            values[k] += eps
            np.testing.assert_array_equal(grid_downsample(_on_axis(values)), [0, 2, 3])
    # a third member at the mean is nearer by a real gap and kept
    np.testing.assert_array_equal(grid_downsample(_on_axis([0.1, 0.3, 0.2 + 1e-6, 0.5, 1.0])), [2, 3, 4])


def test_a_wrench_on_a_cell_boundary_stays_in_one_cell_under_round_off():
    """0.4 is the boundary of [0, 0.4) and [0.4, 0.8) on the range [0, 1]: 0.4 ± 1e-15 is in
    the upper cell both ways (alone there: kept), as 0.4 itself; in the lower cell it would
    make {0, 0.2, 0.4} keep 0.2 (index 1) and leave [1, 3]."""
    for v in (0.4 - 1e-15, 0.4, 0.4 + 1e-15):
        np.testing.assert_array_equal(grid_downsample(_on_axis([0.0, 0.2, v, 1.0])), [0, 2, 3])


def _symmetric_patch():
    """Mirror-symmetric curved patch (15 × 21 elements on the cylinder z = x²/0.06), Hertz-like
    pressure: many of its wrenches are mirror images, equal to the last bits."""
    x, y = np.meshgrid(np.linspace(-0.009, 0.009, 15), np.linspace(-0.019, 0.019, 21))
    x, y = x.ravel(), y.ravel()
    centers = np.column_stack([x, y, x**2 / 0.06])
    normals = np.column_stack([-x / 0.03, 0 * x, np.ones_like(x)])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    pressures = np.clip(1 - (x / 0.008) ** 2 - (y / 0.015) ** 2, 0, None) + 1e-3
    return centers, normals, np.full(x.size, 1e-6), pressures


@pytest.mark.jit_only(
    "7 min as pure Python (two 48,483-twist wrench sets per profile); its kernels run without JIT "
    "in the wrench tests"
)
def test_training_set_and_6dls_model_do_not_follow_round_off():
    """The thesis-code training set of a symmetric contact is the same when its pressures
    move by 1e-12 (relative), and the default ("mix" sampler) 6DLS contact model moves by
    round-off, not by the percents (friction) to 2x (A) that swapped mirror twists gave."""
    from workbench.grasp.models import ModelParameters, contact_sets
    from workbench.limit_surface.cache import LimitSurfaceCache
    from workbench.limit_surface.thesis_code import thesis_code_sample
    from workbench.profile import ContactProfile

    c, n, a, p = _symmetric_patch()
    noisy = p * (1 + 1e-12 * np.random.default_rng(3).standard_normal(p.size))
    prof0, prof1 = ContactProfile(c, n, a, p), ContactProfile(c, n, a, noisy)
    t0, t1 = thesis_code_sample(prof0), thesis_code_sample(prof1)
    np.testing.assert_array_equal(t0.train, t1.train)
    params = ModelParameters(M=100)
    m0, m1 = (contact_sets(q, "6dls", params, cache=LimitSurfaceCache())[0] for q in (prof0, prof1))
    for field in ("friction", "A", "b"):
        v0, v1 = np.asarray(getattr(m0, field)), np.asarray(getattr(m1, field))
        assert np.abs(v1 - v0).max() <= 1e-9 * np.abs(v0).max(), field
