"""The sensitivity study's tables and headline (workbench.grasp.sensitivity_summary): series read
by checkpoint key in the config's order, the robust rows in (n_r, sigma_r) order whatever order
they finished in, a limit surface whose margins are the exact ones has no capacity error, and an
undefined number reads n/a instead of crashing the summary."""

import numpy as np

from workbench.grasp.sensitivity_summary import format_or_na, headline, series_tables, training_distribution


def test_series_tables_read_each_series_by_key_and_sort_the_robust_rows():
    config = {"models": ["6dls"], "k_values": [2.0, 8.0], "mu_offsets": [0.1], "length_offsets": [-0.3]}
    by_key = {
        "k/2.0/6dls": {"precision": 0.9, "recall": 0.5},
        "k/8.0/6dls": {"precision": 0.8, "recall": 0.7},
        "mu_offset/0.1/6dls": {"precision": 0.7, "recall": 0.9},
        "length_offset/-0.3/6dls": {"precision": 1.0, "recall": 0.2},
    }
    robust = [
        {
            "series": "robust",
            "n_r": n,
            "sigma_r": s,
            "precision": p,
            "recall": 0.5,
            "ms_per_grasp": 1.0,
            "x": 0,
        }
        for n, s, p in [(10, 0.002, 0.1), (5, 0.004, 0.2), (5, 0.001, 0.3)]
    ]
    out = series_tables(by_key, [{"series": "k"}, *robust], config)
    assert out["k"] == {"x": [2.0, 8.0], "6dls": {"precision": [0.9, 0.8], "recall": [0.5, 0.7]}}
    assert out["mu_offset"]["6dls"] == {"precision": [0.7], "recall": [0.9]}
    assert out["length_offset"]["6dls"] == {"precision": [1.0], "recall": [0.2]}
    assert [(r["n_r"], r["sigma_r"], r["precision"]) for r in out["robust"]] == [
        (5, 0.001, 0.3),
        (5, 0.004, 0.2),
        (10, 0.002, 0.1),
    ]
    assert set(out["robust"][0]) == {"n_r", "sigma_r", "precision", "recall", "ms_per_grasp"}


def test_margins_equal_to_the_exact_ones_have_no_capacity_error():
    config = {"training_models": ["6dls"], "training_samplers": ["thesis", "mix"], "precision_levels": [0.9]}
    nominal = np.array([0.5, 1.5, 2.0, 0.8])
    truth = nominal >= 1
    by_key = {
        "margin/6dls@thesis": {"margins": list(nominal)},
        "margin/6dls@mix": {"margins": list(2 * nominal)},
    }
    out = training_distribution(by_key, config, truth, nominal, nominal)
    exact = out["6dls"]["thesis"]
    assert exact["vs_exact_nominal"]["median_abs_log_ratio"] == 0.0
    assert exact["vs_noisy_truth"]["median_log_ratio"] == 0.0
    assert exact["recall_at_precision"] == {"0.9": 1.0}  # the truth's own margins separate it
    # twice the margins: optimistic by log 2 on every grasp
    double = out["6dls"]["mix"]["vs_exact_nominal"]
    assert np.isclose(double["median_log_ratio"], np.log(2)) and np.isclose(
        double["median_abs_log_ratio"], np.log(2)
    )


def test_format_or_na():
    assert format_or_na(0.256, ".2f") == "0.26" and format_or_na(0.5, ".0%") == "50%"
    assert format_or_na(None, ".2f") == "n/a" and format_or_na(float("nan"), ".2f") == "n/a"
    assert format_or_na(np.float64("nan"), ".2f") == "n/a" and format_or_na(3, "d") == "3"


def test_sensitivity_headline_reads_undefined_numbers_as_n_a():
    """A sweep point whose truth resisted nothing crashed in the headline (round(None)) after
    the whole run, writing no summary: a recall without positives is None once checkpointed."""
    nan = float("nan")
    config = {"models": ["6dls"], "precision_levels": [0.9]}
    lines = headline(
        np.zeros(4, bool),
        {"k": {"6dls": {"recall": [None, nan]}}},
        {"6dls": nan},
        {"6dls": {"at_levels": {"recall": [nan]}}},
        {"0.9": True},
        {"6dls": {"median_abs_log_ratio": nan, "median_log_ratio": nan}},
        {"6dls": {"thesis": {"vs_exact_nominal": {"median_abs_log_ratio": nan, "median_log_ratio": None}}}},
        config,
    )
    assert lines[0] == "truth: 0% of 4 disturbances resisted (simulated truth, exact 6DFW set)"
    assert lines[1] == "6dls: recall vs k [n/a, n/a], n/a ms/grasp"
    assert "6dls n/a" in lines[2] and "6dls n/a (n/a)" in lines[4] and "thesis n/a (n/a)" in lines[5]
