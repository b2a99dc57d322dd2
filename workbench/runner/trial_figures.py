"""Figures of physical-trial predictions: one panel per grasp — the pad's footprint on the face it
presses, the contact the object settled into, the real outcome and each model's quality."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

__all__ = [
    "facing_surface",
    "fig_3",
    "fig_3_curves",
    "fig_3_figure",
    "fig_3_groups",
    "grasp_panel",
    "jaw_coordinates",
    "judged_figure",
]


def jaw_coordinates(jaw, points: np.ndarray) -> np.ndarray:
    """(n, 2) ``points`` (n, 3) [m] in the jaw's pad-plane coordinates (e1, e2) about its origin,
    in millimetres (the frame of ``jaw.outline``)."""
    rel = np.asarray(points, float) - jaw.origin
    return np.column_stack([rel @ jaw.e1, rel @ jaw.e2]) * 1e3


def grasp_panel(
    ax,
    contact,
    surface: np.ndarray,
    *,
    title: str,
    outcome: str,
    qualities: Mapping[str, float],
    failed: bool,
) -> None:
    """Draw one grasp on ``ax`` (a matplotlib Axes): the object's surface facing jaw 1 near its
    first touch (``surface`` (m, 3) points [m], grey), jaw 1's pad outline where the object
    settled, the contact's elements coloured by pressure, ``outcome`` (e.g. "1/5 held") and the
    models' ``qualities`` as text; a red frame when the real grasp ``failed`` (majority)."""
    jaw = contact.jaws[0]
    if len(surface):
        uv = jaw_coordinates(jaw, surface)
        ax.scatter(uv[:, 0], uv[:, 1], s=0.3, c="0.8", lw=0, rasterized=True)
    pad = np.vstack([jaw.outline, jaw.outline[:1]]) * 1e3
    ax.plot(pad[:, 0], pad[:, 1], "k-", lw=0.8)
    if contact.touches:
        prof = contact.profiles[0]
        uv = jaw_coordinates(jaw, prof.centers)
        ax.scatter(uv[:, 0], uv[:, 1], s=1.0, c=prof.pressures, cmap="viridis", lw=0, rasterized=True)
    ax.set_aspect("equal")
    ax.set_xlim(-22, 22)
    ax.set_ylim(-30, 22)
    ax.set_xticks([])
    ax.set_yticks([])
    text = "\n".join(f"{m} {q:.3f}" for m, q in qualities.items())
    ax.text(0.02, 0.02, text, transform=ax.transAxes, fontsize=5, va="bottom", family="monospace")
    ax.set_title(f"{title}: {outcome}", fontsize=7, color="C3" if failed else "k")
    if failed:
        for side in ax.spines.values():
            side.set_edgecolor("C3")
            side.set_linewidth(1.5)


def facing_surface(mesh, jaw, window: float = 0.004, max_edge: float = 1e-3) -> np.ndarray:
    """(m, 3) centres of the mesh's fine faces that face ``jaw`` within ``window`` [m] of the
    front-most one under its pad's bounding box (what the panel draws as the face)."""
    from ..sources.reach import fine_surface

    cen, normal, _ = fine_surface(mesh, max_edge)
    rel = cen - jaw.origin
    z = rel @ jaw.closing
    facing = normal @ jaw.closing < -0.5
    uv = np.column_stack([rel @ jaw.e1, rel @ jaw.e2])
    near = facing & (np.abs(uv) < 0.03).all(axis=1) & (np.abs(z) < jaw.stroke + 0.03)
    if not near.any():
        return np.empty((0, 3))
    z0 = z[near].min()
    return cen[near & (z <= z0 + window)]


def fig_3(tables: dict[str, str], models, out, quality: str = "robust_held"):
    """6DFC Fig. 3(a, b) on physical trials, written to ``out`` (PNG; :func:`fig_3_figure`), and
    the curves it draws beside it (``out`` with ``.json``; :func:`fig_3_curves`), which the report
    judges."""
    from pathlib import Path

    from .results import save_figure, write_json

    write_json(Path(out).with_suffix(".json"), fig_3_curves(tables, models, quality))
    return save_figure(fig_3_figure(tables, models, quality), out)


#: the two metrics of 6DFC Fig. 3(a, b): the sweep table's column and the paper's name
_FIG_3_METRICS = (("average_precision", "mAP"), ("average_recall", "mAR"))


def _fig_3_frames(tables: dict[str, str]) -> dict:
    """``{swept key: the sweep table's rows that ran, sorted by the key}``."""
    import pandas as pd

    frames = {}
    for key, path in tables.items():
        df = pd.read_parquet(path)
        frames[key] = df[df["status"] == "ok"].sort_values(key)
    return frames


def fig_3_curves(tables: dict[str, str], models, quality: str = "robust_held") -> dict:
    """What :func:`fig_3_figure` draws, JSON-ready: per swept key (``n_robust``, ``sigma_trans``)
    its ``values`` and, per model, ``average_precision`` and ``average_recall`` as ``mean`` and
    ``std`` lists over the robustness seeds (one entry per value), and the ``quality`` scored."""
    out: dict = {"quality": quality}
    for key, df in _fig_3_frames(tables).items():
        out[key] = {
            "values": df[key].to_numpy(float).tolist(),
            "models": {
                m: {
                    metric: {
                        s: df[f"scores.{m}.{quality}.{metric}.{s}"].to_numpy(float).tolist()
                        for s in ("mean", "std")
                    }
                    for metric, _ in _FIG_3_METRICS
                }
                for m in models
            },
        }
    return out


def fig_3_groups(curves: dict) -> list[list[str]]:
    """The models of :func:`fig_3_curves`'s ``curves`` grouped by identical curves: models whose
    every curve (each swept key, mAP and mAR, mean and std) equals the first's of a group, in the
    order of the first key's models — drawn as one line and named together ("reach = 6dls = 6dfc")
    by the figure and by the report."""
    keys = [k for k in curves if k != "quality"]
    models = list(curves[keys[0]]["models"]) if keys else []

    def every_curve(m: str) -> list:
        return [curves[k]["models"][m] for k in keys]

    groups: list[list[str]] = []
    for m in models:
        same = next((g for g in groups if every_curve(g[0]) == every_curve(m)), None)
        groups.append([m]) if same is None else same.append(m)
    return groups


def fig_3_figure(tables: dict[str, str], models, quality: str = "robust_held"):
    """6DFC Fig. 3(a, b) on physical trials: mAP and mAR (mean ± std over the robustness seeds)
    of each model against the swept key of each sweep table — ``tables`` maps the key
    (``n_robust``, ``sigma_trans``) to the ``table.parquet`` of a ``workbench sweep
    physical-trials`` over it (failed points left out).  ``quality``: the robust quality scored
    ("robust_held", the fraction of pose samples held, as 6DFC; or "robust", the mean margin).
    Returns the matplotlib Figure (rows mAP, mAR; a column per table)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    label = {"n_robust": "N_r (pose samples)", "sigma_trans": "σ_r [m] (pose translation)"}
    metrics = _FIG_3_METRICS
    frames = _fig_3_frames(tables)
    groups = fig_3_groups(fig_3_curves(tables, models, quality))
    fig, axes = plt.subplots(2, len(tables), figsize=(5.0 * len(tables), 6.4), squeeze=False)
    for col, (key, df) in enumerate(frames.items()):
        for row, (metric, name) in enumerate(metrics):
            ax = axes[row, col]
            for g in groups:
                base = f"scores.{g[0]}.{quality}.{metric}"
                mean, std = df[f"{base}.mean"].to_numpy(float), df[f"{base}.std"].to_numpy(float)
                ax.plot(df[key], mean, "o-", label=" = ".join(g))
                ax.fill_between(df[key], mean - std, mean + std, alpha=0.2)
            ax.set_xlabel(label.get(key, key))
            ax.set_ylabel(name)
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("6DFC Fig. 3 on the REACH YuMi trials: mean ± std over robustness seeds", fontsize=9)
    return fig


def judged_figure(per_model: Mapping[str, dict], path, title: str) -> str:
    """Bars of each model's precision, recall, F1 and accuracy against the engine and against the
    exact-6DFW truth, mean ± std over seeds (``per_model`` from
    :func:`workbench.grasp.judged.model_tables`), saved to ``path``; returns its file name."""
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .results import save_figure

    models = list(per_model)
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.6), sharey=True)
    x = np.arange(len(models))
    for ax, metric in zip(axes, ("precision", "recall", "f1", "accuracy"), strict=True):
        for k, (truth, colour, label) in enumerate(
            (("vs_engine", "C0", "engine (MuJoCo)"), ("vs_exact_6dfw", "C7", "exact 6DFW truth"))
        ):
            mean = [per_model[m][truth][metric]["mean"] for m in models]
            std = [per_model[m][truth][metric]["std"] for m in models]
            ax.bar(x + (k - 0.5) * 0.38, mean, 0.38, yerr=np.nan_to_num(std), color=colour, label=label)
        ax.set_xticks(x, models, rotation=60, fontsize=8)
        ax.set_title(metric)
        ax.set_ylim(0, 1.05)
    axes[0].legend(fontsize=8, loc="lower left")
    fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return Path(path).name
