"""What the grasp models' training wrenches cost, and what a cheaper set would change (the grasp path's
largest stage): on the jaw contacts of the grasp dataset's top grasps (thesis meshes, upright and
lying), the 6DLS ellipsoid trained by

* "mix" (the default, ``config.DEFAULTS.ls_training_sampler``): the thesis sampler's 600 wrenches
  plus the author's 48,483-twist grid downsampled to one wrench per occupied cell;
* "thesis": the thesis sampler's 600 alone (§3.3.2);
* "mix, grid chosen on a coarsened contact": the grid's cells chosen on the contact coarsened to
  0.5, 1 or 2 mm cells (``workbench.coarsen``), the chosen twists' wrenches then exact.

Each is timed (its training wrenches, one process) and scored by Eq. 3.18 on the same held-out set
(the author's whole grid and 1,000 thesis-sampler wrenches of the fine contact); beside, the
median relative difference of its fitted values from mix's on that set.  Held-out error is not
the grasp question itself: the sensitivity experiment chose "mix" by the resistance margins
(``results/sensitivity`` → ``training_distribution``); this benchmark says what the cheaper sets
cost in fit, not whether a grasp verdict moves.

Writes results/benchmarks/training_sampler.json.  Run: python benchmarks/bench_training_sampler.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np
from bench_wrench import machine_roofline

from workbench.coarsen import coarsen_profile
from workbench.experiments.grasp_dataset import DEFAULT_CONFIG, _gripper, _rested, _spec
from workbench.grasp.gripper_eval import gripper_contact
from workbench.grasp.top_grasps import sample_top_grasps
from workbench.limit_surface import fit_ellipsoid
from workbench.limit_surface.cache import SamplerSpec
from workbench.limit_surface.thesis_code import thesis_code_sample
from workbench.runner.results import CHECKOUT, code_revision, versions, write_json
from workbench.twists import sample_twists_thesis
from workbench.twists_author import sample_twists_author
from workbench.wrench import frictional_wrenches, w_max

OUT = Path(__file__).resolve().parents[1] / "results" / "benchmarks" / "training_sampler.json"
OBJECTS = CHECKOUT.parent / "shared" / "data" / "thesis_objects"
MU = 0.3  # the dataset's pads
CELLS_MM = (0.5, 1.0, 2.0)


def top_grasp_contacts(n_meshes: int, n_grasps: int):
    """(object, lying, gripper contact) of ``n_grasps`` top grasps of every 6th thesis mesh,
    upright and lying: the grasp dataset's gripper, sampler and settled contact."""
    cfg = dict(DEFAULT_CONFIG)
    gripper = _gripper(cfg)
    for path in sorted(OBJECTS.glob("*.obj"))[::6][:n_meshes]:
        for lying in (False, True):
            mesh, _ = _rested(str(path), lying)
            top = sample_top_grasps(
                mesh, n_grasps, cfg["sampling_mu"], gripper, _spec(cfg), seed=0, block=2000, max_blocks=3
            )
            for _, pose in top:
                contact = gripper_contact(mesh, gripper, pose)
                if contact.touches:
                    yield path.stem, lying, contact


def _profiles(n_meshes: int, n_grasps: int):
    """The jaw contacts of ``n_grasps`` top grasps of every 6th thesis mesh, upright and lying."""
    for stem, lying, contact in top_grasp_contacts(n_meshes, n_grasps):
        yield from ((stem, lying, p) for p in contact.profiles)


def _timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, (time.perf_counter() - t) * 1e3


def _coarse_mix(prof, cell_m: float):
    """The thesis sampler's 600 and the grid's cells chosen on the coarsened contact, all exact."""
    code = thesis_code_sample(coarsen_profile(prof, cell_m), MU, 0)
    xi = np.vstack([sample_twists_thesis(300, prof, 0), code.train_twists])
    return xi, frictional_wrenches(prof, xi, MU)


def measure(prof) -> dict:
    wm = w_max(prof)
    test = np.vstack(
        [
            frictional_wrenches(prof, sample_twists_author(prof, 0), MU),
            frictional_wrenches(prof, sample_twists_thesis(500, prof, 99), MU),
        ]
    )
    variants = {
        "mix": lambda: SamplerSpec(kind="mix").training(prof, MU),
        "thesis": lambda: SamplerSpec(kind="thesis").training(prof, MU),
    }
    variants |= {f"mix_coarse_{c:g}mm": (lambda c=c: _coarse_mix(prof, c * 1e-3)) for c in CELLS_MM}
    row: dict = {"n_elements": len(prof.areas)}
    ref = None
    for name, fn in variants.items():
        (_, W), ms = _timed(fn)
        model = fit_ellipsoid(W, "lsq", w_max=wm)
        values = model.value(test)
        ref = values if ref is None else ref
        row[name] = {
            "ms": ms,
            "n_train": len(W),
            "heldout_error": model.fitting_error(test),
            # held-out wrenches of zero (a twist that slides nothing) have value 0 in every model
            "median_rel_value_diff_vs_mix": float(np.median(np.abs(values[ref > 0] / ref[ref > 0] - 1))),
        }
    return row


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(OUT))
    args = parser.parse_args()
    if not OBJECTS.is_dir():
        raise SystemExit(f"needs the thesis meshes in {OBJECTS}")
    t0 = time.perf_counter()
    rows = [
        {"object": o, "lying": lying, **measure(p)}
        for o, lying, p in _profiles(1 if args.quick else 4, 1 if args.quick else 3)
    ]
    names = [k for k in rows[0] if isinstance(rows[0][k], dict)]
    summary = {
        name: {
            stat: float(np.median([r[name][stat] for r in rows]))
            for stat in ("ms", "n_train", "heldout_error", "median_rel_value_diff_vs_mix")
        }
        for name in names
    }
    result = {
        "what": __doc__.split("\n\n")[0],
        "n_contacts": len(rows),
        "median_n_elements": float(np.median([r["n_elements"] for r in rows])),
        "median": summary,
        "mix_over_thesis_time": summary["mix"]["ms"] / summary["thesis"]["ms"],
        "rows": rows,
        "machine": {
            **machine_roofline(quick=True),
            "cpu_count": os.cpu_count(),
            "loadavg_1_5_15": os.getloadavg(),
        },
        "code_revision": code_revision(),
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t0,
    }
    write_json(Path(args.out), result)
    for name, s in summary.items():
        print(
            f"{name:22s} {s['ms']:8.1f} ms  {s['n_train']:5.0f} wrenches  held-out {s['heldout_error']:.4f}  "
            f"vs mix {s['median_rel_value_diff_vs_mix']:.4f}"
        )


if __name__ == "__main__":
    main()
