"""workbench.sources.trials: the REACH trial format (a synthetic file; the packaged 3 cm cube)."""

import json
import logging

import numpy as np
import pytest
import trimesh

from workbench.sources.gripper import yumi
from workbench.sources.reach import pad_profile
from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials

# the object turned 90° about the world x (its +y up), a top-down gripper 0.175 m above its centre
OBJECT = np.array([[1, 0, 0, 0.4], [0, 0, -1, 0.0], [0, 1, 0, 0.0185], [0, 0, 0, 1.0]])
# in the object frame: gripper x = object x, approach z = object -y (down), y = z × x = object +z
GRIPPER = np.array([[1, 0, 0, 0.002], [0, 0, -1, 0.175], [0, 1, 0, 0.001], [0, 0, 0, 1.0]])


def _write(path, rows):
    path.write_text(json.dumps(rows))
    return path


def _rows(n_grasps=2, repeats=2, grasp=None):
    world = (OBJECT @ GRIPPER if grasp is None else grasp).tolist()
    return [
        {
            "obj": "box",
            "attempt": g,
            "trial": r,
            "pose": OBJECT.tolist(),
            "grasp": world,
            "result": bool((g + r) % 2),
            "stable_pose": 1,
            "tf": np.eye(4).tolist(),
        }
        for g in range(n_grasps)
        for r in range(repeats)
    ]


def test_synthetic_trials_give_known_jaws(tmp_path):
    t = read_trials(_write(tmp_path / "box.json", _rows()))
    assert (len(t), t.obj, t.mass, t.pose_spread) == (4, "box", None, 0.0)
    np.testing.assert_array_equal(t.grasp_index, [0, 0, 1, 1])
    np.testing.assert_array_equal(t.repeat, [0, 1, 0, 1])
    np.testing.assert_array_equal(t.success, [False, True, True, False])
    np.testing.assert_allclose(t.gripper_pose, np.broadcast_to(GRIPPER, (4, 4, 4)), atol=1e-15)
    np.testing.assert_allclose(t.down, np.broadcast_to([0, -1, 0], (4, 3)), atol=1e-15)  # the world's -z
    grasps = t.grasps()
    assert list(grasps) == [0, 1] and grasps[1].outcomes == (True, False) and grasps[0].success_rate == 0.5
    # tooltips at (∓0.025, ∓1.1e-5, 0.160098) in the gripper frame, by hand in the object frame
    j0, j1 = yumi().jaws(grasps[0].pose)
    np.testing.assert_allclose(j0.origin, [-0.023, 0.175 - 0.160098, 0.001 - 0.000011], atol=1e-15)
    np.testing.assert_allclose(j1.origin, [0.027, 0.175 - 0.160098, 0.001 + 0.000011], atol=1e-15)
    np.testing.assert_allclose([j0.closing, j0.e1, j0.e2], [[1, 0, 0], [0, 0, 1], [0, -1, 0]], atol=1e-15)
    np.testing.assert_allclose([j1.closing, j1.e1, j1.e2], [[-1, 0, 0], [0, 0, -1], [0, -1, 0]], atol=1e-15)


def test_trial_format_errors_and_warnings(tmp_path, caplog):
    rows = _rows()
    del rows[2]["result"]
    with pytest.raises(ValueError, match=r"trial 2 lacks \['result'\]"):
        read_trials(_write(tmp_path / "a.json", rows))
    rows = _rows()
    rows[1]["pose"] = OBJECT[:3].tolist()
    with pytest.raises(ValueError, match=r"trial 1: 'pose'.*4×4.*\(3, 4\)"):
        read_trials(_write(tmp_path / "b.json", rows))
    sheared = OBJECT.copy()
    sheared[0, 1] = 0.1  # beyond repair
    with pytest.raises(ValueError, match="'pose'.*not rigid"):
        read_trials(_write(tmp_path / "c.json", _sheared(sheared)))
    sheared[0, 1] = 0.01  # the cube file's stray entry: repaired, keeping the up row, with a warning
    with caplog.at_level(logging.WARNING, logger="workbench.sources.trials"):
        t = read_trials(_write(tmp_path / "c2.json", _sheared(sheared)))
    assert "4 pose/grasp rotations were not orthonormal (max |RᵀR − I| up to 0.01)" in caplog.text
    np.testing.assert_allclose(t.object_pose[0], OBJECT, atol=1e-15)
    caplog.clear()
    mm = OBJECT @ GRIPPER
    mm[:3, 3] *= 1000
    with pytest.raises(ValueError, match="millimetres"):
        read_trials(_write(tmp_path / "d.json", _rows(grasp=mm)))
    rows = _rows()
    rows[0]["result"] = 1
    with pytest.raises(ValueError, match="true or false"):
        read_trials(_write(tmp_path / "e.json", rows))
    with pytest.raises(ValueError, match="no such trial file"):
        read_trials(tmp_path / "missing.json")
    # out of blocks: warned, still read by 'attempt'
    rows = _rows()
    rows[1], rows[2] = rows[2], rows[1]
    with caplog.at_level(logging.WARNING, logger="workbench.sources.trials"):
        t = read_trials(_write(tmp_path / "f.json", rows))
    assert "not listed in blocks" in caplog.text
    np.testing.assert_array_equal(t.grasp_index, [0, 1, 0, 1])
    assert [g.outcomes for g in t.grasps().values()] == [(False, True), (True, False)]


def _sheared(pose):
    rows = _rows()
    for r in rows:
        r["pose"] = pose.tolist()
    return rows


@pytest.fixture(scope="module")
def cube_trials():
    return read_trials(default_trials_path())


def test_packaged_cube_trials(cube_trials, caplog):
    """125 trials = 25 grasps × 5 repeats; 24 failures, grasps 19 and 22 all failures."""
    t = cube_trials
    assert (len(t), t.obj, t.mass) == (125, "cube_3cm", 0.003)
    grasps = t.grasps()
    assert len(grasps) == 25 and int((~t.success).sum()) == 24
    assert grasps[19].outcomes == grasps[22].outcomes == (False,) * 5
    failures = {g: 5 - sum(x.outcomes) for g, x in grasps.items() if not all(x.outcomes)}
    assert failures == {1: 1, 2: 4, 4: 1, 6: 4, 8: 3, 10: 1, 19: 5, 22: 5}
    assert t.pose_spread == 0.0  # a grasp's five trials share one gripper pose: attempt is the grasp
    # the stray 0.01 of every pose made orthonormal keeping the up row: gravity along a cube axis
    np.testing.assert_allclose(
        np.sort(np.abs(t.down), axis=1), np.broadcast_to([0, 0, 1], (125, 3)), atol=1e-15
    )
    # against the inverse of the sheared pose as published: the tooltips move by 0.23 mm at most
    rows = json.loads(default_trials_path().read_text())
    raw = np.linalg.inv([r["pose"] for r in rows]) @ np.array([r["grasp"] for r in rows])
    tips = yumi().tooltips[:, :, 3]
    shift = np.linalg.norm(np.einsum("nij,kj->nki", raw - t.gripper_pose, tips), axis=2)
    assert shift.max() == pytest.approx(2.29e-4, abs=1e-6)


def test_every_cube_grasp_straddles_the_cube_within_the_stroke(cube_trials):
    g = yumi()
    for grasp in cube_trials.grasps().values():
        j0, j1 = g.jaws(grasp.pose)
        # opposite sides of the cube centre (the origin) along the closing axis
        s0, s1 = j0.origin @ j0.closing, j1.origin @ j0.closing
        assert s0 < -0.015 and s1 > 0.015  # outside the ±15 mm cube: the open gripper clears it
        assert -s0 - 0.015 < j0.stroke and s1 - 0.015 < j1.stroke  # and each jaw reaches its face
        # top-down: the approach along gravity
        assert j0.e2 @ grasp.down > 0.99


@pytest.mark.parametrize("index", [2, 5, 6, 8, 19, 22])
def test_failed_grasps_touch_a_narrow_strip(cube_trials, index):
    """The README's reading of the failures: pads overlapping a face by a 2–6 mm strip (the
    contact's narrower side here: 2.0–6.3 mm, grasp 6 the widest); grasp 5 holds the whole pad
    on a face (5.25 cm²).  With the pad turned the other way along the approach (rounded end
    towards the palm) grasps 8 and 22 would touch 9.5–11.7 mm strips: this also checks the
    pad's x axis."""
    cube = trimesh.load(default_mesh_path(), force="mesh")
    widths, areas = [], []
    for jaw in yumi().jaws(cube_trials.grasps()[index].pose):
        p = pad_profile(cube, jaw, closing=0.01, max_edge=5e-4)
        rel = p.centers - jaw.origin
        widths.append(min(np.ptp(rel @ jaw.e1), np.ptp(rel @ jaw.e2)))
        areas.append(p.areas.sum())
    if index == 5:
        np.testing.assert_allclose(areas, 5.25e-4, rtol=0.01)
    else:
        assert 0.0015 < min(widths) and max(widths) < 0.0065
