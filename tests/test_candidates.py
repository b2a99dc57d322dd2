"""Candidate grasps read back by another judge (workbench.grasp.candidates): a cost cell of a
CSV, minimal-work's grasps.csv read into rows, and the nested seeded sample per object."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from workbench.grasp.candidates import cost_from_csv, read_candidates_csv, sample_candidates
from workbench.grasp.work_table import TASKS


@pytest.mark.parametrize(
    "text, expected",
    [("", math.inf), ("None", math.inf), ("nan", math.inf), ("inf", math.inf), ("1.5", 1.5), ("0", 0.0)],
)
def test_a_cost_cell_reads_unresisted_as_inf(text, expected):
    assert cost_from_csv(text) == expected


def _candidates(counts: dict[str, int]) -> list[dict]:
    """Rows of objects interleaved (a, b, a, b, ...), each numbered in its object's order."""
    rows, seen = [], dict.fromkeys(counts, 0)
    while any(seen[n] < k for n, k in counts.items()):
        for n, k in counts.items():
            if seen[n] < k:
                rows.append({"object": n, "grasp": seen[n]})
                seen[n] += 1
    return rows


def test_a_smaller_sample_is_part_of_a_larger_one_in_candidate_order():
    grasps = _candidates({"cup": 12, "bottle": 7, "box": 2})
    objects = ["bottle", "cup", "box"]
    for seed in range(5):
        small = sample_candidates(grasps, objects, 3, seed)
        large = sample_candidates(grasps, objects, 5, seed)
        for name, want_small, want_large in (("bottle", 3, 5), ("cup", 3, 5), ("box", 2, 2)):
            s = [g["grasp"] for g in small if g["object"] == name]
            lg = [g["grasp"] for g in large if g["object"] == name]
            assert len(s) == want_small and len(lg) == want_large  # all of the box's 2
            assert set(s) <= set(lg)
            assert s == sorted(s) and lg == sorted(lg)  # each object's in candidate order
            assert len(set(lg)) == len(lg)  # without replacement
        # object by object, in the order asked for
        assert [g["object"] for g in large] == ["bottle"] * 5 + ["cup"] * 5 + ["box"] * 2
        assert all(g in grasps for g in large)


def test_the_sample_is_uniform_and_its_stream_is_keyed_by_seed_and_count():
    grasps = _candidates({"cup": 6})
    counts = np.zeros(6)
    n_seeds = 3000
    for seed in range(n_seeds):
        counts[[g["grasp"] for g in sample_candidates(grasps, ["cup"], 2, seed)]] += 1
    # each candidate drawn with probability n / k = 1/3; binomial sd sqrt(3000 / 3 * 2/3) = 26
    np.testing.assert_allclose(counts / n_seeds, 1 / 3, atol=5 * 26 / n_seeds)
    # the stream the committed runs drew from: the first n of one permutation of k, sorted
    pick = np.sort(np.random.default_rng([4, 6]).permutation(6)[:2])
    assert [g["grasp"] for g in sample_candidates(grasps, ["cup"], 2, 4)] == pick.tolist()
    assert sample_candidates(grasps, ["cup", "absent"], 2, 4) == sample_candidates(grasps, ["cup"], 2, 4)


@pytest.mark.parametrize(
    "n, seed, match",
    [(0, 0, "n_per_object must be an integer >= 1"), (2.0, 0, "n_per_object"), (True, 0, "n_per_object"),
     (2, np.random.default_rng(0), "seed must be an integer")],
)  # fmt: skip
def test_sample_candidates_refuses_a_bad_count_or_seed(n, seed, match):
    with pytest.raises(ValueError, match=match):
        sample_candidates(_candidates({"cup": 3}), ["cup"], n, seed)


def test_read_candidates_csv_reads_minimal_works_columns(tmp_path):
    head = ["object", "grasp", "z"] + [f"{v}_{c}" for v in ("p1", "p2", "axis") for c in "xyz"]
    head += [f"{t}_{m}" for t in TASKS for m in ("truth", "q_robust", "f_sum", "W", "f_required")]
    rows = [
        ["cup", 3, 0.05, 0.01, 0.0, 0.05, -0.01, 0.0, 0.05, 1.0, 0.0, 0.0]
        + [True, 0.75, 4.5, 0.002, 3.0, False, 0.25, "", "nan", 9.0],
        ["box", 0, 0.02, 0.0, 0.02, 0.02, 0.0, -0.02, 0.02, 0.0, -1.0, 0.0]
        + [False, 0.0, "None", "inf", 1.0, False, 0.0, 7.0, 0.5, 2.0],
    ]
    path = tmp_path / "grasps.csv"
    with path.open("w", newline="") as f:
        csv.writer(f).writerows([head, *rows])
    got = read_candidates_csv(path)
    assert [(g["object"], g["grasp"]) for g in got] == [("cup", 3), ("box", 0)]
    assert got[0]["p1"] == [0.01, 0.0, 0.05] and got[0]["p2"] == [-0.01, 0.0, 0.05]
    assert got[1]["axis"] == [0.0, -1.0, 0.0]
    lift, turn = TASKS
    assert got[0][lift] == {"truth": True, "q_robust": 0.75, "f_sum": 4.5, "W": 0.002}
    assert got[0][turn] == {"truth": False, "q_robust": 0.25, "f_sum": math.inf, "W": math.inf}
    assert got[1][lift] == {"truth": False, "q_robust": 0.0, "f_sum": math.inf, "W": math.inf}
    assert got[1][turn] == {"truth": False, "q_robust": 0.0, "f_sum": 7.0, "W": 0.5}
