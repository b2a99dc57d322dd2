"""workbench.blas_threads: one BLAS thread inside, the process's own count restored outside; the
controller is reused until a module is imported."""

import numpy as np
from threadpoolctl import threadpool_info

from workbench.blas_threads import _controller, one_blas_thread


def _blas_threads() -> list[int]:
    return [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]


def test_one_thread_inside_and_the_count_restored_after():
    before = _blas_threads()
    with one_blas_thread():
        assert _blas_threads() and all(n == 1 for n in _blas_threads())
        q = np.linalg.qr(np.random.default_rng(0).standard_normal((600, 127)), mode="r")
    assert _blas_threads() == before
    assert q.shape == (127, 127)


def test_the_controller_is_reused_until_a_module_is_imported():
    import sys

    _controller.cache_clear()
    with one_blas_thread():
        pass
    with one_blas_thread():
        pass
    info = _controller.cache_info()
    assert (info.misses, info.hits) == (1, 1)
    n = len(sys.modules)
    assert _controller(n) is _controller(n) and _controller(n) is not _controller(n + 1)
