"""workbench.grasp.stiffness_map: the measured stiffness interpolated over an object
(thesis §4.3.3.1) — exact at the measured points, rigid where the nearest point is, clamped
to the measured range, scale-free, reproducing a log-linear field exactly, the held-out
error of leave_one_out, and bad input (shapes, NaN, N/mm, millimetres)."""

from pathlib import Path

import numpy as np
import pytest
from grasp_helpers import measured_grid

from workbench import config
from workbench.grasp import StiffnessMap, leave_one_out
from workbench.grasp.stiffness_map import check_stiffness

CUP = Path("/work/shared/data/deformable_objects/stiffness_maps/plastic_cup.json")


def _has(text: str, *words: str) -> None:
    missing = [w for w in words if w not in text]
    assert not missing, f"{missing} not in: {text}"


def test_stiffness_map_exact_rigid_and_clamped():
    P, S = measured_grid(6, 5)
    n = len(P) // 2
    S = S.copy()
    top = P[:, 2] == P[:, 2].max()
    S[top] = 8e10  # the top ring is rigid (a rim), as the maps write it
    smap = StiffnessMap.from_measured(P, S[:, None])
    assert smap.points.shape == (2 * n, 3) and not smap.points.flags.writeable
    np.testing.assert_array_equal(smap.grasp, np.tile(np.arange(n), 2))
    got = smap(P)
    np.testing.assert_allclose(got[~top], S[~top], rtol=1e-9)
    assert np.isinf(got[top]).all()
    # nearest measured point rigid => rigid; elsewhere within the measured range
    rng = np.random.default_rng(3)
    Q = rng.uniform([-0.06, -0.06, -0.05], [0.06, 0.06, 0.15], size=(400, 3))
    s = smap(Q)
    _, near = smap._tree.query(Q)
    np.testing.assert_array_equal(np.isinf(s), top[near])
    soft = s[~np.isinf(s)]
    lo, hi = S[~top].min(), S[~top].max()
    assert soft.min() >= lo * (1 - 1e-12) and soft.max() <= hi * (1 + 1e-12)
    # outside the measured points' hull the spline's trend would leave the range: the clamp
    # holds it; farther from every point than the points span (0.08 m) is refused
    span = float(np.ptp(P, axis=0).max())
    out = smap(np.array([[0.0, 0.0, -0.05], [0.07, 0.07, 0.01]]))
    assert np.all((out >= lo * (1 - 1e-12)) & (out <= hi * (1 + 1e-12)))
    for q in ([0.0, 0.0, -0.5], [0.3, 0.3, 0.01], [0.0, 0.0, 80.0]):  # the last: a height in mm
        dist = float(np.linalg.norm(P - q, axis=1).min())
        assert dist > span
        with pytest.raises(
            ValueError,
            match=rf"{dist:.3g} m from the nearest measured point, farther than the measured points. "
            r"extent.*metres",
        ):
            smap(np.array([[0.0, 0.0, 0.05], q]))
    assert smap([0.0, 0.0, 0.15]).shape == (1,) and np.isinf(smap([0.0, 0.0, 0.15])[0])


def test_stiffness_map_is_scale_free_and_reads_the_threshold():
    P, S = measured_grid(5, 4)
    Q = np.random.default_rng(0).normal(scale=0.03, size=(30, 3))
    a, b = StiffnessMap.from_measured(P, S), StiffnessMap.from_measured(0.5 * P, S)
    np.testing.assert_allclose(a(Q), b(0.5 * Q), rtol=1e-9)
    assert a.kernel == "cubic"
    assert a.rigid_threshold == config.TOL.rigid_stiffness_threshold
    # a lower threshold makes the stiffest grasps rigid
    c = StiffnessMap.from_measured(P, S, rigid_threshold=float(np.median(S)))
    assert np.isinf(c(P)[S >= np.median(S)]).all()
    # too few (or coplanar) soft points for a cubic spline: the linear kernel, still exact
    few = StiffnessMap(P[:3], S[:3])
    assert few.kernel == "linear"
    np.testing.assert_allclose(few(P[:3]), S[:3], rtol=1e-9)
    assert StiffnessMap(P[:2], np.full(2, 8e10)).kernel is None


def test_duplicate_points_with_equal_values_are_accepted():
    P, S = measured_grid(4, 3)
    smap = StiffnessMap(np.vstack([P, P[:2]]), np.concatenate([S, S[:2]]))
    np.testing.assert_allclose(smap(P), S, rtol=1e-9)


def test_leave_one_out_error_is_small_and_shrinks_with_sampling():
    """A held-out grasp is predicted from its neighbours: the error falls as the grid
    refines (a C² spline on a smooth field), and beats a constant by far."""
    r = {}
    for k in (4, 8):
        r[k] = leave_one_out(StiffnessMap.from_measured(*measured_grid(k, k)))
        assert r[k]["n_grasps"] == k * k and r[k]["n_compared"] == 2 * k * k
        assert r[k]["rigid_agreement"] == 1.0
        assert r[k]["median_abs_log_error"] < 0.1 * r[k]["baseline_median_abs_log_error"]
    assert 0 < r[8]["median_abs_log_error"] < 0.3 * r[4]["median_abs_log_error"]
    assert r[8]["max_abs_log_error"] < 0.3 * r[4]["max_abs_log_error"]
    assert r[4]["median_abs_log_error"] < 0.02  # 2 % at 4 x 4 grasps


def test_leave_one_out_flags_rigid_points():
    """The rigid flag of a held-out point is its nearest other grasp's: checked against
    a brute-force nearest neighbour.  The top ring is rigid and lifted by 3 mm: its
    points are 20.7 mm apart, 19 mm above the row below (16 mm apart in z), so a
    held-out ring grasp is predicted soft and every other grasp right, without ties."""
    from scipy.spatial.distance import cdist

    P, S = measured_grid(6, 6)
    ring = P[:, 2] == P[:, 2].max()
    P[ring, 2] += 0.003
    S = np.where(ring, 8e10, S)
    smap = StiffnessMap.from_measured(P, S)
    r = leave_one_out(smap)
    D = cdist(P, P)
    D[smap.grasp[:, None] == smap.grasp[None, :]] = np.inf  # the held-out grasp's own points
    rigid = S >= 1e10
    assert r["rigid_agreement"] == pytest.approx(np.mean(rigid[D.argmin(axis=1)] == rigid))
    assert r["rigid_agreement"] == pytest.approx(1 - 12 / 72)
    assert r["n_compared"] == 72 - 12 and np.isfinite(r["median_abs_log_error"])


def test_measured_plastic_cup():
    if not CUP.exists():
        pytest.skip(f"{CUP} is absent (external data)")
    import json

    data = json.loads(CUP.read_text())
    smap = StiffnessMap.from_measured(data["stiffness_locations"], data["stiffness_map"])
    S = np.asarray(data["stiffness_map"], float).ravel()
    got = smap(np.asarray(data["stiffness_locations"], float))
    rigid = S >= smap.rigid_threshold
    np.testing.assert_allclose(got[~rigid], S[~rigid], rtol=1e-9)
    assert np.isinf(got[rigid]).all()
    r = leave_one_out(smap)
    assert np.isfinite(r["median_abs_log_error"]) and r["median_abs_log_error"] < 2


def test_stiffness_map_rejects_bad_input():
    P, S = measured_grid(4, 3)
    bad = [
        (lambda: StiffnessMap(P[:, :2], S), "points must be"),
        (lambda: StiffnessMap(np.where(P == P[0, 0], np.nan, P), S), "finite"),
        (lambda: StiffnessMap(P, S[:-1]), "stiffness must be"),
        (lambda: StiffnessMap(P, S[:, None]), "stiffness must be"),
        (lambda: StiffnessMap(P, np.where(S == S[0], -1.0, S)), "> 0"),
        (lambda: StiffnessMap(P, np.where(S == S[0], np.nan, S)), "> 0"),
        (lambda: StiffnessMap(P * 1000, S), "millimetres"),  # a map in mm read as m
        (lambda: StiffnessMap(P * 1e-6, S), "less than"),  # converted to metres twice
        (lambda: StiffnessMap(np.vstack([P, P[:1]]), np.append(S, 2 * S[0])), "coincide"),
        (lambda: StiffnessMap(P, S, grasp=np.zeros(3, int)), "grasp must be"),
        (lambda: StiffnessMap(P, S, rigid_threshold=0.0), "rigid_threshold"),
        (lambda: StiffnessMap.from_measured(P[:-1], S[:-1]), "2n points"),
        (lambda: StiffnessMap.from_measured(P, S[:, None].repeat(2, axis=1)), r"\(2n, 1\) or \(2n,\)"),
        (lambda: StiffnessMap.from_measured(P, np.where(np.arange(len(S)) == 3, 2 * S, S)), "differ"),
        (lambda: StiffnessMap.from_measured(P, S)(np.zeros((2, 2))), r"\(k, 3\)"),
        (lambda: leave_one_out(P), "StiffnessMap"),
    ]
    for make, msg in bad:
        with pytest.raises(ValueError, match=msg):
            make()


def test_stiffness_in_n_per_mm_is_refused():
    from workbench.grasp.stiffness_map import StiffnessMap
    from workbench.grasp.work import work

    with pytest.raises(ValueError, match="N/mm") as exc:
        work([3.0, 5.0], [0.4, 20.0], 1e-4)  # 400 and 20 000 N/m written in N/mm
    _has(str(exc.value), "0.4", "pass 400 [N/m]")
    assert work([3.0, 5.0], [400.0, 20000.0], 1e-4) == pytest.approx(
        3 * (3 / 400 + 1e-4) + 5 * (5 / 2e4 + 1e-4)
    )
    P = np.array([[0.03, 0, 0], [0, 0.03, 0], [-0.03, 0, 0], [0, -0.03, 0.01]])
    with pytest.raises(ValueError, match="N/mm"):
        StiffnessMap(P, np.array([0.4, 0.5, 0.6, 0.7]))


# --- added: independent references -------------------------------------------------------


def test_a_log_linear_field_is_reproduced_exactly():
    """The cubic kernel carries a linear polynomial: when log s is linear in position, the
    interpolant is that linear function itself (the RBF weights vanish), so at any convex
    combination of the measured points (inside their hull, hence inside the measured log
    range: no clamping) the map returns ``exp(a + b·x)`` to round-off."""
    P, _ = measured_grid(6, 5)
    a, b = np.log(2000.0), np.array([8.0, -5.0, 12.0])  # log s [log N/m], slope [1/m]
    smap = StiffnessMap(P, np.exp(a + P @ b))
    assert smap.kernel == "cubic"
    rng = np.random.default_rng(7)
    Q = np.einsum("ij,ijk->ik", rng.dirichlet(np.ones(4), 200), P[rng.integers(0, len(P), (200, 4))])
    np.testing.assert_allclose(np.log(smap(Q)), a + Q @ b, rtol=0, atol=1e-9)


def test_two_points_interpolate_log_linearly_between_them():
    """Two soft points: the linear kernel φ(r) = −r with a constant (weights summing to 0)
    is linear along the segment, so log s varies linearly from one point to the other: the
    midpoint carries the geometric mean √(s1 s2), the point at 1/5 of the way s1 (s2/s1)^(1/5)."""
    P = np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0]])
    s1, s2 = 400.0, 2.5e4
    smap = StiffnessMap(P, np.array([s1, s2]))
    assert smap.kernel == "linear"
    got = smap(np.array([[0.025, 0.0, 0.0], [0.01, 0.0, 0.0]]))
    np.testing.assert_allclose(got, [np.sqrt(s1 * s2), s1 * (s2 / s1) ** 0.2], rtol=1e-12)


def test_leave_one_out_of_a_log_linear_field_is_the_clamp_only():
    """Every point its own grasp on a log-linear field: the others reproduce the field (see
    above), so a held-out point's only error is the clamp to the others' log range,
    ``|clip(ℓ_i, min_{j≠i} ℓ_j, max_{j≠i} ℓ_j) − ℓ_i|`` (non-zero at the two extreme points
    only); the baseline predicts ``median_{j≠i} ℓ_j``.  Both references by a plain loop."""
    P, _ = measured_grid(5, 4)
    L = np.log(2000.0) + P @ np.array([8.0, -5.0, 12.0])
    r = leave_one_out(StiffnessMap(P, np.exp(L)))
    err, base = [], []
    for i in range(len(L)):
        rest = np.delete(L, i)
        err.append(abs(np.clip(L[i], rest.min(), rest.max()) - L[i]))
        base.append(abs(np.median(rest) - L[i]))
    assert r["n_grasps"] == r["n_points"] == r["n_compared"] == len(L) and r["rigid_agreement"] == 1.0
    assert r["median_abs_log_error"] == pytest.approx(np.median(err), abs=1e-9)
    assert r["max_abs_log_error"] == pytest.approx(max(err), abs=1e-9) and max(err) > 0.01
    assert r["baseline_median_abs_log_error"] == pytest.approx(np.median(base), rel=1e-12)


def test_a_one_grasp_map_has_nothing_to_hold_out():
    P = np.array([[0.03, 0.0, 0.0], [-0.03, 0.0, 0.0]])
    r = leave_one_out(StiffnessMap.from_measured(P, [700.0, 700.0]))
    assert r["n_grasps"] == r["n_points"] == r["n_compared"] == 0
    assert np.isnan(r["median_abs_log_error"]) and np.isnan(r["rigid_agreement"])


def test_check_stiffness_accepts_rigid_and_names_what_is_wrong():
    lo = config.TOL.min_plausible_stiffness
    got = check_stiffness([500, np.inf, lo], 3, "contact", fix="one per contact")
    assert got.dtype == float and got.tolist() == [500.0, np.inf, lo]
    cases = [
        (
            np.full((3, 1), 500.0),
            r"stiffness must be \(n,\) = \(3,\), one value per contact \[N/m\]; got shape",
        ),
        ([500.0, 500.0], r"got shape \(2,\) \(one per contact\)"),
        (
            [500.0, np.nan, 500.0],
            r"stiffness must be > 0 \[N/m\] \(np.inf for a rigid contact\); got nan at contact 1",
        ),
        ([500.0, 500.0, 0.0], "got 0.0 at contact 2"),
        ([500.0, -1.0, 500.0], "got -1.0 at contact 1"),
        ([500.0, 0.5 * lo, 500.0], r"stiffness at contact 1 .*min_plausible_stiffness.*probably in N/mm"),
    ]
    for values, msg in cases:
        with pytest.raises(ValueError, match=msg):
            check_stiffness(values, 3, "contact", fix="one per contact")
