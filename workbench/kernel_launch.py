"""How a parallel kernel is called: on Numba's threads when the call has work enough for them,
else on the calling thread alone.

Starting a parallel region is cheap on idle threads, but when other processes hold the other
cores the region waits until its threads are scheduled (and they spin afterwards, burning the
CPU time those processes need), so a small call costs many times more on threads than alone
(the measurements: docs/decisions.md).  The same compiled kernel runs either way, with a thread
mask of one (``numba.set_num_threads``), so the bits do not depend on the choice: the kernels
split their loop over items that do not share a sum.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import config

__all__ = ["launch"]


def launch(kernel: Callable[..., Any], work: int, *args: Any) -> None:
    """``kernel(*args)`` — a parallel (``prange``) kernel that writes its output in place — on
    one thread when ``work`` (the call's inner-loop iterations, e.g. elements × twists) is below
    ``config.DEFAULTS.parallel_min_work`` (read now), else on Numba's threads."""
    if work >= config.DEFAULTS.parallel_min_work:
        kernel(*args)
        return
    import numba

    before = numba.get_num_threads()
    if before == 1:
        kernel(*args)
        return
    numba.set_num_threads(1)
    try:
        kernel(*args)
    finally:
        numba.set_num_threads(before)
