"""workbench.grasp.robust: q_robust is seeded and bounded; its rotations are Rodrigues'."""

import warnings

import numpy as np
import pytest
from grasp_helpers import MU, F, antipodal

from workbench.grasp import Perturbation, Task, q_robust


def test_q_robust_deterministic_and_bounded():
    grasp = antipodal(soft=0.004, n=16)
    none = Perturbation(n_samples=5, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)
    assert q_robust(grasp, MU, Task(mass=0.9 * 2 * MU * F / 9.81, com=[0, 0, 0]), none) == 1.0
    assert q_robust(grasp, MU, Task(mass=1.1 * 2 * MU * F / 9.81, com=[0, 0, 0]), none) == 0.0
    p = Perturbation(n_samples=40)
    m = 1.0 * 2 * MU * F / 9.81  # at the limit: perturbations split the outcomes
    q1 = q_robust(grasp, MU, Task(mass=m, com=[0, 0, 0.005]), p, seed=7)
    assert q1 == q_robust(grasp, MU, Task(mass=m, com=[0, 0, 0.005]), p, seed=7)
    assert 0.0 < q1 < 1.0
    assert q_robust(grasp, MU, Task(mass=0.5 * m, com=[0, 0, 0.005]), p, seed=7) >= q1


def test_q_robust_rotations_are_rodrigues_of_the_sampled_vectors():
    # q_robust perturbs the contacts by scipy's Rotation.from_rotvec; Rodrigues' formula
    # written out (tests/naive.py, what it used before) gives the same matrices to round-off
    from naive import rodrigues
    from scipy.spatial.transform import Rotation

    v = np.vstack([np.zeros(3), np.random.default_rng(3).normal(0.0, 0.2, (200, 3)), [[0, 0, np.pi - 1e-9]]])
    R = Rotation.from_rotvec(v).as_matrix()
    assert np.abs(R - rodrigues(v)).max() < 5e-15 and np.array_equal(R[0], np.eye(3))


def test_q_robust_judges_the_task_once_not_each_sample():
    """Found by a new-user trial: an unusual mass warned once per sample (~100 warnings), and
    a perturbed mass drawn past the hard limit would have raised mid-run for a valid task."""
    from workbench.config import TOL
    from workbench.plausible import ImplausibleWarning

    grasp = antipodal(soft=0.004, n=16)
    p = Perturbation(n_samples=30, sigma_mass=0.2)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        task = Task(mass=0.0008, com=[0, 0, 0.005])  # below the usual 1 g: the Task warns
        assert q_robust(grasp, MU, task, p, seed=1) == 1.0  # 8 mN against 2 x 0.5 x 10 N of friction
    assert [w.category for w in got] == [ImplausibleWarning]
    # a task at the mass limit: a fifth of the samples lie above it, none is refused
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleWarning)
        heavy = Task(mass=0.999 * TOL.max_plausible_mass_kg, com=[0, 0, 0])
        assert q_robust(grasp, MU, heavy, p, seed=1) == 0.0
    with pytest.raises(ValueError, match="mass"):  # the user's own mass past the limit still is
        q_robust(grasp, MU, Task(mass=2 * TOL.max_plausible_mass_kg, com=[0, 0, 0]), p, seed=1)


def test_q_robust_takes_a_friction_drawn_past_the_plausible_range():
    """Found by a new-user trial: μ = 1.2 with σ_μ = 0.3 (both ordinary) raised 'mu must be a
    friction coefficient in [0, 2]; got 2.02' from a perturbed sample; μ = 0.02 warned once per
    sample.  The samples are the noise's, judged once as the user's μ."""
    from workbench.plausible import ImplausibleWarning

    grasp = antipodal(soft=0.004, n=16)
    wide = Perturbation(n_samples=60, sigma_mu=0.3, sigma_trans=0, sigma_rot=0, sigma_mass=0, sigma_com=0)
    # 2 x μ x 10 N of friction against 0.5 kg holds unless a draw drops μ below 0.245, i.e.
    # 1 + N(0, 0.3) below 0.204 (z < -2.65, p = 0.004): more than 3 of 60 has p < 1e-4
    assert 0.95 <= q_robust(grasp, 1.2, Task(mass=0.5, com=[0, 0, 0]), wide, seed=0) <= 1.0
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        q_robust(grasp, 0.02, Task(mass=0.005, com=[0, 0, 0]), wide, seed=0)
    assert [w.category for w in got] == [ImplausibleWarning] and "mu = 0.02" in str(got[0].message)


def test_a_centre_of_mass_without_a_mesh_is_judged_by_its_lever():
    """Found by a new-user trial: Task(com=(0, 0, 30)) was refused only when used with a mesh, and
    q_robust ran a 1.5 m lever without a word.  With no mesh the com's distance from the object
    origin is the weight's lever, judged as a task wrench's lever is."""
    with pytest.raises(ValueError, match=r"in millimetres\? pass \[0.0, 0.0, 0.03\]"):
        Task(mass=0.3, com=(0, 0, 30))
    with pytest.raises(
        ValueError, match=r"com's distance from the object origin \[m\] must be .* in \(0, 1\] m"
    ):
        Task(mass=0.3, com=(0, 1.5, 0))
    assert Task(mass=0.3, com=(0, 0, 0.05)).com == (0.0, 0.0, 0.05)


def test_q_robust_logs_the_samples_solver_fallbacks_once(monkeypatch, caplog):
    """Found by a second new-user trial: a QP fallback (the residual LP deciding) was logged once
    per sample, 10 lines in one call.  The call logs one line with the count."""
    import dataclasses
    import logging

    from workbench.grasp import robust
    from workbench.grasp.resistance import api

    real = robust._resists

    def noisy(*args):  # every sample falls back, as resists records and logs a fallback
        text = "QP solver 'x' left a residual; the LP decides"
        api.log.warning("grasp resistance: %s", text)
        return dataclasses.replace(real(*args), fallbacks=(text,))

    monkeypatch.setattr(robust, "_resists", noisy)
    p = Perturbation(n_samples=7, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)
    with caplog.at_level(logging.WARNING):
        assert q_robust(antipodal(soft=0.004, n=16), MU, Task(mass=0.1, com=[0, 0, 0]), p) == 1.0
    lines = [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]
    assert lines == [
        "q_robust: 7 solver fallbacks in 7 samples, e.g. QP solver 'x' left a residual; the LP decides"
    ]


def test_q_robust_does_not_depend_on_where_the_object_sits_in_its_file():
    # the same grasp and load, the object's frame moved 0.3 m (a mesh whose origin is at its
    # base, or a scene's corner): the pose noise turns the gripper about the grasp, so every
    # sample is the same grasp and q is the same; turned about the file's origin a 0.05 rad
    # draw would shift the contacts 15 mm
    grasp = antipodal(soft=0.004, n=16)
    p = Perturbation(n_samples=40)
    m = 1.0 * 2 * MU * F / 9.81
    offset = np.array([0.05, -0.1, -0.3])
    moved = [c.moved(np.eye(3), offset) for c in grasp]
    q = q_robust(grasp, MU, Task(mass=m, com=[0, 0, 0.005]), p, seed=7)
    q_far = q_robust(moved, MU, Task(mass=m, com=offset + [0, 0, 0.005]), p, seed=7)
    assert 0.0 < q < 1.0 and q == q_far


def test_the_grasp_centre_is_the_force_weighted_mean_of_the_contacts():
    from workbench.grasp.robust import grasp_centre

    grasp = antipodal(soft=0.004, n=16)
    by_hand = sum(c.force * c.t for c in grasp) / sum(c.force for c in grasp)
    np.testing.assert_allclose(grasp_centre(grasp), by_hand, atol=1e-15)
    unloaded = [c.with_force(0.0) for c in grasp]
    np.testing.assert_allclose(grasp_centre(unloaded), np.mean([c.t for c in grasp], axis=0))
