"""workbench.sources.surface_index: the cells' query returns every centre inside a turned box (a
brute-force test of every point), and the run concatenation equals a loop of aranges."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from workbench.sources.surface_index import SurfaceIndex, concat_runs


def test_the_index_returns_every_centre_inside_a_turned_box():
    rng = np.random.default_rng(1)
    pts = rng.uniform(-0.05, 0.05, (20000, 3))
    idx = SurfaceIndex.build(pts, 3e-3)
    for _ in range(30):
        R = Rotation.random(random_state=rng).as_matrix()
        a, e1, e2 = R
        origin = rng.uniform(-0.03, 0.03, 3)
        box = (-0.01, 0.012, -0.02, 0.015, -0.03, 0.02)
        rel = pts - origin
        u, v, z = rel @ e1, rel @ e2, rel @ a
        inside = np.flatnonzero(
            (u >= box[0]) & (u <= box[1]) & (v >= box[2]) & (v <= box[3]) & (z >= box[4]) & (z <= box[5])
        )
        got = idx.within(origin, (a, e1, e2), box)
        assert np.all(np.diff(got) > 0)  # sorted, no repeats
        assert np.isin(inside, got).all()
        assert len(got) < 4 * max(len(inside), 1) + 2000  # a superset near the box, not everything


def test_concat_runs_is_the_concatenated_aranges():
    rng = np.random.default_rng(4)
    lo = rng.integers(0, 100, 40)
    hi = lo + rng.integers(0, 6, 40)  # empty runs included
    slow = np.concatenate([np.arange(a, b) for a, b in zip(lo, hi, strict=True)])
    got = concat_runs(lo, hi)
    assert got.dtype == np.int64
    np.testing.assert_array_equal(got, slow)
    assert concat_runs(np.array([], int), np.array([], int)).shape == (0,)
    with pytest.raises(ValueError, match="hi >= lo"):
        concat_runs(hi, lo)
