"""workbench.runner.grasp_figures: a best-grasps render is written, shows its panels, and refuses
an empty mapping."""

import numpy as np
import pytest
import trimesh

from workbench.grasp.gripper_eval import gripper_contact
from workbench.grasp.top_grasps import top_grasp_pose
from workbench.runner.grasp_figures import best_grasps_figure
from workbench.sources.gripper import PadShape, parallel_jaw


def test_a_best_grasps_render_is_a_png_with_one_panel_per_model(tmp_path):
    from PIL import Image

    box = trimesh.creation.box([0.08, 0.05, 0.02])
    box.apply_translation([0, 0, 0.01])
    g = parallel_jaw(PadShape.rectangle(0.02, 0.04, thickness=0.005), 20.0, opening=0.1, mu=0.3)
    pose = top_grasp_pose([0, -0.025, 0.008], [0, 0.025, 0.008], g)
    contact = gripper_contact(box, g, pose, settle=False)
    miss = gripper_contact(box, g, top_grasp_pose([0.5, -0.025, 0.008], [0.5, 0.025, 0.008], g), settle=False)
    path = best_grasps_figure(box, {"soft_point": (contact, 0.9), "6dls": (miss, 0.0)}, tmp_path / "b.png")
    img = np.asarray(Image.open(path))
    assert img.shape[:2] == (380, 720)  # two panels of 360 px
    # the panels are drawn: far from a blank image, and the two halves differ (one has a contact)
    assert img[..., :3].std() > 5
    assert np.abs(img[:, :360, :3].astype(float) - img[:, 360:, :3]).mean() > 1
    with pytest.raises(ValueError, match="at least one model"):
        best_grasps_figure(box, {}, tmp_path / "c.png")
