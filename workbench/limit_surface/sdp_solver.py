"""The conic solvers the SDP ellipsoid (Eqs. 3.11, 3.12) and the SOS-convex quartic
(Eq. 3.17) can use: the fits' own interior point ("IPM", :mod:`.sos_ipm`) and cvxpy's installed
solvers that take positive-semidefinite constraints (CLARABEL, SCS, and MOSEK/CVXOPT/… where
installed and usable)."""

from __future__ import annotations

import logging
from functools import cache

log = logging.getLogger(__name__)

#: the name of the fits' own interior point (:mod:`.sos_ipm`) among their solvers
IPM = "IPM"


@cache
def sdp_solvers() -> tuple[str, ...]:
    """Names (upper case) of the installed cvxpy solvers with PSD-cone support that solve a
    2 x 2 SDP here: an installed commercial solver without a licence (MOSEK, which drake's
    wheel pulls in) is importable, so cvxpy lists it, but fails every solve."""
    from cvxpy.reductions.solvers.defines import INSTALLED_CONIC_SOLVERS, SOLVER_MAP_CONIC

    return tuple(
        name
        for name in INSTALLED_CONIC_SOLVERS
        if any("PSD" in c.__name__ for c in SOLVER_MAP_CONIC[name].SUPPORTED_CONSTRAINTS)
        and _solves_an_sdp(name)
    )


@cache
def _solves_an_sdp(name: str) -> bool:
    """Whether solver ``name`` solves min trace X, X PSD (2 x 2), X_01 = 1 (optimum 2; once per
    process), logging why not."""
    import cvxpy as cp

    X = cp.Variable((2, 2), symmetric=True)
    problem = cp.Problem(cp.Minimize(cp.trace(X)), [X >> 0, X[0, 1] == 1])
    try:
        problem.solve(solver=name)
    except Exception as exc:  # a licence error, a broken install: not a solver to offer
        log.warning("cvxpy lists %s but it cannot solve an SDP here (%s); not offered", name, exc)
        return False
    return problem.value is not None and abs(problem.value - 2.0) < 1e-3


def check_sdp_solver(solver: object, what: str = "solver") -> str:
    """``solver`` if it names one of :func:`sdp_solvers` (any case), else ValueError listing them.
    "CLARABEL" and "SCS" (the defaults; dependencies of workbench and of cvxpy) pass without
    importing cvxpy (a slow import), which a quartic fit with Clarabel never needs."""
    if isinstance(solver, str) and solver.upper() in ("CLARABEL", "SCS"):
        return solver
    valid = sdp_solvers()
    if not isinstance(solver, str) or solver.upper() not in valid:
        raise ValueError(
            f"{what} must name a conic solver with semidefinite support, one of {list(valid)} "
            f"(any case); got {solver!r}. Use e.g. {what}='CLARABEL' (the default)"
        )
    return solver


def check_fit_solver(solver: object, what: str = "solver") -> str:
    """``solver`` in upper case if it is "IPM" (any case: :mod:`.sos_ipm`, the ellipsoid's and the
    quartic's own interior point) or a conic solver with semidefinite support
    (:func:`check_sdp_solver`), else a ValueError listing them."""
    if isinstance(solver, str) and solver.upper() == IPM:
        return IPM
    try:
        return check_sdp_solver(solver, what).upper()
    except ValueError:
        raise ValueError(
            f"{what} must name a conic solver with semidefinite support, one of {list(sdp_solvers())}, "
            f"or 'IPM' (the fits' own interior point), any case; got {solver!r}"
        ) from None


__all__ = ["IPM", "check_fit_solver", "check_sdp_solver", "sdp_solvers"]
