"""Gripper-pose samples of pose robustness (6DFC §V-B.1): perturbed in the gripper's own frame
with the stated standard deviations, reproducible by seed, and careless units refused."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from workbench.grasp.pose_robust import PoseNoise, check_pose, pose_samples


def _pose():
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    T[:3, 3] = [0.01, -0.02, 0.15]
    return T


def test_samples_are_perturbed_in_the_gripper_frame_with_the_stated_sigmas():
    T = _pose()
    n = 20000
    S = pose_samples(T, PoseNoise(n, 0.003, 0.01), seed=1)
    D = np.linalg.inv(T) @ S  # the perturbations in the gripper's frame
    t = D[:, :3, 3]
    xi = Rotation.from_matrix(D[:, :3, :3]).as_rotvec()
    # standard error of a std over 20,000 normal draws: 0.5 %; 3 % is six of them
    np.testing.assert_allclose(t.std(axis=0), 0.003, rtol=0.03)
    np.testing.assert_allclose(xi.std(axis=0), 0.01, rtol=0.03)
    assert np.abs(t.mean(axis=0)).max() < 5 * 0.003 / np.sqrt(n)
    # rigid
    R = S[:, :3, :3]
    assert np.abs(np.einsum("kji,kjl->kil", R, R) - np.eye(3)).max() < 1e-12


def test_same_seed_same_samples_and_zero_noise_is_the_pose():
    T = _pose()
    a = pose_samples(T, PoseNoise(10, 0.003, 0.003), seed=4)
    np.testing.assert_array_equal(a, pose_samples(T, PoseNoise(10, 0.003, 0.003), seed=4))
    assert not np.array_equal(a, pose_samples(T, PoseNoise(10, 0.003, 0.003), seed=5))
    np.testing.assert_allclose(pose_samples(T, PoseNoise(3, 0.0, 0.0)), np.array([T] * 3), atol=1e-15)


def test_defaults_come_from_config():
    from workbench import config

    with config.override(pose_samples=7, pose_sigma_trans=0.002):
        p = PoseNoise().resolved()
    assert (p.n_samples, p.sigma_trans) == (7, 0.002)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((10, 3.0, 0.003), "millimetres — pass 0.003"),
        ((10, 0.2, 0.003), r"position noise .* in \[0, 0.05\] m; got 0.2"),  # 20 cm: a new user's slip
        ((10, 0.003, 5.0), "degrees"),
        ((10, 0.003, 1.0), r"rotation noise .* in \[0, 0.5\] rad; got 1.0"),  # 57 deg
        ((0, 0.003, 0.003), "n_samples"),
        ((10, -0.003, 0.003), "sigma_trans"),
        ((10, float("nan"), 0.003), "sigma_trans"),
    ],
)
def test_careless_noise_is_refused_when_made(args, match):
    with pytest.raises(ValueError, match=match):
        PoseNoise(*args)


def test_careless_poses_are_refused():
    T = _pose()
    mm = T.copy()
    mm[:3, 3] *= 1e3 * 20
    with pytest.raises(ValueError, match="millimetres"):
        check_pose(mm)
    sheared = T.copy()
    sheared[0, 1] += 0.2
    with pytest.raises(ValueError, match="not rigid"):
        check_pose(sheared)
    with pytest.raises(ValueError, match="4×4"):
        check_pose(np.eye(3))
