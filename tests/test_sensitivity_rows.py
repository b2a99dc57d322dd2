"""The sensitivity study's rows (workbench.grasp.sensitivity_rows): task keys are the checkpoint's
contract, the zero offsets share the k row's inputs, a margin row bisects each decider's own
threshold, predictions are scored against the truth, and a row needs only its task and config.
(The experiment's resumption and twin copies: tests/test_experiments.py; rows in any order and
on two worker processes: tests/test_parallel.py.)"""

import numpy as np
import pytest

from workbench.grasp.sensitivity_rows import (
    as_twin,
    margin_row,
    row_inputs,
    row_key,
    row_tasks,
    scored,
    sensitivity_row,
    setting_parameters,
)

CONFIG = {
    "seed": 0,
    "mu": 0.3,
    "k_true": 2.4,
    "a": 0.03,
    "b": 0.02,
    "half_angle": 0.6,
    "length": 0.03,
    "n_elements": 60,
    "n_disturbances": 5,
    "force_range": [20.0, 35.0],
    "noise_mu": 0.05,
    "noise_force": 0.03,
    "truth_start_wrenches": 50,
    "weight_range": [2.0, 14.0],
    "lever_x": 0.04,
    "lever_z": 0.025,
    "models": ["point", "6dls"],
    "M": 50,
    "k_values": [2.0, 2.4],
    "mu_offsets": [0.0, 0.2],
    "length_offsets": [-0.3],
    "robust_n_r": [5],
    "robust_sigma_r": [0.001, 0.002],
    "robust_disturbances": 3,
    "margin_steps": 6,
    "training_samplers": ["thesis", "mix"],
    "training_models": ["6dls"],
}


def test_every_task_has_the_checkpoint_key_the_summary_reads():
    tasks = row_tasks(CONFIG)
    keys = [row_key(t) for t in tasks]
    assert keys == [
        "margin/point",
        "margin/6dls",
        "margin/6dls@thesis",
        "margin/6dls@mix",
        "margin/truth",
        "margin/truth-nominal",
        "k/2.0/point",
        "k/2.0/6dls",
        "k/2.4/point",
        "k/2.4/6dls",
        "mu_offset/0.0/point",
        "mu_offset/0.0/6dls",
        "mu_offset/0.2/point",
        "mu_offset/0.2/6dls",
        "length_offset/-0.3/point",
        "length_offset/-0.3/6dls",
        "robust/5/0.001",
        "robust/5/0.002",
    ]


def test_a_setting_assumes_its_series_parameter_and_the_true_others():
    assert setting_parameters(("setting", "k", 8.0, "6dls"), CONFIG) == (8.0, 0.03, 0.3)
    k, length, mu = setting_parameters(("setting", "mu_offset", 0.2, "6dls"), CONFIG)
    assert (k, length) == (2.4, 0.03) and mu == pytest.approx(0.36, rel=1e-15)
    k, length, mu = setting_parameters(("setting", "length_offset", -0.3, "6dls"), CONFIG)
    assert (k, mu) == (2.4, 0.3) and length == pytest.approx(0.021, rel=1e-15)


def test_rows_with_the_same_inputs_are_twins():
    k_row = row_inputs(("setting", "k", 2.4, "6dls"), CONFIG)
    assert row_inputs(("setting", "mu_offset", 0.0, "6dls"), CONFIG) == k_row
    assert row_inputs(("setting", "length_offset", 0.0, "6dls"), CONFIG) == k_row
    assert row_inputs(("setting", "mu_offset", 0.2, "6dls"), CONFIG) != k_row
    assert row_inputs(("setting", "k", 2.4, "point"), CONFIG) != k_row
    # the default training sampler ("mix") is the plain margin's
    assert row_inputs(("margin", "6dls", None), CONFIG) == row_inputs(("margin", "6dls", "mix"), CONFIG)
    assert row_inputs(("margin", "6dls", None), CONFIG) != row_inputs(("margin", "6dls", "thesis"), CONFIG)
    # a twin is the first row relabelled: its own series and x, its source named, no key
    first = {"key": "k/2.4/6dls", "config_hash": "h", "series": "k", "x": 2.4, "recall": 0.5}
    twin = as_twin(first, ("setting", "mu_offset", 0.0, "6dls"), "k/2.4/6dls")
    assert twin == {"series": "mu_offset", "x": 0.0, "recall": 0.5, "same_inputs_as": "k/2.4/6dls"}
    assert as_twin({"margins": [1.0]}, ("margin", "6dls", "mix"), "margin/6dls") == {
        "margins": [1.0],
        "same_inputs_as": "margin/6dls",
    }


def test_a_margin_row_bisects_each_deciders_threshold():
    # decider i resists v iff |v| <= c_i: the margin of w is c_i / |w| to the bisection's resolution
    c = np.array([2.0, 5.0, 0.5])
    W = np.array([[1.0, 0, 0, 0, 0, 0], [0, 2.0, 0, 0, 0, 0], [0, 0, 0, 0.25, 0, 0]])
    deciders = [lambda v, c=ci: np.linalg.norm(v) <= c for ci in c]
    row = margin_row("toy", deciders, W, 12)
    assert row["series"] == "margin" and row["model"] == "toy" and row["s_per_grasp"] >= 0
    # 12 steps on log2 s in [-6, 6]: resolution 12 / 2^12 in log2
    np.testing.assert_allclose(
        np.log2(row["margins"]), np.log2(c / np.linalg.norm(W, axis=1)), atol=12 / 2**12
    )


def test_scored_predictions_replace_pred_by_their_scores():
    truth = np.array([True, True, False, False, True])
    row = scored({"series": "k", "pred": [True, False, True, False]}, truth)  # the first 4 grasps
    assert "pred" not in row and row["series"] == "k"
    assert row["precision"] == 0.5 and row["recall"] == 0.5 and row["positives"] == 2
    assert row["accuracy"] == 0.5
    margins = {"series": "margin", "margins": [1.0]}
    assert scored(margins, truth) is margins


def test_a_point_contact_setting_resists_no_lever_disturbance():
    # the lever draw always twists about the grasp axis; two hard points resist no such torsion
    row = sensitivity_row(("setting", "mu_offset", 0.2, "point"), CONFIG)
    assert row["series"] == "mu_offset" and row["x"] == 0.2 and row["model"] == "point"
    assert row["pred"] == [False] * CONFIG["n_disturbances"]
