"""workbench.limit_surface.normalize: the two PCA conventions (Table 3.2's centered one, the
fitters' about the origin) and where they agree; planar contacts reduced to 3D (§3.3.4.2)."""

from __future__ import annotations

import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches, sample_twists_thesis
from workbench.limit_surface import LimitSurfaceCache, ModelSpec, SamplerSpec
from workbench.limit_surface.normalize import (
    explained_variance_ratio,
    n_components_above,
    n_components_retaining,
    pca_subspace,
    wrench_pca,
)
from workbench.pressure import power_law


def _sample(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((6, 6)) * np.array([1.0, 0.6, 0.3, 0.1, 0.03, 0.01])
    return rng.standard_normal((500, 6)) @ A.T


def test_the_conventions_agree_on_a_set_symmetric_about_zero():
    w = _sample()
    sym = np.vstack([w, -w])
    std = pca_subspace(sym).std
    about_origin = std**2 / (std**2).sum()
    assert np.allclose(explained_variance_ratio(sym), about_origin, rtol=1e-9, atol=1e-15)
    assert np.allclose(explained_variance_ratio(sym, center=False), about_origin, rtol=1e-9, atol=1e-15)
    assert explained_variance_ratio(sym).sum() == pytest.approx(1.0)


def test_they_differ_on_a_shifted_set_and_only_the_centered_one_ignores_the_shift():
    w = _sample(1)
    shifted = w + np.array([3.0, 0, 0, 0, 0, 0])
    assert np.allclose(explained_variance_ratio(shifted), explained_variance_ratio(w), rtol=1e-9)
    about_origin = explained_variance_ratio(shifted, center=False)
    assert not np.allclose(about_origin, explained_variance_ratio(w), rtol=0.1)


@pytest.mark.parametrize("bad", [np.zeros((5, 3)), np.zeros((1, 6)), np.full((4, 6), np.nan), np.zeros(6)])
def test_careless_input_is_refused(bad):
    with pytest.raises(ValueError, match="w_hat"):
        explained_variance_ratio(bad)


def _disc(n_r=14, n_t=40, R=0.01):
    r = (np.arange(n_r) + 0.5) / n_r * R
    t = (np.arange(n_t) + 0.5) / n_t * 2 * np.pi
    rr, tt = np.meshgrid(r, t, indexing="ij")
    c = np.column_stack([(rr * np.cos(tt)).ravel(), (rr * np.sin(tt)).ravel(), np.zeros(rr.size)])
    a = (rr * (R / n_r) * (2 * np.pi / n_t)).ravel()
    return c, a, rr.ravel(), R


def _rect(nx=30, ny=12, lx=0.03, ly=0.012):
    x = ((np.arange(nx) + 0.5) / nx - 0.5) * lx
    y = ((np.arange(ny) + 0.5) / ny - 0.5) * ly
    xx, yy = np.meshgrid(x, y, indexing="ij")
    c = np.column_stack([xx.ravel(), yy.ravel(), np.zeros(xx.size)])
    r = np.hypot(xx, yy).ravel()
    return c, np.full(xx.size, lx * ly / (nx * ny)), r, r.max() * 1.0001


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.parametrize("shape", ["disc", "rect"])
@pytest.mark.parametrize("k", [np.inf, 2.0])
def test_planar_contacts_reduce_to_3d(shape, k):
    c, a, r, rmax = _disc() if shape == "disc" else _rect()
    p = 1e5 * power_law(r, rmax, k)
    prof = ContactProfile(c, np.tile([0, 0, 1.0], (len(c), 1)), a, p)
    mu = 0.6
    cache = LimitSurfaceCache()
    held_out = frictional_wrenches(prof, sample_twists_thesis(1000, prof, seed=9), mu)
    for spec in (ModelSpec("ellipsoid", "lsq"), ModelSpec("ellipsoid", "sdp"), ModelSpec("quartic")):
        m = cache.get(prof, mu, sampler=SamplerSpec(n=200), spec=spec)
        assert m.dim == 3, spec  # fitted in 3D, not 6D
        assert m.info["fallback"] is None, m.info
        # §2.3.5.3: f_x,max = f_y,max = μF, τ_z,max = μ Σ p a |r|
        np.testing.assert_allclose(m.w_max[:2], mu * prof.F, rtol=1e-3)
        r_o = np.linalg.norm(prof.centers - prof.pressure_center, axis=1)
        np.testing.assert_allclose(m.w_max[5], mu * (prof.forces * r_o).sum(), rtol=1e-3)
        np.testing.assert_allclose(m.w_max[2:5], 0.0, atol=1e-9 * mu * prof.F)
        # held-out fitting error (Eq. 3.18) within the thesis's 6D bounds
        assert m.fitting_error(held_out) <= (0.02 if spec.model == "quartic" else 0.04)


#: a variance spectrum whose cumulative sums hit 0.8, 0.95 and 0.99 exactly (but for round-off)
SPECTRUM = np.array([0.5, 0.3, 0.1, 0.05, 0.04, 0.01])


def _known_spectrum(w_max: np.ndarray) -> np.ndarray:
    """Raw wrenches (16, 6) whose normalised ones ``W / w_max`` have variance fractions
    SPECTRUM along 6 rotated directions: orthogonal zero-mean ±1 columns (Hadamard's, the
    constant one left out) scaled by sqrt(SPECTRUM), turned by a random rotation."""
    h = np.array([[1.0]])
    for _ in range(4):
        h = np.block([[h, h], [h, -h]])
    q, _ = np.linalg.qr(np.random.default_rng(0).standard_normal((6, 6)))
    return (h[:, 1:7] * np.sqrt(SPECTRUM)) @ q.T * w_max


def test_wrench_pca_recovers_a_known_variance_spectrum():
    w_max = np.array([2.0, 0.5, 3.0, 0.01, 0.02, 0.005])
    res = wrench_pca(_known_spectrum(w_max), w_max, retained_variance=0.99, significant_fraction=0.045)
    np.testing.assert_allclose(res.explained_variance_ratio, SPECTRUM, rtol=1e-12)
    # 0.5 + 0.3 + 0.1 + 0.05 + 0.04 reaches 0.99 at k = 5 (round-off short of it still counts)
    assert res.n_retained == 5
    assert res.n_above_fraction == 4  # 0.5, 0.3, 0.1, 0.05 >= 0.045 > 0.04
    res95 = wrench_pca(_known_spectrum(w_max), w_max, retained_variance=0.95, significant_fraction=0.0)
    assert (res95.n_retained, res95.n_above_fraction) == (4, 6)
    # without the normalisation by w_max the spectrum would be another
    assert not np.allclose(explained_variance_ratio(_known_spectrum(w_max)), SPECTRUM, rtol=1e-3)


def test_the_component_counts_by_hand():
    ratio = np.array([0.6, 0.25, 0.1, 0.04, 0.01, 0.0])
    assert n_components_retaining(ratio, 0.6) == 1
    assert n_components_retaining(ratio, 0.61) == 2
    assert n_components_retaining(ratio, 0.95) == 3
    assert n_components_retaining(ratio, 0.95 + 1e-9) == 4
    assert n_components_retaining(ratio, 1.0) == 5  # the last component explains nothing
    # 0.7 + 0.1 is 0.7999999999999999 in floating point: short of 0.8 by round-off only
    short = np.array([0.7, 0.1, 0.1, 0.05, 0.05, 0.0])
    assert np.cumsum(short)[1] < 0.8
    assert n_components_retaining(short, 0.8) == 2
    assert n_components_retaining(short, 0.8 + 1e-9) == 3  # more than round-off: one more
    assert n_components_above(ratio, 0.1) == 3 and n_components_above(ratio, 0.0) == 6


def test_wrench_pca_guards_degenerate_components_and_refuses_percentages():
    # a planar contact's f_z, tau_x, tau_y: w_max 0 there, wrenches 0 there — no division by 0
    w_max = np.array([1.0, 1.0, 0.0, 0.0, 0.0, 0.5])
    W = _known_spectrum(np.ones(6)) * np.array([1.0, 1.0, 0.0, 0.0, 0.0, 0.5])
    res = wrench_pca(W, w_max, retained_variance=0.99, significant_fraction=0.01)
    assert np.isfinite(res.explained_variance_ratio).all() and res.n_above_fraction <= 3
    with pytest.raises(ValueError, match="retained_variance"):
        wrench_pca(W, w_max, retained_variance=99, significant_fraction=0.01)
    with pytest.raises(ValueError, match="significant_fraction"):
        wrench_pca(W, w_max, retained_variance=0.99, significant_fraction=-0.1)


def test_a_planar_triple_is_refused_with_the_6d_layout_that_fits_it():
    """(K, 3) wrenches (f_x, f_y, τ_z) of a planar contact: the error shows the 6D layout, and
    that layout fits in the 3 dimensions it spans (a new-user trial)."""
    from workbench import fit_ellipsoid
    from workbench.limit_surface.normalize import check_wrenches

    z = np.random.default_rng(3).standard_normal((200, 3))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    with pytest.raises(ValueError, match=r"got \(200, 3\) — a planar contact's .*\[f_x, f_y, 0, 0, 0, τ_z\]"):
        check_wrenches(z)
    with pytest.raises(ValueError, match=r"got \(6,\) — one row \[f_x, f_y, f_z, τ_x, τ_y, τ_z\]"):
        check_wrenches(np.ones(6))
    W = np.zeros((200, 6))
    W[:, [0, 1, 5]] = z
    assert fit_ellipsoid(W, "lsq").info["dim"] == 3


def test_a_total_contact_wrench_is_logged_as_not_centred_and_a_frictional_set_is_not(caplog):
    from workbench import normal_wrench
    from workbench.limit_surface import fit_ellipsoid
    from workbench.limit_surface.normalize import wrench_scale

    c, a, r, rmax = _disc()
    prof = ContactProfile(c, np.tile([0, 0, 1.0], (len(c), 1)), a, 1e5 * power_law(r, rmax, 2.0))
    mu = 0.3
    W = frictional_wrenches(prof, sample_twists_thesis(300, prof, seed=4), mu)
    total = W + normal_wrench(prof)  # the normal force's wrench on top: a total contact wrench
    with caplog.at_level("WARNING", logger="workbench.limit_surface.normalize"):
        fit_ellipsoid(W, "lsq")
        assert not caplog.records
        fit_ellipsoid(total, "lsq")
    (rec,) = [r for r in caplog.records if "not centred" in r.getMessage()]
    # the offset by hand: the mean's norm over the RMS norm of the Eq. 3.10-normalised wrenches
    # (wrench_scale: each component over its sampled maximum, the degenerate ones over the largest)
    x = total / wrench_scale(np.abs(total).max(axis=0))
    ratio = np.linalg.norm(x.mean(axis=0)) / np.sqrt((x**2).sum(axis=1).mean())
    assert ratio > 0.5 and f"mean is {ratio:.2g} of their RMS" in rec.getMessage()
    assert "normal_wrench(profile)" in rec.getMessage()
