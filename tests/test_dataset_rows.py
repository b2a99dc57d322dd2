"""workbench.grasp.dataset_rows: one candidate scored by several models, against Coulomb's
bound on the total friction force, the nominal verdict (zero perturbation), the flat-face
geometry, an arc's analytic RMS sagitta and hand arithmetic."""

import math

import numpy as np
import pytest
import trimesh

from workbench.grasp.dataset_rows import (
    DatasetOptions,
    contact_summary,
    dataset_cost,
    model_columns,
    nonplanarity,
    quality_agreement,
    quality_summary,
    score_candidate,
)
from workbench.grasp.gripper_eval import gripper_contact
from workbench.grasp.inputs import Task
from workbench.grasp.robust import Perturbation
from workbench.grasp.top_grasps import top_grasp_pose
from workbench.sources.gripper import PadShape, parallel_jaw

MU, FORCE = 0.3, 20.0
GRIPPER = parallel_jaw(PadShape.rectangle(0.02, 0.04, thickness=0.005), FORCE, opening=0.1, mu=MU)
MODELS = ("soft_point", "planar", "6dls", "6dfc")


def _box():
    """80 x 50 x 20 mm, resting on z = 0."""
    box = trimesh.creation.box([0.08, 0.05, 0.02])
    box.apply_translation([0.0, 0.0, 0.01])
    return box


def _pose(height=0.008, x=0.0):
    """Across the box's 50 mm at ``height``, the pads' bottoms on the axis."""
    return top_grasp_pose([x, -0.025, height], [x, 0.025, height], GRIPPER)


def test_nonplanarity_of_an_arc_is_its_rms_sagitta_and_zero_on_a_plane():
    R, alpha, n = 0.03, 0.4, 4001
    theta = (np.arange(n) + 0.5) / n * 2 * alpha - alpha  # midpoints: equal arc lengths
    x = np.linspace(-0.01, 0.01, 7)
    t, xx = np.meshgrid(theta, x)
    pts = np.column_stack([xx.ravel(), R * np.sin(t.ravel()), R * np.cos(t.ravel())])
    # uniform theta on [-a, a]: E[cos] = sin a / a, E[cos^2] = 1/2 + sin 2a / (4a)
    expected = R * math.sqrt(0.5 + math.sin(2 * alpha) / (4 * alpha) - (math.sin(alpha) / alpha) ** 2)
    assert nonplanarity(pts, np.ones(len(pts))) == pytest.approx(expected, rel=1e-6)
    flat = np.column_stack([np.random.default_rng(0).random((50, 2)), np.full(50, 0.3)])
    assert nonplanarity(flat, np.random.default_rng(1).random(50) + 0.1) < 1e-12
    with pytest.raises(ValueError, match=r"centers must be \(n, 3\)"):
        nonplanarity(np.zeros((4, 2)), np.ones(4))
    with pytest.raises(ValueError, match="areas finite and > 0"):
        nonplanarity(np.zeros((4, 3)), np.array([1.0, 0.0, 1.0, 1.0]))


def test_a_flat_face_contact_carries_the_jaw_force_with_no_nonplanarity():
    c = contact_summary(gripper_contact(_box(), GRIPPER, _pose()))
    for j in (1, 2):
        assert c[f"jaw{j}_F_N"] == pytest.approx(FORCE, rel=1e-9)
        assert c[f"jaw{j}_nonplanarity_mm"] < 1e-9
        # the pad covers the face from the axis (8 mm) to the box's top (20 mm) across its 20 mm:
        # 240 mm², within a 1 mm band of elements along the patch's 64 mm perimeter
        assert abs(c[f"jaw{j}_area_mm2"] - 240.0) < 64.0
    assert c["settle_tilt_deg"] < 1.0 and c["settle_converged"]
    # a flat pad on a flat face at 20 N: compressed F / (k A), A the 240 mm² in contact
    k = GRIPPER.pad.stiffness
    for j in (1, 2):
        expected = FORCE / (k * c[f"jaw{j}_area_mm2"] * 1e-6) * 1e3
        assert c[f"jaw{j}_compression_mm"] == pytest.approx(expected, rel=1e-6)
    # pressed where the gripper stands, nothing was searched: no convergence to report
    pressed = gripper_contact(_box(), GRIPPER, _pose(), settle=False)
    assert contact_summary(pressed)["settle_converged"] is None


def test_a_weight_beyond_twice_mu_f_fails_every_model_and_a_feather_holds_in_every_sample():
    box, pose = _box(), _pose()
    opts = DatasetOptions(mu=MU, robust=Perturbation(n_samples=8))
    # Coulomb: the two pads' friction is at most mu (1 + 3 sigma_mu) 2 F = 15.6 N < m g = 29.4 N
    heavy = score_candidate(box, GRIPPER, pose, Task(mass=3.0, com=(0, 0, 0.01)), MODELS, opts)
    feather = score_candidate(box, GRIPPER, pose, Task(mass=0.01, com=(0, 0, 0.01)), MODELS, opts)
    for m in MODELS:
        assert heavy[f"q_{m}"] == 0.0 and not heavy[f"held_{m}"] and heavy[f"margin_{m}"] == 0.0
        # 0.1 N against 12 N of friction: held in every perturbed sample, the force needed < 2 %
        assert feather[f"q_{m}"] == 1.0 and feather[f"held_{m}"] and feather[f"margin_{m}"] > 0.98
        assert set(model_columns(m)) <= set(feather)
    assert heavy["status"] == feather["status"] == "scored"


def test_without_perturbation_q_is_the_nominal_verdict_and_q_lies_on_the_sample_grid():
    """One meaning of "held": with every sigma 0 each of the N_r samples is the nominal grasp, so
    q is 1 or 0 as the verdict — also where the models disagree (the weight's torque about the
    grasp axis near the pads' torsional friction, 25 mm from the axis)."""
    box = _box()
    still = Perturbation(n_samples=3, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)
    verdicts = set()
    for mass, x in ((0.3, 0.02), (0.3, 0.025), (0.4, 0.025)):
        task = Task(mass=mass, com=(x, 0.0, 0.01))
        row = score_candidate(box, GRIPPER, _pose(), task, MODELS, DatasetOptions(robust=still))
        for m in MODELS:
            assert row[f"q_{m}"] == float(row[f"held_{m}"]), (mass, x, m)
        verdicts.add(tuple(row[f"held_{m}"] for m in MODELS))
    assert len(verdicts) == 3  # all held, the models split, none held
    task = Task(mass=0.3, com=(0.02, 0.0, 0.01))
    noisy = score_candidate(
        box, GRIPPER, _pose(), task, MODELS, DatasetOptions(robust=Perturbation(n_samples=7))
    )
    for m in MODELS:
        assert noisy[f"q_{m}"] * 7 == pytest.approx(round(noisy[f"q_{m}"] * 7), abs=1e-12)


def test_a_gripper_that_misses_scores_zero_and_careless_input_is_refused():
    miss = top_grasp_pose([0.5, -0.025, 0.008], [0.5, 0.025, 0.008], GRIPPER)
    row = score_candidate(_box(), GRIPPER, miss, Task(mass=0.1, com=(0, 0, 0.01)), ("6dfc",))
    assert row["status"] == "miss" and row["q_6dfc"] == 0.0 and not row["held_6dfc"]
    assert row["jaw1_n_elements"] == 0 and math.isnan(row["jaw1_F_N"])
    task = Task(mass=0.1, com=(0, 0, 0.01))
    with pytest.raises(ValueError, match="task must be gravity"):
        score_candidate(_box(), GRIPPER, _pose(), Task(w_ext=(0, 0, -1, 0, 0, 0)), MODELS)
    with pytest.raises(ValueError, match="at least one contact model"):
        score_candidate(_box(), GRIPPER, _pose(), task, ())
    with pytest.raises(ValueError, match="6dsl"):
        score_candidate(_box(), GRIPPER, _pose(), task, ("6dsl",))
    with pytest.raises(ValueError, match="options must be"):
        score_candidate(_box(), GRIPPER, _pose(), task, MODELS, {"mu": 0.3})
    with pytest.raises(ValueError, match="mu"):
        DatasetOptions(mu=30)


def test_dataset_cost_is_the_arithmetic():
    c = dataset_cost(400.0, 500_000, workers=(1, 2, 32), utilisation=0.93)
    assert c["core_hours"] == pytest.approx(400 * 500_000 / 3.6e6)  # 55.6 core-h
    assert c["hours_on"][2] == pytest.approx(400 * 500_000 / 3.6e6 / (2 * 0.93))
    assert c["hours_on"][32] == pytest.approx(c["hours_on"][1] / 32)
    with pytest.raises(ValueError, match="ms_per_grasp"):
        dataset_cost(0.0, 10)
    with pytest.raises(ValueError, match="n_grasps"):
        dataset_cost(1.0, 2.5)


def test_quality_summary_and_agreement_by_hand():
    s = quality_summary([0.1, 0.9, 0.5, 0.9, 0.0], [10, 11, 12, 13, 14])
    assert s == {"max_q": 0.9, "median_q": 0.5, "frac_q_ge_half": 0.6, "best_candidate": 11}
    # ranks 1..4 against 1, 2, 4, 3: rho = 1 - 6 * (0 + 0 + 1 + 1) / (4 * 15) = 0.8
    rho, dq = quality_agreement([0.1, 0.2, 0.3, 0.4], [0.1, 0.2, 0.5, 0.4])
    assert rho == pytest.approx(0.8) and dq == pytest.approx(0.0)
    assert quality_agreement([0.0, 0.0, 0.0], [0.1, 0.5, 0.2]) == (None, pytest.approx(0.2))
    with pytest.raises(ValueError, match=r"qualities in \[0, 1\]"):
        quality_summary([0.2, 1.5], [0, 1])
    with pytest.raises(ValueError, match="same n >= 2"):
        quality_agreement([0.1, 0.2], [0.1, 0.2, 0.3])


def test_a_pad_pressed_deeper_than_its_layer_is_marked_bottomed_out():
    # the rule against the contact's own depths: a layer thinner than the deepest press bottoms out
    from workbench.grasp.dataset_rows import _bottomed_out

    c = gripper_contact(_box(), GRIPPER, _pose())
    deepest = max(c.depths)
    assert not _bottomed_out(c, GRIPPER.pad.thickness) and deepest < GRIPPER.pad.thickness
    assert _bottomed_out(c, 0.5 * deepest) and not _bottomed_out(c, 2 * deepest)
    row = score_candidate(_box(), GRIPPER, _pose(), Task(mass=0.01, com=(0, 0, 0.01)), ("soft_point",))
    assert row["bottomed_out"] is False and "layer" not in row["reason"]
