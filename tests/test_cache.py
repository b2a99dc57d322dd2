"""workbench.limit_surface.cache: hits rescale by the force, misses solve once, the disk persists;
mu = 0 is refused by name."""

import naive
import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches, mesh_profile
from workbench.limit_surface import LimitSurfaceCache, SamplerSpec
from workbench.limit_surface import quartic as quart_mod
from workbench.sources.surface_catalog import S4


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
