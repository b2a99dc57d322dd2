"""Continuous surfaces: analytic values, the thesis's printed numbers, quadrature
error estimates, meshes."""

import numpy as np
import pytest

from workbench import (
    ContactProfile,
    mesh_surface,
    project_to_plane,
    sample_twists_thesis,
    surface_moments,
    surface_w_max,
    surface_wrenches,
    twists_from_plucker,
    w_max,
)
from workbench.config import TOL
from workbench.sources.surface_catalog import PLANAR_NORMAL, S1, S3, THESIS_SURFACES, example_3_2_5
from workbench.sources.surfaces import ParametricSurface, mesh_profile, wrench_error_rate


def test_example_3_2_5_matches_closed_form_and_thesis():
    ex = example_3_2_5()
    m = surface_moments(ex)
    # closed forms: o_y = 0.02 * sqrt(2) / (pi/2); F = p * R * (pi/2) * 0.02; f_y = -p R sqrt(2) 0.02
    np.testing.assert_allclose(m.pressure_center, [0, 0.02 * np.sqrt(2) / (np.pi / 2), -0.04], atol=1e-15)
    assert m.F == pytest.approx(1e3 * 0.02 * np.pi / 2 * 0.02, rel=1e-13)
    np.testing.assert_allclose(m.normal_wrench, [0, -1e3 * 0.02 * np.sqrt(2) * 0.02, 0, 0, 0, 0], atol=1e-14)
    # thesis printed values
    np.testing.assert_allclose(m.pressure_center, [0, 0.018, -0.04], atol=5e-5)
    assert round(m.F, 4) == 0.6283
    assert round(m.normal_wrench[1], 4) == -0.5657
    xi = twists_from_plucker([0, -1, 0], [0, 0, 0], 0.0)[0]
    w = surface_wrenches(ex, xi, 0.3, rtol=1e-9)
    assert round(w[4], 4) == 0.0018
    np.testing.assert_allclose(np.delete(w, 4), 0.0, atol=1e-14)


def test_example_wrench_matches_direct_1d_integral():
    # independent check: tau_y by scipy dblquad of the closed-form integrand printed in §3.2.5.2
    from scipy import integrate

    def integrand(u, v):
        s, c = np.sin(u), np.cos(u)
        vr = np.array([-(s**2) * (v + 0.04), s * c * (v + 0.04), 0.02 * c])
        vr /= np.linalg.norm(vr)
        r = np.array([0.02 * c, 0.02 * s - 0.02 * np.sqrt(2) / (np.pi / 2), v + 0.04])
        return -0.3 * 1e3 * np.cross(r, vr)[1] * 0.02

    ref, _ = integrate.dblquad(integrand, -0.05, -0.03, 0.25 * np.pi, 0.75 * np.pi, epsabs=1e-13)
    xi = twists_from_plucker([0, -1, 0], [0, 0, 0], 0.0)[0]
    got = surface_wrenches(example_3_2_5(), xi, 0.3, rtol=1e-10)[4]
    assert got == pytest.approx(ref, rel=1e-8)


THESIS_TABLE_3_2 = {
    "6d": [0.64, 0.64, 1.00, 0.34, 0.69, 0.59],
    "3d": [0.64, 0.00, 1.00, 0.00, 0.69, 0.00],
    "planar": [1.00, 0.00, 1.00, 0.00, 0.59, 0.00],
}


def test_table_3_2_s1():
    six = surface_w_max(S1.normalized())
    three = six * np.array([1, 0, 1, 0, 1, 0])
    planar = surface_w_max(project_to_plane(S1, PLANAR_NORMAL).normalized())
    for got, key in ((six, "6d"), (three, "3d"), (planar, "planar")):
        assert np.abs(got - THESIS_TABLE_3_2[key]).max() <= 0.01, (key, got)


def test_analytic_w_max():
    # S1 (unit half cylinder, p̂ = 1/π): f_x = f_y = 2/π, f_z = 1
    s1 = surface_w_max(S1.normalized(), rtol=1e-9)
    np.testing.assert_allclose(s1[:3], [2 / np.pi, 2 / np.pi, 1.0], rtol=1e-8)
    # S3 (hemisphere): mean of sin(angle to the axis) over a sphere = π/4 for every axis force
    s3 = surface_w_max(S3.normalized(), rtol=1e-9)
    np.testing.assert_allclose(s3[:3], np.pi / 4, rtol=1e-8)
    # planar 2x1 rectangle: tau = mean distance to the center (closed form)
    a, b = 1.0, 0.5
    d = np.hypot(a, b)
    quarter = (2 * a * b * d + a**3 * np.log((b + d) / a) + b**3 * np.log((a + d) / b)) / 6
    planar = surface_w_max(project_to_plane(S1, PLANAR_NORMAL).normalized(), rtol=1e-9)
    assert planar[4] == pytest.approx(quarter / (a * b), rel=1e-7)
    np.testing.assert_allclose(planar[[1, 3, 5]], 0.0, atol=1e-12)


@pytest.mark.parametrize("name", list(THESIS_SURFACES))
def test_quadrature_meets_requested_tolerance(name):
    # canonical twists, thesis-sampled and random twists against a 1e-9 reference
    S = THESIS_SURFACES[name].normalized()
    rng = np.random.default_rng(1)
    xi = np.vstack(
        [np.eye(6), sample_twists_thesis(15, S.length_scale, seed=2), rng.standard_normal((10, 6))]
    )
    w, est = surface_wrenches(S, xi, rtol=1e-4, return_error=True)
    ref = surface_wrenches(S, xi, rtol=1e-9)
    scale = np.array([1.0] * 3 + [S.length_scale] * 3)  # mu F = 1
    true_err = (np.abs(w - ref) / scale).max(axis=1)
    assert (true_err <= 1e-4).all(), true_err.max()
    assert (est <= TOL.quadrature_safety * 1e-4).all()
    # tightening the tolerance really reduces the error
    w2 = surface_wrenches(S, xi, rtol=1e-6)
    assert (np.abs(w2 - ref) / scale).max() <= 1e-6


def test_surface_moments_areas():
    np.testing.assert_allclose(surface_moments(S1).area, np.pi, rtol=1e-12)
    np.testing.assert_allclose(surface_moments(S3).area, 2 * np.pi, rtol=1e-12)
    # S5 paraboloid half: area = (π/2) * ((1 + 4)^{3/2} - 1) / 6
    np.testing.assert_allclose(
        surface_moments(THESIS_SURFACES["S5"]).area, np.pi / 12 * (5**1.5 - 1), rtol=1e-12
    )


def test_user_surface_with_numeric_derivatives_and_pressure():
    # a user σ(u, v) without derivatives and a non-uniform pressure: flat disc of radius 0.01
    # with Hertz-like p = p0 sqrt(1 - r²/R²) -> F = 2/3 π R² p0
    R, p0 = 0.01, 1e5
    disc = ParametricSurface(
        "disc",
        lambda r, t: np.stack([r * np.cos(t), r * np.sin(t), 0 * r], axis=-1),
        (0.0, R),
        (0.0, 2 * np.pi),
        pressure=lambda r, t, xyz: p0 * np.sqrt(np.clip(1 - (r / R) ** 2, 0, None)),
    )
    # the sqrt edge makes the integrand rough at r = R, so ask for 1e-6 only
    m = surface_moments(disc, rtol=1e-6)
    assert m.error <= 1e-6
    assert m.F == pytest.approx(2 / 3 * np.pi * R**2 * p0, rel=1e-6)
    wm = surface_w_max(disc, mu=0.5, rtol=1e-6)
    np.testing.assert_allclose(wm[:2], 0.5 * m.F, rtol=1e-6)  # planar: f_max = μF
    # torsion: μ ∫ p r dA = μ p0 2π R³ ∫_0^1 s² sqrt(1-s²) ds = μ p0 2π R³ π/16
    assert wm[5] == pytest.approx(0.5 * p0 * 2 * np.pi * R**3 * np.pi / 16, rel=1e-5)


def _polar_disc(name, R, pressure=None, analytic=True, **kw):
    """Flat disc of radius R in the xy-plane, σ(r, t) = (r cos t, r sin t, 0)."""
    su = sv = None
    if analytic:
        su = lambda r, t: np.stack([np.cos(t), np.sin(t), 0 * r], axis=-1)  # noqa: E731
        sv = lambda r, t: np.stack([-r * np.sin(t), r * np.cos(t), 0 * r], axis=-1)  # noqa: E731
    return ParametricSurface(
        name,
        kw.pop("sigma", lambda r, t: np.stack([r * np.cos(t), r * np.sin(t), 0 * r], axis=-1)),
        (0.0, R),
        (0.0, 2 * np.pi),
        su,
        sv,
        pressure=pressure,
        **kw,
    )


def _wrenches_evaluating_every_cell(surface, xi, mu, rtol):
    """surface_wrenches as it was before the cell cache: every cell of every chunk and pass
    evaluated afresh (the reference of the cache)."""
    from workbench import _kernels, config
    from workbench.sources import surfaces as srf

    mom = surface_moments(surface)
    order, q = config.TOL.quadrature_order, config.TOL.quadrature_order**2
    rtol2 = config.TOL.tangential_velocity_rtol**2

    def evaluate(cells, groups, twists):
        xyz, n, da, p = srf._cell_points(surface, cells, order)
        r = xyz - mom.pressure_center
        out = np.empty((cells.shape[0], 6))
        lo = np.arange(0, cells.shape[0] * q, q, dtype=np.int64)
        cols = [np.ascontiguousarray(c) for c in (*r.T, *n.T, da * p)]
        _kernels._fw_segments(twists, groups.astype(np.int64), lo, lo + q, *cols, 1.0, rtol2, out)
        return out

    ls = srf._length_scale(surface)
    scale = np.array([mom.F] * 3 + [mom.F * ls] * 3)
    chunk, target = config.TOL.quadrature_twist_chunk, config.TOL.quadrature_safety * rtol
    vals = np.empty((len(xi), 6))
    for start in range(0, len(xi), chunk):
        part = xi[start : start + chunk]
        vals[start : start + len(part)] = srf._adaptive(
            lambda c, g, part=part: evaluate(c, g, part),
            srf._initial_cells(surface),
            len(part),
            np.tile(scale, (len(part), 1)),
            target,
            config.TOL.quadrature_max_passes,
        )[0]
    return vals * mu


@pytest.mark.parametrize("name", ["S1", "S4", "S6"])
def test_the_cell_cache_changes_no_bit(name):
    """Cells revisited by other twists and chunks are evaluated once (surfaces._CellGeometry):
    the wrenches are those of evaluating every cell afresh, bit for bit — with the default
    cache, and with a cache of 40 cells that starts afresh many times over."""
    from workbench import config

    surface = THESIS_SURFACES[name].normalized()
    xi = sample_twists_thesis(30, surface.length_scale, seed=11)
    reference = _wrenches_evaluating_every_cell(surface, xi, 0.7, 1e-4)
    np.testing.assert_array_equal(surface_wrenches(surface, xi, 0.7, rtol=1e-4), reference)
    for cap in (40, 0):
        with config.override(quadrature_cache_cells=cap):
            np.testing.assert_array_equal(surface_wrenches(surface, xi, 0.7, rtol=1e-4), reference)


def _cell_tree(surface, depth):
    """Every cell of the first ``depth`` levels below a surface's initial cells and its id
    (surfaces._split, _split_ids), level by level: (n, 4) bounds, (n,) ids."""
    from workbench.sources import surfaces as srf

    cells = [srf._initial_cells(surface)]
    ids = [np.arange(len(cells[0]), 2 * len(cells[0]), dtype=np.int64)]
    for _ in range(depth):
        cells.append(srf._split(cells[-1]))
        ids.append(srf._split_ids(ids[-1]))
    return np.concatenate(cells), np.concatenate(ids)


def test_cell_ids_name_one_cell_each_and_never_overflow():
    """The 4-ary heap numbering: across levels, one id per cell and one cell per id; a child
    past _ID_LIMIT gets a negative id (none), as do its descendants — the cell cache keys by them."""
    from workbench.sources import surfaces as srf

    cells, ids = _cell_tree(THESIS_SURFACES["S1"], 7)
    assert len(ids) == 14 * (4**8 - 1) // 3 and (ids > 0).all()
    assert len(np.unique(ids)) == len(ids) == len(np.unique(cells, axis=0))
    deep = np.array([srf._ID_LIMIT // 4 - 1, srf._ID_LIMIT // 4, -1, -5])
    kids = srf._split_ids(deep)
    assert (kids[:4] == 4 * deep[0] + np.arange(4)).all() and kids[3] < srf._ID_LIMIT
    assert (kids[4:] < 0).all()
    assert (srf._split_ids(kids[4:]) < 0).all()


@pytest.mark.parametrize("cap", [100_000, 300, 0])
def test_the_cell_cache_returns_each_cells_own_points(cap):
    """_CellGeometry over calls of revisited, new and id-less (-1) cells, growing its table and
    (small caps) starting afresh: every segment holds its own cell's Gauss points, bit for bit."""
    from workbench.sources import surfaces as srf

    surface = THESIS_SURFACES["S4"]
    order, center = 3, np.array([0.01, -0.02, 0.03])
    cells, ids = _cell_tree(surface, 4)
    ids[len(ids) // 2 :: 7] = -1  # as if too deep for an id: keyed by their bounds
    ids[len(ids) // 2 + 3 :: 11] = -6
    xyz, n, da, p = srf._cell_points(surface, cells, order)
    q = order * order
    rng = np.random.default_rng(5)
    geometry = srf._CellGeometry(surface, order, center, cap)
    for _ in range(12):
        rows = rng.choice(len(cells), rng.integers(1, 900))
        rows = np.concatenate([rows, rows[: len(rows) // 3]])  # repeats within a call
        lo, hi = geometry.segments(cells[rows], ids[rows])
        assert (hi - lo == q).all()
        points = (lo[:, None] + np.arange(q)).ravel()
        own = (rows[:, None] * q + np.arange(q)).ravel()
        np.testing.assert_array_equal(geometry.cols[0:3, points], (xyz[own] - center).T)
        np.testing.assert_array_equal(geometry.cols[3:6, points], n[own].T)
        np.testing.assert_array_equal(geometry.cols[6, points], da[own] * p[own])
        assert geometry.n <= max(cap, len(np.unique(rows)))


def test_cells_without_an_id_change_no_bit(monkeypatch):
    """With ids ending two levels down (every deeper cell keyed by its bounds), the wrenches
    are those of evaluating every cell afresh."""
    from workbench.sources import surfaces as srf

    surface = THESIS_SURFACES["S1"].normalized()
    xi = sample_twists_thesis(12, surface.length_scale, seed=3)
    reference = _wrenches_evaluating_every_cell(surface, xi, 0.7, 1e-4)
    monkeypatch.setattr(srf, "_ID_LIMIT", 4 * 16 * 4**2)
    np.testing.assert_array_equal(surface_wrenches(surface, xi, 0.7, rtol=1e-4), reference)


def test_rough_integrand_stops_at_the_cell_cap_with_an_honest_estimate(caplog):
    R = 0.01
    disc = _polar_disc("disc-rough", R, lambda r, t, xyz: np.sqrt(np.clip(1 - (r / R) ** 2, 0, None)))
    m = surface_moments(disc, rtol=1e-14)
    assert "cell cap (config.TOL.quadrature_max_cells)" in caplog.text
    assert "(surface_moments(rtol=1e-14))" in caplog.text  # names the setting to loosen
    assert m.error > 1e-14  # did not converge, and says so
    assert m.F == pytest.approx(2 / 3 * np.pi * R**2, rel=1e-6)


@pytest.mark.parametrize("name", list(THESIS_SURFACES))
@pytest.mark.parametrize("n", [25, 300, 1000])
def test_meshes(name, n):
    S = THESIS_SURFACES[name]
    verts, faces, uv = mesh_surface(S, n)
    assert abs(len(faces) - n) <= max(2, 0.03 * n)
    prof = ContactProfile.from_mesh(verts, faces, 1.0)
    _, nrm, _, _ = S.evaluate(uv[:, 0], uv[:, 1])
    assert (np.einsum("ij,ij->i", prof.normals, nrm) > 0.5).all()  # outward like the surface
    assert prof.areas.sum() <= surface_moments(S).area * (1 + 1e-12)  # inscribed flat triangles


@pytest.mark.parametrize("name", ["S3", "S4", "S5", "S6"])
def test_mesh_area_converges_at_second_order(name):
    # chordal area deficit of an inscribed mesh is O(h²) = O(1/n): 4x the triangles -> ~4x smaller
    S = THESIS_SURFACES[name]
    area = surface_moments(S).area
    deficit = [area - ContactProfile.from_mesh(*mesh_surface(S, n)[:2], 1.0).areas.sum() for n in (300, 1200)]
    assert deficit[0] > 0 and deficit[1] > 0
    assert deficit[0] / deficit[1] >= 3.0


def test_discrete_converges_to_continuous():
    S = THESIS_SURFACES["S4"]
    cont = surface_w_max(S.normalized(), rtol=1e-8)
    errs = [np.mean(np.abs(w_max(mesh_profile(S, n).normalized()) - cont) / cont) for n in (100, 400, 1600)]
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 0.002


def test_central_difference_derivatives_bound_the_moments_tolerance(caplog):
    # a flat disc without sigma_u, sigma_v under the default moments_rtol (1e-12, below the
    # ~1e-10 accuracy of central differences) ran to the cell cap (6 s) and warned "loosen
    # rtol" though none was passed; it now integrates to CENTRAL_DIFFERENCE_RTOL at once
    from workbench.sources.surfaces import CENTRAL_DIFFERENCE_RTOL

    a, p = 0.01, 2.0e4
    disc = _polar_disc("disc-fd", a, lambda r, t, xyz: np.full(np.shape(r), p), analytic=False)
    assert TOL.moments_rtol < CENTRAL_DIFFERENCE_RTOL == 1e-10
    m = surface_moments(disc)
    assert caplog.records == []
    assert m.F == pytest.approx(p * np.pi * a**2, rel=CENTRAL_DIFFERENCE_RTOL)  # 1.7e-11 measured
    assert m.area == pytest.approx(np.pi * a**2, rel=CENTRAL_DIFFERENCE_RTOL)
    assert 0 < m.error <= CENTRAL_DIFFERENCE_RTOL
    # with analytic derivatives the default tolerance is kept and met
    exact = surface_moments(_polar_disc("disc-analytic", a, lambda r, t, xyz: np.full(np.shape(r), p)))
    assert exact.error <= TOL.moments_rtol and exact.F == pytest.approx(p * np.pi * a**2, rel=1e-14)


@pytest.mark.parametrize(
    ("pressure", "match"),
    [
        (
            lambda r, t, xyz: -2e4 + 0 * r,
            r"the pressure must be finite and >= 0 \[Pa\].*got -20000 at \(u, v\)",
        ),
        (
            lambda r, t, xyz: np.where(r > 0.005, np.nan, 1.0),
            r"the pressure must be finite and >= 0 .*got nan at",
        ),
        (lambda r, t, xyz: 0 * r, r"the pressure is zero at every quadrature point of its 16 initial cells"),
    ],
)
def test_a_pressure_that_is_negative_nan_or_zero_is_refused(pressure, match):
    disc = _polar_disc("disc-bad-p", 0.01, pressure)
    with pytest.raises(ValueError, match=r"surface 'disc-bad-p': " + match):
        surface_moments(disc)


def test_sigma_of_the_wrong_shape_is_refused_where_it_is_evaluated():
    flat = _polar_disc("disc-xy", 0.01, sigma=lambda r, t: np.stack([r * np.cos(t), r * np.sin(t)], axis=-1))
    with pytest.raises(
        ValueError, match=r"surface 'disc-xy': sigma must map u, v of shape \(\d+,\) to .*got shape"
    ):
        surface_moments(flat)
    rows = _polar_disc("disc-rows", 0.01, analytic=False, sigma=lambda r, t: np.stack([r, t, 0 * r]))
    with pytest.raises(ValueError, match=r"sigma must map .*\(3, \d+\).*np.stack\(np.broadcast_arrays"):
        mesh_profile(rows, 20)


def test_cell_slot_kernel_matches_a_dict(rng):
    """workbench._kernels._cell_slots against a Python dict: slots by first appearance, the
    rows of new ids, over calls that repeat, add and mix ids (runs of consecutive ids as a
    level holds, random large ones, and the < -1 keys of cells without an id)."""
    from workbench import _kernels

    table = np.full((2, 1 << 12), -1, dtype=np.int64)
    ref: dict[int, int] = {}
    for call in range(6):
        ids = np.concatenate(
            [
                np.arange(1000 + 50 * call, 1100 + 50 * call),  # consecutive: overlaps the last call
                rng.integers(0, 2**62, 30),
                -2 - rng.integers(0, 40, 10),
                rng.choice(np.array(list(ref) or [7]), 20),  # held already
            ]
        ).astype(np.int64)
        rng.shuffle(ids)
        want_rows, want = [], np.empty_like(ids)
        for i, key in enumerate(ids.tolist()):
            if key not in ref:
                ref[key] = len(ref)
                want_rows.append(i)
            want[i] = ref[key]
        slots, rows = np.empty_like(ids), np.empty_like(ids)
        k = _kernels._cell_slots(table, ids, len(ref) - len(want_rows), slots, rows)
        np.testing.assert_array_equal(slots, want)
        np.testing.assert_array_equal(rows[:k], want_rows)


def test_the_wrench_error_rate_is_the_mean_relative_deviation_over_six_components():
    true = np.array([1.0, 2.0, 4.0, 0.5, 0.25, 1.0])
    # deviations 10 %, 0, 25 %, 0, 20 %, 30 % (signs do not cancel): mean 85 % / 6
    approx = np.array([1.1, 2.0, 3.0, 0.5, 0.3, 0.7])
    assert wrench_error_rate(approx, true) == pytest.approx(0.85 / 6, rel=1e-14)
    assert wrench_error_rate(true, true) == 0.0
    # relative: both scaled together (another mu or force), the same rate
    assert wrench_error_rate(3 * approx, 3 * true) == pytest.approx(0.85 / 6, rel=1e-14)


def test_the_wrench_error_rate_refuses_a_truth_without_all_six_components():
    with pytest.raises(ValueError, match="w_max_true must be > 0"):
        wrench_error_rate(np.ones(6), np.array([1.0, 1.0, 0.0, 0.0, 0.0, 1.0]))  # a planar contact
    with pytest.raises(ValueError, match=r"\(6,\) maxima"):
        wrench_error_rate(np.ones(3), np.ones(3))
