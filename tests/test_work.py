"""Minimal work (thesis §4.3, Eq. 4.4-4.6): the work of analytic grasps against closed
forms, q_work = q_force ranking on rigid objects, the stiffness map's interpolation
(exact, rigid, clamped, held-out error that shrinks with sampling), the fitted
normaliser, and bad input."""

from pathlib import Path

import numpy as np
import pytest
from scipy.stats import spearmanr

from workbench import config
from workbench.grasp import (
    StiffnessMap,
    balanced_accuracy,
    fit_normaliser,
    gravity_wrench,
    leave_one_out,
    minimal_work,
    point_contact,
    q_force,
    q_work,
    work,
)
from workbench.grasp.work import displacements

G = 9.81  # workbench.grasp.robust.G_ACC
F_NOM = 10.0  # the contacts' nominal force bound [N]: sets the residual band's scale
CUP = Path("/work/shared/data/deformable_objects/stiffness_maps/plastic_cup.json")


def _two_jaws(a: float, f_nom: float = F_NOM):
    """Two hard point contacts at (±a, 0, 0) squeezing along x, inscribed 8-gons (a
    vertex along ±z: the friction limit along gravity is exactly μ f)."""
    return [
        point_contact([a, 0, 0], [1, 0, 0], f_nom, n_edges=8),
        point_contact([-a, 0, 0], [-1, 0, 0], f_nom, n_edges=8),
    ]


def _closed_form_forces(mass: float, mu: float, a: float, c: float) -> np.ndarray:
    """Minimal normal forces of :func:`_two_jaws` holding ``mass`` whose centre of mass
    is at (c, 0, 0), gravity along −z (independent reference, by hand):

    x-balance: the normals are ±x, so f_1 = f_2 = f.  z-balance: t_1 + t_2 = m g, with
    t_i the jaws' friction along +z.  Torque about y about the origin: gravity at
    (c, 0, 0) gives + c m g, the jaw at (±a, 0, 0) gives ∓ a t_i, so t_1 − t_2 = c m g / a
    and t_{1,2} = m g (1 ± c / a) / 2.  Friction |t_i| <= μ f (exact along z) needs
    f >= m g (1 + |c| / a) / (2 μ), and Σ f = 2 f is minimal at equality."""
    f = mass * G * (1 + abs(c) / a) / (2 * mu)
    return np.array([f, f])


def _band(mu: float, f_nom: float = F_NOM) -> float:
    """Absolute force slack of "resisted": config.TOL.resist_rtol of the contacts'
    capacity ~f_nom (1 + μ), on both jaws."""
    return 2 * config.TOL.resist_rtol * f_nom * (1 + mu)


# --- Eq. 4.5 on analytic grasps ------------------------------------------------------


@pytest.mark.parametrize("representation", ["outer", "model"])
@pytest.mark.parametrize("c", [0.0, 0.01])
def test_work_of_two_opposing_point_contacts_matches_the_closed_form(representation, c):
    mass, mu, a, eps = 1.0, 0.5, 0.03, 1e-4
    s = np.array([500.0, 2000.0])  # unequal stiffness: the jaws displace differently
    res = minimal_work(
        _two_jaws(a), gravity_wrench(mass, [c, 0, 0]), mu, s, eps=eps, representation=representation
    )
    f = _closed_form_forces(mass, mu, a, c)
    assert res.feasible and res.converged
    np.testing.assert_allclose(res.forces, f, atol=_band(mu))
    assert res.f_sum == pytest.approx(f.sum(), abs=2 * _band(mu))
    W_ref = float(np.sum(f * (f / s + eps)))  # Eq. 4.5 by hand
    # W is quadratic in f: dW/df_i = 2 f_i / s_i + eps
    assert res.W == pytest.approx(W_ref, abs=float(np.sum((2 * f / s + eps) * _band(mu))))
    np.testing.assert_allclose(res.displacements, res.forces / s + eps, rtol=1e-12)
    assert res.W == pytest.approx(work(res.forces, s, eps), rel=1e-12)
    assert res.representation == representation and res.eps == eps


def test_work_by_hand_and_rigid_contacts():
    f = np.array([3.0, 5.0, 0.0])
    s = np.array([100.0, np.inf, 700.0])  # the third carries no force
    assert work(f, s, 0.002) == pytest.approx(3 * (3 / 100 + 0.002) + 5 * 0.002)
    np.testing.assert_allclose(displacements(f, s, 0.002), [0.032, 0.002, 0.002])
    assert work(f, s, 0.0) == pytest.approx(0.09)  # ε = 0: a rigid contact does no work
    # ε defaults to the config's, read at call time
    assert work(f, s) == pytest.approx(
        3 * (3 / 100 + config.DEFAULTS.work_eps) + 5 * config.DEFAULTS.work_eps
    )


def test_unresisted_grasp_has_infinite_work():
    """Point contacts cannot resist a torque about their common axis (Eq. 2.100)."""
    res = minimal_work(_two_jaws(0.03), np.array([0, 0, 0, 0.1, 0, 0]), 0.5, [500.0, 500.0])
    assert not res.feasible
    assert res.W == np.inf and res.f_sum == np.inf
    assert np.isnan(res.forces).all() and np.isnan(res.displacements).all()
    assert q_work(res.W, 1.0) == -np.inf


def test_rigid_objects_rank_by_q_work_as_by_q_force():
    """s = inf everywhere: W = ε Σ f (Eq. 4.5), so q_work and q_force order grasps alike."""
    eps = 1e-4
    grasps = [  # (mass [kg], μ, half-width a [m], centre-of-mass offset c [m])
        (1.0, 0.5, 0.03, 0.0),
        (0.5, 0.5, 0.03, 0.0),
        (1.0, 0.8, 0.03, 0.0),
        (1.0, 0.5, 0.03, 0.012),
        (1.0, 0.5, 0.05, 0.012),
        (0.3, 0.3, 0.02, -0.004),
        (0.8, 1.0, 0.04, 0.02),
    ]
    f_sum, W = [], []
    for mass, mu, a, c in grasps:
        res = minimal_work(_two_jaws(a), gravity_wrench(mass, [c, 0, 0]), mu, [np.inf, np.inf], eps=eps)
        assert res.f_sum == pytest.approx(_closed_form_forces(mass, mu, a, c).sum(), abs=2 * _band(mu))
        assert res.W == pytest.approx(eps * res.f_sum, rel=1e-12)
        f_sum.append(res.f_sum)
        W.append(res.W)
    f_sum, W = np.array(f_sum), np.array(W)
    assert len(np.unique(np.round(f_sum, 6))) == len(grasps)  # no ties to hide behind
    qf = q_force(f_sum, 1.5 * f_sum.max())
    qw = q_work(W, 1.5 * W.max())
    assert isinstance(qf, np.ndarray) and qf.shape == (len(grasps),)
    np.testing.assert_array_equal(np.argsort(qw), np.argsort(qf))
    assert spearmanr(qw, qf).statistic == pytest.approx(1.0)
    # with equal normalisers (W_max = ε f_max) the two qualities coincide
    np.testing.assert_allclose(q_work(W, eps * 40.0), q_force(f_sum, 40.0), rtol=1e-12)


def test_q_is_unclipped_and_vectorised():
    assert q_work(3.0, 2.0) == pytest.approx(-0.5)  # W > W_max: q < 0, ranking kept
    assert q_force(0.0, 2.0) == 1.0
    np.testing.assert_allclose(q_work(np.array([[0.0, 1.0], [4.0, np.inf]]), 2.0), [[1, 0.5], [-1, -np.inf]])


# --- the stiffness map --------------------------------------------------------------

R_CYL, H_CYL = 0.04, 0.10


def _field(P):
    """A smooth stiffness field on a cylinder [N/m], symmetric under θ -> θ + π (so
    both jaws of an antipodal grasp carry one value, as in the measured maps)."""
    th, z = np.arctan2(P[:, 1], P[:, 0]), P[:, 2]
    return np.exp(np.log(1500.0) + 0.6 * np.cos(2 * th) + 1.2 * (z / H_CYL - 0.5) ** 2)


def _measured_grid(nt: int, nz: int):
    """(2n, 3) antipodal jaw points on the cylinder (i and i + n one grasp) and values."""
    th = np.linspace(0, np.pi, nt, endpoint=False) + 0.1
    z = np.linspace(0.1 * H_CYL, 0.9 * H_CYL, nz)
    T, Z = np.meshgrid(th, z)
    a = np.column_stack([R_CYL * np.cos(T.ravel()), R_CYL * np.sin(T.ravel()), Z.ravel()])
    P = np.vstack([a, a * [-1, -1, 1]])
    return P, _field(P)


def test_stiffness_map_exact_rigid_and_clamped():
    P, S = _measured_grid(6, 5)
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
    P, S = _measured_grid(5, 4)
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


def test_defaults_are_read_from_the_config_at_call_time(monkeypatch):
    import dataclasses

    P, S = _measured_grid(4, 3)
    monkeypatch.setattr(config, "TOL", dataclasses.replace(config.TOL, rigid_stiffness_threshold=2000.0))
    monkeypatch.setattr(config, "DEFAULTS", dataclasses.replace(config.DEFAULTS, work_eps=0.01))
    smap = StiffnessMap.from_measured(P, S)
    assert smap.rigid_threshold == 2000.0
    np.testing.assert_array_equal(np.isinf(smap(P)), S >= 2000.0)
    assert work([2.0], [np.inf]) == pytest.approx(0.02)
    with pytest.raises(dataclasses.FrozenInstanceError):
        smap.stiffness = S
    with pytest.raises(ValueError, match="read-only"):
        smap.points[0, 0] = 1.0


def test_duplicate_points_with_equal_values_are_accepted():
    P, S = _measured_grid(4, 3)
    smap = StiffnessMap(np.vstack([P, P[:2]]), np.concatenate([S, S[:2]]))
    np.testing.assert_allclose(smap(P), S, rtol=1e-9)


def test_leave_one_out_error_is_small_and_shrinks_with_sampling():
    """A held-out grasp is predicted from its neighbours: the error falls as the grid
    refines (a C² spline on a smooth field), and beats a constant by far."""
    r = {}
    for k in (4, 8):
        r[k] = leave_one_out(StiffnessMap.from_measured(*_measured_grid(k, k)))
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

    P, S = _measured_grid(6, 6)
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


# --- the normaliser -----------------------------------------------------------------


def test_balanced_accuracy_by_hand():
    truth = np.array([1, 1, 1, 1, 0, 0], bool)
    pred = np.array([1, 1, 1, 0, 0, 1], bool)
    # recall of successes 3/4, of failures 1/2
    assert balanced_accuracy(pred, truth) == pytest.approx((3 / 4 + 1 / 2) / 2)
    assert balanced_accuracy([1, 0, 1], [1, 1, 1]) == pytest.approx(2 / 3)  # one class: its recall
    assert balanced_accuracy([0, 0], [0, 0]) == 1.0


def test_held_out_accuracy_by_hand():
    """Per object on the held-out grasps (None without any), and over all of them."""
    from workbench.grasp.threshold import held_out_accuracy

    truth = np.array([1, 0, 1, 1, 0, 1, 0], bool)
    pred = np.array([1, 1, 0, 1, 0, 1, 1], bool)
    train = np.array([0, 0, 0, 1, 1, 0, 0], bool)
    groups = np.array(["a", "a", "a", "b", "b", "c", "c"])
    got = held_out_accuracy(pred, truth, train, groups, ["a", "b", "c"])
    # a: successes 1/2 recalled, failures 0/1; b: none held out; c: 1/1 and 0/1
    # All: successes (0, 2, 5) 2/3, failures (1, 6) 0/2
    assert got == {"a": 0.25, "b": None, "c": 0.5, "All": pytest.approx(1 / 3)}
    assert list(got) == ["a", "b", "c", "All"]
    with pytest.raises(ValueError, match="one shape"):
        held_out_accuracy(pred, truth, train[:-1], groups, ["a"])
    with pytest.raises(ValueError, match="no held-out grasp"):
        held_out_accuracy(pred, truth, np.ones(7, bool), groups, ["a"])


def test_fit_normaliser_separates_a_separable_set():
    W = np.array([0.2, 0.05, 1.5, 0.9, 0.1, np.inf, 2.0, 0.3])
    truth = W < 0.5  # low work succeeds; the unresisted grasp fails
    sigma = 0.5
    W_max = fit_normaliser(W, truth, sigma)
    pred = q_work(W, W_max) >= sigma
    assert balanced_accuracy(pred, truth) == 1.0
    # the only perfect threshold lies between 0.3 and 0.9: its midpoint
    assert (1 - sigma) * W_max == pytest.approx(0.6)
    assert fit_normaliser(W, truth, 0.8) == pytest.approx(0.6 / 0.2)


def test_fit_normaliser_ties_and_inf():
    # one class only: predicting every resisted grasp a success (t = 2 v_max) is perfect
    x = np.array([1.0, 2.0, 3.0, 4.0])
    assert (1 - 0.5) * fit_normaliser(x, np.ones(4, bool)) == pytest.approx(8.0)
    # t = 1.5 and t = 3.5 both reach balanced accuracy 3/4 (by hand: recalls 1/2 + 1 and
    # 1 + 1/2): the lower middle of the tied candidates
    truth = np.array([True, False, True, False])
    assert (1 - 0.5) * fit_normaliser(x, truth) == pytest.approx(1.5)
    assert balanced_accuracy(x <= 1.5, truth) == balanced_accuracy(x <= 3.5, truth) == 0.75
    # unresisted grasps are failures whatever X_max is
    x = np.array([1.0, np.inf, 2.0])
    X = fit_normaliser(x, np.array([True, True, False]))
    assert q_force(np.inf, X) < 0.5 and q_force(1.0, X) >= 0.5 and q_force(2.0, X) < 0.5


# --- bad input ----------------------------------------------------------------------


@pytest.mark.parametrize(
    "forces, stiffness, eps",
    [
        ([1.0, -1.0], [1.0, 1.0], 0.0),
        ([1.0, np.nan], [1.0, 1.0], 0.0),
        ([1.0, np.inf], [1.0, 1.0], 0.0),
        ([[1.0, 1.0]], [1.0, 1.0], 0.0),
        ([1.0, 1.0], [1.0, 0.0], 0.0),
        ([1.0, 1.0], [1.0, -5.0], 0.0),
        ([1.0, 1.0], [1.0, np.nan], 0.0),
        ([1.0, 1.0], [1.0, 1.0, 1.0], 0.0),
        ([1.0, 1.0], [1.0, 1.0], -1e-3),
        ([1.0, 1.0], [1.0, 1.0], np.nan),
        ([1.0, 1.0], [1.0, 1.0], True),
    ],
)
def test_work_rejects_bad_input(forces, stiffness, eps):
    with pytest.raises(ValueError):
        work(forces, stiffness, eps)


def test_qualities_reject_bad_input():
    for bad_max in (0.0, -1.0, np.inf, np.nan, [1.0, 2.0]):
        with pytest.raises(ValueError, match="must be a finite number > 0"):
            q_work(1.0, bad_max)
    for bad in (-1.0, np.nan, [1.0, -0.1]):
        with pytest.raises(ValueError, match="must be >= 0"):
            q_force(bad, 1.0)


def test_minimal_work_rejects_bad_input():
    grasp, w = _two_jaws(0.03), gravity_wrench(1.0, [0, 0, 0])
    with pytest.raises(ValueError, match=r"one value per contact"):
        minimal_work(grasp, w, 0.5, [500.0])
    with pytest.raises(ValueError, match="stiffness must be > 0"):
        minimal_work(grasp, w, 0.5, [500.0, 0.0])
    with pytest.raises(ValueError, match="eps"):
        minimal_work(grasp, w, 0.5, [500.0, 500.0], eps=-1.0)
    with pytest.raises(ValueError, match="representation"):
        minimal_work(grasp, w, 0.5, [500.0, 500.0], representation="exact")
    with pytest.raises(ValueError, match="ContactSet"):
        minimal_work(grasp[0], w, 0.5, [500.0])


def test_stiffness_map_rejects_bad_input():
    P, S = _measured_grid(4, 3)
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


def test_threshold_rejects_bad_input():
    with pytest.raises(ValueError, match="one shape"):
        balanced_accuracy([True, False], [True])
    with pytest.raises(ValueError, match="booleans"):
        balanced_accuracy([0.2, 0.9], [True, False])
    with pytest.raises(ValueError, match="non-empty"):
        balanced_accuracy([], [])
    with pytest.raises(ValueError, match=">= 0"):
        fit_normaliser([1.0, -2.0], [True, False])
    with pytest.raises(ValueError, match=">= 0"):
        fit_normaliser([1.0, np.nan], [True, False])
    with pytest.raises(ValueError, match="sigma"):
        fit_normaliser([1.0, 2.0], [True, False], sigma=1.0)
    with pytest.raises(ValueError, match="finite value > 0"):
        fit_normaliser([np.inf, np.inf], [True, False])
    with pytest.raises(ValueError, match="one shape"):
        fit_normaliser([1.0, 2.0, 3.0], [True, False])
