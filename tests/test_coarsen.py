"""coarsen_profile: conservation, the cell count on a regular grid, a brute-force
merge on a small case, and careless input."""

import numpy as np
import pytest
from naive import random_profile

from workbench import ContactProfile
from workbench.coarsen import NoTangentPlane, coarsen_profile
from workbench.plausible import ImplausibleWarning


def _flat_grid(n: int, h: float) -> ContactProfile:
    """n × n elements of side h on z = 0 (pressure varying), normals +z."""
    u = (np.arange(n) + 0.5) * h
    X, Y = np.meshgrid(u, u, indexing="ij")
    c = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    p = 1e5 * (1.0 + c[:, 0] / (n * h)) * (1.0 + 0.5 * c[:, 1] / (n * h))
    return ContactProfile(c, np.tile([0.0, 0, 1], (n * n, 1)), np.full(n * n, h * h), p)


def test_force_area_and_pressure_centre_are_conserved(rng):
    prof = ContactProfile(*random_profile(rng, 400))
    coarse = coarsen_profile(prof, 3e-3)
    assert len(coarse) < len(prof)
    assert coarse.F == pytest.approx(prof.F, rel=1e-12)
    kept = prof.pressures > 0  # zero-pressure elements only drop out with their whole cell
    assert coarse.areas.sum() <= prof.areas.sum() + 1e-18
    assert coarse.areas.sum() >= prof.areas[kept].sum() * (1 - 1e-12)
    # force-weighted position: each cell's centre is area-weighted, so only the
    # pressure variation inside a cell moves the centre of pressure (< one cell)
    assert np.linalg.norm(coarse.pressure_center - prof.pressure_center) < 3e-3


def test_regular_grid_merges_into_the_expected_cells():
    prof = _flat_grid(12, 1e-3)  # 12 mm square of 1 mm elements
    coarse = coarsen_profile(prof, 3e-3)
    assert len(coarse) == 16  # 4 × 4 cells of 3 × 3 elements
    np.testing.assert_allclose(coarse.areas, 9e-6, rtol=1e-12)
    # brute force: each cell is the 3 × 3 block of elements it covers
    c, p = prof.centers, prof.pressures
    for centre, pressure in zip(coarse.centers, coarse.pressures, strict=True):
        block = np.all(np.abs(c[:, :2] - centre[:2]) < 1.5e-3, axis=1)
        assert block.sum() == 9
        assert pressure == pytest.approx(p[block].mean(), rel=1e-12)
        np.testing.assert_allclose(centre, c[block].mean(axis=0), atol=1e-15)
    # flat: the normal force vector is exact; the centre of pressure moves by the
    # pressure gradient inside a cell (here 0.04 mm), well under a cell
    np.testing.assert_allclose(coarse.normal_wrench[:3], prof.normal_wrench[:3], rtol=1e-12)
    shift = np.linalg.norm(coarse.pressure_center - prof.pressure_center)
    assert 0 < shift < 0.1e-3


def test_a_cell_smaller_than_the_elements_changes_nothing(rng):
    prof = _flat_grid(6, 1e-3)
    fine = coarsen_profile(prof, 0.999e-3)
    order = np.lexsort(fine.centers.T[::-1])
    ref = np.lexsort(prof.centers.T[::-1])
    np.testing.assert_allclose(fine.centers[order], prof.centers[ref], atol=1e-15)
    np.testing.assert_allclose(fine.pressures[order], prof.pressures[ref], rtol=1e-12)


@pytest.mark.parametrize(
    "cell, match",
    [
        (3.0, "millimetres"),
        (0.0, "positive length"),
        (np.nan, "positive length"),
        ("0.003", "positive length in metres \\(a number\\)"),
        (True, "a number"),
        (None, "a number"),
        (1e-300, "over 1e9 times smaller"),
    ],
)
def test_careless_cell_is_refused(rng, cell, match):
    prof = ContactProfile(*random_profile(rng, 50))
    with pytest.raises(ValueError, match=match):
        coarsen_profile(prof, cell)


def test_opposing_normals_get_cells_of_their_own_and_cancelling_ones_are_refused():
    """Both sides of a thin wall: the far side (facing away from the mean normal) is not merged
    into the near side's cell; all of them cancelling leaves no tangent plane."""
    c = np.array([[0.0, 0, 0], [0.2e-3, 0, 0], [2e-3, 0, 0], [4e-3, 0, 0]])
    n = np.array([[0.0, 0, 1], [0, 0, -1], [0, 0, 1], [0, 0, 1]])
    with pytest.warns(ImplausibleWarning, match="normals pointing away"):
        prof = ContactProfile(c, n, np.full(4, 1e-8), np.full(4, 1e5))
    with pytest.warns(ImplausibleWarning):  # the coarse contact has its far side too
        coarse = coarsen_profile(prof, 1e-3)
    assert len(coarse) == 4  # the first two share (i, j) but not a side
    np.testing.assert_array_equal(np.sort(coarse.normals[:, 2]), [-1.0, 1.0, 1.0, 1.0])
    with pytest.warns(ImplausibleWarning), pytest.raises(NoTangentPlane, match="normals cancel"):
        coarsen_profile(ContactProfile(c[:2], n[:2], np.full(2, 1e-8), np.full(2, 1e5)), 1e-3)


def test_a_wrap_past_90_degrees_is_not_merged_front_to_back():
    """A 3 mm rod wrapped ±150° (a new-user trial): one plane would merge the element at θ with
    the one at 180° − θ, cells 0.9 mm inside the rod; by sides, every cell stays on the surface
    within a cell's sagitta and keeps elements of one side only."""
    r, n_el = 3e-3, 600
    theta = np.linspace(-150, 150, n_el) * np.pi / 180
    y = np.repeat([0.0, 1e-3], n_el)
    t = np.tile(theta, 2)
    normals = np.column_stack([np.sin(t), np.zeros_like(t), np.cos(t)])
    centres = r * normals + np.column_stack([np.zeros_like(t), y, np.zeros_like(t)])
    areas = np.full(2 * n_el, r * (theta[1] - theta[0]) * 1e-3)
    with pytest.warns(ImplausibleWarning):  # elements facing away from the mean normal, as built
        prof = ContactProfile(centres, normals, areas, np.full(2 * n_el, 1e5))
    with pytest.warns(ImplausibleWarning):
        coarse = coarsen_profile(prof, 0.5e-3, centre="pressure")
    radius = np.hypot(coarse.centers[:, 0], coarse.centers[:, 2])
    # a chord of at most one cell's arc, 0.5 mm... or the arc of a steep rim cell (its projection
    # 0.5 mm): no more than 0.3 mm inside the surface, where front-to-back merging put 0.87 mm
    assert radius.min() > r - 0.3e-3
    np.testing.assert_allclose(coarse.F, prof.F, rtol=1e-12)
    np.testing.assert_allclose(coarse.pressure_center, prof.pressure_center, atol=1e-17)


def test_pressure_centres_are_each_cells_centre_of_pressure_and_keep_the_contacts(rng):
    prof = _flat_grid(12, 1e-3)
    coarse = coarsen_profile(prof, 3e-3, centre="pressure")
    c, w = prof.centers, prof.pressures * prof.areas
    for centre in coarse.centers:  # brute force: the 3 × 3 block's own centre of pressure
        block = np.all(np.abs(c[:, :2] - centre[:2]) < 1.5e-3, axis=1)
        assert block.sum() == 9
        np.testing.assert_allclose(centre, (w[block] @ c[block]) / w[block].sum(), atol=1e-15)
    # the "area" centres move the contact's pressure centre by 0.04 mm (the test above); these not
    np.testing.assert_allclose(coarse.pressure_center, prof.pressure_center, atol=1e-17)
    curved = ContactProfile(*random_profile(rng, 400))  # zero-pressure elements and a bumpy patch
    kept = coarsen_profile(curved, 3e-3, centre="pressure")
    np.testing.assert_allclose(kept.pressure_center, curved.pressure_center, atol=1e-17)
    assert kept.F == pytest.approx(curved.F, rel=1e-12)
    with pytest.raises(ValueError, match="centre must be 'area' or 'pressure'"):
        coarsen_profile(prof, 3e-3, centre="mass")
