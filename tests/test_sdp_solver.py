"""workbench.limit_surface.sdp_solver: the installed cvxpy solvers with semidefinite
support — each solves a small SDP to its known optimum — and the check of a solver name."""

import numpy as np
import pytest

from workbench.limit_surface.sdp_solver import check_sdp_solver, sdp_solvers


def test_the_default_solvers_are_listed_and_each_listed_one_solves_an_sdp():
    """min trace X subject to X ⪰ 0 (2×2), X_01 = 1: X ⪰ 0 needs X_00 X_11 >= 1, and
    X_00 + X_11 >= 2 √(X_00 X_11) >= 2 (AM-GM), so the optimum is 2 at [[1, 1], [1, 1]]."""
    import cvxpy as cp

    names = sdp_solvers()
    assert {"CLARABEL", "SCS"} <= set(names) and all(n == n.upper() for n in names)
    assert set(names) <= set(cp.installed_solvers())
    for name in names:
        X = cp.Variable((2, 2), symmetric=True)
        prob = cp.Problem(cp.Minimize(cp.trace(X)), [X >> 0, X[0, 1] == 1])
        prob.solve(solver=name)
        assert prob.value == pytest.approx(2.0, abs=1e-4), name
        np.testing.assert_allclose(X.value, np.ones((2, 2)), atol=1e-3)


def test_installed_solvers_without_psd_cones_or_a_licence_are_not_listed():
    """cvxpy's LP/QP solvers (SciPy's HiGHS, OSQP, ...) cannot take X ⪰ 0, and a commercial
    conic solver without a licence (MOSEK, pulled in by drake) cannot solve at all: whichever of
    them is installed, the same SDP fails with them, and they are not listed."""
    import cvxpy as cp

    others = [s for s in cp.installed_solvers() if s not in sdp_solvers()]
    for name in others:
        X = cp.Variable((2, 2), symmetric=True)
        prob = cp.Problem(cp.Minimize(cp.trace(X)), [X >> 0, X[0, 1] == 1])
        with pytest.raises(Exception) as failure:  # noqa: PT011 - cvxpy's SolverError or the solver's own
            prob.solve(solver=name)
        assert failure.type is cp.error.SolverError or name == "MOSEK", (name, failure.value)
        with pytest.raises(ValueError, match=rf"solver must name a conic solver .*got '{name}'"):
            check_sdp_solver(name)


def test_check_sdp_solver_takes_any_case_and_names_the_valid_ones():
    for name in ("CLARABEL", "clarabel", "Scs"):
        assert check_sdp_solver(name) == name  # returned as given
    for name in sdp_solvers():
        assert check_sdp_solver(name.lower()) == name.lower()
    valid = str(list(sdp_solvers())).replace("[", r"\[").replace("]", r"\]")
    for bad in ("NOT_A_SOLVER", "", None, 3, ["SCS"]):
        with pytest.raises(
            ValueError, match=rf"solver must name a conic solver with semidefinite support, one of {valid}"
        ):
            check_sdp_solver(bad)
    with pytest.raises(
        ValueError, match=r"^fallback_solver must name .*got 'ECOS_X'. Use e.g. fallback_solver='CLARABEL'"
    ):
        check_sdp_solver("ECOS_X", what="fallback_solver")


def test_a_quartic_fallback_is_another_solver():
    from workbench.limit_surface.quartic import _fallback_for

    # "auto": Clarabel after the IPM or SCS, SCS after Clarabel — never the solver itself
    assert [_fallback_for(s, "auto") for s in ("IPM", "SCS", "CLARABEL")] == ["CLARABEL", "CLARABEL", "SCS"]
    assert _fallback_for("IPM", None) is None and _fallback_for("IPM", "scs") == "SCS"
    for solver, fallback in (("IPM", "ipm"), ("CLARABEL", "Clarabel"), ("SCS", "SCS")):
        with pytest.raises(ValueError, match=r"fallback_solver is the solver itself .* would fail again"):
            _fallback_for(solver, fallback)


def test_every_listed_solver_fits_the_quartic_to_the_ipms_optimum():
    # a solver offered by sdp_solvers() must solve the quartic's SOS program, not only a 2 x 2 SDP
    # (CVXOPT failed every fit with its default KKT solver)
    from workbench.limit_surface import fit_quartic

    rng = np.random.default_rng(3)
    # points of a convex surface: an ellipsoid's, pushed out along two axes by a quartic term
    x = rng.normal(size=(500, 6))
    size = np.sqrt((x**2).sum(axis=1) + (x[:, 0] ** 4 + x[:, 3] ** 4) / (x**2).sum(axis=1))
    W = x / size[:, None] * [1.0, 1.0, 1.0, 0.1, 0.1, 0.2]
    W, probe = W[:300], W[300:]
    ipm = fit_quartic(W, solver="IPM", fallback_solver=None)
    for name in sdp_solvers():
        q = fit_quartic(W, solver=name, fallback_solver=None)
        assert q.info["solver"] == name
        assert q.fitting_error(W) == pytest.approx(ipm.fitting_error(W), rel=1e-3)
        assert np.abs(q.value(probe) - ipm.value(probe)).max() < 2e-3 * np.abs(ipm.value(probe)).max()
