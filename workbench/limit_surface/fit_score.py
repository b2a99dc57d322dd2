"""Fit a named 6DLS model to a wrench set and score it (thesis §3.3.4-3.3.5, Eq. 3.18).

One name per fitted model, used by every experiment that compares them:

* ``"ellipsoid_lsq"`` — Eq. 3.13: unconstrained least squares on ``A_e``
  (:func:`~.ellipsoid.fit_ellipsoid` ``method="lsq"``);
* ``"ellipsoid_sdp"`` — Eq. 3.11 with ``A_e ⪰ 0`` (Eq. 3.12; its log-det term only
  with ``alpha``), ``method="sdp"``;
* ``"quartic_values"`` — Eq. 3.17 on the values ``f(x̂_k) = 1`` alone, as the
  thesis text writes it (:func:`~.quartic.fit_quartic` without twists);
* ``"quartic_normals"`` — Eq. 3.17 plus the sampling twists as outward normals
  (maximum dissipation; ``fit_quartic(twists=...)``), as the author's code does with
  other weights.

:func:`fit_and_score` fits one of them (timed) and scores it: Eq. 3.18 on the
training wrenches and, as its :class:`Scoring` asks, Eq. 3.18 and the radial error on
test wrenches and — given the contact's exact wrenches — the sampler-independent
support error (:mod:`.support_error`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from ..seeds import check_seed
from ..timing import median_runtime
from .base import LimitSurfaceModel
from .ellipsoid import fit_ellipsoid
from .normalize import check_twists, check_wrenches
from .quartic import fit_quartic
from .sdp_solver import check_fit_solver
from .sos import exponents
from .support_error import SupportError, support_error

#: the fitted models by name, with what each fits
MODELS = {
    "ellipsoid_lsq": "Eq. 3.13: least-squares ellipsoid, A_e unconstrained (projected to PD if needed)",
    "ellipsoid_sdp": "Eqs. 3.11, 3.12: least-squares ellipsoid with A_e positive semidefinite",
    "quartic_values": "Eq. 3.17: SOS-convex quartic fitted to the values alone (the thesis text)",
    "quartic_normals": "Eq. 3.17 plus the sampling twists as outward normals (maximum dissipation)",
}


def check_model(model: str) -> str:
    """``model`` if it is one of :data:`MODELS`, else ``ValueError`` naming them."""
    if model not in MODELS:
        raise ValueError(
            f"model must be one of {sorted(MODELS)}; got {model!r} (a bare 'ellipsoid' / 'quartic' is "
            "ambiguous: say which fit, e.g. 'ellipsoid_sdp' or 'quartic_values')"
        )
    return model


def min_wrenches(model: str) -> int:
    """Unknowns of ``model`` on a nonplanar (6D) contact — the fewest wrenches it can be
    fitted to there: 21 entries of the symmetric 6 × 6 ``A_e``, 126 = C(9, 5) quartic
    coefficients.  (A planar contact's 3D subspace needs fewer: 6 and 15.)"""
    degree = 2 if check_model(model).startswith("ellipsoid") else 4
    return len(exponents(6, degree))


def fit_model(
    model: str,
    wrenches: np.ndarray,
    *,
    w_max: np.ndarray | None,
    twists: np.ndarray | None = None,
    solver: str | None = None,
    alpha: float | None = None,
) -> LimitSurfaceModel:
    """The fit named ``model`` (:data:`MODELS`) of raw wrenches (K, 6) normalised by
    ``w_max`` (6,) (``None``: the sampled maxima).

    twists : (K, 6) twists the wrenches were computed from; ``"quartic_normals"`` needs
        them, the other models do not use them.
    solver : solver of the "sdp" ellipsoid and the quartics ("IPM", their own interior point, or a
        conic solver with semidefinite support, "CLARABEL", "SCS", any of
        :func:`~.sdp_solver.sdp_solvers`; checked for every model: ValueError otherwise).  None:
        each model's default (``config.DEFAULTS.ellipsoid_solver`` for the ellipsoid,
        ``config.DEFAULTS.quartic_solver`` for the quartics).
    alpha : Eq. 3.12's log-det weight, ``"ellipsoid_sdp"`` only.
    cvxpy's warm start stays off: a fit does not depend on what the process fitted before.
    """
    check_model(model)
    _check_solver(model, solver)
    if alpha is not None and model != "ellipsoid_sdp":
        raise ValueError(f"alpha (Eq. 3.12's log-det weight) belongs to 'ellipsoid_sdp'; got model {model!r}")
    if model == "quartic_normals" and twists is None:
        raise ValueError("model 'quartic_normals' fits the twists as normals: pass twists (K, 6)")
    if model == "ellipsoid_lsq":
        return fit_ellipsoid(wrenches, "lsq", w_max=w_max)
    if model == "ellipsoid_sdp":
        return fit_ellipsoid(wrenches, "sdp", w_max=w_max, solver=solver, alpha=alpha, warm_start=False)
    normals = twists if model == "quartic_normals" else None
    return fit_quartic(wrenches, twists=normals, w_max=w_max, solver=solver, warm_start=False)


def _check_solver(model: str, solver: str | None) -> None:
    """ValueError unless ``solver`` is None or a solver the fits can use ("IPM" or a conic solver
    with semidefinite support); the first check of a cvxpy name imports cvxpy, so it runs before
    any timed fit."""
    if solver is not None:
        check_fit_solver(solver)


@dataclass(frozen=True)
class FitScore:
    """A fitted model, its fit time and its errors (``None`` where no data was given)."""

    model: LimitSurfaceModel
    fit_s: float  # median wall time of the fit [s] over the repeats
    train_error: float  # Eq. 3.18 on the training wrenches
    test_error: float | None  # Eq. 3.18 on the test wrenches
    test_radial: float | None  # radial |f^(1/deg) - 1| on them
    support: SupportError | None  # at exact surface points of uniform normals

    @property
    def fallback(self) -> str | None:
        """The solver that answered when the first failed (``None``: it did not)."""
        return self.model.info.get("fallback")


@dataclass(frozen=True)
class Scoring:
    """What a fit is scored on besides its training wrenches (:func:`fit_and_score`).

    test : (N, 6) wrenches of the same contact: Eq. 3.18 and the radial error (held-out
        ones, or the thesis-code protocol's whole set); ``None``: not scored.
    wrenches_of : ``(n, 6) twists -> (n, 6)`` exact wrenches of the contact (same μ and
        normalisation as the training wrenches): the support error at ``support_directions``
        uniform normals drawn with ``support_seed``; ``None``: no support error.

    Checked on construction, before any fit: ``test`` is kept as the checked float array.
    """

    test: Any = None
    wrenches_of: Callable[[np.ndarray], np.ndarray] | None = None
    support_directions: int = 2000
    support_seed: int = 0

    def __post_init__(self) -> None:
        if self.test is not None:
            object.__setattr__(self, "test", check_wrenches(self.test, "test"))
        if self.wrenches_of is not None:  # before the fit: a bad seed would only show after it
            check_seed(self.support_seed, "support_seed")
        if self.wrenches_of is not None and not callable(self.wrenches_of):
            raise ValueError(
                "wrenches_of must map (n, 6) twists to the contact's exact (n, 6) wrenches, e.g. "
                f"partial(frictional_wrenches, profile, mu=mu); got {type(self.wrenches_of).__name__}"
            )


def fit_and_score(
    model: str,
    wrenches: Any,
    *,
    w_max: Any,
    twists: Any = None,
    scoring: Scoring | None = None,
    solver: str | None = None,
    alpha: float | None = None,
    repeats: int = 1,
) -> FitScore:
    """Fit ``model`` (:data:`MODELS`) to ``wrenches`` (K, 6) and score it: Eq. 3.18 on them and
    as ``scoring`` asks.

    w_max : (6,) exact maxima of the wrenches' contact (Eq. 3.10), or ``None`` for the
        sampled ones.
    twists : (K, 6) their twists (required by ``"quartic_normals"``).
    scoring : the test wrenches and the support error's exact wrenches (:class:`Scoring`);
        ``None``: the training error only.
    solver, alpha : as :func:`fit_model`.
    repeats : the fit is timed this many times (median; short fits vary with thread-pool
        contention) — the model is the same each time.
    """
    check_model(model)
    _check_solver(model, solver)  # before the timed fit
    W = check_wrenches(wrenches)
    if twists is not None:
        twists = check_twists(W, twists)
    if isinstance(repeats, bool) or not (isinstance(repeats, int) and repeats >= 1):
        raise ValueError(f"repeats must be an integer >= 1 (fits timed, median kept); got {repeats!r}")
    sc = Scoring() if scoring is None else scoring
    fit = partial(fit_model, model, W, w_max=w_max, twists=twists, solver=solver, alpha=alpha)
    fit_s, fitted = median_runtime(fit, repeats, warmup=0)
    support = None
    if sc.wrenches_of is not None:
        support = support_error(fitted, sc.wrenches_of, sc.support_directions, seed=sc.support_seed)
    return FitScore(
        model=fitted,
        fit_s=fit_s,
        train_error=fitted.fitting_error(W),
        test_error=None if sc.test is None else fitted.fitting_error(sc.test),
        test_radial=None if sc.test is None else fitted.fitting_error(sc.test, "radial"),
        support=support,
    )


def convexity(model: LimitSurfaceModel, n_points: int = 10_000) -> float:
    """Smallest eigenvalue relative to the largest of ``A_e`` (an ellipsoid) or of the
    quartic's Hessian at ``n_points`` random points of its subspace: > 0 strictly convex."""
    if hasattr(model, "A_e"):
        lam = np.linalg.eigvalsh(model.A_e)
        return float(lam.min() / lam.max())
    return model.min_hessian_eigenvalue(n_points)


__all__ = [
    "MODELS",
    "FitScore",
    "Scoring",
    "check_model",
    "convexity",
    "fit_and_score",
    "fit_model",
    "min_wrenches",
]
