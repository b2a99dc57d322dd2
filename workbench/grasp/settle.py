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
with a deeper-pressed patch (``config.DEFAULTS.settle_start_closing``) and ending at the pad's
own compression.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from ..profile import ContactProfile
from ..sources.jaws import with_axis_force

log = logging.getLogger(__name__)

__all__ = ["SettledContact", "normal_torque", "settle_contact", "turned_jaw"]

#: a pad press: (jaw, closing [m]) -> the jaw's contact profile, or None when it touches nothing
Press = Callable[[object, float], "ContactProfile | None"]


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


class _Settled(Exception):
    """Raised inside the residual to stop the solver at a turn whose torque is well inside the
    tolerance (least_squares has no such stopping rule)."""

    def __init__(self, theta: np.ndarray) -> None:
        super().__init__()
        self.theta = np.array(theta, dtype=float)


def _flush_turn(profiles, axis: np.ndarray, b1: np.ndarray, b2: np.ndarray) -> np.ndarray:
    """The turn (2,) about ``b1``, ``b2`` that brings the closing ``axis`` onto the mean of the
    two patches' net normals (jaw 1's against it, jaw 2's along it): the pads flush with flat
    faces — the settle's first guess."""
    n1, n2 = (-p.normal_wrench[:3] / np.linalg.norm(p.normal_wrench[:3]) for p in profiles)
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
    closing: float,
    settle: bool = True,
    max_tilt: float | None = None,
    tol: float | None = None,
) -> SettledContact:
    """Both jaws' contact with the object free to turn between them (module docstring).

    jaws : the two jaws (:class:`~workbench.sources.gripper.Jaw`, object frame) as the gripper
        pose puts them; press : ``press(jaw, closing)`` the jaw's profile pressed ``closing``
        [m] past first touch, or None when its pad touches nothing
        (:func:`~workbench.sources.reach.pad_profile`); force : each jaw's force [N] along
        its closing axis; closing : the pad's compression at ``force`` [m] (the pressure's
        shape; the last stage of the search).
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
    if not (np.isfinite(closing) and closing > 0):
        raise ValueError(f"closing must be the pad's compression [m], > 0; got {closing!r}")
    st = _Settle(jaws, press, force, closing, max_tilt, tol)
    theta = np.zeros(2)
    if settle and max_tilt > 0:
        theta = st.search(config.DEFAULTS.settle_start_closing)
    R, turned, profs, reason = st.pressed(theta, closing)
    if profs is None:
        log.debug("settle: %s", reason)
        tilt = float(np.linalg.norm(theta))
        return SettledContact(None, turned, R, st.pivot, tilt, np.nan, False, reason, st.n_eval)
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
        profs, turned, R, st.pivot, float(np.linalg.norm(theta)), rel, ok, reason, st.n_eval
    )


class _Settle:
    """The search of :func:`settle_contact`: the jaws turned by ``theta`` (2,) [rad] about the
    two axes ``b1``, ``b2`` normal to the closing axis, through ``pivot``, and pressed."""

    def __init__(self, jaws, press: Press, force: float, closing: float, max_tilt: float, tol: float) -> None:
        self.j1, self.j2 = jaws
        self.press, self.force, self.closing = press, force, closing
        self.max_tilt, self.tol = max_tilt, tol
        j1, j2 = self.j1, self.j2
        self.axis = np.asarray(j1.closing, float)
        self.pivot = 0.5 * (np.asarray(j1.origin, float) + np.asarray(j2.origin, float))
        self.b1, self.b2 = _basis(self.axis)
        self.size = float(np.ptp(np.asarray(j1.outline, float), axis=0).max())
        self.n_eval = 0
        self.opening = float((np.asarray(j2.origin, float) - np.asarray(j1.origin, float)) @ self.axis)

    def pressed(self, theta: np.ndarray, depth: float, scale: bool = True):
        """(R (3, 3), the turned jaws, their profiles pressed ``depth`` [m] — scaled to the
        force unless ``scale`` is False — or None, and the reason when None)."""
        R = Rotation.from_rotvec(theta[0] * self.b1 + theta[1] * self.b2).as_matrix()
        turned = tuple(turned_jaw(j, R, self.pivot) for j in (self.j1, self.j2))
        self.n_eval += 1
        profs = []
        for k, jaw in enumerate(turned):
            prof = self.press(jaw, depth)
            if prof is None:
                return R, turned, None, f"the pad of tooltip {k} touches nothing"
            profs.append(with_axis_force(prof, jaw.closing, self.force) if scale else prof)
        # the object slides along the closing axis, but it must fit between the open jaws
        width = float((profs[1].pressure_center - profs[0].pressure_center) @ turned[0].closing)
        if width > self.opening:
            return (
                R,
                turned,
                None,
                (
                    f"the object is {width * 1e3:.1f} mm wide between the pads, wider than the gripper's "
                    f"opening {self.opening * 1e3:.1f} mm"
                ),
            )
        return R, turned, tuple(profs), ""

    def residual(self, theta: np.ndarray, depth: float) -> np.ndarray:
        """(2,) the normal forces' torque about ``b1``, ``b2`` relative to force × pad size at the
        turn ``theta`` pressed ``depth`` [m]; raises :class:`_Settled` well inside the tolerance."""
        force, tol = self.force, self.tol
        _, turned, profs, _ = self.pressed(theta, depth, scale=False)
        if profs is None:  # lost contact: push back towards the start
            return np.array([1.0, 1.0]) * (1.0 + np.linalg.norm(theta) / max(self.max_tilt, 1e-12))
        # each jaw's torque at the force (the profiles' own pressures scaled, as with_axis_force does)
        point = 0.5 * (turned[0].origin + turned[1].origin)
        tau = sum(
            normal_torque([p], point) * force / abs(p.normal_wrench[:3] @ j.closing)
            for p, j in zip(profs, turned, strict=True)
        )
        r = np.array([tau @ self.b1, tau @ self.b2]) / (force * self.size)
        # settled well inside the tolerance at the pad's compression (loosely at a deeper one,
        # which only gives the next stage its start): no more iterations
        if np.linalg.norm(r) <= (tol / 10 if depth == self.closing else tol):
            raise _Settled(theta)
        return r

    def search(self, start: float) -> np.ndarray:
        """The turn (2,) [rad] at which the torque vanishes: from the flush turn of a patch
        pressed ``start`` [m] (when deeper than the pad's compression), stage by stage to the
        pad's compression; no turn when a pad misses at the pose as given."""
        theta = np.zeros(2)
        stages = ([start] if start > self.closing else []) + [self.closing]
        _, _, deep, _ = self.pressed(theta, stages[0], scale=False)
        if deep is None:  # a pad that misses at the pose as given is a miss (no search)
            return theta
        lo, hi = np.full(2, -self.max_tilt), np.full(2, self.max_tilt)
        theta = np.clip(_flush_turn(deep, self.axis, self.b1, self.b2), lo, hi)
        for depth in stages:
            try:
                theta = least_squares(
                    self.residual, theta, args=(depth,), bounds=(lo, hi), diff_step=1e-3, xtol=1e-9, ftol=1e-9
                ).x
            except _Settled as done:
                theta = np.array(done.theta, dtype=float)
        return theta
