"""workbench.timing: the median of repeats after warm-up, on a scripted clock (exact
durations known in advance) and on a real workload (sleep, a lower bound only: no timed
assertion that a busy machine could break)."""

import time

import pytest

from workbench import timing
from workbench.timing import median_runtime


class _Clock:
    """perf_counter replacement: each call of the timed function advances it by the next
    scripted duration; the calls of ``fn`` are counted."""

    def __init__(self, durations):
        self.now, self.durations, self.calls = 100.0, list(durations), 0

    def perf_counter(self):
        return self.now

    def fn(self):
        self.calls += 1
        self.now += self.durations.pop(0)
        return f"result {self.calls}"


@pytest.mark.parametrize(
    "durations, repeats, warmup, median",
    [
        ([9.0, 3.0, 1.0, 2.0], 3, 1, 2.0),  # warm-up 9 s ignored; median of 3, 1, 2
        ([5.0, 4.0, 1.0, 3.0, 2.0], 4, 1, 2.5),  # even count: mean of the middle two (2, 3)
        ([0.5], 1, 0, 0.5),
        ([7.0, 8.0, 0.25, 0.75, 100.0], 3, 2, 0.75),  # an outlier does not move the median
    ],
)
def test_median_of_scripted_durations(monkeypatch, durations, repeats, warmup, median):
    clock = _Clock(durations)
    monkeypatch.setattr(timing.time, "perf_counter", clock.perf_counter)
    got, result = median_runtime(clock.fn, repeats, warmup=warmup)
    assert got == pytest.approx(median, rel=1e-12)
    assert clock.calls == repeats + warmup and not clock.durations  # every call made, no more
    assert result == f"result {repeats + warmup}"  # the last call's result


def test_a_real_workload_takes_at_least_its_sleep():
    """time.sleep(d) sleeps at least d (Python >= 3.5), so every timed call lasts >= d."""
    calls = []

    def work():
        calls.append(1)
        time.sleep(0.005)
        return len(calls)

    median, last = median_runtime(work, 3)
    assert median >= 0.005 and last == 4 == len(calls)


@pytest.mark.parametrize("repeats, warmup", [(0, 1), (-2, 1), (True, 1), (2.0, 1), (3, -1), (3, None)])
def test_bad_counts_are_refused_before_any_call(repeats, warmup):
    calls = []
    with pytest.raises(ValueError, match="repeats must be|warmup must be"):
        median_runtime(lambda: calls.append(1), repeats, warmup)
    assert calls == []
