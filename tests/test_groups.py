"""workbench.groups: a settings group is given as itself or None (its defaults), never as a dict —
the same answer and the same message at every entry point that takes one."""

import math
import re
from dataclasses import dataclass

import numpy as np
import pytest
import trimesh

from workbench.fem.wall import SqueezeControls, build_wall, circle_surface, squeeze
from workbench.grasp import (
    GraspSampling,
    Jaws,
    ModelOptions,
    Perturbation,
    Task,
    antipodal_grasps,
    evaluate_grasp,
)
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.robust import q_robust
from workbench.groups import checked_group, public_name
from workbench.sources.reach import WinklerPress, reach_profile


@dataclass(frozen=True)
class _Toy:
    """A group of this test module: not exported by any enclosing package."""

    a: float = 1.0


def test_a_group_or_none_passes_and_anything_else_is_refused_with_the_fix():
    t = _Toy(2.0)
    assert checked_group(t, _Toy, "toy") is t  # the same object, not a copy
    assert checked_group(None, _Toy, "toy") == _Toy(1.0)
    with pytest.raises(ValueError) as e:
        checked_group({"a": 3.0}, _Toy, "toy")
    assert str(e.value) == (
        f"toy must be a {_Toy.__module__}._Toy (or None: its defaults); got dict — pass _Toy(**toy)"
    )
    with pytest.raises(
        ValueError, match=r"got float — pass a _Toy\(\.\.\.\) or leave toy out for the defaults$"
    ):
        checked_group(3.0, _Toy, "toy")
    with pytest.raises(ValueError, match=r"got str — build one with _Toy\(a=\.\.\.\)$"):
        checked_group("3", _Toy, "toy", hint="build one with _Toy(a=...)")
    # a dict is refused even with a hint: its fix is always the same call
    with pytest.raises(ValueError, match=r"got dict — pass _Toy\(\*\*toy\)$"):
        checked_group({}, _Toy, "toy", hint="unused")


def test_the_public_name_is_the_shortest_import_path():
    assert public_name(Task) == "workbench.grasp.Task"  # defined in workbench.grasp.inputs
    assert public_name(ModelParameters) == "workbench.grasp.ModelParameters"  # in workbench.grasp.models
    assert public_name(SqueezeControls) == "workbench.fem.wall.SqueezeControls"  # not in workbench.fem
    assert public_name(_Toy).endswith("test_groups._Toy")


def _box():
    return trimesh.creation.box(extents=(0.06, 0.06, 0.06))


def _profile():
    return reach_profile(_box(), (0.03, 0.0, 0.0), (-1.0, 0.0, 0.0))


def _point_contacts():
    return contact_sets(_profile(), "point")


GRASP = {"center": (0.0, 0.0, 0.0), "axis": (1.0, 0.0, 0.0), "up": (0.0, 0.0, 1.0)}

#: (group, argument name, a call of a public entry point with the group given as a dict)
ENTRY_POINTS = [
    (Task, "task", lambda: evaluate_grasp(_box(), GRASP, {"mass": 0.1})),
    (Jaws, "jaws", lambda: evaluate_grasp(_box(), GRASP, Task(mass=0.1, com=(0, 0, 0)), jaws={"force": 5})),
    (
        ModelOptions,
        "options",
        lambda: evaluate_grasp(_box(), GRASP, Task(mass=0.1, com=(0, 0, 0)), options={"model": "point"}),
    ),
    (
        ModelParameters,
        "params",
        lambda: contact_sets(reach_profile(_box(), (0.03, 0, 0), (-1, 0, 0)), "point", {}),
    ),
    (WinklerPress, "press", lambda: reach_profile(_box(), (0.03, 0, 0), (-1, 0, 0), press={"closing": 1e-3})),
    (Perturbation, "perturbation", lambda: q_robust(_point_contacts(), 0.5, np.zeros(6), {"n_samples": 3})),
    (GraspSampling, "sampling", lambda: antipodal_grasps(_box(), 4, 0.5, {"table_z": None})),
    (
        SqueezeControls,
        "controls",
        lambda: squeeze(
            build_wall(circle_surface(0.03), n_theta=16, n_z=4, z_range=(0.0, 0.04)),
            np.array([0.0, 0.0, 0.03]),
            np.array([1.0, 0.0, 0.0]),
            controls={"margin": 1.0},
        ),
    ),
]


@pytest.mark.parametrize(
    ("kind", "name", "call"), ENTRY_POINTS, ids=[e[1] + "-" + e[0].__name__ for e in ENTRY_POINTS]
)
def test_every_entry_point_refuses_a_dict_for_its_group_with_one_message(kind, name, call):
    fix = f"pass {kind.__name__}(**{name})"
    what = "required" if kind is Task else "or None: its defaults"  # a task has no default load
    expected = f"{name} must be a {public_name(kind)} ({what}); got dict — {fix}"
    with pytest.raises(ValueError, match=re.escape(expected) + "$"):
        call()


def test_a_required_group_refuses_none_and_says_how_to_build_one():
    with pytest.raises(
        ValueError,
        match=re.escape(
            "task must be a workbench.grasp.Task (required); got NoneType — "
            "pass Task(w_ext=...) or Task(mass=..., com=...)"
        ),
    ):
        evaluate_grasp(_box(), GRASP, None)
    with pytest.raises(ValueError, match=r"\(required\); got int — pass Task\(w_ext=\.\.\.\)"):
        evaluate_grasp(_box(), GRASP, 3)


def test_a_group_checks_its_own_fields_when_made():
    """Found by a new-user trial: fields accepted when made and misread later (a string taken as
    True, a foreign sampler crashing in asdict, 500 % penetration allowed)."""
    from workbench.fem.nonlinear import NonlinearControls
    from workbench.grasp.inputs import ModelOptions
    from workbench.grasp.models import ModelParameters

    for kwargs, match in (
        ({"M": -5}, r"M must be an integer >= 1 \(linearisation directions\); got -5"),
        ({"n_edges": 2.5}, r"n_edges must be an integer >= 3"),
        ({"reach_triangles": -1}, r"reach_triangles must be an integer >= 1"),
        ({"quartic": "no"}, r"quartic must be True or False; got 'no'"),
        ({"sampler": 5}, r"sampler must be a SamplerSpec or None .*got int — pass SamplerSpec"),
    ):
        with pytest.raises(ValueError, match=match):
            ModelParameters(**kwargs)
    with pytest.raises(ValueError, match="min_force must be True or False; got 'no'"):
        ModelOptions(model="6dls", min_force="no")
    with pytest.raises(ValueError, match="representation must be 'model', 'outer' or 'inner'; got 'outr'"):
        ModelOptions(model="6dls", representation="outr")
    with pytest.raises(ValueError, match=r"gap_tol must be < 1 \(a fraction of the jaw displacement\)"):
        NonlinearControls(gap_tol=5.0)
    with pytest.raises(ValueError, match="newton_rtol must be < 1"):
        NonlinearControls(newton_rtol=1.0)
    # the defaults and ordinary values stay accepted; μ read from a file as "0.5" is kept as 0.5
    assert ModelParameters(M=50, n_edges=4, reach_triangles=8, quartic=True).M == 50
    assert ModelOptions(model="6dls", mu="0.5").mu == 0.5 and isinstance(ModelOptions(mu="0.5").mu, float)
    assert NonlinearControls(gap_tol=0.01).gap_tol == 0.01


def test_a_length_in_a_group_is_judged_as_the_length_it_is():
    """Found by a new-user trial: a 200 mm contact-set margin and a 20 m search window were
    accepted, and a negative depth_window failed only at use with a message naming no field."""
    from workbench.fem.wall import SqueezeControls
    from workbench.sources.reach import WinklerPress

    with pytest.raises(
        ValueError, match=r"SqueezeControls\.margin .* got 0\.2: probably in millimetres — pass 0\.0002"
    ):
        SqueezeControls(margin=0.2)
    with pytest.raises(ValueError, match=r"WinklerPress\.window \(0, 20\): \|hi\| .* pass 0\.02 "):
        WinklerPress(window=(0, 20))
    with pytest.raises(ValueError, match=r"WinklerPress\.depth_window .* got -1"):
        WinklerPress(depth_window=-1)
    with pytest.raises(ValueError, match=r"WinklerPress\.window must be \(lo, hi\)"):
        WinklerPress(window=(0.02, 0.0))
    # the defaults and ordinary values stay accepted: margin 0 (first touch only), a window
    # behind the jaw's centre
    assert SqueezeControls(margin=0.0).margin == 0.0 and SqueezeControls().margin == 0.2e-3
    assert SqueezeControls(margin=math.inf).margin == math.inf  # every footprint node
    assert WinklerPress(window=(-0.01, 0.05)).window == (-0.01, 0.05)
    assert WinklerPress(depth_window=0.03).depth_window == 0.03
