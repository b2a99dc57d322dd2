"""workbench.grasp.simulated_truth: the force the exact 6DFW sets need, and the simulated outcome.

Reference: two opposed jaws on an elliptic cylinder (axis z) hold a force f along z — a
direction tangent to every element — iff the friction of both jaws reaches it, 2 μ F s >= f
(the pressure centre makes the frictional torque of a pure translation vanish, and the jaws'
torques about the origin cancel by symmetry), so the smallest force scale is f / (2 μ F) with
F = Σ p a of a jaw — more than the scene's 10 N reading, which is the grasp-axis component.

The sensitivity studies' truth (``truth_deciders``) on the same reference — a lift far below /
above 2 μ s Σ p a is resisted / not, at each grasp's own μ and force scale, whatever reading the
profiles were made at — and on the lever scene against ExactContacts / resists_exact called
directly, as the studies wrote it inline.
"""

from __future__ import annotations

import numpy as np
import pytest

from workbench.grasp.exact import ExactContacts, resists_exact
from workbench.grasp.lever_scene import scene_inputs, scene_profiles
from workbench.grasp.simulated_truth import (
    TruthModel,
    required_force_scale,
    simulated_success,
    truth_deciders,
)
from workbench.sources.scenes import elliptic_cylinder_grasp

F0, MU = 10.0, 0.5


@pytest.fixture(scope="module")
def profiles() -> list:
    return elliptic_cylinder_grasp(force=F0, n_elements=60)


@pytest.fixture(scope="module")
def exact(profiles) -> ExactContacts:
    return ExactContacts(profiles, n_start=100, seed=0)


def _sum_pa(profiles) -> float:
    """Σ p a of one jaw [N] (both jaws are mirror images)."""
    return float((profiles[0].pressures * profiles[0].areas).sum())


def _lift(f: float) -> np.ndarray:
    return np.array([0.0, 0.0, -f, 0.0, 0.0, 0.0])


def test_required_force_scale_is_the_friction_limit(exact, profiles):
    f = 6.0
    s_true = f / (2 * MU * _sum_pa(profiles))
    s = required_force_scale(exact, _lift(f), MU, hi=2.0)
    # bisection on log s over [hi/1000, hi] in 12 steps: at most 1000^(2^-12) above the limit;
    # resisted within resist_rtol (1e-5) of the capacity, hence the small slack below
    assert s_true * (1 - 1e-4) <= s <= s_true * 1000 ** (2.0**-12) * (1 + 1e-4)
    assert required_force_scale(exact, _lift(25.0), MU, hi=2.0) == np.inf  # needs 2.5 > hi
    assert required_force_scale(exact, _lift(1e-3), MU, hi=2.0) == 2.0 / 1000  # resisted at hi/1000
    with pytest.raises(ValueError, match="hi must be a finite scale > 0"):
        required_force_scale(exact, _lift(1.0), MU, hi=0.0)


def test_simulated_success_force_and_closing(exact, profiles):
    def gripper(closing_limit: float, sigma_mu: float = 0.0, noise_samples: int = 3) -> TruthModel:
        return TruthModel(1.25, 20.0, closing_limit, noise_samples, sigma_mu, sigma_force=0.0)

    rng = np.random.default_rng(1)
    need = 6.0 * F0 / (2 * MU * _sum_pa(profiles))  # the jaw reading that holds 6 N: 5.41 N
    # applied 1.25 x 5.41 = 6.77 N: a 1000 N/m wall closes 6.8 mm
    ok, f_req = simulated_success(
        exact, _lift(6.0)[None], MU, F0, stiffness=1000.0, model=gripper(10e-3), rng=rng
    )
    assert ok and f_req == pytest.approx(need, rel=2e-3)
    ok, _ = simulated_success(exact, _lift(6.0)[None], MU, F0, stiffness=1000.0, model=gripper(5e-3), rng=rng)
    assert not ok  # crushed: 6.8 mm > 5 mm
    ok, _ = simulated_success(exact, _lift(6.0)[None], MU, F0, stiffness=np.inf, model=gripper(0.0), rng=rng)
    assert ok  # rigid: no closing
    # 25 N needs a 22.6 N reading, more than the gripper's 20 N: fails, and the noise is never drawn
    state = rng.bit_generator.state
    ok, f_req = simulated_success(
        exact, _lift(25.0)[None], MU, F0, stiffness=np.inf, model=gripper(1.0), rng=rng
    )
    assert not ok and f_req == np.inf and rng.bit_generator.state == state
    # 18 N needs a 16.2 N reading; at safety 1.25 the gripper is capped at 20 N (x 1.23), which a
    # 30 % friction noise drops below the need in ~27 % of the draws: most hold
    ok, f_req = simulated_success(
        exact,
        _lift(18.0)[None],
        MU,
        F0,
        stiffness=np.inf,
        model=gripper(1.0, sigma_mu=0.3, noise_samples=200),
        rng=np.random.default_rng(0),
    )
    assert f_req == pytest.approx(18.0 * F0 / (2 * MU * _sum_pa(profiles)), rel=2e-3) and ok
    with pytest.raises(ValueError, match="reading"):
        simulated_success(exact, _lift(1.0)[None], MU, 0.0, stiffness=1.0, model=gripper(1.0), rng=rng)


def test_truth_deciders_hold_a_lift_below_the_friction_limit_of_each_grasp(profiles):
    """Three grasps of the same 10 N profiles, each its own μ and force scale: a lift along the
    cylinder axis is held iff f <= 2 μ s Σ p a; 0.9 and 1.1 of the limit are far from it next to
    the column generation's 1e-5 tolerance."""
    mu, scale = [0.5, 0.3, 0.5], [1.0, 1.0, 2.5]
    deciders = truth_deciders(profiles, mu, scale, n_start=100)
    assert len(deciders) == 3
    for d, m, s in zip(deciders, mu, scale, strict=True):
        limit = 2 * m * s * _sum_pa(profiles)  # 5.54 N, 3.33 N, 13.9 N
        assert d(_lift(0.9 * limit)) is True
        assert d(_lift(1.1 * limit)) is False
        assert d(_lift(1e-3)) is True and d(_lift(1e3)) is False  # far inside / far outside
    # grasp 0 holds what grasp 1 (less friction) drops
    between = 0.5 * (2 * 0.5 + 2 * 0.3) * _sum_pa(profiles)
    assert deciders[0](_lift(between)) and not deciders[1](_lift(between))


def test_truth_at_the_true_force_does_not_depend_on_the_profiles_reading():
    """Profiles at a unit reading scaled by the true force, or at the sensor's reading scaled by
    true / read (the bottles' form): the same limit, so the same verdicts either side of it."""
    f_read, f_true, mu = 20.0, 23.0, 0.3
    unit = elliptic_cylinder_grasp(force=1.0, n_elements=60)
    read = elliptic_cylinder_grasp(force=f_read, n_elements=60)
    limit = 2 * mu * f_true * _sum_pa(unit)
    assert limit == pytest.approx(2 * mu * (f_true / f_read) * _sum_pa(read), rel=1e-12)
    for k in (0.95, 1.05):
        (a,) = truth_deciders(unit, [mu], [f_true], n_start=100)
        (b,) = truth_deciders(read, [mu], [f_true / f_read], n_start=100)
        assert a(_lift(k * limit)) == b(_lift(k * limit)) == (k < 1)


def test_truth_deciders_are_the_inline_exact_truth_on_the_lever_scene():
    """The studies' old inline truth, written here from the library's primitives: ExactContacts
    of the true profiles (starting columns seeded 1), resists_exact at each grasp's noisy μ and
    force — the same verdict per grasp, at the disturbance and at the scales a margin bisects."""
    config = {
        "seed": 2, "n_disturbances": 8, "weight_range": [2.0, 14.0], "lever_x": 0.04, "lever_z": 0.025,
        "force_range": [20.0, 35.0], "mu": 0.3, "noise_mu": 0.05, "noise_force": 0.03,
        "a": 0.03, "b": 0.02, "half_angle": 0.6, "n_elements": 60,
    }  # fmt: skip
    W, forces, mu_true, f_true = scene_inputs(config)
    true_prof = scene_profiles(config, 2.4, 0.03)
    exact = ExactContacts(true_prof, n_start=50, seed=1)
    deciders = truth_deciders(true_prof, mu_true, f_true, n_start=50)
    got, want = [], []
    for d, w, m, f in zip(deciders, W, mu_true, f_true, strict=True):
        for s in (0.25, 0.5, 1.0, 2.0, 4.0):
            got.append(d(s * w))
            want.append(resists_exact(exact, s * w, m, forces=exact.F * f)[0])
    assert got == want
    assert 0 < sum(got) < len(got)  # both verdicts occur: the comparison is not vacuous
    # the nominal truth (sensor force, nominal μ) likewise
    nominal = truth_deciders(true_prof, [0.3] * len(W), forces, n_start=50)
    assert [d(w) for d, w in zip(nominal, W, strict=True)] == [
        resists_exact(exact, w, 0.3, forces=exact.F * f)[0] for w, f in zip(W, forces, strict=True)
    ]


def test_truth_deciders_refuse_a_mu_per_grasp_without_its_force(profiles):
    with pytest.raises(ValueError, match="one value per grasp"):
        truth_deciders(profiles, [0.3, 0.3], [1.0], n_start=50)
