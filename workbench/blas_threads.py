"""One BLAS/OpenMP thread around the library's small dense algebra.

The workbench's matrices are small (a 600 × 127 QR, a 246-square Cholesky): a threaded BLAS
gains little on them when the machine is idle, and when other processes hold the cores its
threads wait to be scheduled — a new-user trial measured a quartic fit's 600 × 126 QR at 0.87 s
with the default threads on a loaded 2-core machine and 4 ms on one.  One thread also fixes the
order of the sums, so a fit's last bits do not depend on how many threads the process had
(docs/decisions.md).  The runner pins one thread per task as well
(``workbench.runner.parallel``); this is the same limit for a direct library call.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from contextlib import AbstractContextManager
from functools import lru_cache, wraps
from typing import Any, TypeVar

__all__ = ["on_one_blas_thread", "one_blas_thread"]

F = TypeVar("F", bound=Callable[..., Any])


def one_blas_thread() -> AbstractContextManager[Any]:
    """A context manager limiting BLAS/OpenMP libraries to one thread (``threadpoolctl``),
    through this process's controller, made again only when modules were imported since (an
    import is how a new BLAS gets loaded): making one scans every loaded library (~0.1 ms),
    reusing it costs a few microseconds."""
    return _controller(len(sys.modules)).limit(limits=1)


@lru_cache(maxsize=1)
def _controller(n_modules: int) -> Any:
    """The controller made when ``n_modules`` modules were loaded (the key of its cache)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def on_one_blas_thread(fn: F) -> F:
    """``fn`` run inside :func:`one_blas_thread` (a decorator for the library's fits)."""

    @wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with one_blas_thread():
            return fn(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
