"""One grasp trial: close by force, lift against gravity (and turn), hold; the verdict from
the object's pose relative to the gripper."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from .pad import add_tips, compile_spec, flexcomp_xml
from .settings import EngineSettings, import_mujoco

log = logging.getLogger(__name__)

#: task -> the gripper's turn about the grasp axis [deg] after lifting (thesis §4.3.3.3)
TASKS = {"vertical_lifting": 0.0, "lift_and_rotate": 90.0}

G = 9.81  # m/s², the magnitude MuJoCo's gravity is given


@dataclass(frozen=True)
class TrialPhases:
    """Durations [s] and motions of a trial; the defaults are the thesis's tasks at a
    robot's pace (5 cm in 1 s)."""

    gap: float = 5e-4  # pad face to the object before closing [m]
    close: float = 0.3  # the jaws' force ramps from 0 to its value
    settle: float = 0.2  # the force held, still without gravity
    gravity_ramp: float = 0.1  # gravity switched on (the object lifted off a support)
    # the gripper rises by `lift_height` along a smoothstep: peak acceleration 6 h / T² =
    # 0.3 m/s² (3 % of g on top of the weight) at the defaults
    lift: float = 1.0
    lift_height: float = 0.05  # [m]
    rotate: float = 1.0  # the turn of lift_and_rotate
    hold: float = 0.5  # held still at the end
    # held: the object moved less than this relative to the gripper from the end of settling
    max_drift: float = 5e-3  # [m]
    max_turn_deg: float = 5.0  # [deg]


@dataclass(frozen=True)
class TrialOutcome:
    """The verdict and the record of one simulated trial.

    held : the object stayed within ``phases.max_drift`` and ``max_turn_deg`` of its pose
        relative to the gripper from the end of settling to the end.
    drift, turn_deg : the largest such translation [m] and rotation [deg].
    slip_speed : the object's speed relative to the gripper over the final hold [m/s].
    times : (T,) [s]; rel_pos : (T, 3) the object's origin in the gripper frame [m];
    rel_turn_deg : (T,) its rotation from the settled pose [deg].
    seconds : wall time of the simulation; steps : engine steps.
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


def _check_grasp(grasp: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    from ..sources.jaws import check_grasp

    return check_grasp(grasp)


def _object_xml(mesh, mass: float, com, mu: float, settings: EngineSettings) -> tuple[str, str]:
    """(asset, body) MJCF of the rigid object: its mesh (MuJoCo collides with its convex hull),
    ``mass`` [kg] with the mesh's inertia scaled to it about ``com`` (3,) [m]."""
    v = np.asarray(mesh.vertices, float)
    f = np.asarray(mesh.faces, int)
    vs = " ".join(f"{x:.9g}" for x in v.ravel())
    fs = " ".join(str(i) for i in f.ravel())
    asset = f'<mesh name="object" vertex="{vs}" face="{fs}"/>'
    # the solid's inertia about its centroid, scaled to the given mass, moved to com
    I = np.asarray(mesh.moment_inertia, float) * (mass / mesh.mass)
    d = np.asarray(com, float) - np.asarray(mesh.center_mass, float)
    I = I + mass * ((d @ d) * np.eye(3) - np.outer(d, d))
    full = " ".join(f"{x:.9g}" for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
    c = " ".join(f"{x:.9g}" for x in com)
    body = (
        '<body name="object"><freejoint/>'
        f'<inertial pos="{c}" mass="{mass:g}" fullinertia="{full}"/>'
        f'<geom type="mesh" mesh="object" mass="0" contype="1" conaffinity="3" {settings.contact_attrs(mu)}/>'
        "</body>"
    )
    return asset, body


def build_model(
    mesh,
    grasp: dict,
    *,
    force: float,
    mu: float,
    mass: float,
    com=None,
    pad=(0.02, 0.04, 0.005),
    pad_E: float = 1e6,
    pad_nu: float = 0.45,
    up=(0.0, 0.0, 1.0),
    down=(0.0, 0.0, -1.0),
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
):
    """(MjModel, info) of a trial scene: the object (frame = world at the start), a mocap
    gripper at the origin with two jaws on slide joints along the grasp axis, each with a flex
    pad whose face is ``phases.gap`` from its contact point; ``info`` holds ids and the pads'
    tip counts."""
    mujoco = import_mujoco()
    settings = EngineSettings() if settings is None else settings
    phases = TrialPhases() if phases is None else phases
    p1, p2, axis = _check_grasp(grasp)
    com = np.asarray(mesh.center_mass if com is None else com, float)
    asset, body = _object_xml(mesh, mass, com, mu, settings)
    jaws = []
    for k, (p, a) in enumerate(((p1, axis), (p2, -axis)), start=1):
        face = p - phases.gap * a
        pad_xml = flexcomp_xml(f"pad{k}", tuple(pad), pad_E, pad_nu, face, a, np.asarray(up, float), settings)
        ax = " ".join(f"{x:.12g}" for x in a)
        back = face - (pad[2] + 1e-3) * a
        bp = " ".join(f"{x:.9g}" for x in back)
        jaws.append(
            f'<body name="jaw{k}"><joint name="jaw{k}" type="slide" axis="{ax}" damping="200" '
            f'range="-0.01 0.05"/>'
            f'<geom type="sphere" size="0.002" pos="{bp}" mass="0.05" contype="0" conaffinity="0"/>'
            f"{pad_xml}</body>"
        )
    # the gripper: a carriage rising against gravity, a wrist turning about the grasp axis
    # through the grasp's centre, each a stiff position servo (flex pads cannot ride a mocap body)
    lift_dir = -np.asarray(down, float) / np.linalg.norm(down)
    ld = " ".join(f"{x:.12g}" for x in lift_dir)
    ax = " ".join(f"{x:.12g}" for x in axis)
    ctr = " ".join(f"{x:.9g}" for x in 0.5 * (p1 + p2))
    xml = (
        f"<mujoco>{settings.option_xml()}<size memory='200M'/><asset>{asset}</asset><worldbody>"
        f"{body}"
        f'<body name="carriage"><joint name="lift" type="slide" axis="{ld}"/>'
        f'<geom type="sphere" size="0.002" mass="0.5" contype="0" conaffinity="0"/>'
        f'<body name="hand"><joint name="turn" type="hinge" axis="{ax}" pos="{ctr}"/>'
        f'<geom type="sphere" size="0.002" pos="{ctr}" mass="0.5" contype="0" conaffinity="0"/>'
        f"{''.join(jaws)}</body></body>"
        "</worldbody><actuator>"
        '<motor name="jaw1" joint="jaw1" gear="1"/><motor name="jaw2" joint="jaw2" gear="1"/>'
        '<position name="lift" joint="lift" kp="2e5" dampratio="1"/>'
        '<position name="turn" joint="turn" kp="2e3" dampratio="1"/>'
        "</actuator></mujoco>"
    )
    spec = mujoco.MjSpec.from_string(xml)
    for f in spec.flexes:
        f.contype, f.conaffinity = 0, 0
    tips = [add_tips(spec, f"pad{k}", a, mu, settings) for k, a in ((1, axis), (2, -axis))]
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


def simulate_grasp(
    mesh,
    grasp: dict,
    *,
    force: float,
    mu: float,
    mass: float,
    com=None,
    task: str = "vertical_lifting",
    pad=(0.02, 0.04, 0.005),
    pad_E: float = 1e6,
    pad_nu: float = 0.45,
    up=(0.0, 0.0, 1.0),
    down=(0.0, 0.0, -1.0),
    settings: EngineSettings | None = None,
    phases: TrialPhases | None = None,
    record_every: int = 10,
) -> TrialOutcome:
    """Simulate one trial of the grasp ``grasp`` (``p1``, ``p2``, ``axis`` in the frame of the
    watertight ``mesh`` [m]) with jaw force ``force`` [N], pad–object friction ``mu``, object
    ``mass`` [kg] at ``com`` (3,) [m; default the mesh's centroid], gravity along ``down`` (3,,
    the object frame's) and ``task`` ("vertical_lifting" or "lift_and_rotate": the gripper then
    turns by 90° about the grasp axis).  ``pad`` = (width, length, thickness) [m], ``pad_E``
    [Pa], ``pad_nu``: the silicone of each jaw, its length along ``up`` (3,).

    Returns a :class:`TrialOutcome`; its verdict, ``held``, is the engine's: no contact model of
    this package is used.
    """
    mujoco = import_mujoco()
    from ..plausible import check
    from ..units import closed_mesh
    from ..wrench import check_mu

    if task not in TASKS:
        raise ValueError(f"task must be one of {tuple(TASKS)}; got {task!r}")
    mesh = closed_mesh(mesh, "mesh passed to simulate_grasp")
    check("jaw_force", force, "force")
    mu = check_mu(mu)
    check("mass", mass, "mass")
    phases = TrialPhases() if phases is None else phases
    settings = EngineSettings() if settings is None else settings
    model, info = build_model(
        mesh, grasp, force=force, mu=mu, mass=mass, com=com, pad=pad, pad_E=pad_E, pad_nu=pad_nu,
        up=up, down=down, settings=settings, phases=phases,
    )  # fmt: skip
    data = mujoco.MjData(model)
    dt = model.opt.timestep
    g_dir = np.asarray(down, float) / np.linalg.norm(down)
    obj, hand = info["object"], info["hand"]
    t_close, t_settle = phases.close, phases.close + phases.settle
    t_grav = t_settle + phases.gravity_ramp
    t_lift = t_grav + phases.lift
    turn = np.radians(TASKS[task])
    t_turn = t_lift + (phases.rotate if turn else 0.0)
    t_end = t_turn + phases.hold
    n = int(round(t_end / dt))
    times, rel_p, rel_turn = [], [], []
    ref = None
    t0 = time.perf_counter()
    for i in range(n):
        t = (i + 1) * dt
        data.ctrl[:2] = force * min(1.0, t / t_close)
        s = np.clip((t - t_settle) / phases.gravity_ramp, 0.0, 1.0)
        model.opt.gravity[:] = G * s * g_dir
        # the gripper's motion: a smooth rise, then a smooth turn about the grasp axis
        u = np.clip((t - t_grav) / phases.lift, 0.0, 1.0)
        data.ctrl[2] = phases.lift_height * (3 * u**2 - 2 * u**3)
        if turn:
            v = np.clip((t - t_lift) / phases.rotate, 0.0, 1.0)
            data.ctrl[3] = turn * (3 * v**2 - 2 * v**3)
        mujoco.mj_step(model, data)
        if t >= t_settle and (i % record_every == 0 or i == n - 1):
            Rh = data.xmat[hand].reshape(3, 3)
            ph = data.xpos[hand]
            Ro = data.xmat[obj].reshape(3, 3)
            po = Rh.T @ (data.xpos[obj] - ph)
            Rrel = Rh.T @ Ro
            if ref is None:
                ref = (po.copy(), Rrel.copy())
            times.append(t)
            rel_p.append(po)
            rel_turn.append(_rotvec_deg(ref[1].T @ Rrel))
    seconds = time.perf_counter() - t0
    times, rel_p, rel_turn = np.array(times), np.array(rel_p), np.array(rel_turn)
    drift = np.linalg.norm(rel_p - rel_p[0], axis=1)
    last = times >= t_end - phases.hold
    span = times[last][-1] - times[last][0]
    slip = float(np.linalg.norm(rel_p[last][-1] - rel_p[last][0]) / span) if span > 0 else 0.0
    held = bool(drift.max() <= phases.max_drift and rel_turn.max() <= phases.max_turn_deg)
    log.info(
        "engine trial: %s, drift %.2f mm, turn %.2f deg, %d steps in %.1f s",
        "held" if held else "slipped",
        drift.max() * 1e3,
        rel_turn.max(),
        n,
        seconds,
    )
    return TrialOutcome(
        held, float(drift.max()), float(rel_turn.max()), slip, times, rel_p, rel_turn, seconds, n
    )
