"""workbench.runner.pareto against hand-worked fronts and log-log interpolation."""

import numpy as np
import pytest

from workbench.runner.pareto import at_equal, pareto_front


def test_front_drops_dominated_points_and_sorts_by_runtime():
    t = [4.0, 1.0, 2.0, 3.0, 2.0]
    e = [0.01, 0.5, 0.1, 0.2, 0.1]  # (3, 0.2) is beaten by (2, 0.1); the second (2, 0.1) is a duplicate
    assert pareto_front(t, e).tolist() == [1, 2, 0]


def test_front_of_brute_force_random_points():
    rng = np.random.default_rng(3)
    t, e = rng.uniform(0.1, 10, 60), rng.uniform(1e-4, 1, 60)
    front = set(pareto_front(t, e).tolist())
    brute = {i for i in range(60) if not any((t[j] <= t[i]) and (e[j] <= e[i]) and j != i for j in range(60))}
    assert front == brute


def test_equal_runtime_and_error_interpolate_on_log_axes():
    # error = runtime^-2 on the front: at runtime 2 (between 1 and 4) the error is 1/4 exactly
    t, e = [1.0, 4.0, 16.0], [1.0, 1 / 16, 1 / 256]
    r = at_equal(t, e, runtime_at=2.0)
    assert r["value"] == pytest.approx(0.25, rel=1e-12) and not r["clamped"]
    r = at_equal(t, e, error_at=0.01)  # runtime = 0.01^-1/2 = 10
    assert r["value"] == pytest.approx(10.0, rel=1e-12) and not r["clamped"]
    r = at_equal(t, e, runtime_at=100.0)  # slower than measured: the error is at most the best
    assert r == {"value": pytest.approx(1 / 256), "clamped": True, "beyond": "at most"}
    assert at_equal(t, e, runtime_at=0.5)["beyond"] == "at least"  # faster: at least the worst error
    assert at_equal(t, e, error_at=2.0)["beyond"] == "at most"  # sloppier than measured: at most as slow
    assert at_equal(t, e, error_at=1e-3)["beyond"] == "at least"
    assert at_equal(t, e, runtime_at=4.0)["beyond"] is None


def test_careless_input_is_refused():
    with pytest.raises(ValueError, match="> 0"):
        pareto_front([1.0, 2.0], [0.0, 0.1])
    with pytest.raises(ValueError, match="one length"):
        pareto_front([1.0, 2.0], [0.1])
    with pytest.raises(ValueError, match="exactly one"):
        at_equal([1.0], [0.1])
