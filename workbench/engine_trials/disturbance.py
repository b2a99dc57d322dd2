"""A held object loaded by a disturbance wrench: does the grasp resist it?

The question the thesis's §4.1.3 experiments ask with weight plates hung on an assembly at
lever arms, asked of the engine: the jaws close by force on an object floating free (no
gravity: the disturbance carries the load, as the thesis's frame at the object's centre of
mass does), the wrench then rises smoothly to its value and is held; the grasp resists it iff
the object stays within the phases' drift and turn of its pose relative to the gripper.  The
wrench is fixed in the world, as a hung weight's is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..groups import checked_group
from .settings import EngineSettings
from .trial import (
    _DRIFT_EXAMPLES,
    EngineObject,
    EnginePad,
    TrialOutcome,
    TrialPhases,
    _check_force,
    _check_grasp,
    _check_run,
    _check_trial,
    _miss,
    _starts_inside,
    build_scene,
    check_flag,
    check_record_count,
    check_record_every,
    check_turn_limit,
    step_trial,
)


@dataclass(frozen=True)
class DisturbancePhases:
    """Durations [s] of a disturbance trial and its verdict's limits.  The verdict reads the
    poses recorded over ramp and hold: each must span at least
    ``config.TOL.engine_min_samples_per_phase`` records (:func:`~.trial.check_record_every`)."""

    gap: float = 5e-4  # pad face to the object before closing [m]
    close: float = 0.3  # the jaws' force ramps from 0 to its value
    settle: float = 0.2  # the force held before the wrench is applied
    # the wrench rises from 0 to its value along a smoothstep: slow against the grasp's own
    # dynamics (pad and object oscillate at ~100 Hz), so the load is quasi-static
    ramp: float = 0.5
    hold: float = 0.3  # the full wrench held
    # resisted: the object moved less than this relative to the gripper from the end of
    # settling; an unresisted wrench accelerates the free object away, far past both limits
    max_drift: float = 5e-3  # [m]
    max_turn_deg: float = 5.0  # [deg]
    # engine steps between the recorded poses the verdict reads (:func:`~.trial.check_record_every`)
    record_every: int = 10
    # stop once the object is past every verdict limit (as TrialPhases.stop_when_lost)
    stop_when_lost: bool = False

    def __post_init__(self) -> None:
        from ..plausible import check

        check_record_count(self.record_every)
        check_flag("stop_when_lost", self.stop_when_lost, "stop a trial once the object is past every limit")
        for name in ("close", "settle", "ramp", "hold"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0 < v <= 60):
                raise ValueError(f"DisturbancePhases.{name} must be a duration in (0, 60] s; got {v!r}")
        check("compression", self.gap, "DisturbancePhases.gap (pad face to object [m])", warn=False)
        what = "DisturbancePhases.max_drift (held below this drift [m])"
        check("closing", self.max_drift, what, warn=False, examples=_DRIFT_EXAMPLES, named="drift limit")
        if not self.max_drift > 0:
            raise ValueError(f"DisturbancePhases.max_drift must be > 0 [m]; got {self.max_drift!r}")
        check_turn_limit(self.max_turn_deg, "DisturbancePhases.max_turn_deg")


def _check_wrench(wrench) -> np.ndarray:
    from ..grasp.robust import check_task_wrench

    w = np.asarray(wrench, float) if not isinstance(wrench, (str, bytes, dict)) else None
    if w is None or w.shape != (6,) or not np.all(np.isfinite(w)):
        raise ValueError(
            f"wrench must be 6 finite numbers (f_x, f_y, f_z [N], tau_x, tau_y, tau_z [N m]) about the "
            f"object frame's origin; got {wrench!r}"
        )
    check_task_wrench(w, name="wrench")
    return w


def simulate_disturbance(
    mesh,
    grasp: dict,
    wrench,
    *,
    force: float,
    obj: EngineObject,
    pad: EnginePad | None = None,
    settings: EngineSettings | None = None,
    phases: DisturbancePhases | None = None,
) -> TrialOutcome:
    """Does the grasp ``grasp`` (``p1``, ``p2``, ``axis`` in the frame of the watertight
    ``mesh`` [m]) with jaw force ``force`` [N] resist ``wrench`` (6,: force [N] and torque [N m]
    about the mesh frame's origin, in that frame)?  The object ``obj`` (its mass [kg] at its
    centre of mass (3,) [m], its friction μ with the pads) floats free, without gravity
    (``obj.down`` only lays its collision slabs); ``pad``: each jaw's silicone
    (:class:`~.trial.EnginePad`), its length along ``pad.up``; ``pad.conform``: the pads moulded
    to the object (:func:`~.pad.conform_pad`), else flat.

    ``phases.record_every``: engine steps between the recorded poses the verdict reads; ramp and
    hold must each span at least ``config.TOL.engine_min_samples_per_phase`` of them
    (:func:`~.trial.check_record_every`): at most 15 at the default phases and 1 ms step, 10 by
    default.

    Returns a :class:`~.trial.TrialOutcome` whose ``held`` is the engine's verdict: no contact
    model of this package is used; its reason names the limit crossed first."""
    phases = checked_group(phases, DisturbancePhases, "phases")
    mesh, obj = _check_trial(mesh, "simulate_disturbance", "vertical_lifting", obj)
    _, settings = _check_run(None, settings)
    w = _check_wrench(wrench)
    judged = {"DisturbancePhases.ramp": phases.ramp, "DisturbancePhases.hold": phases.hold}
    check_record_every(phases.record_every, judged, settings.timestep)
    pad = _check_force(force, pad)
    p1, p2, axis = _check_grasp(grasp, mesh)
    faces = (p1 - phases.gap * axis, p2 + phases.gap * axis)
    inside = "" if pad.conform else _starts_inside(mesh, faces, axis, pad.up, pad.size)
    if inside:
        return _miss(inside)
    model, info = build_scene(
        mesh, faces, axis, force=force, obj=obj, pad=pad, settings=settings,
        phases=TrialPhases(gap=phases.gap, table=False),
    )  # fmt: skip
    obj = info["object"]
    t_settle = phases.close + phases.settle
    t_load = t_settle + phases.ramp

    def control(t: float, model, data) -> None:
        model.opt.gravity[:] = 0.0
        data.ctrl[:2] = force * np.clip(t / phases.close, 0.0, 1.0)
        u = np.clip((t - t_settle) / phases.ramp, 0.0, 1.0)
        s = 3 * u**2 - 2 * u**3
        # the wrench about the object frame's origin, moved to the body's centre of mass
        lever = data.xpos[obj] - data.xipos[obj]
        data.xfrc_applied[obj, :3] = s * w[:3]
        data.xfrc_applied[obj, 3:] = s * (w[3:] + np.cross(lever, w[:3]))

    return step_trial(
        model, info, control, t_settle, t_load + phases.hold, phases, phases.record_every, judged
    )
