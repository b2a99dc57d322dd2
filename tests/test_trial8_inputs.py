"""Careless inputs of the eighth new-user trial ("no silent nonsense"): each was
accepted silently, crashed, or was refused with a misleading hint.  Each is refused or warned
now, naming what was expected and the fix."""

import logging

import numpy as np
import pytest
import trimesh

from workbench import ContactProfile
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.plausible import check


def _disc(radius: float = 0.005, n: int = 12) -> ContactProfile:
    """A flat disc patch of n x n elements (pressure 1 Pa) facing -z."""
    x = (np.arange(n) + 0.5) / n * 2 * radius - radius
    X, Y = np.meshgrid(x, x)
    keep = X**2 + Y**2 <= radius**2
    c = np.c_[X[keep], Y[keep], np.zeros(keep.sum())]
    area = (2 * radius / n) ** 2
    return ContactProfile(c, np.tile([0.0, 0.0, 1.0], (len(c), 1)), np.full(len(c), area), np.ones(len(c)))


def test_c13_n_wrenches_zero_is_refused_and_an_unused_one_is_said_to_be_unused(caplog):
    """contact_sets(prof, '6dls', n_wrenches=0): accepted without a word (the argument sets only
    the 6DFW samples of '6dfw' / '3dls_nonplanar')."""
    prof = _disc()
    with pytest.raises(ValueError, match=r"n_wrenches must be an even integer >= 2"):
        contact_sets(prof, "6dls", ModelParameters(n_wrenches=0))
    # a valid count on a model that does not use it (one kwargs dict for every model of a loop)
    # is logged, not warned
    with caplog.at_level(logging.INFO, logger="workbench.grasp.models"):
        contact_sets(prof, "6dls", ModelParameters(n_wrenches=100))
    assert "n_wrenches=100 has no effect on '6dls'" in caplog.text
    assert len(contact_sets(prof, "6dfw", ModelParameters(n_wrenches=100))) == 1


def test_c111_a_string_obstacle_is_refused_naming_the_obstacle_types():
    """press(PadGeometry(), Material(), 'sphere', [1e-3]): AttributeError 'str' object has no
    attribute 'signed_distance', from deep in workbench/fem/contact.py."""
    from workbench.fem.fidelity import press
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry

    with pytest.raises(
        ValueError, match=r"obstacle must be an obstacle of workbench.fem.obstacles .*got str"
    ):
        press(PadGeometry(), Material(), "sphere", [1e-3])
    with pytest.raises(ValueError, match=r"MeshObstacle\(mesh\) for a trimesh\); got Trimesh"):
        press(PadGeometry(), Material(), trimesh.creation.icosphere(radius=0.01), [1e-3])


def test_mu_of_5_is_not_read_as_per_cent():
    """frictional_wrenches / resists / evaluate_grasp / Gripper(mu=5) said "probably in per cent —
    pass 0.05": 5 is a typo more often than 5 %, and 0.05 is itself at the warned edge."""
    with pytest.raises(ValueError, match="more than any real friction coefficient") as exc:
        check("mu", 5)
    assert "per cent" not in str(exc.value)
    # 30 and 50 still read as per cent: 0.3 and 0.5 are ordinary pad friction
    with pytest.raises(ValueError, match=r"probably in per cent — pass 0.3"):
        check("mu", 30)


def test_c92_a_mesh_squashed_flat_is_named_flat_not_non_manifold():
    """A box with z scaled by 0 was refused as "not watertight ... non-manifold", not by the
    documented flat-mesh rule."""
    from workbench.units import closed_mesh

    box = trimesh.creation.box(extents=(0.06, 0.04, 0.08))
    flat = trimesh.Trimesh(box.vertices * [1.0, 1.0, 0.0], box.faces, process=False)
    with pytest.raises(ValueError, match=r"is flat: its bounding box is \[0.06, 0.04, 0.0\]"):
        closed_mesh(flat, "mesh")


def test_c96_too_wide_says_the_object_is_wider_than_max_width():
    """antipodal_grasps(max_width=0.01) on a 40 mm object logged "the jaw opening exceeds
    max_width": it is the object's width across the grasp that does."""
    from workbench.grasp.sampling import DROP_REASONS

    assert DROP_REASONS["too_wide"][0] == "the object is wider across the grasp than max_width"
    assert DROP_REASONS["too_narrow"][0] == "the object is narrower across the grasp than min_width"


def test_c146_engine_grasp_points_off_the_surface_are_refused_before_simulating():
    """simulate_grasp with p1, p2 10 mm off a capsule's surface ran a full trial and then said
    both jaws touched nothing; evaluate_grasp refuses the same grasp up front."""
    pytest.importorskip("mujoco")
    from workbench.engine_trials import EngineObject, simulate_grasp

    capsule = trimesh.creation.capsule(height=0.04, radius=0.02)
    off = {"p1": [-0.03, 0.0, 0.0], "p2": [0.03, 0.0, 0.0], "axis": [1.0, 0.0, 0.0]}
    with pytest.raises(ValueError, match=r"grasp point p1 is 10 mm from the object's surface"):
        simulate_grasp(capsule, off, force=5.0, obj=EngineObject(mass=0.1, mu=0.5))
