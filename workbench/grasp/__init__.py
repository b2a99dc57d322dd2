"""Grasp analysis with every contact model (thesis §2.4–2.5, §4.1–4.3; 6DFC §V).

contacts.py — contact models as wrench sets; models.py — every model of a profile
by name; gws.py — grasp map, GWS, hull, ε-metric;
resistance/ — one meaning of "resisted" (Eq. 2.100) and the minimal grasp force
(Eq. 4.4); robust.py — q_robust; stiffness_map.py — measured object stiffness on the
surface; work.py — minimal work and q_work / q_force (Eqs. 4.5–4.6); threshold.py —
balanced accuracy and the fitted normaliser W_max / f⊥max (§4.3); margin.py — the
resistance margin by bisection; precision.py — precision, recall, matched precision;
simulated_truth.py — the sensitivity and minimal-work studies' simulated outcomes (exact
6DFW sets; noise, wall closing); evaluate.py — one call from a grasp and its jaws' profiles
(any source, workbench.sources) to the verdict; inputs.py — its grouped inputs (Task, Jaws, ModelOptions),
the Task shared with gripper_eval.py's evaluation of a gripper at a pose (GripperOptions).
Profiles are made in workbench.sources, not here.
"""

from .contacts import (
    ContactSet,
    contact_map,
    limit_surface_contact,
    normal_frame,
    point_contact,
    reach_contacts,
    soft_point_contact,
    wrench_hull_contact,
)
from .evaluate import GraspEvaluation, evaluate_grasp
from .gws import WrenchHull, build_gws, grasp_map, gws_points
from .inputs import GripperOptions, Jaws, ModelOptions, Task
from .margin import margin_vs_truth, resistance_margin
from .models import MODELS, ModelParameters, contact_sets
from .precision import matched_precision, scores
from .resistance import (
    CutStore,
    MinimalForce,
    Resistance,
    min_grasp_force,
    resists,
    resists_lp,
    wrench_resistance,
)
from .robust import Perturbation, gravity_wrench, q_robust
from .sampling import GraspSampling, antipodal_grasps
from .stiffness_map import StiffnessMap, leave_one_out
from .threshold import balanced_accuracy, fit_normaliser
from .work import MinimalWork, minimal_work, q_force, q_work, work

__all__ = [
    "ContactSet",
    "CutStore",
    "GraspEvaluation",
    "GraspSampling",
    "GripperOptions",
    "Jaws",
    "MODELS",
    "MinimalForce",
    "MinimalWork",
    "ModelOptions",
    "ModelParameters",
    "Perturbation",
    "Resistance",
    "StiffnessMap",
    "Task",
    "WrenchHull",
    "antipodal_grasps",
    "balanced_accuracy",
    "build_gws",
    "contact_map",
    "contact_sets",
    "evaluate_grasp",
    "fit_normaliser",
    "grasp_map",
    "gravity_wrench",
    "gws_points",
    "leave_one_out",
    "limit_surface_contact",
    "margin_vs_truth",
    "matched_precision",
    "min_grasp_force",
    "minimal_work",
    "normal_frame",
    "point_contact",
    "q_force",
    "q_robust",
    "q_work",
    "reach_contacts",
    "resistance_margin",
    "resists",
    "resists_lp",
    "scores",
    "soft_point_contact",
    "work",
    "wrench_hull_contact",
    "wrench_resistance",
]
