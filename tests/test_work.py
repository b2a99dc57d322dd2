"""Minimal work (thesis §4.3, Eqs. 4.4–4.6): the work of analytic grasps against closed
forms, q_work = q_force ranking on rigid objects, the defaults read at call time, and bad
input.  The stiffness map is tested in test_stiffness_map.py, the fitted normaliser in
test_threshold.py."""

import numpy as np
import pytest
from grasp_helpers import measured_grid
from scipy.stats import spearmanr

from workbench import config
from workbench.grasp import (
    StiffnessMap,
    gravity_wrench,
    minimal_work,
    point_contact,
    q_force,
    q_work,
    work,
)
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.work import displacements
from workbench.sources.scenes import elliptic_cylinder_grasp

G = 9.81  # workbench.grasp.robust.G_ACC
F_NOM = 10.0  # the contacts' nominal force bound [N]: sets the residual band's scale


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


# --- the defaults -------------------------------------------------------------------


def test_defaults_are_read_from_the_config_at_call_time(monkeypatch):
    import dataclasses

    P, S = measured_grid(4, 3)
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


@pytest.mark.parametrize("half_angle", [0.6, 1.0])
def test_minimal_force_of_a_curved_jaw_obeys_coulomb_and_outer_is_only_a_lower_bound(half_angle):
    """Two elliptic-cylinder patches (normals horizontal) hold a vertical weight: friction alone
    carries it, at most μ f per jaw, so any Coulomb contact needs Σ f >= m g / μ (by hand).  The
    default program (the 6DLS itself) honours that to the 6DLS's fitting error (a few per cent,
    thesis Fig 3.9); the thesis's C_outer of 200 tangent half-spaces lies outside the ellipsoid,
    so its Σ f is below the 6DLS's, here below the physical bound."""
    mass, mu = 0.3, 0.5
    profiles = elliptic_cylinder_grasp(0.03, 0.02, half_angle, 0.03, 2.4, 10.0, 300)
    assert max(np.abs(p.normals[:, 2]).max() for p in profiles) < 1e-12  # no normal carries weight
    contacts = [contact_sets(p, "6dls", ModelParameters(M=200), seed=0)[0] for p in profiles]
    w, s = gravity_wrench(mass, [0.0, 0.0, 0.0]), np.array([1e3, 1e3])
    bound = mass * G / mu
    model = minimal_work(contacts, w, mu, s)
    outer = minimal_work(contacts, w, mu, s, representation="outer")
    assert model.representation == "model" and model.feasible
    assert model.f_sum >= 0.95 * bound
    assert outer.f_sum < model.f_sum
