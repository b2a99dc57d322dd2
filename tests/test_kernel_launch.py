"""How a parallel kernel is called (workbench.kernel_launch): one thread below the size rule,
Numba's threads above it, the same bits either way."""

from __future__ import annotations

import naive
import numpy as np
import pytest

from workbench import config
from workbench.kernel_launch import launch


def test_launch_uses_one_thread_below_the_rule_read_at_call_time():
    numba = pytest.importorskip("numba")
    seen = []

    def kernel(tag):  # records how many threads a parallel region would get
        seen.append((tag, numba.get_num_threads()))

    before = numba.get_num_threads()
    threshold = config.DEFAULTS.parallel_min_work
    launch(kernel, threshold - 1, "small")
    launch(kernel, threshold, "large")
    with config.override(parallel_min_work=10):
        launch(kernel, 9, "small, rule 10")
        launch(kernel, 10, "large, rule 10")
    assert seen == [("small", 1), ("large", before), ("small, rule 10", 1), ("large, rule 10", before)]
    assert numba.get_num_threads() == before  # restored

    def failing(_):
        raise RuntimeError("kernel failed")

    with pytest.raises(RuntimeError, match="kernel failed"):
        launch(failing, 0, None)
    assert numba.get_num_threads() == before  # restored after an exception too
    with pytest.raises(ValueError, match="parallel_min_work"):
        config.configure(parallel_min_work=-1)


def test_callers_give_the_same_bits_on_one_thread_and_on_all(rng):
    """frictional_wrenches, the surface quadrature, a quartic's values and gradients and the
    contact solve's projections, every call forced onto Numba's threads and then onto one: the
    same bits (the kernels split their loops over items that share no sum)."""
    numba = pytest.importorskip("numba")
    from workbench import frictional_wrenches
    from workbench.fem.contact import solve_contact
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Sphere
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.limit_surface.normalize import Subspace
    from workbench.limit_surface.quartic import QuarticLS
    from workbench.limit_surface.sos import exponents
    from workbench.profile import ContactProfile
    from workbench.sources.surface_catalog import S1
    from workbench.sources.surfaces import surface_wrenches
    from workbench.twists import sample_twists_thesis

    if numba.config.NUMBA_NUM_THREADS < 2 and not numba.config.DISABLE_JIT:
        pytest.skip("one Numba thread on this machine: both ways are the same call")
    c, nrm, a, p = naive.random_profile(rng, 200)
    prof = ContactProfile(c, nrm, a, p)
    xi = sample_twists_thesis(50, prof, seed=2)
    eye = np.eye(6)
    q = QuarticLS(
        np.ones(6),
        np.ones(6),
        Subspace(basis=eye, complement=eye[:, :0], std=np.ones(6)),
        {},
        A_q=rng.standard_normal(len(exponents(6, 4))),
        gram=np.eye(36),
    )
    w = rng.standard_normal((300, 6))
    geometry = PadGeometry(width=0.01, length=0.01, thickness=0.004, nx=6, ny=6, nz=2)
    pad = condense_pad(geometry, Material(1e6, 0.45), cache_dir=False)
    sphere = Sphere((0.0, 0.0, geometry.thickness + 0.02), 0.02)
    got = []
    for threshold in (0, 10**12):  # every call on all threads, then every call on one
        with config.override(parallel_min_work=threshold):
            sol = solve_contact(pad, sphere, 1e-3)
            got.append(
                (
                    frictional_wrenches(prof, xi),
                    surface_wrenches(S1, sample_twists_thesis(3, 0.02, seed=4)),
                    q.value(w),
                    q.gradient(w),
                    sol.lam,
                )
            )
    for x, y in zip(*got, strict=True):
        np.testing.assert_array_equal(x, y)
