"""Fig 4.2(d): the power law of Eq. 4.3 fitted to the FEM pad's pressure on elliptic cylinders.

Thesis §4.1.3.2: a fin-ray jaw pressed on the type I objects (elliptic cylinders) in ANSYS; the
element pressures against r / r_max, r the distance across the grasp axis and the cylinder's
axis, follow Eq. 4.3 with k = 2.4, and "the exact k value varies from 2.4 to 5.5 for the
elliptic cylinders under different loads".  Here the same fit on our pad (the 20 × 40 × 5 mm
silicone layer of fem-fitting, condensed SRI) pressed 1–3 mm on five cylinders
(:func:`workbench.fem.cylinder_pressure.cylinder_pressure_laws`).  The thesis prints neither its
cylinders' radii nor its jaw's material: ours share a semi-axis along the grasp axis and differ
across it, which sets the contact's curvature.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from workbench.fem.cylinder_pressure import cylinder_pressure_laws
from workbench.fem.material import Material
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.pressure import power_law
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.results import save_figure, write_csv, write_summary

NAME = "power-law"

DEFAULT_CONFIG = {
    "seed": 0,  # nothing is random here; kept for the summaries' common fields
    "pad": {"width": 0.02, "length": 0.04, "thickness": 0.005, "nx": 20, "ny": 40, "nz": 5},
    "E": 1.0e6,  # silicone [Pa]: the fitted shape does not depend on it (linear elasticity)
    "nu": 0.45,  # as fem-fitting
    "a": 0.03,  # every cylinder's semi-axis along the grasp axis [m] (the scenes' default)
    "b": [0.015, 0.02, 0.03, 0.04, 0.06],  # semi-axes across it [m]: contact radius b²/a 7.5-120 mm
    "deltas_mm": [1.0, 2.0, 3.0],  # jaw displacements from first touch, as §3.5.2
}
_PAD_M = {"width": ("pad_size", 1.0), "length": ("pad_size", 1.0), "thickness": ("pad_thickness", 1.0)}
#: what each key means, its unit and plausible range (``workbench run power-law --help``)
KEYS = {
    "pad": Key("silicone pad: width, length, thickness [m] and hexes nx, ny, nz", "m", fields=_PAD_M),
    "E": Key("pad Young's modulus (the pressure's shape does not depend on it)", "Pa", "pad_modulus"),
    "nu": Key("pad Poisson ratio", "", "poisson"),
    "a": Key("the cylinders' semi-axis along the grasp axis", "m", "lever"),
    "b": Key("the cylinders' semi-axes across the grasp axis, one cylinder each", "m", "lever"),
    "deltas_mm": Key("jaw displacements from first touch, increasing, each below the pad's thickness", "mm"),
}
QUICK_CONFIG = {"pad": {**DEFAULT_CONFIG["pad"], "nx": 10, "ny": 20, "nz": 3}, "b": [0.02, 0.04]}

#: the thesis's numbers (§4.1.3.2, Fig 4.2(d)), for the figure and the headline
THESIS_K, THESIS_K_RANGE = 2.4, (2.4, 5.5)


def check_config(config: dict) -> None:
    """The settings, before any work: each key's rule, then displacements inside the pad."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    geom = PadGeometry(**config["pad"])
    d = [float(x) for x in config["deltas_mm"]]
    if not d or d != sorted(d) or not all(0 < x < geom.thickness * 1e3 for x in d):
        raise ValueError(
            f"deltas_mm must be increasing displacements in (0, {geom.thickness * 1e3:g}) mm (the pad's "
            f"thickness); got {config['deltas_mm']}"
        )
    if not config["b"]:
        raise ValueError("b must list at least one semi-axis [m], e.g. [0.02]")


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    pad = condense_pad(PadGeometry(**config["pad"]), Material(config["E"], config["nu"]))
    laws = cylinder_pressure_laws(
        pad, [(config["a"], b) for b in config["b"]], [d * 1e-3 for d in config["deltas_mm"]]
    )
    rows = [
        [
            law.a,
            law.b,
            law.delta * 1e3,
            law.force,
            law.n_elements,
            law.fit.k,
            law.fit.p0,
            law.fit.r_max,
            law.fit.rms_rel,
            law.fit.at_bound,
        ]
        for law in laws
    ]
    write_csv(
        out / "power_law.csv",
        ["a_m", "b_m", "delta_mm", "force_N", "n_elements", "k", "p0_Pa", "r_max_m", "rms_rel", "k_at_bound"],
        rows,
    )
    resolved = [law.fit.k for law in laws if not law.fit.at_bound]
    fig = save_figure(_figure(laws, config), out / "fig_4_2d_power_law.png")
    k_range = [min(resolved), max(resolved)] if resolved else None
    summary = {
        "cases": [
            {
                "a_m": law.a,
                "b_m": law.b,
                "contact_radius_m": law.b**2 / law.a,
                "delta_mm": law.delta * 1e3,
                "force_N": law.force,
                "n_elements": law.n_elements,
                "k": law.fit.k,
                "rms_rel": law.fit.rms_rel,
                "r_max_m": law.fit.r_max,
                "k_at_bound": law.fit.at_bound,
            }
            for law in laws
        ],
        "k_range": k_range,
        "n_k_at_bound": len(laws) - len(resolved),
        "max_rms_rel": max(law.fit.rms_rel for law in laws),
        "thesis": {"k": THESIS_K, "k_range": list(THESIS_K_RANGE)},
        "figures": [str(fig)],
        "headline": [
            (f"k from {k_range[0]:.2f} to {k_range[1]:.2f}" if k_range else "no k resolved")
            + f" over {len(laws)} pressings (thesis: {THESIS_K}, "
            f"range {THESIS_K_RANGE[0]}–{THESIS_K_RANGE[1]}); "
            f"worst relative RMS residual {max(law.fit.rms_rel for law in laws):.3f}"
        ],
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _figure(laws, config: dict):
    """Fig 4.2(d) per cylinder: p / p0 against r / r_max, the elements as dots and the fitted
    law as a line, a colour per displacement."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    bs = list(dict.fromkeys(law.b for law in laws))
    fig, axes = plt.subplots(1, len(bs), figsize=(3.2 * len(bs), 3.0), sharey=True, squeeze=False)
    s = np.linspace(0, 1, 200)
    for ax, b in zip(axes[0], bs, strict=True):
        for i, law in enumerate(x for x in laws if x.b == b):
            f = law.fit
            ax.plot(law.r / f.r_max, law.p / f.p0, ".", ms=2, color=f"C{i}", alpha=0.5)
            ax.plot(
                s, power_law(s, 1.0, f.k), "-", color=f"C{i}", label=f"{law.delta * 1e3:g} mm: k = {f.k:.2f}"
            )
        ax.plot(s, power_law(s, 1.0, THESIS_K), "k--", lw=0.8, label=f"thesis k = {THESIS_K}")
        ax.set_title(f"b = {b * 1e3:g} mm (a = {config['a'] * 1e3:g} mm)", fontsize=8)
        ax.set_xlabel("r / r_max")
        ax.legend(fontsize=6)
    axes[0, 0].set_ylabel("p / p0")
    fig.suptitle("Fig 4.2(d) on our pad: Eq. 4.3 fitted to the FEM pressures", fontsize=9)
    fig.tight_layout()
    return fig
