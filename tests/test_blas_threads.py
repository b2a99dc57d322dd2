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


def test_the_fits_run_on_one_thread(monkeypatch):
    """fit_ellipsoid and fit_quartic hold the BLAS to one thread for their whole call (a QR of
    600 × 127 took 0.87 s on a threaded BLAS with the cores busy, 4 ms on one): seen from inside
    the fit's own linear algebra."""
    import workbench.limit_surface.ellipsoid as ell
    import workbench.limit_surface.quartic as quart
    from workbench import fit_ellipsoid, fit_quartic

    seen = []
    for mod, name in ((ell, "prepare"), (quart, "prepare")):
        real = getattr(mod, name)

        def spy(*a, real=real, **k):
            seen.append(_blas_threads())
            return real(*a, **k)

        monkeypatch.setattr(mod, name, spy)
    rng = np.random.default_rng(1)
    W = rng.standard_normal((400, 6))
    W /= np.linalg.norm(W, axis=1, keepdims=True)
    fit_ellipsoid(W)
    fit_quartic(W)
    assert len(seen) == 2 and all(n and all(t == 1 for t in n) for n in seen)
