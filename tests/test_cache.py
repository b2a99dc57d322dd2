"""workbench.limit_surface.cache: hits rescale by the force, misses solve once, the disk persists;
mu = 0 is refused by name."""

import naive
import numpy as np
import pytest

from workbench import ContactProfile, config, frictional_wrenches, mesh_profile
from workbench.coarsen import coarsen_profile
from workbench.limit_surface import LimitSurfaceCache, SamplerSpec
from workbench.limit_surface import quartic as quart_mod
from workbench.plausible import ImplausibleWarning
from workbench.sources.surface_catalog import S4
from workbench.twists_author import sample_twists_author


@pytest.mark.jit_only("over 15 s as pure Python")
def test_cache_hits_rescale_and_skip_unneeded_work(tmp_path):
    prof = mesh_profile(S4, 300).with_pressures(np.full(len(mesh_profile(S4, 300)), 2e4))
    cache = LimitSurfaceCache(tmp_path)
    q_builds = quart_mod.BUILD_COUNT["quartic"]
    m1 = cache.get(prof, 0.5, sampler=SamplerSpec(n=150))
    assert cache.stats["sampling"] == 1 and cache.stats["solves"] == 1
    # same profile pair, 3x the force: no sampling, no solve, wrenches scale by 3
    m2 = cache.get(prof.with_pressures(prof.pressures * 3), 0.5, sampler=SamplerSpec(n=150))
    assert cache.stats["sampling"] == 1 and cache.stats["solves"] == 1 and cache.stats["hits"] == 1
    np.testing.assert_allclose(m2.w_max, 3 * m1.w_max, rtol=1e-12)
    w = m1.linearize(20).vertices
    np.testing.assert_allclose(m2.value(3 * w), m1.value(w), rtol=1e-12)
    # the ellipsoid never built the quartic problem
    assert quart_mod.BUILD_COUNT["quartic"] == q_builds
    # a different mu or sampler is a different key
    cache.get(prof, 0.4, sampler=SamplerSpec(n=150))
    assert cache.stats["solves"] == 2
    # persisted: a fresh cache on the same directory loads instead of solving
    fresh = LimitSurfaceCache(tmp_path)
    m3 = fresh.get(prof, 0.5, sampler=SamplerSpec(n=150))
    assert fresh.stats["disk_hits"] == 1 and fresh.stats["solves"] == 0
    np.testing.assert_allclose(m3.value(w), m1.value(w), rtol=1e-12)


def test_mu_zero_is_named_when_a_limit_surface_is_asked_for(rng):
    from workbench.limit_surface.thesis_code import thesis_code_sample

    prof = ContactProfile(*naive.random_profile(rng, 40))
    with pytest.raises(ValueError, match="mu = 0 has no friction wrench"):
        LimitSurfaceCache().get(prof, 0.0)
    with pytest.raises(ValueError, match="mu = 0 has no friction wrench"):
        thesis_code_sample(prof, 0.0)
    # the wrenches themselves are fine at mu = 0 (all zero), only a fit is meaningless
    assert not frictional_wrenches(prof, np.eye(6), 0.0).any()


def _flat_square(n: int = 24, side: float = 0.02) -> ContactProfile:
    """n × n elements on z = 0 under a pressure rising along x and y (its centre off the middle)."""
    u = (np.arange(n) + 0.5) * side / n
    X, Y = np.meshgrid(u, u, indexing="ij")
    c = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    p = 1e5 * (1.0 + 3.0 * c[:, 0] / side) * (1.0 + c[:, 1] / side)
    return ContactProfile(c, np.tile([0.0, 0.0, 1.0], (n * n, 1)), np.full(n * n, (side / n) ** 2), p)


def test_training_cell_zero_is_the_contacts_own_wrenches_bit_for_bit(rng):
    prof = ContactProfile(*naive.random_profile(rng, 300))
    xi, W = SamplerSpec(kind="thesis", n=50, cell_fraction=0).training(prof, 0.4)
    assert np.array_equal(W, frictional_wrenches(prof, xi, 0.4))
    assert SamplerSpec(kind="thesis").cell_fraction == 0.0  # the config default: the contact as given


def test_a_coarse_training_contact_keeps_the_twists_reference_point():
    """Sliding a flat contact in its plane: every element's friction is -mu p a v/|v|, so the
    wrench about the pressure centre is (-mu F v/|v|, 0) exactly (Eq. 3.6 with c - o summing to
    zero under p a); the coarse training contact must give it too."""
    prof = _flat_square()
    spec = SamplerSpec(kind="thesis", n=20, cell_fraction=0.25)  # ~5 mm cells (l_s: the centres' 19.2 mm)
    coarse = spec.sliding_profile(prof)
    assert len(coarse.areas) == 25 and coarse.areas.sum() == pytest.approx(4e-4, rel=1e-12)
    v = np.array([[1.0, 0.0, 0, 0, 0, 0], [0.6, -0.8, 0, 0, 0, 0], [-0.3, 0.2, 0, 0, 0, 0]])
    dirs = v[:, :3] / np.linalg.norm(v[:, :3], axis=1, keepdims=True)
    expected = np.hstack([-0.5 * prof.F * dirs, np.zeros((3, 3))])
    scale = 0.5 * prof.F * np.array([1, 1, 1, prof.length_scale, prof.length_scale, prof.length_scale])
    np.testing.assert_allclose(frictional_wrenches(coarse, v, 0.5) / scale, expected / scale, atol=1e-13)
    # its wrenches are about the contact's own pressure centre, where the model is placed: area-
    # centred cells would move that point by 0.1 mm, and a slide's torque about o by (o' - o) x f
    np.testing.assert_allclose(coarse.pressure_center, prof.pressure_center, atol=1e-17)
    moved = coarsen_profile(prof, 0.25 * prof.length_scale)
    assert np.linalg.norm(moved.pressure_center - prof.pressure_center) > 5e-5


def test_a_coarse_training_contact_trains_the_cached_model(caplog):
    prof = _flat_square()
    cache = LimitSurfaceCache()
    fine = cache.get(prof, 0.5, sampler=SamplerSpec(kind="thesis", n=100))
    coarse = cache.get(prof, 0.5, sampler=SamplerSpec(kind="thesis", n=100, cell_fraction=0.25))
    assert cache.stats["solves"] == 2  # the cell is part of the key
    assert coarse.info["training_cells"] == 25 and "training_cells" not in fine.info
    # a 5 mm cell on a 20 mm contact: the model moves, by less than its own fit error
    w = fine.linearize(40).vertices
    change = np.abs(coarse.value(w) - 1.0)
    assert 1e-4 < np.median(change) < 0.05
    # the config's default is read when a spec is made
    with config.override(ls_training_cell_fraction=0.25):
        assert SamplerSpec(kind="thesis", n=100).cell_fraction == 0.25
        again = cache.get(prof, 0.5, sampler=SamplerSpec(kind="thesis", n=100))
    assert cache.stats["hits"] == 1 and again.info["training_cells"] == 25
    # a contact whose normals fold cannot be laid in cells: trained as given, logged, recorded
    flip = prof.normals.copy()
    flip[: len(flip) // 2] *= -1
    with pytest.warns(ImplausibleWarning, match="normals pointing away"):
        folded = ContactProfile(prof.centers, flip, prof.areas, prof.pressures)
    with caplog.at_level("WARNING", logger="workbench.limit_surface.cache"):
        spec = SamplerSpec(kind="thesis", n=50, cell_fraction=0.25)
        assert spec.sliding_profile(folded) is folded
    assert "training wrenches on the contact as given" in caplog.text


@pytest.mark.parametrize("bad", [-0.1, 0.6, 1.0, 3, 1e-300, float("nan"), "0.1", True])
def test_a_careless_training_cell_is_refused(bad):
    with pytest.raises(
        ValueError, match=r"SamplerSpec cell_fraction \(a fraction of the contact's l_s\) must"
    ):
        SamplerSpec(cell_fraction=bad)
    with pytest.raises(ValueError, match="not millimetres or metres"):
        config.configure(ls_training_cell_fraction=bad)


def test_the_training_cell_keys_and_twists():
    """-0.0 is 0.0 (one cache key); the twists of every kind are the contact's own whatever the
    cell (the author's grid on the contact's box, not the coarse one's); a 0.3 m contact at half
    its size is coarsened, not refused as millimetres; one element is trained as given."""
    assert SamplerSpec(cell_fraction=-0.0) == SamplerSpec(cell_fraction=0)
    prof = _flat_square()
    fine_xi, _ = SamplerSpec(kind="thesis", n=40).training(prof, 0.5)
    coarse_xi, _ = SamplerSpec(kind="thesis", n=40, cell_fraction=0.2).training(prof, 0.5)
    assert np.array_equal(fine_xi, coarse_xi)
    # the grid kinds keep the twists whose coarse wrenches fill the grid's cells: each is one of the
    # author's grid on the contact's own box (on the coarse cells' box, 25 of 26 were not)
    grid = {tuple(x) for x in sample_twists_author(prof, 0)}
    for kind in ("mix", "thesis-code"):
        kept, _ = SamplerSpec(kind=kind, n=40, cell_fraction=0.2).training(prof, 0.5)
        assert all(tuple(x) in grid for x in kept[-20:])
    big = _flat_square(side=0.3)
    assert len(SamplerSpec(kind="thesis", cell_fraction=0.5).sliding_profile(big).areas) < 10
    one = ContactProfile(np.zeros((1, 3)), np.array([[0.0, 0, 1]]), np.array([1e-6]), np.array([1e5]))
    assert SamplerSpec(cell_fraction=0.2).sliding_profile(one) is one
