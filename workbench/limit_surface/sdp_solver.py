"""The conic solvers the SDP ellipsoid (Eq. 3.11/3.12) and the SOS-convex quartic
(Eq. 3.17) can use: cvxpy's installed solvers that take positive-semidefinite
constraints (CLARABEL, SCS, and MOSEK/CVXOPT/… where installed)."""

from __future__ import annotations

from functools import cache


@cache
def sdp_solvers() -> tuple[str, ...]:
    """Names (upper case) of the installed cvxpy solvers with PSD-cone support."""
    from cvxpy.reductions.solvers.defines import INSTALLED_CONIC_SOLVERS, SOLVER_MAP_CONIC

    return tuple(
        name
        for name in INSTALLED_CONIC_SOLVERS
        if any("PSD" in c.__name__ for c in SOLVER_MAP_CONIC[name].SUPPORTED_CONSTRAINTS)
    )


def check_sdp_solver(solver: object, what: str = "solver") -> str:
    """``solver`` if it names one of :func:`sdp_solvers` (any case), else ValueError listing them.
    "CLARABEL" and "SCS" (the defaults; dependencies of workbench and of cvxpy) pass without
    importing cvxpy (~1.3 s), which a quartic fit with Clarabel never needs."""
    if isinstance(solver, str) and solver.upper() in ("CLARABEL", "SCS"):
        return solver
    valid = sdp_solvers()
    if not isinstance(solver, str) or solver.upper() not in valid:
        raise ValueError(
            f"{what} must name a conic solver with semidefinite support, one of {list(valid)} "
            f"(any case); got {solver!r}. Use e.g. {what}='CLARABEL' (the default)"
        )
    return solver


__all__ = ["check_sdp_solver", "sdp_solvers"]
