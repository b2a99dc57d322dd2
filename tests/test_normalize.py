"""workbench.limit_surface.normalize: the two PCA conventions (Table 3.2's centered one, the
fitters' about the origin) and where they agree."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.limit_surface.normalize import explained_variance_ratio, pca_subspace


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
