"""Grasp trials simulated on an existing engine (MuJoCo), as an independent judge of the models.

A parallel-jaw gripper whose silicone pads are MuJoCo deformable bodies (3D flex, its own
finite elements and elasticity) closes on an object by force control, lifts it against gravity
(and turns it, for the thesis's "lifting and 90° rotation" task), and holds it; the verdict is
read from the object's pose relative to the gripper. A disturbance trial
(:func:`simulate_disturbance`) asks the thesis's §4.1.3 question instead: the object floats
free between the closed jaws and a wrench is applied to it and held. Contact, friction and
deformation are the engine's own: no contact profile, 6DFW, limit surface or resistance program
of this package takes part, so a model scored against these trials is scored against something
it does not feed. What the trials share with the models is stated where they are scored: the
object's mesh, μ, the grasp pose, the pad's size and material.

Engine settings (:class:`EngineSettings`) are measured choices — cone, impratio, contact
stiffness, time step, the pad's contact points — validated before the simulator judges anything
(:mod:`.probes`: friction of a pulled block, a tilted plane, the creep of a held block, the
torsion of a flat pad; :mod:`.indentation`: the pad indented by a flat and spheres against our
neo-Hookean FEM pad, on MuJoCo and on Drake), each a test (``tests/test_engine_trials.py``,
``tests/test_engine_indentation.py``). MuJoCo comes with the
``peers`` extra; without it every call raises ``ImportError`` naming the fix.
"""

from . import indentation, probes
from .disturbance import DisturbancePhases, simulate_disturbance
from .settings import EngineSettings
from .trial import (
    TASKS,
    VERDICT_LIMITS,
    EngineObject,
    EnginePad,
    EngineWarning,
    TrialOutcome,
    TrialPhases,
    build_scene,
    check_record_every,
    simulate_grasp,
    simulate_grasp_tasks,
    simulate_gripper,
    step_trial,
)

__all__ = [
    "TASKS",
    "VERDICT_LIMITS",
    "DisturbancePhases",
    "EngineObject",
    "EnginePad",
    "EngineSettings",
    "EngineWarning",
    "TrialOutcome",
    "TrialPhases",
    "build_scene",
    "check_record_every",
    "indentation",
    "probes",
    "simulate_disturbance",
    "simulate_grasp",
    "simulate_grasp_tasks",
    "simulate_gripper",
    "step_trial",
]
