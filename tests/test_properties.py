"""Property-based tests (hypothesis) of the invariances every user relies on, and of the input
validation of the public wrappers: a clear ``ValueError`` or a correct result, never a
traceback from deep inside.

Covariances of the 6D frictional wrench, Eqs. 3.6–3.8, about the pressure center:
* permutation of the elements: the same wrenches;
* pressure scaling ``p -> s p``: wrenches times ``s``;
* rigid motion ``x -> R x + t``: the twists and wrenches rotate with ``R`` (both are taken
  about the pressure center, which moves along);
* geometric scale ``x -> s x`` (areas ``s²``): a twist ``[s v; ω]`` gives ``[s² f; s³ τ]``.
Limit surfaces: ``model.scaled(k)`` takes ``k w`` to where ``model`` takes ``w`` (the grasp
layer's rescaling by the normal force, ``ContactSet.with_force``)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from naive import random_profile
from scipy.spatial.transform import Rotation

from workbench import ContactProfile, fit_ellipsoid, frictional_wrenches, sample_twists_thesis

PROPS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
seeds = st.integers(0, 2**32 - 1)
sizes = st.integers(3, 60)


def _profile(seed: int, n: int, curved: bool = True) -> ContactProfile:
    c, nrm, a, p = random_profile(np.random.default_rng(seed), n, curved)
    p[0] = max(p[0], 1.0)  # at least one pressed element
    return ContactProfile(c, nrm, a, p)


def _twists(seed: int, k: int = 12) -> np.ndarray:
    xi = np.random.default_rng(seed).normal(size=(k, 6))
    xi[:, :3] *= 0.01  # a translation of ~1 cm per radian: both parts matter at this size
    return xi


def _close(a: np.ndarray, b: np.ndarray, rtol: float = 1e-10) -> bool:
    return bool(np.abs(a - b).max() <= rtol * max(np.abs(b).max(), 1e-300))


@PROPS
@given(seeds, sizes, st.data())
def test_wrenches_do_not_depend_on_the_order_of_the_elements(seed, n, data):
    prof = _profile(seed, n)
    perm = np.array(data.draw(st.permutations(range(n))))
    moved = ContactProfile(prof.centers[perm], prof.normals[perm], prof.areas[perm], prof.pressures[perm])
    xi = _twists(seed + 1)
    assert _close(frictional_wrenches(moved, xi, 0.7), frictional_wrenches(prof, xi, 0.7))


@PROPS
@given(seeds, sizes, st.floats(1e-3, 1e3))
def test_wrenches_scale_with_the_pressure(seed, n, s):
    prof = _profile(seed, n)
    xi = _twists(seed + 2)
    scaled = prof.with_pressures(s * prof.pressures)
    assert _close(frictional_wrenches(scaled, xi, 0.5), s * frictional_wrenches(prof, xi, 0.5))


@PROPS
@given(
    seeds,
    sizes,
    st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3),
    st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
)
def test_wrenches_move_with_the_contact(seed, n, rotvec, t):
    prof = _profile(seed, n)
    R = Rotation.from_rotvec(rotvec).as_matrix()
    moved = prof.transformed(R, np.array(t))
    xi = _twists(seed + 3)
    T = np.kron(np.eye(2), R)  # twists and wrenches: both 3-vectors rotate
    got = frictional_wrenches(moved, xi @ T.T, 0.6)
    assert _close(got, frictional_wrenches(prof, xi, 0.6) @ T.T, 1e-9)
    assert _close(moved.pressure_center, R @ prof.pressure_center + t, 1e-9)


@PROPS
@given(seeds, sizes, st.floats(0.05, 20.0))
def test_wrenches_scale_with_the_size_of_the_contact(seed, n, s):
    prof = _profile(seed, n)
    big = ContactProfile(s * prof.centers, prof.normals, s**2 * prof.areas, prof.pressures)
    xi = _twists(seed + 4)
    W = frictional_wrenches(prof, xi, 0.8)
    got = frictional_wrenches(big, xi * np.r_[s, s, s, 1, 1, 1], 0.8)
    assert _close(got, W * np.r_[[s**2] * 3, [s**3] * 3], 1e-9)


@pytest.fixture(scope="module")
def ellipsoid():
    prof = _profile(11, 80).normalized()
    W = frictional_wrenches(prof, sample_twists_thesis(150, prof, seed=0), 1.0)
    return fit_ellipsoid(W, "lsq")


@PROPS
@given(seeds, st.floats(1e-3, 1e3))
def test_a_scaled_limit_surface_takes_scaled_wrenches_where_the_model_takes_them(ellipsoid, seed, k):
    w = np.random.default_rng(seed).normal(size=(20, 6)) * ellipsoid.w_max
    assert _close(ellipsoid.scaled(k).value(k * w), ellipsoid.value(w), 1e-9)


# ---------------------------------------------------------------- careless input
finite_or_not = st.sampled_from([np.nan, np.inf, -np.inf])


@PROPS
@given(seeds, sizes, st.sampled_from(["centers", "normals", "areas", "pressures"]), finite_or_not, st.data())
def test_a_profile_with_a_non_finite_entry_is_refused_by_name(seed, n, field, bad, data):
    c, nrm, a, p = random_profile(np.random.default_rng(seed), n)
    arrays = {"centers": c, "normals": nrm, "areas": a, "pressures": p}
    arr = arrays[field]
    idx = data.draw(st.integers(0, arr.size - 1))
    arr.flat[idx] = bad
    with pytest.raises(ValueError, match=field):
        ContactProfile(**arrays)


@PROPS
@given(seeds, st.sampled_from(["centers", "normals", "areas", "pressures"]), st.integers(1, 4))
def test_a_profile_with_a_wrong_shape_is_refused(seed, field, extra):
    c, nrm, a, p = random_profile(np.random.default_rng(seed), 10)
    arrays = {"centers": c, "normals": nrm, "areas": a, "pressures": p}
    arr = arrays[field]
    arrays[field] = arr[:-extra] if extra % 2 else np.concatenate([arr, arr[:extra]])
    with pytest.raises(ValueError):
        ContactProfile(**arrays)


@PROPS
@given(
    seeds,
    st.one_of(
        st.just(np.zeros((3, 5))),
        st.just(np.full((2, 6), np.nan)),
        st.just(np.array([[1, 0, 0, 0, 0, np.inf]])),
        st.just("twist"),
        st.just(np.zeros((2, 6, 1))),
    ),
)
def test_careless_twists_are_refused(seed, twists):
    prof = _profile(seed, 10)
    with pytest.raises(ValueError, match="twist"):
        frictional_wrenches(prof, twists, 0.5)


@PROPS
@given(seeds, st.one_of(st.floats(max_value=-1e-12), st.sampled_from([np.nan, np.inf, "mu", None])))
def test_careless_friction_coefficients_are_refused(seed, mu):
    prof = _profile(seed, 10)
    with pytest.raises(ValueError, match="mu"):
        frictional_wrenches(prof, _twists(seed), mu)


def test_an_empty_batch_and_a_numeric_string_are_answered_not_refused():
    # the "correct result" half of the rule: nothing to compute gives nothing; "0.5" is 0.5
    prof = _profile(5, 10)
    assert frictional_wrenches(prof, np.zeros((0, 6)), 0.5).shape == (0, 6)
    xi = _twists(5)
    assert np.array_equal(frictional_wrenches(prof, xi, "0.5"), frictional_wrenches(prof, xi, 0.5))
