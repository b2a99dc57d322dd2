"""Validation probes of the engine's friction before it judges any grasp: scenes whose
Coulomb answer is known in closed form.

- :func:`pulled_block`: a rigid block on a plane pulled by a slowly ramped horizontal force
  starts to slide at μ m g;
- :func:`tilted_block`: on a slowly tilted plane it starts to slide at atan μ;
- :func:`held_block_creep`: held by a constant fraction of its slip load it should not move
  (MuJoCo's soft contacts creep; the speed is measured);
- :func:`spun_pad`: a flat flex pad pressed on a plane and turned by a ramped torque starts to
  spin at τ = μ Σ N_i |r_i|, the contact forces' own torsion capacity (μ∫p|r|dA).

Each returns the measured value, the Coulomb value and their ratio.  Onset is the first time
after which the speed stays above ``v_onset`` to the end; a ramp of rate ``k`` crosses that
threshold ``√(2 v_onset / (k/m))`` late even for an ideal Coulomb block, so the probes ramp
slowly (the bias is returned as ``bias``, a fraction of the Coulomb value).
"""

from __future__ import annotations

import numpy as np

from .pad import add_tips, compile_spec, flexcomp_xml, pad_spec
from .settings import EngineSettings, import_mujoco

G = 9.81


def rectangle_mean_radius(width: float, length: float) -> float:
    """Mean distance [m] of a ``width`` × ``length`` rectangle's points from its centre (closed
    form of ∫|r|dA / A, half-sides a, b, diagonal d: (2abd + a³ ln((b+d)/a) + b³ ln((a+d)/b)) / 6ab)."""
    a, b = width / 2, length / 2
    d = np.hypot(a, b)
    return float((2 * a * b * d + a**3 * np.log((b + d) / a) + b**3 * np.log((a + d) / b)) / (6 * a * b))


def _onset(speed: np.ndarray, v: float) -> int | None:
    """Index from which ``speed`` stays above ``v`` to the end, or None."""
    below = np.flatnonzero(speed <= v)
    if len(below) == 0:
        return 0
    i = int(below[-1]) + 1
    return i if i < len(speed) else None


def _block_model(mu: float, settings: EngineSettings, mass: float, gravity: tuple[float, float, float]):
    mujoco = import_mujoco()
    c = settings.contact_attrs(mu)
    xml = (
        f"<mujoco>{settings.option_xml(gravity)}<worldbody>"
        f'<geom name="floor" type="plane" size="0 0 1" {c}/>'
        '<body name="block" pos="0 0 0.01"><freejoint/>'
        f'<geom type="box" size="0.025 0.025 0.01" mass="{mass:g}" {c}/></body>'
        "</worldbody></mujoco>"
    )
    return mujoco.MjModel.from_xml_string(xml)


def _settled_block(mu: float, settings: EngineSettings | None, mass: float):
    """(model, data, block body id) of the block resting on the plane under gravity for 0.2 s."""
    mujoco = import_mujoco()
    m = _block_model(mu, EngineSettings() if settings is None else settings, mass, (0.0, 0.0, -G))
    d = mujoco.MjData(m)
    for _ in range(int(0.2 / m.opt.timestep)):
        mujoco.mj_step(m, d)
    return m, d, m.body("block").id


def pulled_block(
    mu: float,
    settings: EngineSettings | None = None,
    *,
    mass: float = 0.2,
    angle_deg: float = 0.0,
    duration: float = 2.0,
    v_onset: float = 1e-3,
) -> dict:
    """A 50 × 50 × 20 mm block of ``mass`` [kg] on a plane, pulled along ``angle_deg`` from the
    x axis by a force ramped from 0 to 2 μ m g over ``duration`` [s] (applied at its centre):
    ``{"measured": F_onset [N], "coulomb": μ m g, "ratio", "bias"}``."""
    mujoco = import_mujoco()
    m, d, bid = _settled_block(mu, settings, mass)
    dt = m.opt.timestep
    fc = mu * mass * G
    e = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg)), 0.0])
    n = int(round(duration / dt))
    force = 2.0 * fc * np.arange(1, n + 1) / n
    speed = np.empty(n)
    for i in range(n):
        d.xfrc_applied[bid, :3] = force[i] * e
        mujoco.mj_step(m, d)
        speed[i] = np.linalg.norm(d.qvel[:2])
    k = _onset(speed, v_onset)
    measured = float(force[k]) if k is not None else float("nan")
    rate = 2.0 * fc / duration
    bias = np.sqrt(2.0 * v_onset / (rate / mass)) * rate / fc
    return {"measured": measured, "coulomb": fc, "ratio": measured / fc, "bias": float(bias)}


def tilted_block(
    mu: float,
    settings: EngineSettings | None = None,
    *,
    rate_deg: float = 2.0,
    span_deg: float = 6.0,
    v_onset: float = 1e-3,
) -> dict:
    """The block on a plane tilted from atan μ − ``span_deg``/2 at ``rate_deg`` per second
    (gravity turned about the y axis): ``{"measured": onset angle [deg], "coulomb": atan μ
    [deg], "ratio", "bias"}``."""
    mujoco = import_mujoco()
    settings = EngineSettings() if settings is None else settings
    crit = float(np.degrees(np.arctan(mu)))
    start = crit - span_deg / 2
    m = _block_model(mu, settings, 0.2, (G * np.sin(np.radians(start)), 0.0, -G * np.cos(np.radians(start))))
    d = mujoco.MjData(m)
    dt = m.opt.timestep
    for _ in range(int(0.2 / dt)):
        mujoco.mj_step(m, d)
    n = int(round(span_deg / rate_deg / dt))
    angle = start + rate_deg * dt * np.arange(1, n + 1)
    speed = np.empty(n)
    for i in range(n):
        a = np.radians(angle[i])
        m.opt.gravity[:] = (G * np.sin(a), 0.0, -G * np.cos(a))
        mujoco.mj_step(m, d)
        speed[i] = np.linalg.norm(d.qvel[:3])
    k = _onset(speed, v_onset)
    measured = float(angle[k]) if k is not None else float("nan")
    # the excess acceleration grows as g cos θ (1 + μ²) dθ/dt · t: the ideal block is late by
    # the angle that makes v_onset
    w = np.radians(rate_deg)
    bias_deg = float(np.degrees(np.sqrt(2.0 * v_onset * w / (G * np.cos(np.radians(crit)) * (1 + mu**2)))))
    return {"measured": measured, "coulomb": crit, "ratio": measured / crit, "bias": bias_deg / crit}


def held_block_creep(
    mu: float,
    fraction: float,
    settings: EngineSettings | None = None,
    *,
    mass: float = 0.2,
    duration: float = 3.0,
) -> dict:
    """The block held by a constant horizontal force of ``fraction`` of μ m g (reached in 0.5 s):
    ``{"speed": its mean speed over the last ``duration`` − 1 s [m/s]}`` — zero for Coulomb."""
    mujoco = import_mujoco()
    m, d, bid = _settled_block(mu, settings, mass)
    dt = m.opt.timestep
    fc = mu * mass * G
    n = int(round(duration / dt))
    x0 = None
    for i in range(n):
        t = (i + 1) * dt
        d.xfrc_applied[bid, 0] = fraction * fc * min(1.0, t / 0.5)
        mujoco.mj_step(m, d)
        if x0 is None and t >= 1.0:
            x0 = d.xpos[bid, 0]
    return {"speed": float((d.xpos[bid, 0] - x0) / (duration - 1.0)), "fraction": fraction}


def spun_pad(
    mu: float,
    settings: EngineSettings | None = None,
    *,
    force: float = 10.0,
    size=(0.02, 0.04, 0.005),
    E: float = 1e6,
    nu: float = 0.45,
    duration: float = 2.0,
    v_onset: float = 1e-3,
) -> dict:
    """A flat flex pad (``size`` = width, length, thickness [m], ``E`` [Pa], ``nu``) pressed on a
    plane by ``force`` [N] and turned about its normal by a torque ramped to 1.5 μ F r_corner over
    ``duration`` [s]: ``{"measured": τ at spin onset [N·m], "coulomb": μ Σ N_i |r_i| of the
    contact forces at that moment, "ratio", "uniform": μ F mean|r| of the face (uniform
    pressure), "penetration": mean contact depth before turning [m]}``.  Onset: the face's
    mean slip speed (ω × mean|r|) stays above ``v_onset``."""
    mujoco = import_mujoco()
    settings = EngineSettings() if settings is None else settings
    w, ln, h = size
    c = settings.contact_attrs(mu)
    pad = flexcomp_xml(
        "pad", tuple(size), E, nu, np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), settings
    )
    xml = (
        f"<mujoco>{settings.option_xml()}<worldbody>"
        f'<geom name="floor" type="plane" size="0 0 1" {c} contype="1" conaffinity="3"/>'
        '<body name="jaw" pos="0 0 1e-5">'
        '<joint name="z" type="slide" axis="0 0 1"/><joint name="rz" type="hinge" axis="0 0 1"/>'
        f'<geom type="box" size="{w / 2:g} {ln / 2:g} 0.001" pos="0 0 {h + 0.001:g}" mass="0.05" '
        f'contype="0" conaffinity="0"/>{pad}</body>'
        "</worldbody></mujoco>"
    )
    spec = pad_spec(xml)
    add_tips(spec, "pad", np.array([0, 0, -1.0]), mu, settings)
    m = compile_spec(spec)
    d = mujoco.MjData(m)
    bid = m.body("jaw").id
    vz = m.joint("rz").dofadr[0]
    dt = m.opt.timestep
    for i in range(int(round(0.5 / dt))):
        d.xfrc_applied[bid, 2] = -force * min(1.0, (i + 1) * dt / 0.2)
        mujoco.mj_step(m, d)
    f6 = np.zeros(6)

    def contact_torsion() -> tuple[float, float]:
        s, depth = 0.0, []
        for j in range(d.ncon):
            mujoco.mj_contactForce(m, d, j, f6)
            p = d.contact[j].pos
            s += f6[0] * np.hypot(p[0] - d.xpos[bid, 0], p[1] - d.xpos[bid, 1])
            depth.append(-d.contact[j].dist)
        return mu * s, float(np.mean(depth)) if depth else float("nan")

    _, penetration = contact_torsion()
    r_mean = rectangle_mean_radius(w, ln)
    r_corner = float(np.hypot(w / 2, ln / 2))
    n = int(round(duration / dt))
    tau = 1.5 * mu * force * r_corner * np.arange(1, n + 1) / n
    slip = np.empty(n)
    cap = np.empty(n)
    for i in range(n):
        d.xfrc_applied[bid, 5] = tau[i]
        mujoco.mj_step(m, d)
        slip[i] = abs(d.qvel[vz]) * r_mean
        cap[i], _ = contact_torsion()
    k = _onset(slip, v_onset)
    measured = float(tau[k]) if k is not None else float("nan")
    coulomb = float(cap[k]) if k is not None else float("nan")
    return {
        "measured": measured,
        "coulomb": coulomb,
        "ratio": measured / coulomb,
        "uniform": mu * force * r_mean,
        "penetration": penetration,
    }
