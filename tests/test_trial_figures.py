"""The per-grasp panels of the physical trials: points in a jaw's pad-plane coordinates (the pad's
own outline maps back to itself, in mm), the face drawn is the one the jaw faces, and a panel
draws the pad, the contact and the outcome."""

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from workbench.grasp.gripper_eval import gripper_contact  # noqa: E402
from workbench.runner.trial_figures import facing_surface, grasp_panel, jaw_coordinates  # noqa: E402
from workbench.sources.gripper import yumi  # noqa: E402
from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials  # noqa: E402


def test_panel_of_a_real_grasp():
    cube = trimesh.load(default_mesh_path(), force="mesh")
    grasp = read_trials(default_trials_path()).grasps()[19]
    c = gripper_contact(cube, yumi(), grasp.pose)
    jaw = c.jaws[0]
    np.testing.assert_allclose(jaw_coordinates(jaw, jaw.outline_points), jaw.outline * 1e3, atol=1e-12)
    face = facing_surface(cube, jaw)
    # the 30 mm face the pad presses, subdivided to 1 mm: all its points on one plane facing the jaw
    assert len(face) > 500 and np.ptp(face @ jaw.closing) < 1e-3
    fig, ax = plt.subplots()
    grasp_panel(ax, c, face, title="grasp 19", outcome="0/5 held", qualities={"6dls": 0.66}, failed=True)
    outline = ax.lines[0].get_xydata()
    assert len(outline) == len(jaw.outline) + 1  # closed
    assert ax.get_title() == "grasp 19: 0/5 held" and len(ax.collections) == 2  # face and contact
    plt.close(fig)


def test_fig_3_draws_each_models_mean_against_the_swept_key(tmp_path):
    import pandas as pd

    from workbench.runner.trial_figures import fig_3, fig_3_figure

    rows = []
    for n in (1, 3, 10):
        row = {"n_robust": n, "status": "ok"}
        for m in ("point", "6dfc", "reach"):  # reach: every value as 6dfc's
            for metric in ("average_precision", "average_recall"):
                base = f"scores.{m}.robust_held.{metric}"
                row[f"{base}.mean"] = 0.5 + 0.01 * n + (0.1 if m != "point" else 0.0)
                row[f"{base}.std"] = 0.02
        rows.append(row)
    rows.append({**rows[0], "n_robust": 20, "status": "failed"})  # a failed point is left out
    table = tmp_path / "table.parquet"
    pd.DataFrame(rows).to_parquet(table)
    assert fig_3({"n_robust": table}, ["point", "6dfc"], tmp_path / "fig3.png").is_file()
    # the curves it draws, beside it, for the report: the failed point left out, sorted by the key
    curves = json.loads((tmp_path / "fig3.json").read_text())
    assert curves["quality"] == "robust_held" and curves["n_robust"]["values"] == [1, 3, 10]
    np.testing.assert_allclose(
        curves["n_robust"]["models"]["6dfc"]["average_recall"]["mean"], [0.61, 0.63, 0.70]
    )
    assert curves["n_robust"]["models"]["point"]["average_precision"]["std"] == [0.02] * 3
    fig = fig_3_figure({"n_robust": table}, ["point", "6dfc", "reach"])
    ax = fig.axes[0]
    # models with the same curves are drawn once and named together
    assert [line.get_label() for line in ax.lines] == ["point", "6dfc = reach"]
    x, y = ax.lines[1].get_data()
    np.testing.assert_allclose(x, [1, 3, 10])
    np.testing.assert_allclose(y, [0.61, 0.63, 0.70])
    plt.close("all")
