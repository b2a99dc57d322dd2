"""Runtime-versus-error trade-offs: the Pareto front of (runtime, error) points and the comparison
of two methods' fronts at equal runtime and at equal error.

A point is one setting of one method (a mesh resolution, a twist count ...) measured as
``(runtime [s], error [-])``, both > 0.  The *front* is the set of points no other point beats in
both; between two front points the trade-off is read on log-log axes (runtimes and errors span
decades), i.e. ``log error`` is interpolated linearly in ``log runtime``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["at_equal", "pareto_front"]


def _points(runtime: Any, error: Any) -> tuple[np.ndarray, np.ndarray]:
    try:
        t = np.asarray(runtime, dtype=np.float64).reshape(-1)
        e = np.asarray(error, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError("runtime and error must be numeric (n,) arrays") from None
    if t.shape != e.shape or t.size == 0:
        raise ValueError(
            f"runtime and error must be (n,) arrays of one length n >= 1; got {t.shape} and {e.shape}"
        )
    if not (np.isfinite(t).all() and np.isfinite(e).all()) or (t <= 0).any() or (e <= 0).any():
        raise ValueError(
            "runtimes [s] and errors must be finite and > 0 (log axes); got "
            f"runtime {t.tolist()}, error {e.tolist()} — floor an exact error at the round-off "
            "level (e.g. 1e-16) rather than 0"
        )
    return t, e


def pareto_front(runtime: Any, error: Any) -> np.ndarray:
    """Indices of the non-dominated points, by increasing runtime (hence decreasing error).

    runtime, error : (n,) float, > 0.  A point is dominated when another is no slower and no
    less accurate and differs in one of the two; of exact duplicates the first is kept.
    Returns (m,) int.
    """
    t, e = _points(runtime, error)
    order = np.lexsort((e, t))  # by runtime, ties by error
    front, best = [], np.inf
    for i in order:
        if e[i] < best:
            front.append(int(i))
            best = e[i]
    return np.array(front, dtype=np.int64)


def at_equal(
    runtime: Any, error: Any, *, runtime_at: float | None = None, error_at: float | None = None
) -> dict:
    """Read a method's front at a given runtime (its error there) or at a given error (its runtime).

    runtime, error : (n,) the method's points; only its :func:`pareto_front` is used.
    Exactly one of ``runtime_at`` [s] / ``error_at`` must be given.  Returns
    ``{"value": float, "clamped": bool, "beyond": str | None}``: the log-log interpolated error
    (or runtime) on the front; outside the front's range the end point's value, with
    ``clamped=True`` and ``beyond`` saying which way the true value lies from it:

    - at a runtime beyond the slowest point, the error there is *at most* the value
      (``beyond="at most"``); below the fastest, *at least* (``"at least"``);
    - at an error above the least accurate point, the runtime is *at most* the value; below
      the most accurate, *at least*.

    The method was not measured there, so a ratio built on the value is that bound.
    """
    if (runtime_at is None) == (error_at is None):
        raise ValueError("give exactly one of runtime_at [s] or error_at")
    t, e = _points(runtime, error)
    idx = pareto_front(t, e)
    lt, le = np.log(t[idx]), np.log(e[idx])  # lt increasing, le decreasing
    if runtime_at is not None:
        x, xs, ys = float(runtime_at), lt, le
    else:
        x, xs, ys = float(error_at), le[::-1], lt[::-1]
    if not (np.isfinite(x) and x > 0):
        raise ValueError(f"the runtime/error to read at must be finite and > 0; got {x}")
    lx = np.log(x)
    # beyond the largest runtime (or error) the other quantity can only be smaller; before the
    # smallest, only larger
    beyond = "at most" if lx > xs[-1] else ("at least" if lx < xs[0] else None)
    value = float(np.exp(ys[0])) if xs.size == 1 else float(np.exp(np.interp(lx, xs, ys)))
    return {"value": value, "clamped": beyond is not None, "beyond": beyond}
