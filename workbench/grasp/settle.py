"""The contact a free object makes between two parallel jaws: both pads' patches solved together.

A jaw pressed on its own meets a face 3–9° off its normal along a strip at the pad's edge, and
two such strips put the jaws' pressure centres centimetres apart: a couple no free object
holds still under.  Between force-controlled parallel jaws the object is free to turn until
the pads' normal forces balance (equal and opposite forces on one line, no net torque) —
what the thesis's quasi-static analysis presumes of the contact it analyses (§4.1.3.2, both
jaws at one force reading) and what a soft pad does to a cube that is grasped a few degrees
off square.

The model (stated, not tuned): the object is rigid, the pads are Winkler foundations
(:mod:`workbench.sources.reach`: pressure ∝ local compression), each jaw pushes with the same
force along the closing axis, and the object turns relative to the gripper about the point
midway between the tooltips, about the two axes normal to the closing axis, by at most
``config.DEFAULTS.settle_max_tilt`` (beyond it a finger, not the pad, would have to stop it).
Turning about the closing axis and sliding are left to friction: they are the
resistance question itself.  :func:`settle_contact` finds the turn at which the normal
forces' torque about the axes normal to the closing axis vanishes (relative to force × pad
size, ``config.TOL.settle_torque_rtol``), starting from the turn that makes the pads flush
with a deeper-pressed patch (``config.DEFAULTS.settle_start_closing``) and ending with each
pad pressed until its normal force along the closing axis is the jaw's force
(:meth:`~workbench.sources.pad_patch.PadPatch.depth_for_force`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from ..profile import ContactProfile
from ..sources.pad_patch import PadPatch

log = logging.getLogger(__name__)

__all__ = ["SettledContact", "normal_torque", "settle_contact", "turned_jaw"]

#: a pad press: jaw -> the surface its pad reaches at that pose, or None when it touches nothing
#: (:func:`~workbench.sources.reach.pad_patch`)
Press = Callable[[object], "PadPatch | None"]


@dataclass(frozen=True)
class SettledContact:
    """Both jaws' contact after the object settled between them.

    profiles : the two jaws' profiles scaled to ``force`` each, or None when a pad touches
        nothing (then ``reason`` says which).
    jaws : the jaws where the object settled (object frame), after the turn ``rotation``.
    rotation : (3, 3) the turn of the gripper relative to the object about ``pivot`` (the
        object turns by its transpose relative to the gripper: gravity's direction in the
        object frame turns by ``rotation`` too).
    tilt : the turn's angle [rad]; torque : the remaining normal-force torque normal to the
        closing axis relative to force × pad size; converged : ``torque <= tol``.
    depths : each pad's compression [m] at the force (NaN for a miss): a pad pressed about as
        deep as its layer is thick has bottomed out, past what a Winkler pad describes.
    searched : whether the turn was searched (``settle=True``); without it ``converged`` only
        says whether the pads pressed at the pose as given happen to balance.
    """

    profiles: tuple[ContactProfile, ContactProfile] | None
    jaws: tuple
    rotation: np.ndarray = field(repr=False)
    pivot: np.ndarray = field(repr=False)
    tilt: float
    torque: float
    converged: bool
    reason: str = ""
    n_evaluations: int = 0
    depths: tuple[float, float] = (np.nan, np.nan)
    searched: bool = True

    @property
    def touches(self) -> bool:
        """Both pads touch the object."""
        return self.profiles is not None


def turned_jaw(jaw, rotation: np.ndarray, pivot: np.ndarray):
    """``jaw`` turned by ``rotation`` (3, 3) about ``pivot`` (3,) [m] (a rigid motion of the
    gripper in the object frame; :meth:`~workbench.sources.gripper.Jaw.turned`)."""
    return jaw.turned(rotation, pivot)


def normal_torque(profiles, point: np.ndarray) -> np.ndarray:
    """(3,) torque about ``point`` of the profiles' normal forces on the object
    (``Σ (c − point) × (−p a n)``, CONVENTIONS.md: normals out of the object)."""
    tau = np.zeros(3)
    for prof in profiles:
        f = -(prof.pressures * prof.areas)[:, None] * prof.normals
        tau += np.cross(prof.centers - point, f).sum(axis=0)
    return tau


def torque_jacobian(pats, depths, axes, pivot: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The normal forces' torque about ``pivot`` (3,) [m] along the rows of ``b`` (2, 3) [N·m], and
    its derivative (2, 2) [N·m/rad] in a turn of the gripper about ``pivot`` along ``b``'s rows,
    each pad kept at its force.

    pats : the pads' :class:`~workbench.sources.pad_patch.PadPatch`; depths : each pad's depth
    [m]; axes : each pad's closing axis (3,).  A turn ω moves element i of a pad (closing axis
    a, stiffness k) ``ω·(a × r_i)`` along a (``r_i = c_i − pivot``); the pad then moves by the
    mean of that over its contact weighted by each element's area along a (``w_i = a_i (−n_i·a)``,
    its force unchanged), so element i's compression changes by ``ω·g_i``,
    ``g_i = a × (r̄ − r_i)``, and the torque by ``−k Σ a_i (r_i × n_i)(g_i·ω)``.  Elements that
    enter or leave the contact do so at zero pressure: the derivative is the contact's own.
    """
    tau, jac = np.zeros(2), np.zeros((2, 2))
    for p, d, a in zip(pats, depths, axes, strict=True):
        pen = p.z0 + d - p.z
        sel = pen > 0
        r, n, area = p.centers[sel] - pivot, p.normals[sel], p.areas[sel]
        arm = np.cross(r, n) @ b.T  # (m, 2): b · (r × n)
        tau -= (p.stiffness * pen[sel] * area) @ arm
        w = area * -(n @ a)
        g = np.cross(a, w @ r / w.sum() - r) @ b.T  # (m, 2): g · b
        jac -= p.stiffness * (area[:, None] * arm).T @ g
    return tau, jac


def _stiff(r: np.ndarray, jac: np.ndarray, max_tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """The residual ``r`` (2,) and Jacobian ``jac`` (2, 2) along the directions of turn the settle
    works on, leaving out the neutral ones: a torque along them below
    ``config.DEFAULTS.settle_neutral_torque`` with a stiffness below
    ``config.DEFAULTS.settle_neutral_stiffness`` of the stiffest direction's, or too low to
    cancel it within ``max_tilt`` [rad] — a round object turning about its own axis, or a ball
    about any, where the contact rolls and what torque is left is the facets' noise."""
    from .. import config

    u, sv, vt = np.linalg.svd(jac)
    along = np.abs(u.T @ r)
    soft = (sv < config.DEFAULTS.settle_neutral_stiffness * sv[0]) | (along > max_tilt * sv)
    keep = ~(soft & (along <= config.DEFAULTS.settle_neutral_torque))
    return u[:, keep] @ (u[:, keep].T @ r), (u[:, keep] * sv[keep]) @ vt[keep]


class _Settled(Exception):
    """Raised inside the solver's residual to stop it at a turn whose torque is well inside the
    tolerance (least_squares has no such stopping rule)."""

    def __init__(self, theta: np.ndarray) -> None:
        super().__init__()
        self.theta = np.array(theta, dtype=float)


def _flush_turn(net: tuple, axis: np.ndarray, b1: np.ndarray, b2: np.ndarray) -> np.ndarray:
    """The turn (2,) about ``b1``, ``b2`` that brings the closing ``axis`` onto the mean of the
    two patches' net normal forces ``net`` (3,) each (jaw 1's against it, jaw 2's along it): the
    pads flush with flat faces — the settle's first guess."""
    n1, n2 = (-f / np.linalg.norm(f) for f in net)
    target = n2 - n1
    target /= np.linalg.norm(target)
    rv = np.cross(axis, target)
    s = np.linalg.norm(rv)
    if s < 1e-15:
        return np.zeros(2)
    rv *= np.arcsin(min(s, 1.0)) / s
    return np.array([rv @ b1, rv @ b2])


def _basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors normal to ``axis`` and to each other."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    b1 = np.cross(axis, helper)
    b1 /= np.linalg.norm(b1)
    return b1, np.cross(axis, b1)


def settle_contact(
    jaws,
    press: Press,
    force: float,
    *,
    settle: bool = True,
    max_tilt: float | None = None,
    tol: float | None = None,
) -> SettledContact:
    """Both jaws' contact with the object free to turn between them (module docstring).

    jaws : the two jaws (:class:`~workbench.sources.gripper.Jaw`, object frame) as the gripper
        pose puts them; press : ``press(jaw)`` the surface the jaw's pad reaches
        (:class:`~workbench.sources.pad_patch.PadPatch`), or None when it touches nothing
        (:func:`~workbench.sources.reach.pad_patch`); force : each jaw's force [N] along its
        closing axis, to which each pad is pressed.
    settle : False gives each jaw's own patch at the pose as given (no turn): the
        contact of the jaws pressed one by one.
    max_tilt, tol : ``config.DEFAULTS.settle_max_tilt`` [rad] and
        ``config.TOL.settle_torque_rtol`` when None.
    """
    from .. import config

    max_tilt = config.DEFAULTS.settle_max_tilt if max_tilt is None else float(max_tilt)
    tol = config.TOL.settle_torque_rtol if tol is None else float(tol)
    if not (np.isfinite(force) and force > 0):
        raise ValueError(f"force must be each jaw's force in newtons, finite and > 0; got {force!r}")
    st = _Settle(jaws, press, force, max_tilt, tol)
    theta = np.zeros(2)
    if settle and max_tilt > 0:
        theta = st.search(config.DEFAULTS.settle_start_closing)
    R, turned, pats, reason = st.patches(theta)
    depths = None if pats is None else st.depths(pats, None)
    reason = reason or st.too_wide(turned, pats, depths)
    if reason:
        log.debug("settle: %s", reason)
        tilt = float(np.linalg.norm(theta))
        return SettledContact(
            None, turned, R, st.pivot, tilt, np.nan, False, reason, st.n_eval, searched=settle
        )
    profs = tuple(p.profile(d) for p, d in zip(pats, depths, strict=True))
    tau = normal_torque(profs, 0.5 * (turned[0].origin + turned[1].origin))
    rel = float(np.hypot(tau @ st.b1, tau @ st.b2) / (force * st.size))
    ok = rel <= tol
    if settle and not ok:
        reason = (
            f"the normal forces keep a torque of {rel:.2g} × force × pad size after a turn of "
            f"{np.degrees(np.linalg.norm(theta)):.1f}° (limit {np.degrees(max_tilt):.0f}°)"
        )
        log.info("settle: %s", reason)
    return SettledContact(
        profs, turned, R, st.pivot, float(np.linalg.norm(theta)), rel, ok, reason, st.n_eval, depths, settle
    )


class _Settle:
    """The search of :func:`settle_contact`: the jaws turned by ``theta`` (2,) [rad] about the
    two axes ``b1``, ``b2`` normal to the closing axis, through ``pivot``, and pressed."""

    def __init__(self, jaws, press: Press, force: float, max_tilt: float, tol: float) -> None:
        self.j1, self.j2 = jaws
        self.press, self.force = press, force
        self.max_tilt, self.tol = max_tilt, tol
        j1, j2 = self.j1, self.j2
        self.axis = np.asarray(j1.closing, float)
        self.pivot = 0.5 * (np.asarray(j1.origin, float) + np.asarray(j2.origin, float))
        self.b1, self.b2 = _basis(self.axis)
        self.size = float(np.ptp(np.asarray(j1.outline, float), axis=0).max())
        self.n_eval = 0
        self.last = None  # (the turn's bytes, what patches() gave for it)
        self.opening = float((np.asarray(j2.origin, float) - np.asarray(j1.origin, float)) @ self.axis)

    def patches(self, theta: np.ndarray):
        """(R (3, 3), the turned jaws, the surfaces their pads reach — or None, and the reason
        when None)."""
        key = np.asarray(theta, float).tobytes()
        if self.last is not None and self.last[0] == key:  # the solver's last turn, asked again
            return self.last[1]
        R = Rotation.from_rotvec(theta[0] * self.b1 + theta[1] * self.b2).as_matrix()
        turned = tuple(turned_jaw(j, R, self.pivot) for j in (self.j1, self.j2))
        self.n_eval += 1
        pats = []
        out = None
        for k, jaw in enumerate(turned):
            pat = self.press(jaw)
            if pat is None:
                out = (R, turned, None, f"the pad of tooltip {k} touches nothing")
                break
            pats.append(pat)
        out = out or (R, turned, tuple(pats), "")
        self.last = (key, out)
        return out

    def depths(self, pats, depth: float | None) -> tuple[float, float]:
        """Each pad's depth [m]: ``depth`` for both, or (None) the depth that gives it the force."""
        if depth is None:
            return tuple(p.depth_for_force(self.force) for p in pats)
        return (depth, depth)

    def too_wide(self, turned, pats, depths) -> str:
        """Why the object does not fit between the open jaws ("" when it does): it slides along
        the closing axis, but its pressure centres must lie within the opening."""
        if pats is None:
            return ""
        centre = []
        for p, d in zip(pats, depths, strict=True):
            w = p.pressures(d) * p.areas
            centre.append(w @ p.centers / w.sum())
        width = float((centre[1] - centre[0]) @ turned[0].closing)
        if width > self.opening:
            return (
                f"the object is {width * 1e3:.1f} mm wide between the pads, wider than the gripper's "
                f"opening {self.opening * 1e3:.1f} mm"
            )
        return ""

    def at_force(self, theta: np.ndarray):
        """The normal forces' torque about ``b1``, ``b2`` (2,) relative to force × pad size at the
        turn ``theta`` [rad], each pad pressed to the force, and its Jacobian (2, 2) in the turn
        (:func:`torque_jacobian`); (None, None) when a pad loses contact or the object no longer
        fits."""
        _, turned, pats, _ = self.patches(theta)
        depths = None if pats is None else self.depths(pats, None)
        if pats is None or self.too_wide(turned, pats, depths):
            return None, None
        scale = 1.0 / (self.force * self.size)
        axes = np.array([self.b1, self.b2])
        tau, jac = torque_jacobian(pats, depths, [j.closing for j in turned], self.pivot, axes)
        return tau * scale, jac * scale

    def solve(self, theta: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """The turn (2,) [rad] in ``[lo, hi]`` at which the torque at the force vanishes: a
        trust-region least-squares solve from ``theta`` with the Jacobian of
        :func:`torque_jacobian` (one press of both pads a step; the torque is only piecewise
        smooth, as a pad's contact set changes with the turn), stopped well inside the tolerance."""
        from .. import config

        memo: dict = {}

        def at(x):
            key = x.tobytes()
            if key not in memo:
                memo.clear()
                r, jac = self.at_force(x)
                if r is None:  # lost contact: push back towards the start
                    r = np.ones(2) * (1.0 + np.linalg.norm(x) / max(self.max_tilt, 1e-12))
                    jac = np.zeros((2, 2))
                else:
                    r_stiff, jac = _stiff(r, jac, self.max_tilt)  # no step along a neutral direction
                    if np.linalg.norm(r_stiff) <= self.tol / 10:
                        raise _Settled(x)
                memo[key] = (r, jac)
            return memo[key]

        try:
            return least_squares(
                lambda x: at(x)[0],
                theta,
                jac=lambda x: at(x)[1],
                bounds=(lo, hi),
                xtol=1e-9,
                ftol=1e-9,
                max_nfev=config.DEFAULTS.settle_max_steps,
            ).x
        except _Settled as done:
            return np.array(done.theta, dtype=float)

    def search(self, start: float) -> np.ndarray:
        """The turn (2,) [rad] at which the torque vanishes: :meth:`solve` from
        the flush turn of the patches pressed ``start`` [m] (wider than at the force, their net
        normals steadier); no turn when a pad misses at the pose as given."""
        theta = np.zeros(2)
        _, _, pats, _ = self.patches(theta)
        if pats is None:  # a pad that misses at the pose as given is a miss (no search)
            return theta
        first = self.depths(pats, max(start, *self.depths(pats, None)))
        net = tuple(-(p.pressures(d) * p.areas) @ p.normals for p, d in zip(pats, first, strict=True))
        lo, hi = np.full(2, -self.max_tilt), np.full(2, self.max_tilt)
        return self.solve(np.clip(_flush_turn(net, self.axis, self.b1, self.b2), lo, hi), lo, hi)
