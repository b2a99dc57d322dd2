"""The engine judge validated before it judges anything (items (a)–(e)), in one summary.

Each probe of :mod:`workbench.engine_trials` against its closed form or our own FEM, run as a
Dask task and checkpointed: (a) the pad indented by a flat and by spheres against our
neo-Hookean pad (:func:`~workbench.engine_trials.indentation.indent_pad`; MuJoCo always, Drake
with ``drake=true`` and the ``peers`` extra — minutes per indenter); (b) friction — a block
pulled at μ m g, a block on a tilting plane at atan μ, the creep of a block held below its slip
load; (c) the torsion of a flat pad against μ Σ N_i |r_i|; (d) shells — not run (MuJoCo 4.0's 2D
flex misses our wall FEM by 19–30 %, README); (e) reality — the REACH cube trials at their
recorded poses against the 125 real outcomes.  Each entry carries the engine and its settings.
"""

from __future__ import annotations

import json
import shlex
import time
from dataclasses import asdict
from functools import partial
from pathlib import Path

import numpy as np

from workbench.code_key import code_digest
from workbench.engine_trials.indentation import indenter_pad_mesh
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_checkpointed
from workbench.runner.results import write_summary

NAME = "engine-validation"

DEFAULT_CONFIG = {
    "mus": [0.2, 0.5, 1.0],  # friction coefficients of the block probes
    "pull_angles_deg": [0.0, 45.0],  # pull directions (elliptic cones are isotropic)
    "creep_fractions": [0.5, 0.9],  # held loads as fractions of the slip load
    "indenters": ["flat", "sphere10", "sphere25"],  # (a): a rigid flat, spheres of R 10 / 25 mm
    "depths_mm": [0.25, 0.5, 1.0],  # (a): indentations
    "drake": False,  # (a) also on Drake (peers extra; far slower than MuJoCo)
    "reach_grasps": [],  # (e): REACH cube grasp indices; [] = all 25
    "workers": 0,
    "scheduler": "",
}
KEYS = {
    "mus": Key("friction coefficients of the block probes", "", "mu"),
    "pull_angles_deg": Key("pull directions of the pulled block [deg]"),
    "creep_fractions": Key("held loads as fractions of the slip load, in (0, 1)"),
    "indenters": Key("indenters of (a)", choices=("flat", "sphere10", "sphere25")),
    "depths_mm": Key("indentations of (a)", "mm", "compression", 1e-3),
    "drake": Key("also indent on Drake (the peers extra)"),
    "reach_grasps": Key("REACH cube grasp indices of (e); [] = all"),
}
QUICK_CONFIG = {
    "mus": [0.5],
    "pull_angles_deg": [0.0],
    "creep_fractions": [0.5],
    "indenters": ["sphere10"],
    "depths_mm": [0.25],
    "reach_grasps": [0, 19],  # one held in all 5 real repeats, one dropped in all 5
}
#: (a)'s engine pad per indenter: the spheres need a graded mesh under them (indentation's tests)
_RADIUS = {"flat": None, "sphere10": 0.01, "sphere25": 0.025}


#: the probe lists of (a) and (b): each must name at least one probe (an empty one ran the
#: other items for minutes and then failed, or left its item's criterion judged on nothing)
_NON_EMPTY = ("mus", "pull_angles_deg", "creep_fractions", "indenters", "depths_mm")


def check_config(config: dict) -> None:
    """Every key by :data:`KEYS`; no empty probe list (``reach_grasps``: [] = all 25); creep
    fractions in (0, 1); indentations shallower than (a)'s pad; grasp indices of the 25."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    for key in _NON_EMPTY:
        if not config[key]:
            example = shlex.quote(f"{key}={json.dumps(DEFAULT_CONFIG[key])}")
            raise ValueError(f"{key} is empty ({KEYS[key].doc}): give at least one, e.g. --set {example}")
    h_mm = min(indenter_pad_mesh(_RADIUS[i]).thickness for i in config["indenters"]) * 1e3
    deep = [d for d in config["depths_mm"] if d >= h_mm]
    if deep:  # in mm as asked, only deeper than the pad (the FEM's own refusal blames the unit)
        example = shlex.quote(f"depths_mm={json.dumps(DEFAULT_CONFIG['depths_mm'])}")
        raise ValueError(
            f"depths_mm {deep} reach (a)'s pad thickness of {h_mm:g} mm: an indenter pressed that deep "
            f"would hit the pad's rigid back — give indentations below {h_mm:g} mm, e.g. --set {example}"
        )
    if not all(0 < f < 1 for f in config["creep_fractions"]):
        raise ValueError(f"creep_fractions must lie in (0, 1); got {config['creep_fractions']}")
    if not all(isinstance(g, int) and 0 <= g < 25 for g in config["reach_grasps"]):
        raise ValueError(f"reach_grasps must be grasp indices in [0, 25); got {config['reach_grasps']}")
    check_workers(config["workers"], config["scheduler"])


def _tasks(config: dict) -> list[tuple]:
    tasks: list[tuple] = [("indent", i, "mujoco") for i in config["indenters"]]
    if config["drake"]:
        tasks += [("indent", i, "drake") for i in config["indenters"]]
    grasps = config["reach_grasps"] or list(range(25))
    tasks += [("reach", g) for g in grasps]
    tasks += [("pull", mu, a) for mu in config["mus"] for a in config["pull_angles_deg"]]
    tasks += [("tilt", mu) for mu in config["mus"]]
    tasks += [("creep", f) for f in config["creep_fractions"]]
    tasks.append(("spin",))
    return tasks


def _key(task: tuple) -> str:
    return "/".join(map(str, task))


def _row(task: tuple, config: dict) -> dict:
    """One probe (driver or Dask worker)."""
    from workbench.engine_trials import probes

    kind = task[0]
    t0 = time.perf_counter()
    if kind == "indent":
        from workbench.engine_trials.indentation import STIFF_CONTACT, indent_pad

        name, engine = task[1], task[2]
        radius = _RADIUS[name]
        mesh = indenter_pad_mesh(radius)
        depths = tuple(d * 1e-3 for d in config["depths_mm"])
        r = indent_pad(
            "flat" if radius is None else "sphere",
            radius,
            depths,
            engine,
            mesh=mesh,
            settings=STIFF_CONTACT if engine == "mujoco" else None,
        )
        row = {**r.as_dict(), "max_abs_error": float(np.max(np.abs(r.error)))}
    elif kind == "reach":
        from workbench.engine_trials.reality import reach_trial

        row = reach_trial(task[1])
    elif kind == "pull":
        row = probes.pulled_block(task[1], angle_deg=task[2])
    elif kind == "tilt":
        row = probes.tilted_block(task[1])
    elif kind == "creep":
        row = probes.held_block_creep(0.5, task[1])  # μ 0.5, as the tests' creep
    else:
        row = probes.spun_pad(0.5)  # μ 0.5 on a 20 x 40 mm pad pressed by 10 N
    # the checkpoint turns numpy values into JSON ones (results.Checkpoint.add)
    return {**row, "seconds": time.perf_counter() - t0}


def run(config: dict) -> dict:
    from workbench.engine_trials import EngineSettings
    from workbench.engine_trials.reality import score_reach

    t_start = time.perf_counter()
    out = Path(config["out"])
    ckpt, n_resumed, ran_on = run_checkpointed(
        partial(_row, config=config),
        _tasks(config),
        _key,
        out,
        config,
        desc=NAME,
        unit="probe",
        code=code_digest(__name__),
    )
    rows = {_key(t): ckpt.rows[_key(t)] for t in _tasks(config)}

    def strip(r: dict) -> dict:
        return {k: v for k, v in r.items() if k not in ("key", "config_hash")}

    a = {k.removeprefix("indent/"): strip(r) for k, r in rows.items() if k.startswith("indent/")}
    reach = [strip(r) for k, r in rows.items() if k.startswith("reach/")]
    summary = {
        "engine": "MuJoCo (mujoco.__version__ in versions); Drake for (a) where drake=true",
        "settings": asdict(EngineSettings()),
        "a_indentation": {
            "criterion": "force within 10 % of our neo-Hookean pad (fem.fidelity.press, nonlinear), δ ≤ 1 mm",
            "runs": a,
            "passes": {k: bool(r["max_abs_error"] <= 0.10) for k, r in a.items()},
        },
        "b_friction": {
            "criterion": "slip at μ within 5 %; creep at half the slip load measured (mm/s)",
            "pulled_block": {
                k.removeprefix("pull/"): strip(r) for k, r in rows.items() if k.startswith("pull/")
            },
            "tilted_block": {
                k.removeprefix("tilt/"): strip(r) for k, r in rows.items() if k.startswith("tilt/")
            },
            "creep_mm_per_s": {
                k.removeprefix("creep/"): r["speed"] * 1e3 for k, r in rows.items() if k.startswith("creep/")
            },
        },
        "c_torsion": {"criterion": "spin onset at μ Σ N_i |r_i| within 10 %", **strip(rows["spin"])},
        "d_shells": {
            "run": False,
            "why": (
                "MuJoCo 4.0's 2D flex misses our wall FEM's squeeze stiffness of a PET cylinder (r 30 mm, "
                "t 0.5 mm) by -30/-25/-19 % at 32x22/48x33/96x65 vertices (its hinge bending depends on "
                "the triangles' shape); Drake 1.51 has no shells and its linear tets lock in bending: a "
                "free 10 mm PET ring is within 15 % of Roark only at 8 layers x 1024 around (49,152 tets, "
                "5.9 GB), every tube mesh that fits in this machine's memory is +208 to "
                "+272 % too stiff. Blocked on both engines; README, 'Thin-walled objects'"
            ),
        },
        "e_reality": score_reach(reach),
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
    }
    summary["headline"] = _headline(summary)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _headline(s: dict) -> list[str]:
    b = s["b_friction"]
    pulls = [r["ratio"] for r in b["pulled_block"].values()]
    tilts = [r["ratio"] for r in b["tilted_block"].values()]
    lines = [
        f"(a) indentation within 10 % at every depth: {s['a_indentation']['passes']}",
        f"(b) pulled block onset {min(pulls):.3f}-{max(pulls):.3f} x mu m g; tilt {min(tilts):.3f}-"
        f"{max(tilts):.3f} x atan mu; creep {b['creep_mm_per_s']} mm/s",
        f"(c) torsion onset {s['c_torsion']['ratio']:.3f} x mu sum N|r|",
        "(d) shells not run (MuJoCo 4.0's 2D flex misses the wall FEM by 19-30 %)",
    ]
    e = s["e_reality"]
    lines.append(
        f"(e) REACH cube: balanced accuracy {e['balanced_accuracy']:.3f}, AUC {e['roc_auc']:.3f} over "
        f"{e['n_trials']} real trials (TPR {e['true_positive_rate']:.3f}, TNR {e['true_negative_rate']:.3f})"
    )
    return lines
