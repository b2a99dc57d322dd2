"""workbench.limit_surface.downsample: grid downsampling of wrench samples (the author's
``downsamplewrench.m``, "thesis-code" protocol of issue 12) against a brute-force loop over
the cells, hand-counted cells, and bad input."""

import itertools

import numpy as np
import pytest

from workbench.limit_surface.downsample import grid_downsample


def _reference_downsample(W, steps):
    """Slow reference: loop over every grid cell like the author's code (closed cells)."""
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
            keep.add(int(idx[np.argmin(np.linalg.norm(W[idx] - W[idx].mean(0), axis=1))]))
    return np.array(sorted(keep))


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
    ],
)
def test_careless_input_is_refused(wrenches, steps, match):
    with pytest.raises(ValueError, match=match):
        grid_downsample(wrenches, steps)
