"""The sensitivity study's tables and headline (thesis Fig 4.4; 6DFC Fig 3) from its scored rows
(:mod:`.sensitivity_rows`, by checkpoint key): precision and recall per model along each
parameter series, the training-sampler comparison of the limit surfaces' margins, and the
summary's headline lines.  Undefined numbers — a recall with no positive truth, a precision with
no positive prediction: NaN in a fresh row, None once checkpointed as JSON — read ``n/a``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .margin import margin_vs_truth
from .precision import matched_precision
from .sensitivity_rows import SERIES

__all__ = ["format_or_na", "headline", "series_tables", "training_distribution"]


def series_tables(by_key: Mapping[str, dict], rows: Sequence[dict], config: Mapping) -> dict:
    """Precision and recall per model along each parameter series (from the rows ``by_key``),
    and the robust metric's rows among ``rows`` in (n_r, sigma_r) order."""
    series_out = {}
    for s, key in SERIES:
        xs = config[key]
        series_out[s] = {
            "x": xs,
            **{
                m: {
                    "precision": [by_key[f"{s}/{x}/{m}"]["precision"] for x in xs],
                    "recall": [by_key[f"{s}/{x}/{m}"]["recall"] for x in xs],
                }
                for m in config["models"]
            },
        }
    # in (n_r, sigma_r) order, not the checkpoint's (the order the tasks finished in)
    series_out["robust"] = sorted(
        (
            {k: r[k] for k in ("n_r", "sigma_r", "precision", "recall", "ms_per_grasp")}
            for r in rows
            if r["series"] == "robust"
        ),
        key=lambda r: (r["n_r"], r["sigma_r"]),
    )
    return series_out


def training_distribution(
    by_key: Mapping[str, dict],
    config: Mapping,
    truth: np.ndarray,
    true_margin: np.ndarray,
    nominal: np.ndarray,
) -> dict:
    """Margins of ``training_models`` with limit surfaces trained by each of
    ``training_samplers`` (rows ``margin/<model>@<kind>``): the capacity error against the
    noise-free exact margin ``nominal`` (n,) (the limit surface's own error — the noisy truth's
    margins differ from it by ~4 % median, which would hide it), against the noisy truth's
    ``true_margin`` (n,), and recall at matched precision against ``truth`` (n,) bool."""
    out = {}
    for model in config["training_models"]:
        out[model] = {}
        for kind in config["training_samplers"]:
            s_m = np.array(by_key[f"margin/{model}@{kind}"]["margins"])
            pr = matched_precision(s_m, truth, config["precision_levels"])
            out[model][kind] = {
                "vs_exact_nominal": margin_vs_truth(s_m, nominal),
                "vs_noisy_truth": margin_vs_truth(s_m, true_margin),
                "recall_at_precision": dict(
                    zip(map(str, config["precision_levels"]), pr["at_levels"]["recall"], strict=True)
                ),
            }
    return out


def format_or_na(value: object, spec: str) -> str:
    """``value`` formatted by ``spec``, or ``n/a`` where it is undefined (None or NaN)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return "n/a"
    return format(value, spec)


def headline(
    truth: np.ndarray,
    series_out: Mapping,
    ms_model: Mapping[str, float],
    matched: Mapping[str, dict],
    nonplanar_ge: object,
    margin_error: Mapping[str, dict],
    training: Mapping[str, dict],
    config: Mapping,
) -> list[str]:
    """The summary's headline lines; undefined numbers (None or NaN) read ``n/a``.  ``truth``
    (n,) bool; ``series_out`` of :func:`series_tables`; per model its ms per grasp, its
    :func:`~.precision.matched_precision` and :func:`~.margin.margin_vs_truth`;
    ``nonplanar_ge`` of :func:`~.precision.recall_at_least`; ``training`` of
    :func:`training_distribution`."""
    levels = config["precision_levels"]
    na = format_or_na
    return [
        f"truth: {na(truth.mean(), '.0%')} of {len(truth)} disturbances resisted "
        "(simulated truth, exact 6DFW set)",
        *(
            f"{m}: recall vs k [{', '.join(na(v, '.2f') for v in series_out['k'][m]['recall'])}], "
            f"{na(ms_model[m], '.2f')} ms/grasp"
            for m in config["models"]
        ),
        "recall at matched precision "
        + "; ".join(
            f"P>={lv}: "
            + ", ".join(f"{m} {na(matched[m]['at_levels']['recall'][j], '.2f')}" for m in config["models"])
            for j, lv in enumerate(levels)
        ),
        f"6DLS/6DFC recall >= planar and point at matched precision: {nonplanar_ge}",
        "resistance margin vs the truth's, median |log ratio| (bias): "
        + ", ".join(
            f"{m} {na(e['median_abs_log_ratio'], '.3f')} ({na(e['median_log_ratio'], '+.3f')})"
            for m, e in margin_error.items()
        ),
        *(
            f"training wrenches of {m}, margin vs the noise-free exact margin, median |log ratio| "
            "(bias): "
            + ", ".join(
                f"{k} {na(e['vs_exact_nominal']['median_abs_log_ratio'], '.4f')} "
                f"({na(e['vs_exact_nominal']['median_log_ratio'], '+.4f')})"
                for k, e in by.items()
            )
            for m, by in training.items()
        ),
    ]
