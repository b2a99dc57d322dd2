"""Careless inputs a new user fed the profile, work, robustness and linearisation calls, each
accepted silently or refused by numpy: a profile moved by a translation in millimetres, a
work ε in millimetres, a seed that is not a number, and an outer linearisation with too few
directions, which resisted any load.  Each is refused now, naming the fix; the right call
keeps its closed-form answer."""

import numpy as np
import pytest

from workbench import ContactProfile
from workbench.grasp.work import displacements


def _patch() -> ContactProfile:
    x, y = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.01, 0.01, 5))
    c = np.column_stack([x.ravel(), y.ravel(), np.zeros(25)])
    return ContactProfile(c, np.tile([0.0, 0, 1], (25, 1)), np.full(25, 1e-5), np.full(25, 4e4))


def test_a_profile_moved_by_millimetres_is_refused():
    p = _patch()
    with pytest.raises(
        ValueError, match=r"moves the profile 50 m.*probably in millimetres — pass \[0.0, 0.0, 0.05\]"
    ):
        p.transformed(None, [0, 0, 50])
    moved = p.transformed(None, [0, 0, 0.05])
    assert moved.pressure_center == pytest.approx([0, 0, 0.05]) and moved.F == pytest.approx(p.F)
    with pytest.raises(ValueError, match="finite"):
        p.transformed(None, [0, np.nan, 0])


def test_a_work_epsilon_in_millimetres_is_refused():
    # ε = 1 (meant 1 mm) added a metre to every displacement
    with pytest.raises(ValueError, match=r"eps .*got 1.0: probably in millimetres — pass 0.001"):
        displacements([10.0, 10.0], [5000.0, 5000.0], eps=1.0)
    assert displacements([10.0, 10.0], [5000.0, 5000.0], eps=1e-3) == pytest.approx([0.003, 0.003])


def test_a_seed_that_is_not_an_integer_is_refused():
    from workbench.grasp import Perturbation, Task, q_robust
    from workbench.grasp.contacts import soft_point_contact

    sets = [
        soft_point_contact([0.0, -0.02, 0], [0, -1.0, 0], 10.0, 0.005),
        soft_point_contact([0.0, 0.02, 0], [0, 1.0, 0], 10.0, 0.005),
    ]
    noise = Perturbation(n_samples=4)
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 .*got 'abc'"):
        q_robust(sets, 0.5, Task(mass=0.1, com=[0, 0, 0]), noise, seed="abc")
    # two soft points 2 μ F = 10 N against 0.98 N: every sample holds
    assert q_robust(sets, 0.5, Task(mass=0.1, com=[0, 0, 0]), noise, seed=3) == 1.0


@pytest.mark.jit_only("the 6DFC fit is over 15 s as pure Python")
def test_an_outer_linearisation_too_coarse_to_be_bounded_is_refused():
    # a 6DFC linearised by one outer direction held 100 N sideways with a 10 N grip
    from workbench.grasp import contact_sets, resists
    from workbench.grasp.models import ModelParameters
    from workbench.sources.scenes import elliptic_cylinder_grasp

    jaws = elliptic_cylinder_grasp(force=10.0, n_elements=100)
    with pytest.raises(
        ValueError, match=r"M = 1 outer directions leave the linearised limit surface open.*M >= 64"
    ):
        contact_sets(jaws[0], "6dfc", ModelParameters(M=1))
    sets = [c for p in jaws for c in contact_sets(p, "6dfc", ModelParameters(M=64))]
    # the capacity along the jaws' length is about 2 μ F: 100 N is not held, 1 N is
    assert not resists(sets, [0, 0, 100.0, 0, 0, 0], 0.5, representation="outer").resisted
    assert resists(sets, [0, 0, 1.0, 0, 0, 0], 0.5, representation="outer").resisted
