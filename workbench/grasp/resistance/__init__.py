"""Wrench resistance and minimal grasp force (thesis Eqs. 2.100, 4.4; 6DFC Eq. IV.3).

program.py — the one convex program (variables, rows, cones) for every question and
representation; solvers.py — adapters (dense QP, HiGHS LP, Clarabel SOCP);
cuts.py — the explicit cut store of the cutting-plane refinement; result.py — the
result types; api.py — :func:`resists` (= :func:`wrench_resistance`) and
:func:`min_grasp_force`; gws_lp.py — :func:`resists_lp`, membership by one LP over the
contacts' vertices.
"""

from .api import OBJECTIVES, min_grasp_force, resists, wrench_resistance
from .cuts import CutStore
from .gws_lp import resists_lp
from .program import REPRESENTATIONS
from .result import MinimalForce, Resistance

__all__ = [
    "OBJECTIVES",
    "REPRESENTATIONS",
    "CutStore",
    "MinimalForce",
    "Resistance",
    "min_grasp_force",
    "resists",
    "resists_lp",
    "wrench_resistance",
]
