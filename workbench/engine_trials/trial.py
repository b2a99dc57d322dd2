"""One grasp trial: close by force, lift against gravity (and turn), hold; the verdict from
the object's pose relative to the gripper."""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from .. import config
from ..groups import checked_group
from ..units import check_turn_limit
from .pad import add_tips, compile_spec, conform_pad, flexcomp_xml, pad_bodies, pad_spec
from .settings import EngineSettings, import_mujoco

log = logging.getLogger(__name__)

#: real values quoted when a trial's drift limit is refused (a drift, not a pad's indentation)
_DRIFT_EXAMPLES = "the thesis labels a grasp failed beyond 9 mm and 5 deg of object motion (§4.1.3.1)"

#: task -> the gripper's turn about the grasp axis [deg] after lifting (thesis §4.3.3.3)
TASKS = {"vertical_lifting": 0.0, "lift_and_rotate": 90.0}

G = 9.81  # m/s², the magnitude MuJoCo's gravity is given


class EngineWarning(UserWarning):
    """MuJoCo warned during a trial (its warnings are in ``TrialOutcome.engine_warnings``): an
    instability — bad accelerations, a solver out of iterations, a degenerate inertia — can make
    the verdict unreliable."""


def check_record_count(record_every) -> int:
    """``record_every`` if it is an integer >= 1 (engine steps between recorded poses), else a
    ValueError; :func:`check_record_every` adds the bound the judged phases set."""
    if isinstance(record_every, bool) or not isinstance(record_every, (int, np.integer)) or record_every < 1:
        raise ValueError(
            f"record_every must be an integer >= 1 (steps between records); got {record_every!r}"
        )
    return int(record_every)


def check_flag(name: str, flag, meaning: str) -> bool:
    """``flag`` if it is a bool (a string such as "no" would read as True), else a ValueError."""
    if not isinstance(flag, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False ({meaning}); got {flag!r}")
    return bool(flag)


def check_record_every(record_every, judged: dict, timestep: float) -> int:
    """``record_every`` (engine steps between the poses a trial records and its verdict reads) if
    it is an integer >= 1 that leaves every judged phase (``judged``: {name: duration [s]}) at
    least ``config.TOL.engine_min_samples_per_phase`` recorded poses at ``timestep`` [s] — at most
    ``max(1, round(shortest / timestep) // 20)``, 25 for the default phases (hold 0.5 s) and 15 for
    a disturbance's (hold 0.3 s) at 1 ms — else a ValueError saying the bound."""
    check_record_count(record_every)
    fewest = config.TOL.engine_min_samples_per_phase
    name, shortest = min(judged.items(), key=lambda kv: kv[1])
    steps = int(round(shortest / timestep))
    limit = max(1, steps // fewest)
    if record_every > limit:
        raise ValueError(
            f"record_every = {record_every} records the object's pose every {record_every * timestep:.3g} s, "
            f"but the verdict (held, drift, turn) reads only the recorded poses: the shortest judged "
            f"phase, {name} ({shortest:g} s = {steps} steps of {timestep:g} s), must hold at least "
            f"{fewest} of them — pass record_every <= {limit} (the default, 10, records "
            f"every {10 * timestep:g} s), or lengthen {name}"
        )
    return int(record_every)


@dataclass(frozen=True)
class TrialPhases:
    """Durations [s] and motions of a trial; the defaults are the thesis's tasks at a
    robot's pace (5 cm in 1 s).  The verdict reads the poses recorded over lift, rotate (the
    lift_and_rotate task) and hold: each must span at least ``config.TOL.engine_min_samples_per_phase``
    records (:func:`check_record_every`)."""

    gap: float = 5e-4  # pad face to the object before closing [m]
    gravity_ramp: float = 0.1  # gravity switched on: the object settles on the table
    close: float = 0.3  # the jaws' force ramps from 0 to its value, the object on the table
    settle: float = 0.2  # the force held before lifting
    # the table's friction with the object (it holds the object while the jaws close, as a
    # real table does; the pads do not touch it)
    table_mu: float = 0.5
    # the gripper rises by `lift_height` along a smoothstep: peak acceleration 6 h / T² =
    # 0.3 m/s² (3 % of g on top of the weight) at the defaults
    lift: float = 1.0
    lift_height: float = 0.05  # [m]
    rotate: float = 1.0  # the turn of lift_and_rotate
    hold: float = 0.5  # held still at the end
    # held: the object moved less than this relative to the gripper from the end of settling
    max_drift: float = 5e-3  # [m]
    max_turn_deg: float = 5.0  # [deg]
    # engine steps between the recorded poses the verdict reads (:func:`check_record_every`)
    record_every: int = 10
    # a plane under the object, touching it only (False: the object floats free)
    table: bool = True
    # stop once the object is past every verdict limit (these phases' and VERDICT_LIMITS'): each
    # verdict is settled then, but the recorded drift and turn stop growing, so a ranking of
    # failed trials by how far the object went (engine_trials.reality's AUC) needs False
    stop_when_lost: bool = False

    def __post_init__(self) -> None:
        from ..plausible import check

        check_record_count(self.record_every)
        check_flag("table", self.table, "a table under the object, or none")
        check_flag("stop_when_lost", self.stop_when_lost, "stop a trial once the object is past every limit")
        for name in ("close", "settle", "gravity_ramp", "lift", "rotate", "hold"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0 < v <= 60):
                raise ValueError(f"TrialPhases.{name} must be a duration in (0, 60] s; got {v!r}")
        check("compression", self.gap, "TrialPhases.gap (pad face to object [m])", warn=False)
        check("mu", self.table_mu, "TrialPhases.table_mu")
        check(
            "lever",
            self.lift_height,
            "TrialPhases.lift_height [m]",
            warn=False,
            examples="a robot lifts an object 20-200 mm (the thesis: 5 cm)",
            named="lift height",
        )
        check(
            "closing",
            self.max_drift,
            "TrialPhases.max_drift (held below this drift [m])",
            warn=False,
            examples=_DRIFT_EXAMPLES,
            named="drift limit",
        )
        if not self.max_drift > 0:
            raise ValueError(f"TrialPhases.max_drift must be > 0 [m]; got {self.max_drift!r}")
        check_turn_limit(self.max_turn_deg, "TrialPhases.max_turn_deg")


def _vector(v) -> tuple[float, ...]:
    """``v`` (3,) as a tuple of floats (a value: no array shared with the caller)."""
    return tuple(float(x) for x in np.asarray(v, float).ravel())


@dataclass(frozen=True)
class EnginePad:
    """Each jaw's silicone pad in a trial: ``size`` = (width, length, thickness) [m], Young's
    modulus ``E`` [Pa] and Poisson's ratio ``nu``, its length along ``up`` (3,) [the object
    frame's]; ``conform``: moulded to the object at the phases' gap (:func:`~.pad.conform_pad`),
    else flat.  The grid the engine meshes it with is ``EngineSettings.pad_grid``.  Each value is
    checked by its plausible range (a size in mm, a modulus in MPa, ν in per cent are refused)."""

    size: tuple[float, float, float] = (0.02, 0.04, 0.005)
    E: float = 1e6
    nu: float = 0.45
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    conform: bool = False

    def __post_init__(self) -> None:
        from ..plausible import check
        from ..sources.jaws import check_direction

        size = self.size
        if not (isinstance(size, (tuple, list, np.ndarray)) and len(size) == 3):
            raise ValueError(f"pad must be (width, length, thickness) [m]; got {size!r}")
        check("pad_size", size[0], "pad width [m]")
        check("pad_size", size[1], "pad length [m]")
        check("pad_thickness", size[2], "pad thickness [m]")
        check("pad_modulus", self.E, "pad_E")
        check("poisson", self.nu, "pad_nu")
        check_direction(self.up, "up", "the pads' length direction, across the grasp axis")
        check_flag("conform", self.conform, "the pads moulded to the object, or flat")
        object.__setattr__(self, "size", tuple(float(x) for x in size))
        object.__setattr__(self, "up", _vector(self.up))


@dataclass(frozen=True)
class EngineObject:
    """The gripped object's physics in a trial (its shape is the mesh): ``mass`` [kg] at ``com``
    (3,) [m; None: the mesh's centroid], friction ``mu`` with the pads (None: the gripper's, in
    :func:`simulate_gripper` only), gravity along ``down`` (3,, the object frame's; a
    disturbance trial has no gravity and only lays the object's collision slabs across it).
    The rules that need the mesh (density, a centre of mass inside the hull) are applied by the
    simulators."""

    mass: float
    mu: float | None = None
    com: tuple[float, float, float] | None = None
    down: tuple[float, float, float] = (0.0, 0.0, -1.0)

    def __post_init__(self) -> None:
        from ..grasp.robust import check_com, check_object_mass
        from ..sources.jaws import check_direction
        from ..wrench import check_mu

        if self.mu is not None:
            check_mu(self.mu)
        check_object_mass(self.mass)
        if self.com is not None:
            object.__setattr__(self, "com", _vector(check_com(self.com)))
        check_direction(self.down, "down", "gravity's direction in the object frame")
        object.__setattr__(self, "down", _vector(self.down))


#: other verdict limits an experiment re-reads from its recorded trials (largest drift [mm],
#: turn [deg]): the thesis chose 9 mm / 5 deg so that half its grasps succeeded (§4.1.3.1)
VERDICT_LIMITS = ((2.0, 2.0), (5.0, 5.0), (9.0, 5.0), (9.0, 10.0))


@dataclass(frozen=True)
class TrialOutcome:
    """The verdict and the record of one simulated trial.

    held : the object stayed within ``phases.max_drift`` and ``max_turn_deg`` of its pose
        relative to the gripper from the end of settling to the end.
    drift, turn_deg : the largest such translation [m] and rotation [deg].
    slip_speed : the object's speed relative to the gripper over the final hold [m/s].
    times : (T,) [s]; rel_pos : (T, 3) the object's origin in the gripper frame [m];
    rel_turn_deg : (T,) its rotation from the settled pose [deg].
    seconds : wall time of the simulation; steps : engine steps taken (the trial's own and
        any shared).
    stopped_at : the time [s] the trial stopped, the object past every verdict limit
        (``phases.stop_when_lost``; ``drift`` and ``turn_deg`` are then those reached by that
        time, ``slip_speed`` NaN); None when it ran to its end.
    shared_steps : the steps this outcome took from another task's run of the same scene
        (:func:`simulate_grasp_tasks`: their control the same; those steps' wall time is in the
        first task's ``seconds``); 0 for a trial stepped alone and for the first task.
    reason : why it was not held ("" when held): a jaw that touched nothing after closing, or
        the drift or turn beyond the limits.
    engine_warnings : MuJoCo's warnings during the trial {name: count} (empty when none).
    """

    held: bool
    drift: float
    turn_deg: float
    slip_speed: float
    times: np.ndarray = field(repr=False)
    rel_pos: np.ndarray = field(repr=False)
    rel_turn_deg: np.ndarray = field(repr=False)
    seconds: float = 0.0
    steps: int = 0
    reason: str = ""
    engine_warnings: dict = field(default_factory=dict)
    shared_steps: int = 0
    stopped_at: float | None = None

    def row(self) -> dict:
        """The verdict and its measures as a checkpoint row (drift in mm)."""
        return {
            "held": self.held,
            "drift_mm": self.drift * 1e3,
            "turn_deg": self.turn_deg,
            "seconds": self.seconds,
            "steps": self.steps,
            "shared_steps": self.shared_steps,
            "stopped_at": self.stopped_at,
            "reason": self.reason,
            "engine_warnings": self.engine_warnings,
        }


def _check_grasp(grasp: dict, mesh=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(p1, p2, axis) of ``grasp`` (``sources.jaws.check_grasp``'s rule), each point on the
    surface of ``mesh`` within ``config.TOL.engine_grasp_point_max_offset_m``."""
    import trimesh

    from .. import config
    from ..sources.jaws import check_grasp

    p1, p2, axis = check_grasp(grasp)
    if mesh is not None:
        _, dist, _ = trimesh.proximity.closest_point(mesh, np.array([p1, p2]))
        tol = config.TOL.engine_grasp_point_max_offset_m
        for name, d in zip(("p1", "p2"), dist, strict=True):
            if d > tol:
                raise ValueError(
                    f"grasp point {name} is {d * 1e3:.3g} mm from the object's surface (at most "
                    f"{tol * 1e3:g} mm, config.TOL.engine_grasp_point_max_offset_m): give the contact points "
                    "on the surface, as antipodal_grasps does (a point in other units or off the object?)"
                )
    return p1, p2, axis


def _object_xml(mesh, mass: float, com, mu: float, settings: EngineSettings, down) -> tuple[str, str]:
    """(asset, body) MJCF of the rigid object: its convex pieces (:func:`.collision.collision_pieces`:
    the hull of a convex mesh, else slabs across gravity ``down``), ``mass`` [kg] with the mesh's
    inertia scaled to it about ``com`` (3,) [m]."""
    from .collision import collision_pieces

    assets, geoms = [], []
    for k, piece in enumerate(collision_pieces(mesh, down, settings.object_slab)):
        vs = " ".join(f"{x:.9g}" for x in np.asarray(piece.vertices, float).ravel())
        fs = " ".join(str(i) for i in np.asarray(piece.faces, int).ravel())
        assets.append(f'<mesh name="object{k}" vertex="{vs}" face="{fs}"/>')
        geoms.append(
            f'<geom type="mesh" mesh="object{k}" mass="0" contype="1" conaffinity="3" '
            f"{settings.contact_attrs(mu)}/>"
        )
    # the solid's inertia about its centroid, scaled to the given mass, moved to com
    I = np.asarray(mesh.moment_inertia, float) * (mass / mesh.mass)
    d = np.asarray(com, float) - np.asarray(mesh.center_mass, float)
    I = I + mass * ((d @ d) * np.eye(3) - np.outer(d, d))
    full = " ".join(f"{x:.9g}" for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
    c = " ".join(f"{x:.9g}" for x in com)
    body = (
        '<body name="object"><freejoint/>'
        f'<inertial pos="{c}" mass="{mass:g}" fullinertia="{full}"/>{"".join(geoms)}</body>'
    )
    return "".join(assets), body


def open_pad_depth(mesh, faces, axis, up, pad, grid: tuple[int, int] = (5, 9)) -> np.ndarray:
    """(2,) how deep [m] each open pad's face starts inside ``mesh`` (0 when clear): the largest
    signed distance into the object of a ``grid`` of points over each face (width across ``up``,
    length along it), face ``k`` centred at ``faces[k]`` (3,) looking along ``±axis``."""
    import trimesh

    from ..sources.jaws import check_direction
    from .pad import pad_rotation

    axis = check_direction(axis, "axis", "the grasp axis, jaw 1's closing direction")
    out = []
    for face, a in zip(faces, (axis, -axis), strict=True):
        R = pad_rotation(a, np.asarray(up, float))
        u = np.linspace(-pad[0] / 2, pad[0] / 2, grid[0])
        v = np.linspace(-pad[1] / 2, pad[1] / 2, grid[1])
        U, V = np.meshgrid(u, v, indexing="ij")
        pts = np.asarray(face, float) + np.outer(U.ravel(), R[:, 0]) + np.outer(V.ravel(), R[:, 1])
        depth = trimesh.proximity.signed_distance(mesh, pts)  # > 0 inside
        out.append(max(0.0, float(depth.max())))
    return np.array(out)


def _miss(reason: str) -> TrialOutcome:
    """The outcome of a trial that cannot start: not held, nothing simulated."""
    log.info("engine trial: not run — %s", reason)
    empty = np.zeros(0)
    nan = float("nan")
    return TrialOutcome(False, nan, nan, nan, empty, np.zeros((0, 3)), empty, 0.0, 0, reason, {})


def _starts_inside(mesh, faces, axis, up, pad) -> str:
    """Why the open pads cannot close on the object ("" when they can): a face that starts
    deeper inside it than the pad is thick (an object wider than the opening, a grasp point
    inside the object)."""
    depth = open_pad_depth(mesh, faces, axis, up, pad)
    deep = [k for k in (0, 1) if depth[k] > pad[2]]
    if not deep:
        return ""
    which = " and ".join(f"jaw {k + 1}" for k in deep)
    return (
        f"the open pad of {which} starts {depth[deep].max() * 1e3:.3g} mm inside the object (its "
        f"thickness {pad[2] * 1e3:.3g} mm): the object is wider than the opening, or the grasp is "
        "inside it"
    )


def build_scene(
    mesh,
    faces,
    axis,
    *,
    force: float,
    obj: EngineObject,
    pad: EnginePad | None = None,
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
):
    """(MjModel, info) of a trial scene: the object ``obj`` (its frame = world at the start;
    ``obj.mu`` given), a gripper (a lifting carriage and a turning wrist) with two jaws on slide
    joints along ``axis`` (3,; jaw 1 closes along it, jaw 2 against it), each with a flex ``pad``
    whose face centre starts at ``faces[k]`` (3,) [m]; ``info`` holds ids and the pads' tip
    counts.  ``phases.table``: a plane under the object (False: the object floats free);
    ``pad.conform``: each pad moulded to the object at ``phases.gap`` (:func:`~.pad.conform_pad`),
    not flat."""
    import_mujoco()  # the extra's ImportError before any work
    settings = EngineSettings() if settings is None else settings
    phases = TrialPhases() if phases is None else phases
    pad = EnginePad() if pad is None else pad
    from ..sources.jaws import check_direction

    axis = check_direction(axis, "axis", "the grasp axis, jaw 1's closing direction")
    f1, f2 = (np.asarray(f, float) for f in faces)
    mu, down, size = obj.mu, obj.down, pad.size
    com = np.asarray(mesh.center_mass if obj.com is None else obj.com, float)
    asset, body = _object_xml(mesh, obj.mass, com, mu, settings, down)
    jaws = []
    for k, (face, a) in enumerate(((f1, axis), (f2, -axis)), start=1):
        pad_xml = flexcomp_xml(f"pad{k}", size, pad.E, pad.nu, face, a, np.asarray(pad.up, float), settings)
        ax = " ".join(f"{x:.12g}" for x in a)
        back = face - (size[2] + 1e-3) * a
        bp = " ".join(f"{x:.9g}" for x in back)
        jaws.append(
            f'<body name="jaw{k}" gravcomp="1"><joint name="jaw{k}" type="slide" axis="{ax}" damping="200" '
            f'range="-0.01 0.05"/>'
            f'<geom type="sphere" size="0.002" pos="{bp}" mass="0.05" contype="0" conaffinity="0"/>'
            f"{pad_xml}</body>"
        )
    # the gripper: a carriage rising against gravity, a wrist turning about the grasp axis
    # through the grasp's centre, each a stiff position servo (flex pads cannot ride a mocap body)
    lift_dir = -np.asarray(down, float) / np.linalg.norm(down)
    ld = " ".join(f"{x:.12g}" for x in lift_dir)
    # the table: a plane under the object's lowest point along gravity, touching the object only
    base = float(np.min(np.asarray(mesh.vertices, float) @ lift_dir))
    tp = " ".join(f"{x:.9g}" for x in base * lift_dir)
    table = (
        f'<geom name="table" type="plane" size="0 0 1" pos="{tp}" zaxis="{ld}" contype="1" '
        f'conaffinity="1" {settings.contact_attrs(phases.table_mu)}/>'
        if phases.table
        else ""
    )
    ax = " ".join(f"{x:.12g}" for x in axis)
    ctr = " ".join(f"{x:.9g}" for x in 0.5 * (f1 + f2))
    xml = (
        f"<mujoco>{settings.option_xml()}<size memory='200M'/><asset>{asset}</asset><worldbody>"
        f"{table}{body}"
        f'<body name="carriage" gravcomp="1"><joint name="lift" type="slide" axis="{ld}"/>'
        f'<geom type="sphere" size="0.002" mass="0.5" contype="0" conaffinity="0"/>'
        f'<body name="hand" gravcomp="1"><joint name="turn" type="hinge" axis="{ax}" pos="{ctr}"/>'
        f'<geom type="sphere" size="0.002" pos="{ctr}" mass="0.5" contype="0" conaffinity="0"/>'
        f"{''.join(jaws)}</body></body>"
        "</worldbody><actuator>"
        '<motor name="jaw1" joint="jaw1" gear="1"/><motor name="jaw2" joint="jaw2" gear="1"/>'
        '<position name="lift" joint="lift" kp="2e5" dampratio="1"/>'
        '<position name="turn" joint="turn" kp="2e3" dampratio="1"/>'
        "</actuator></mujoco>"
    )
    spec = pad_spec(xml)
    tips = []
    for k, a in ((1, axis), (2, -axis)):
        _, _, face = pad_bodies(spec, f"pad{k}", a)
        if pad.conform:
            conform_pad(spec, f"pad{k}", a, float(size[2]), mesh, phases.gap)
        tips.append(add_tips(spec, f"pad{k}", a, mu, settings, face=face))
    model = compile_spec(spec)
    info = {
        "object": model.body("object").id,
        "hand": model.body("hand").id,
        "tips": tips,
        "axis": axis,
        "force": float(force),
    }
    return model, info


def _rotvec_deg(R: np.ndarray) -> float:
    c = (np.trace(R) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _check_task(task) -> None:
    if not (isinstance(task, str) and task in TASKS):
        raise ValueError(f"task must be one of {tuple(TASKS)}; got {task!r}")


def _check_trial(mesh, caller: str, task, obj: EngineObject):
    """The inputs the simulators share, checked: ``(mesh, obj)`` (the mesh watertight, outward,
    in metres; ``obj`` an :class:`EngineObject` with μ given, its mass by the density rule, its
    centre of mass near the object — filled in from the mesh when None — and gravity a unit
    direction); :func:`_check_run` checks the phases and settings next."""
    import_mujoco()  # the extra's ImportError before any other message
    from ..grasp.robust import check_com, check_object_mass
    from ..sources.jaws import check_direction
    from ..units import closed_mesh
    from ..wrench import check_mu

    if not isinstance(obj, EngineObject):
        raise ValueError(f"obj must be an EngineObject (mass, mu, com, down); got {type(obj).__name__}")
    _check_task(task)
    # the trials take metres only (no units= argument): the remedy is to scale the mesh
    mesh = closed_mesh(
        mesh,
        f"mesh passed to {caller}",
        fix="scale it by {factor:g} first: mesh.apply_scale({factor:g})",
        override=None,
    )
    if obj.mu is None:
        raise ValueError(
            f"EngineObject.mu (the pad–object friction) must be given to {caller}; None takes the "
            "gripper's only in simulate_gripper"
        )
    mu = check_mu(obj.mu)
    check_object_mass(obj.mass, mesh)
    com = check_com(mesh.center_mass if obj.com is None else obj.com, mesh)
    down = check_direction(obj.down, "down", "gravity's direction in the object frame")
    return mesh, replace(obj, mu=mu, com=com, down=down)


def _check_run(phases, settings) -> tuple[TrialPhases, EngineSettings]:
    """``(phases, settings)``, each its default when None, checked to be of their types."""
    phases = TrialPhases() if phases is None else phases
    settings = EngineSettings() if settings is None else settings
    if not isinstance(phases, TrialPhases) or not isinstance(settings, EngineSettings):
        raise ValueError(
            f"phases must be a TrialPhases and settings an EngineSettings; got "
            f"{type(phases).__name__}, {type(settings).__name__} — pass e.g. TrialPhases(hold=0.3) "
            "and EngineSettings(...), or leave them out for the defaults"
        )
    return phases, settings


def _check_force(force, pad) -> EnginePad:
    """The jaw force [N], checked by its plausible range, and ``pad`` an :class:`EnginePad` (which
    checks its own values; None: the default pad)."""
    from ..plausible import check

    check("jaw_force", force, "force")
    return checked_group(
        pad, EnginePad, "pad", hint="pass EnginePad(size=(width, length, thickness)) for a size [m]"
    )


def _check_up_down(up, down: np.ndarray) -> None:
    """ValueError unless gravity ``down`` (3,, unit) points away from the pads' ``up`` (3,): at
    least 90 deg from it (a pad lying across gravity at 90, the upright side grasp at 180).  A
    gravity with a component along ``up`` contradicts the name — a sign slip in one of them."""
    u = np.asarray(up, float) / np.linalg.norm(np.asarray(up, float))
    flip = (np.round(-u, 4) + 0.0).tolist()  # + 0.0: no "-0.0" in the message
    angle = float(np.degrees(np.arccos(np.clip(u @ down, -1.0, 1.0))))
    # 1e-6 deg: a perpendicular pair computed from a rotation is 90 deg only to rounding
    if angle < 90.0 - 1e-6:
        raise ValueError(
            f"down {np.round(down, 4).tolist()} (gravity) is {angle:.3g} deg from up "
            f"{np.round(u, 4).tolist()} (the pads' length direction): it must be at least 90 deg from it "
            "(90: pads lying across gravity; 180: the upright side grasp) — gravity along up is a sign "
            f"slip: pass down = {flip}, or, for an object meant upside down in its frame, up = {flip} "
            "(the same pad, turned end over end)"
        )


def simulate_grasp(
    mesh,
    grasp: dict,
    *,
    force: float,
    obj: EngineObject,
    pad: EnginePad | None = None,
    task: str = "vertical_lifting",
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
) -> TrialOutcome:
    """Simulate one trial of the grasp ``grasp`` (``p1``, ``p2``, ``axis`` in the frame of the
    watertight ``mesh`` [m]) with jaw force ``force`` [N] on the object ``obj`` (its mass [kg],
    pad–object friction μ, centre of mass (3,) [m; default the mesh's centroid] and gravity's
    direction ``down`` (3,, the object frame's)) and ``task`` ("vertical_lifting" or
    "lift_and_rotate": the gripper then turns by 90° about the grasp axis).  ``pad``: the silicone
    of each jaw (:class:`EnginePad`), its length along ``pad.up``, which must be at least 90 deg
    from ``obj.down`` (gravity may lie across the pads or along their length against ``up``,
    never along ``up``: a sign slip); a conforming pad is moulded to the object and not judged
    by where its flat face would start.

    ``phases.record_every``: engine steps between the recorded poses the verdict reads; each
    judged phase (lift, the turn of lift_and_rotate, hold) must span at least
    ``config.TOL.engine_min_samples_per_phase`` of them (:func:`check_record_every`): at most 25 at
    the default phases and 1 ms step, 10 by default.

    Returns a :class:`TrialOutcome`; its verdict, ``held``, is the engine's: no contact model of
    this package is used.  MuJoCo's own warnings during the trial are recorded in its
    ``engine_warnings`` and raised as an :class:`EngineWarning`.
    """

    _check_task(task)
    return simulate_grasp_tasks(
        mesh, grasp, force=force, obj=obj, pad=pad, tasks=(task,), settings=settings, phases=phases
    )[task]


def _check_tasks(tasks) -> tuple[str, ...]:
    """``tasks`` as a tuple of distinct task names (:data:`TASKS`), at least one, in the given
    order (a list or tuple: the first task's outcome carries the shared steps' time)."""
    hint = f"e.g. tasks={tuple(TASKS)!r}, or tasks=('vertical_lifting',) for one"
    if isinstance(tasks, str):
        raise ValueError(
            f"tasks must be a list or tuple of task names, not one name; got {tasks!r} — pass "
            f"tasks=({tasks!r},), or simulate_grasp(..., task={tasks!r}) for one trial"
        )
    if not isinstance(tasks, (list, tuple)):
        raise ValueError(
            f"tasks must be a list or tuple of task names from {tuple(TASKS)} (an ordered sequence: "
            f"the first carries the shared steps' time); got {tasks!r} — {hint}"
        )
    out = tuple(tasks)
    bad = [t for t in out if not (isinstance(t, str) and t in TASKS)]
    if bad:
        raise ValueError(f"tasks must be names from {tuple(TASKS)}; {bad[0]!r} is not a task — {hint}")
    if not out or len(set(out)) != len(out):
        raise ValueError(f"tasks must be distinct names, at least one; got {tasks!r} — {hint}")
    return out


def simulate_grasp_tasks(
    mesh,
    grasp: dict,
    *,
    force: float,
    obj: EngineObject,
    pad: EnginePad | None = None,
    tasks=tuple(TASKS),
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
) -> dict[str, TrialOutcome]:
    """{task: TrialOutcome}: the trials of one grasp for each of ``tasks`` (default both of
    :data:`TASKS`), each as :func:`simulate_grasp` would simulate it alone — bit for bit —
    on one scene: the tasks' control is the same until the turn starts at the end of the lift,
    so those steps are taken once (each outcome's ``shared_steps``; their wall time is in the
    first task's ``seconds``) and each task goes on from a copy of the engine's state.  The
    arguments are those of :func:`simulate_grasp`."""
    tasks = _check_tasks(tasks)
    mesh, obj = _check_trial(mesh, "simulate_grasp", tasks[0], obj)  # every task already checked
    phases, settings = _check_run(phases, settings)
    pad = _check_force(force, pad)
    _check_up_down(pad.up, np.asarray(obj.down))
    for task in tasks:
        check_record_every(phases.record_every, _judged(phases, task), settings.timestep)
    p1, p2, axis = _check_grasp(grasp, mesh)
    faces = (p1 - phases.gap * axis, p2 + phases.gap * axis)  # each pad's face gap before its point
    inside = "" if pad.conform else _starts_inside(mesh, faces, axis, pad.up, pad.size)
    if inside:
        return dict.fromkeys(tasks, _miss(inside))
    model, info = build_scene(
        mesh, faces, axis, force=force, obj=obj, pad=pad, settings=settings, phases=phases
    )
    return _run_tasks(model, info, force, obj.down, tasks, phases)


def _judged(phases: TrialPhases, task: str) -> dict:
    """{name: duration [s]} of the phases a trial's verdict reads (after settling)."""
    judged = {"TrialPhases.lift": phases.lift, "TrialPhases.hold": phases.hold}
    if TASKS[task]:
        judged["TrialPhases.rotate"] = phases.rotate
    return judged


def _lift_times(phases: TrialPhases) -> tuple[float, float, float]:
    """(gravity on, settled, lifted) [s]: the ends of a lifting trial's first phases."""
    t_grav = phases.gravity_ramp
    t_settle = t_grav + phases.close + phases.settle
    return t_grav, t_settle, t_settle + phases.lift


def _lift_control(force: float, down, task: str, phases: TrialPhases):
    """``control(t, model, data)`` of a lifting trial of ``task``: gravity on, the jaws' force
    ramped, a smooth rise, then (lift_and_rotate) a smooth turn about the grasp axis."""
    g_dir = np.asarray(down, float) / np.linalg.norm(down)
    t_grav, t_settle, t_lift = _lift_times(phases)
    turn = np.radians(TASKS[task])

    def control(t: float, model, data) -> None:
        model.opt.gravity[:] = G * min(1.0, t / t_grav) * g_dir
        data.ctrl[:2] = force * np.clip((t - t_grav) / phases.close, 0.0, 1.0)
        # the gripper's motion: a smooth rise, then a smooth turn about the grasp axis
        u = np.clip((t - t_settle) / phases.lift, 0.0, 1.0)
        data.ctrl[2] = phases.lift_height * (3 * u**2 - 2 * u**3)
        if turn:
            v = np.clip((t - t_lift) / phases.rotate, 0.0, 1.0)
            data.ctrl[3] = turn * (3 * v**2 - 2 * v**3)

    return control


def _lift_end(task: str, phases: TrialPhases) -> float:
    """The end [s] of a lifting trial of ``task``."""
    return _lift_times(phases)[2] + (phases.rotate if TASKS[task] else 0.0) + phases.hold


def _run_tasks(model, info: dict, force: float, down, tasks: tuple, phases: TrialPhases) -> dict:
    """{task: TrialOutcome}: the trials of ``tasks`` on one scene.  Every task's control is the
    same until the turn starts (at the end of the lift), so the steps before it are stepped once
    and each task goes on from a copy of that state: the outcomes are those of separate trials,
    bit for bit (MuJoCo's step is a function of its model and data); the shared steps' wall time
    is counted in the first task's ``seconds``."""
    _, t_settle, t_lift = _lift_times(phases)
    dt = model.opt.timestep
    # steps whose time is half a step or more before the lift's end (the lift's last step is
    # each task's own): the turn's smoothstep is exactly 0 there (its argument clipped), so
    # every task's control is the same
    t_fork = t_lift - 0.5 * dt
    n_fork = max(0, int(np.floor(t_fork / dt)))
    first = _lift_control(force, down, tasks[0], phases)
    shared = _Track.start(model, info)
    lost = _lost_limits(phases)
    shared.advance(model, first, t_settle, 0, n_fork, None, phases.record_every, lost)
    n_shared = shared.steps
    out = {}
    for k, task in enumerate(tasks):
        track = shared if k == len(tasks) - 1 else shared.copy()
        if k:
            track.seconds = 0.0  # the shared steps are the first task's
        t_end = _lift_end(task, phases)
        n = int(round(t_end / dt))
        control = _lift_control(force, down, task, phases)
        track.advance(model, control, t_settle, n_fork, n, n, phases.record_every, lost)
        out[task] = _judge(track, t_end, phases, shared_steps=n_shared if k else 0)
    return out


def step_trial(
    model,
    info: dict,
    control,
    t_ref: float,
    t_end: float,
    phases,
    record_every: int = 10,
    judged: dict | None = None,
) -> TrialOutcome:
    """Step a scene of :func:`build_scene` to ``t_end`` [s], calling ``control(t, model, data)``
    before each step, and judge it: the object's pose relative to the gripper (the ``hand``
    body) is recorded from ``t_ref`` [s] on, and it is held iff it stays within
    ``phases.max_drift`` [m] and ``phases.max_turn_deg`` of its pose at ``t_ref`` and both jaws
    touch something at ``t_ref``; the slip speed is measured over the last ``phases.hold``.

    The pose is recorded every ``record_every`` steps, and the verdict reads only those: each
    phase of ``judged`` ({name: duration [s]}; default the recorded window and ``phases.hold``)
    must span at least ``config.TOL.engine_min_samples_per_phase`` records (:func:`check_record_every`).  The
    reason of a failure names the limit crossed first (a spin that then throws the object out
    is a turn).  MuJoCo's warnings are recorded in ``engine_warnings`` and raised as an
    :class:`EngineWarning`."""
    judged = {"the recorded window": t_end - t_ref, "phases.hold": phases.hold} if judged is None else judged
    check_record_every(record_every, judged, model.opt.timestep)
    n = int(round(t_end / model.opt.timestep))
    track = _Track.start(model, info)
    track.advance(model, control, t_ref, 0, n, n, record_every, _lost_limits(phases))
    return _judge(track, t_end, phases)


class _Track:
    """A trial's engine state and its record so far: the object's pose relative to the ``hand``
    body every ``record_every`` steps from ``t_ref`` on (and at the trial's last step), whether
    each jaw's tips touched something at the first record, and the stepping's wall time."""

    def __init__(self, data, info: dict, tips: list) -> None:
        self.data, self.info, self.tips = data, info, tips
        self.times: list = []
        self.rel_p: list = []
        self.rel_turn: list = []
        self.ref: tuple | None = None
        self.touching: list | None = None
        self.seconds = 0.0
        self.steps = 0
        self.stopped_at: float | None = None

    @classmethod
    def start(cls, model, info: dict) -> _Track:
        """A new trial's track: fresh engine data, nothing recorded."""
        mujoco = import_mujoco()
        # each pad's tip geoms: after closing, a jaw whose tips touch nothing holds nothing
        tips = [
            {g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.startswith(f"pad{k}_")}
            for k in (1, 2)
        ]
        return cls(mujoco.MjData(model), info, tips)

    def copy(self) -> _Track:
        """An independent copy: the engine data (``copy.copy`` of MjData is MuJoCo's
        mj_copyData) and the record."""
        import copy

        out = _Track(copy.copy(self.data), self.info, self.tips)
        out.times, out.rel_p, out.rel_turn = list(self.times), list(self.rel_p), list(self.rel_turn)
        out.ref, out.touching, out.seconds = self.ref, self.touching, self.seconds
        out.steps, out.stopped_at = self.steps, self.stopped_at
        return out

    def advance(
        self,
        model,
        control,
        t_ref: float,
        i0: int,
        i1: int,
        n: int | None,
        record_every: int,
        lost: tuple[float, float] | None = None,
    ) -> None:
        """Steps ``i0 .. i1 - 1`` of a trial of ``n`` steps (None: not its end), each at time
        ``(i + 1) dt`` after ``control(t, model, data)``; with ``lost`` (drift [m], turn [deg])
        it stops at the first record beyond either (``stopped_at``), and a stopped track takes
        no more steps."""
        if self.stopped_at is not None:
            return
        mujoco = import_mujoco()
        data, dt = self.data, model.opt.timestep
        obj, hand = self.info["object"], self.info["hand"]
        last = -1 if n is None else n - 1
        t0 = time.perf_counter()
        for i in range(i0, i1):
            t = (i + 1) * dt
            control(t, model, data)
            mujoco.mj_step(model, data)
            self.steps += 1
            if t >= t_ref and (i % record_every == 0 or i == last):
                Rh = data.xmat[hand].reshape(3, 3)
                ph = data.xpos[hand]
                Ro = data.xmat[obj].reshape(3, 3)
                po = Rh.T @ (data.xpos[obj] - ph)
                Rrel = Rh.T @ Ro
                if self.ref is None:
                    self.ref = (po.copy(), Rrel.copy())
                    geoms = {int(g) for c in data.contact[: data.ncon] for g in c.geom}
                    self.touching = [bool(t_k & geoms) for t_k in self.tips]
                turn = _rotvec_deg(self.ref[1].T @ Rrel)
                self.times.append(t)
                self.rel_p.append(po)
                self.rel_turn.append(turn)
                if lost is not None and (np.linalg.norm(po - self.ref[0]) > lost[0] or turn > lost[1]):
                    self.stopped_at = t
                    break
        self.seconds += time.perf_counter() - t0


def _lost_limits(phases) -> tuple[float, float] | None:
    """(drift [m], turn [deg]) past which every verdict a trial's record is read at is settled —
    ``phases``' own limits and :data:`VERDICT_LIMITS` — when ``phases.stop_when_lost``, else None."""
    if not getattr(phases, "stop_when_lost", False):
        return None
    drift = max(phases.max_drift, max(d for d, _ in VERDICT_LIMITS) * 1e-3)
    return drift, max(phases.max_turn_deg, max(t for _, t in VERDICT_LIMITS))


def _judge(track: _Track, t_end: float, phases, shared_steps: int = 0) -> TrialOutcome:
    """The :class:`TrialOutcome` of a track finished at ``t_end`` [s] or stopped before it."""
    times, rel_p, rel_turn = np.array(track.times), np.array(track.rel_p), np.array(track.rel_turn)
    drift = np.linalg.norm(rel_p - rel_p[0], axis=1)
    last = times >= t_end - phases.hold
    if track.stopped_at is not None:
        slip = float("nan")  # the hold was not reached
    else:
        span = times[last][-1] - times[last][0]
        slip = float(np.linalg.norm(rel_p[last][-1] - rel_p[last][0]) / span) if span > 0 else 0.0
    held, reason = _verdict(times, drift, rel_turn, track.touching, phases)
    engine_warnings = _engine_warnings(track.data, held)
    log.info(
        "engine trial: %s, drift %.2f mm, turn %.2f deg, %d steps in %.1f s",
        "held" if held else "slipped",
        drift.max() * 1e3,
        rel_turn.max(),
        track.steps,
        track.seconds,
    )
    return TrialOutcome(
        held,
        float(drift.max()),
        float(rel_turn.max()),
        slip,
        times,
        rel_p,
        rel_turn,
        track.seconds,
        track.steps,
        reason,
        engine_warnings,
        shared_steps,
        track.stopped_at,
    )


def _verdict(
    times: np.ndarray, drift: np.ndarray, rel_turn: np.ndarray, touching, phases
) -> tuple[bool, str]:
    """(held, reason) of a recorded trial: held iff the ``drift`` (T,) [m] and ``rel_turn``
    (T,) [deg] stay within ``phases.max_drift`` and ``phases.max_turn_deg`` and both jaws
    were ``touching``; the reason names the limit crossed first ("" when held)."""
    held = bool(drift.max() <= phases.max_drift and rel_turn.max() <= phases.max_turn_deg)
    reason = ""
    # the first recorded pose beyond each limit (len(times): never): a spin that then throws the
    # object out of the jaws slides it far, but it failed by turning
    slid, turned = drift > phases.max_drift, rel_turn > phases.max_turn_deg
    i_slid = int(np.argmax(slid)) if slid.any() else len(times)
    i_turn = int(np.argmax(turned)) if turned.any() else len(times)
    slid_by = f"slid {drift.max() * 1e3:.3g} mm (limit {phases.max_drift * 1e3:g} mm)"
    turned_by = f"turned {rel_turn.max():.3g} deg (limit {phases.max_turn_deg:g} deg)"
    if touching is not None and not all(touching):
        held = False
        missed = " and ".join(f"jaw {k + 1}" for k, t_k in enumerate(touching) if not t_k)
        reason = f"{missed} touched nothing after closing (the grasp misses the object?)"
    elif slid.any() and i_slid <= i_turn:
        reason = f"the object {slid_by}"
    elif slid.any():
        reason = (
            f"the object {turned_by} first, past its limit at {times[i_turn]:.3g} s, then {slid_by} "
            f"from {times[i_slid]:.3g} s"
        )
    elif turned.any():
        reason = f"the object {turned_by}"
    return held, reason


def _engine_warnings(data, held: bool) -> dict:
    """MuJoCo's warnings during a trial {name: count}, logged and raised as an
    :class:`EngineWarning` (pointing at :func:`step_trial`'s caller) when any."""
    mujoco = import_mujoco()
    engine_warnings = {
        mujoco.mjtWarning(k).name: int(w.number) for k, w in enumerate(data.warning) if w.number > 0
    }
    if engine_warnings:
        # an instability (bad qacc, a solver that ran out of iterations) makes a verdict unreliable
        log.warning("engine trial: MuJoCo warned %s; the verdict may not be reliable", engine_warnings)
        warnings.warn(
            f"MuJoCo warned {engine_warnings} during the trial (recorded in TrialOutcome.engine_warnings): "
            f"the verdict ({'held' if held else 'not held'}) may not be reliable — an instability (bad "
            "accelerations, a solver out of iterations, a degenerate inertia) usually comes from an input "
            "far from the validated settings (a pad or object the 1 ms step cannot resolve)",
            EngineWarning,
            stacklevel=3,
        )
    return engine_warnings


def simulate_gripper(
    mesh,
    gripper,
    pose,
    *,
    obj: EngineObject,
    task: str = "vertical_lifting",
    pad_nu: float = 0.45,
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
) -> TrialOutcome:
    """Simulate one trial of ``gripper`` (a :class:`~workbench.sources.gripper.Gripper`, e.g.
    ``yumi()``) at ``pose`` (4, 4: the gripper frame in the object frame [m], e.g. a physical
    trial's :attr:`~workbench.sources.trials.Trials.gripper_pose`), open by its opening, closing
    each jaw with ``gripper.force`` [N] until its pad meets whatever it meets — as the robot did.

    Each pad is the rectangle that bounds the gripper's pad outline (in its tooltip frame, the
    outline's centre offset kept), ``gripper.pad.thickness`` thick, of ``gripper.pad.modulus``
    and ``pad_nu``.  The object ``obj``: its μ defaults (None) to ``gripper.mu``; its mass [kg]
    at its centre of mass (3,) [m], gravity along its ``down`` (3,; the object frame's, e.g. the
    trial's); ``task`` and ``phases`` (its ``record_every``) as :func:`simulate_grasp`.
    """
    from ..sources.gripper import check_gripper

    gripper = check_gripper(gripper)
    if isinstance(obj, EngineObject) and obj.mu is None:
        obj = replace(obj, mu=gripper.mu)
    mesh, obj = _check_trial(mesh, "simulate_gripper", task, obj)
    phases, settings = _check_run(phases, settings)
    check_record_every(phases.record_every, _judged(phases, task), settings.timestep)
    jaws = gripper.jaws(pose)  # checks the pose
    lo, hi = jaws[0].outline.min(axis=0), jaws[0].outline.max(axis=0)
    c, size = (lo + hi) / 2, hi - lo
    faces = [j.origin + c[0] * j.e1 + c[1] * j.e2 for j in jaws]
    pad = EnginePad(
        size=(float(size[0]), float(size[1]), gripper.pad.thickness),
        E=gripper.pad.modulus,
        nu=pad_nu,
        up=jaws[0].e2,
    )
    inside = _starts_inside(mesh, faces, jaws[0].closing, pad.up, pad.size)
    if inside:
        return _miss(inside)
    model, info = build_scene(
        mesh, faces, jaws[0].closing, force=gripper.force, obj=obj, pad=pad, settings=settings, phases=phases
    )
    return _run_tasks(model, info, gripper.force, obj.down, (task,), phases)[task]
