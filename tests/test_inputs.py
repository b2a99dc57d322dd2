"""workbench.grasp.inputs: the grouped inputs of a grasp evaluation — each a frozen value of
numbers and tuples (equal when their numbers are, unchanged when the caller's arrays change),
each field refused when it is made by the one rule of its quantity, with that rule's message."""

import dataclasses

import numpy as np
import pytest

from workbench.grasp import GripperOptions, Jaws, ModelOptions, Perturbation, Task
from workbench.grasp.inputs import check_down_direction
from workbench.grasp.pose_robust import PoseNoise


def test_a_task_is_a_wrench_or_gravity_kept_as_given():
    w = np.array([0.0, 0.0, -2.9, 0.01, 0.0, 0.0])
    t = Task(w_ext=w)
    w[2] = -100.0  # the caller's array changes afterwards: the task does not
    assert t.w_ext == (0.0, 0.0, -2.9, 0.01, 0.0, 0.0) and t.mass is None and t.com is None
    com = np.array([0.0, 0.01, 0.02])
    g = Task(mass=0.3, com=com, down=(0, -2, 0))
    com[0] = 5.0
    # the com as floats; down as given (a direction, not normalised: the numbers stay the caller's)
    assert g.com == (0.0, 0.01, 0.02) and g.down == (0.0, -2.0, 0.0) and g.mass == 0.3
    assert Task(mass=0.3).com is None and Task(mass=0.3).down == (0.0, 0.0, -1.0)
    # values only: equal by their numbers, hashable, frozen
    assert Task(mass=0.3, com=[0, 0.01, 0.02], down=[0, -2.0, 0]) == g and hash(g) == hash(Task(**vars(g)))
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.mass = 1.0


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({}, r"give the task as w_ext \(6,\) or as mass \[kg\] and com \(3,\) \[m\]"),
        ({"com": [0, 0, 0]}, "give the task as w_ext"),
        ({"w_ext": np.zeros(6), "mass": 0.3}, "either as w_ext or as mass and com, not both"),
        ({"w_ext": np.zeros(6), "com": [0, 0, 0]}, "not both"),
        ({"w_ext": {"fz": -2.9}}, r"w_ext must be a \(6,\) wrench .*got dict"),
        ({"w_ext": [0, 0, -2.9, 0, 0, 29.0]}, r"at least 10 m from the object origin.*probably in N·mm"),
        ({"mass": 270.0}, "probably in grams — pass 0.27"),
        ({"mass": 0.3, "com": [0, 0]}, r"com must be the centre of mass, \(3,\) finite numbers"),
        ({"mass": 0.3, "down": (0, 0, 0)}, r"down must be a non-zero \(3,\) gravity direction"),
    ],
)
def test_a_careless_task_is_refused_when_made(kw, match):
    with pytest.raises(ValueError, match=match):
        Task(**kw)


def test_the_gravity_direction_is_one_rule():
    np.testing.assert_array_equal(check_down_direction((0, 3.0, -4.0)), [0.0, 0.6, -0.8])
    for bad in ((0, 0, 0), (0, np.nan, -1), (0, -1)):
        with pytest.raises(ValueError, match="down must be a non-zero"):
            check_down_direction(bad)


def test_jaws_hold_the_force_pad_and_up_checked():
    j = Jaws(force=np.float64(6.0), pad=np.array([0.016, 0.024]), up=[0, 1, 0])
    assert j == Jaws(6, (0.016, 0.024), (0.0, 1.0, 0.0)) and type(j.force) is float
    assert Jaws() == Jaws(10.0, (0.02, 0.04), (0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="millinewtons — pass 10"):
        Jaws(force=1e4)
    with pytest.raises(ValueError, match=r"force \(each jaw's reading \[N\]\) must be a number"):
        Jaws(force=True)
    with pytest.raises(ValueError, match=r"pad \(width, length\) \[m\] .*millimetres — pass 0.02"):
        Jaws(pad=(20, 40))
    with pytest.raises(ValueError, match=r"pad must be the jaw face \(width, length\) \[m\]"):
        Jaws(pad="0.02")
    with pytest.raises(ValueError, match=r"up must be a non-zero finite \(3,\) direction .*a zero vector"):
        Jaws(up=(0, 0, 0))


def test_model_options_are_checked_when_made():
    o = ModelOptions("soft_point", 0.3, seed=np.int64(4))
    assert (o.model, o.mu, o.representation, o.min_force, o.robust, o.seed) == (
        "soft_point",
        0.3,
        "model",
        True,
        None,
        4,
    )
    assert type(o.seed) is int
    assert ModelOptions(robust=Perturbation(n_samples=3)).robust.n_samples == 3
    with pytest.raises(ValueError, match=r"model must be one of \('point', "):
        ModelOptions(model="6d")
    with pytest.raises(ValueError, match="per cent — pass 0.5"):
        ModelOptions(mu=50)
    with pytest.raises(ValueError, match=r"robust must be a Perturbation .*got PoseNoise — .*GripperOptions"):
        ModelOptions(robust=PoseNoise(4, 0.003, 0.003))
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0"):
        ModelOptions(seed=-3)
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 here \(the same draw on every"):
        ModelOptions(seed=np.random.default_rng(0))


def test_gripper_options_are_checked_when_made():
    assert GripperOptions() == GripperOptions(None, None, True, 0)
    assert GripperOptions(mu=0.3, robust=PoseNoise(4, 0.003, 0.003), settle=False, seed=2).seed == 2
    with pytest.raises(ValueError, match="per cent — pass 0.3"):
        GripperOptions(mu=30.0)
    with pytest.raises(ValueError, match="got 0: without friction a parallel-jaw grasp holds nothing"):
        GripperOptions(mu=0.0)
    with pytest.raises(ValueError, match=r"robust must be a PoseNoise .*got Perturbation"):
        GripperOptions(robust=Perturbation())
    with pytest.raises(ValueError, match=r"settle must be True or False; got 'no'"):
        GripperOptions(settle="no")


def test_a_zero_task_wrench_is_refused_as_nothing_to_resist():
    from workbench.grasp.inputs import Task

    with pytest.raises(ValueError, match="zero wrench: there is nothing to resist"):
        Task(w_ext=[0, 0, 0, 0, 0, 0])
    assert Task(w_ext=[0, 0, -1.0, 0, 0, 0]).w_ext == (0.0, 0.0, -1.0, 0.0, 0.0, 0.0)
