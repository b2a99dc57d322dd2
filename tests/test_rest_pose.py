"""workbench.grasp.rest_pose: a box turned and moved anywhere rests on its broad face at z = 0
with its sides in order (the box's own dimensions are the reference), upright only moves."""

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from workbench.grasp.rest_pose import flatness, rest_on_table


def _turned_box():
    box = trimesh.creation.box([0.05, 0.02, 0.08])
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec([0.3, -0.7, 1.1]).as_matrix()
    T[:3, 3] = [0.1, -0.2, 0.3]
    box.apply_transform(T)
    return box


def test_lying_puts_the_longest_side_along_x_and_the_shortest_up_on_the_table():
    box = _turned_box()
    rested, T = rest_on_table(box, lying=True)
    np.testing.assert_allclose(rested.extents, [0.08, 0.05, 0.02], atol=1e-9)
    assert rested.bounds[0, 2] == pytest.approx(0.0, abs=1e-12)
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)  # a turn, not a mirror
    np.testing.assert_allclose(trimesh.transform_points(box.vertices, T), rested.vertices, atol=1e-12)
    assert flatness(rested) == pytest.approx(0.02 / 0.08)
    assert np.array_equal(box.vertices, _turned_box().vertices)  # the given mesh is not moved


def test_upright_only_moves_the_mesh_onto_the_table():
    box = trimesh.creation.box([0.08, 0.05, 0.02])
    box.apply_translation([0.01, 0.02, 0.5])
    rested, T = rest_on_table(box)
    np.testing.assert_allclose(T, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -0.49], [0, 0, 0, 1]], atol=1e-12)
    assert rested.bounds[0, 2] == pytest.approx(0.0, abs=1e-12)
    cyl = trimesh.creation.cylinder(radius=0.025, height=0.06)
    assert flatness(rest_on_table(cyl)[0]) == pytest.approx(0.06 / 0.05, rel=1e-3)


def test_careless_input_is_refused():
    with pytest.raises(ValueError, match="trimesh.Trimesh"):
        rest_on_table(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="lying must be True or False"):
        rest_on_table(trimesh.creation.box([0.01] * 3), lying="yes")
