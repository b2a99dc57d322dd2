"""Wall stiffness of thin-walled objects (thesis §4.3.3.1, the s_i of Eq. 4.5): maps over
the bottle family, or any mesh at given grasps (--set object=PATH.obj --set locations=PATH.json,
JSON {"stiffness_locations": 2n points [m], i and i + n one grasp}; README).

The thesis measured ``s_i = f_⊥ / (l_s − l_e)`` with a
parallel-jaw gripper closing to 10 N per jaw at antipodal grasp locations; here
a PET-like wall (linear elastic, 0.5 mm, clamped base, open top) of bottles
from the thesis family is squeezed between two rigid 20 × 40 mm jaws
(:mod:`workbench.fem.wall`) at a grid of heights × grasp-axis angles, giving a stiffness
map over the surface.  Validation first: the thin ring under diametral loads
(Roark), perpendicular diameter (load applied) and load-line closing (through
:func:`workbench.fem.wall.squeeze`, i.e. the contact solve itself), with mesh refinement;
then the bottle's mesh convergence at one location.

Rows are checkpointed per (bottle, height, angle) so a killed run resumes.  The family's
maps run as Dask tasks, one per (bottle, height) — each worker process builds a bottle's wall
once (:func:`workbench.fem.wall_family.bottle_wall`, a per-process memo) — and the
mesh-convergence study as one more, while the driver runs the ring validation
(:mod:`workbench.runner.parallel`; ``workers`` / ``scheduler``; the numbers are the serial run's).

With ``object=PATH.obj`` (a watertight mesh in metres of a thin-walled object) and
``locations=PATH.json`` (``stiffness_locations``, 2n points, i and i + n one grasp —
the measured maps' format) it instead squeezes that object's wall at those grasps
(:mod:`workbench.fem.mesh_wall`, :mod:`workbench.fem.wall_grasps`) and writes ``stiffness_n_per_m`` in
grasp order with ``rigid`` and ``failed`` flags; when the JSON also holds a
``stiffness_map`` the summary compares the two (uncalibrated).
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.fem.bottle import Bottle, bottle_family
from workbench.fem.calibration import uncalibrated_scores
from workbench.fem.material import Material
from workbench.fem.object_wall import TOPS, wall_geometry
from workbench.fem.wall import ring_validation, squeeze
from workbench.fem.wall_family import bottle_wall, grasp_axis, mesh_convergence, mesh_error, stiffness_map
from workbench.fem.wall_grasps import grasp_pairs, read_locations, stiffness_at
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import CHECKOUT, Checkpoint, save_figure, write_csv, write_summary

NAME = "wall-stiffness"

DEFAULT_CONFIG = {
    "seed": 0,
    "bottles": [0, 5, 20],  # indices into bottle_family(seed); 16..23 are the asymmetric ones
    "E": 2.5e9,  # PET ~2-4 GPa
    "nu": 0.4,
    "thickness": 0.5e-3,  # wall thickness [m]
    "mesh": [48, 24],  # hexes around, along the height (one triquadratic hex through the wall)
    "height_fractions": [0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8],
    "n_angles": 6,  # grasp-axis angles in [0, π) from the section's major axis
    "force": 10.0,  # N per jaw (thesis)
    "jaw": [0.02, 0.04],  # width (horizontal), length (vertical) [m]
    "ring_meshes": [32, 64, 128],
    "convergence_meshes": [[32, 16], [48, 24], [64, 32]],
    "object": "",  # a watertight mesh (metres) of a thin-walled object; "" = the bottle family
    "locations": "",  # JSON with stiffness_locations (2n, 3) [m] for object=
    "rigid_closing_mm": 0.05,  # closings below this are rigid (smallest measured: 0.052 mm)
    "top": "auto",  # object=: top edge of the wall: auto | lip | clamped | free (workbench.fem.object_wall)
    # where the family's maps run (workbench.runner.parallel.row_client): 0 = a local Dask cluster of
    # one worker per core when there are many rows, 1 = serially here, N = N local workers;
    # scheduler = an existing cluster's address.  Neither changes a number.
    "workers": 0,
    "scheduler": "",
}
#: what each key means, its unit and plausible range (``workbench run wall-stiffness --help``)
KEYS = {
    "bottles": Key(
        "bottle family only (no object=): indices into bottle_family(seed), 0-23 (16-23 asymmetric)"
    ),
    "E": Key("wall Young's modulus", "Pa", "wall_modulus"),
    "nu": Key("wall Poisson ratio", "", "poisson"),
    "thickness": Key("wall thickness", "m", "wall_thickness"),
    "mesh": Key("wall hexes [around, along the height]; memory grows ~ their product squared"),
    "height_fractions": Key("bottle family only: grasp heights as fractions of the wall's height, in [0, 1]"),
    "n_angles": Key("bottle family only: grasp-axis angles in [0, pi) per height"),
    "force": Key("force per jaw", "N", "jaw_force"),
    "jaw": Key("jaw face [width (horizontal), length (vertical)]", "m", "pad_size"),
    "ring_meshes": Key("bottle family only: hexes around the Roark ring of the validation"),
    "convergence_meshes": Key(
        "bottle family only: wall meshes [around, along] of the mesh-convergence study"
    ),
    "object": Key("a watertight mesh file in metres of a thin-walled object; empty = the bottle family"),
    "locations": Key("JSON file with stiffness_locations (2n, 3) [m] for object="),
    "rigid_closing_mm": Key("closings below this count as rigid", "mm", "closing", 1e-3),
    "top": Key("object=: top edge of the wall", choices=lambda: TOPS),
}
#: settings that do not enter the checkpoint key: where rows run changes no number
WHERE_KEYS = ("out", "workers", "scheduler")
#: the measured discretisation error of wall meshes at body and shoulder grasps
#: (benchmarks/bench_shoulder_convergence.py; ``make bench-shoulder``), beside the experiments;
#: read by :func:`workbench.fem.wall_family.mesh_error`
CONVERGENCE_FILE = CHECKOUT / "results" / "benchmarks" / "shoulder_convergence.json"
QUICK_CONFIG = {
    "bottles": [0],
    "mesh": [24, 12],
    "height_fractions": [0.3, 0.7],
    "n_angles": 2,
    "ring_meshes": [32, 64],
    "convergence_meshes": [],
}


def ring_rows(config: dict) -> list[dict]:
    """Thin ring (R = 35 mm mid-surface) under diametral line loads, two ways, at the run's
    material and thickness on each of ``ring_meshes`` (:func:`workbench.fem.wall.ring_validation`)."""
    return ring_validation(Material(config["E"], config["nu"]), config["thickness"], config["ring_meshes"])


def _map_task(job: tuple, config: dict) -> list[tuple[str, dict]]:
    """The map rows of one (bottle ``i``, height fraction ``hf``) at ``angles``: [(key, row)]."""
    i, hf, angles = job
    nt, nz = config["mesh"]
    b, wall = bottle_wall(
        config["seed"], i, float(config["E"]), float(config["nu"]), float(config["thickness"]), nt, nz
    )
    out = []
    for a in angles:
        t0 = time.perf_counter()
        r = squeeze(
            wall, *grasp_axis(b, hf * b.params.height, a), force=config["force"], jaw=tuple(config["jaw"])
        )
        row = {
            "bottle": i,
            "height_fraction": hf,
            "angle": a,
            # an impossible closing (jaws meeting inside the object) is flagged, not a stiffness
            "stiffness_N_per_m": None if r.implausible else r.stiffness,
            "implausible": r.implausible,
            "closing_mm": r.delta * 1e3,
            "contact_nodes": r.contact_nodes,
            "contact_points": r.contact_points.tolist(),
            "ms": (time.perf_counter() - t0) * 1e3,
            "build_s": wall.seconds,
        }
        out.append((f"{i}/{hf}/{a:.6f}", row))
    return out


def _convergence_task(config: dict) -> list[dict]:
    """The first bottle's stiffness at mid-height, two axes, on each of ``convergence_meshes``."""
    mat = Material(config["E"], config["nu"])
    b = Bottle(bottle_family(seed=config["seed"])[config["bottles"][0]])
    return mesh_convergence(
        b, mat, config["thickness"], config["convergence_meshes"], config["force"], tuple(config["jaw"])
    )


def task(job, config: dict):
    """A Dask task of the family run: a map job ``(bottle, height fraction, angles)`` — its rows
    ``[(key, row)]`` — or ``"convergence"`` (the mesh-convergence rows)."""
    return _convergence_task(config) if job == "convergence" else _map_task(job, config)


def _jobs(config: dict, angles: np.ndarray, ckpt: Checkpoint) -> tuple[list, int]:
    """The tasks still to run — ``(bottle, height fraction, angles)`` without a checkpointed row,
    the mesh-convergence study first — and the number of grasps they squeeze."""
    jobs: list = []
    for i in config["bottles"]:
        for hf in config["height_fractions"]:
            todo = tuple(float(a) for a in angles if f"{i}/{hf}/{a:.6f}" not in ckpt.rows)
            if todo:
                jobs.append((i, hf, todo))
    n_todo = sum(len(j[2]) for j in jobs)
    if config["convergence_meshes"]:
        jobs.insert(0, "convergence")  # the longest task first (its finest wall)
    return jobs, n_todo


def _headline(
    ring: list[dict], maps: dict, rows: list[dict], ms: np.ndarray, angles: np.ndarray, config: dict
) -> list[str]:
    return [
        "ring (Roark) at n_theta = {}: perpendicular {:+.2%}, load line {:+.2%}".format(
            ring[-1]["n_theta"], ring[-1]["perpendicular_rel_err"], ring[-1]["load_line_rel_err"]
        ),
        *(
            f"bottle {k}: stiffness {m['min']:.0f}..{m['max']:.0f} N/m over "
            f"{len(config['height_fractions'])} heights x {len(angles)} axes"
            + (f" ({m['n_implausible']} flagged implausible)" if m["n_implausible"] else "")
            if m["min"] is not None
            else f"bottle {k}: IMPLAUSIBLE — at every grasp the jaws would close by more than the "
            "bottle's width (the linear wall model does not hold: E or thickness in another unit?)"
            for k, m in maps.items()
        ),
        f"{len(rows)} grasps, median {np.median(ms):.0f} ms per grasp after a one-off wall factorisation",
        f"discretisation: {mesh_error(config['mesh'], CONVERGENCE_FILE)['note']}",
    ]


def run(config: dict) -> dict:
    if config["object"]:
        return run_object(config)
    t_start = time.perf_counter()
    out = Path(config["out"])
    mat = Material(config["E"], config["nu"])
    family = bottle_family(seed=config["seed"])
    angles = np.arange(config["n_angles"]) * np.pi / config["n_angles"]
    key_config = {k: v for k, v in config.items() if k not in WHERE_KEYS}
    ckpt = Checkpoint(out / "rows.jsonl", key_config, code=code_digest(__name__))
    n_resumed = len(ckpt.rows)
    jobs, n_todo = _jobs(config, angles, ckpt)
    got: dict = {}

    def keep(job, res) -> None:  # the driver alone writes the checkpoint
        if job == "convergence":
            got["conv"] = res
        else:
            for key, row in res:
                ckpt.add(key, row)

    n_bar = n_todo + 2 * len(config["convergence_meshes"])
    with tqdm(total=n_bar, desc="stiffness map", unit="grasp") as bar:
        # the ring validation is the driver's share while the workers squeeze the bottles
        ring, ran_on = run_rows(
            partial(task, config=config),
            jobs,
            keep,
            config,
            n_rows=n_todo,
            progress=bar,
            meanwhile=lambda: ring_rows(config),
        )
    write_csv(out / "ring_validation.csv", list(ring[0]), [list(r.values()) for r in ring])
    conv = got.get("conv", [])
    if conv:
        write_csv(out / "mesh_convergence.csv", list(conv[0]), [list(r.values()) for r in conv])
    build_s = {r["bottle"]: r["build_s"] for r in ckpt.rows.values() if "build_s" in r}

    # by bottle, height, angle (tasks finish in any order)
    rows = sorted(ckpt.rows.values(), key=lambda r: (r["bottle"], r["height_fraction"], r["angle"]))
    cols = ["bottle", "height_fraction", "angle", "stiffness_N_per_m", "closing_mm", "contact_nodes", "ms"]
    write_csv(out / "stiffness_map.csv", cols, [[r[c] for c in cols] for r in rows])

    maps = {
        str(i): stiffness_map(
            rows, i, config["height_fractions"], angles, asymmetric=bool(family[i].asymmetric)
        )
        for i in config["bottles"]
    }
    figures = _figures(out, family, maps, config)
    ms = np.array([r["ms"] for r in rows])
    summary = {
        "ring_validation": ring,
        "mesh_convergence": conv,
        "maps": maps,
        "n_grasps": len(rows),
        "n_implausible": sum(m["n_implausible"] for m in maps.values()),
        "n_resumed": n_resumed,
        "rows_ran_on": ran_on,
        "wall_build_s": build_s,
        "ms_per_grasp": {"median": float(np.median(ms)), "max": float(ms.max())},
        "mesh_error": mesh_error(config["mesh"], CONVERGENCE_FILE),
        "model": (
            f"linear elastic wall E = {mat.E:.3g} Pa, nu = {mat.nu}, t = {config['thickness'] * 1e3} mm, "
            "clamped base, open top, rigid frictionless jaws, secant stiffness at the target force"
        ),
        "figures": figures,
        "headline": _headline(ring, maps, rows, ms, angles, config),
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _file_hash(path: str) -> str:
    import hashlib

    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]


def _object_inputs(config: dict) -> tuple:
    """(mesh, locations (2n, 3), measured (n,) or None) of ``object=`` / ``locations=``, or a
    ``ValueError`` naming the key, what it expects, what it got and the fix: the wall options,
    both files, a watertight mesh in metres, 2n points.  Cheap (no ray casting), so
    :func:`check_config` runs it before any work; the locations are checked against the
    wall's surface by :func:`run_object`, before the wall is assembled."""
    import trimesh

    from workbench.fem.object_wall import check_wall_options
    from workbench.units import closed_mesh

    if not config["locations"]:
        raise ValueError(
            "object= needs locations=PATH.json (stiffness_locations: 2n points, i and i + n one grasp); "
            "got none — add --set locations=PATH.json"
        )
    check_wall_options(config["thickness"], config["top"])
    for key, what in (("object", "a watertight .obj mesh in metres"), ("locations", "a JSON file")):
        if not Path(config[key]).is_file():
            raise ValueError(f"{key}={config[key]}: no such file — give the path of {what}")
    try:
        mesh = trimesh.load(config["object"], force="mesh")
    except Exception as exc:  # trimesh raises many kinds for an unreadable file
        raise ValueError(
            f"object={config['object']}: expected a triangle mesh file (.obj, .stl, .ply); "
            f"trimesh cannot read it: {exc}"
        ) from exc
    mesh = closed_mesh(
        mesh,
        f"object={config['object']}",
        fix="re-export it in metres (scale it by {factor:g}, e.g. trimesh's mesh.apply_scale({factor:g}))",
        override=None,  # no allow_scale on the command line: a wall is metres-sized
    )
    L, measured = read_locations(config["locations"])
    return mesh, L, measured


def _check_family(config: dict) -> None:
    """The bottle family's keys: bottles, angles and heights."""
    bad = [i for i in config["bottles"] if not 0 <= i < 24]
    if bad or not config["bottles"]:
        raise ValueError(
            "bottles must be indices into the thesis's bottle family, 0-23, at least one; "
            f"got {config['bottles']!r}"
        )
    if config["n_angles"] < 1:
        raise ValueError(f"n_angles must be >= 1 (grasp axes per height); got {config['n_angles']!r}")
    bad = [h for h in config["height_fractions"] if not 0 <= h <= 1]
    if bad or not config["height_fractions"]:
        hint = (
            f" — per cent? pass {[h / 100 for h in config['height_fractions']]}"
            if bad and all(0 <= h <= 100 for h in config["height_fractions"])
            else ""
        )
        raise ValueError(
            f"height_fractions must be fractions of the wall's height in [0, 1], at least one; "
            f"got {config['height_fractions']!r}{hint}"
        )


def _check_meshes(config: dict) -> None:
    """The wall mesh, and the convergence study's meshes for the bottle family."""
    for key in ("mesh", *(["convergence_meshes"] if not config["object"] else [])):
        meshes = [config[key]] if key == "mesh" else config[key]
        for m in meshes:
            if len(m) != 2 or min(m) < 1:
                raise ValueError(
                    f"{key} must give [hexes around, hexes along the height], two integers >= 1, e.g. "
                    f"[48, 24]; got {m!r}"
                )


def check_config(config: dict) -> None:
    """With ``object=``, refuse careless inputs before any work (:func:`_object_inputs`);
    ``workbench run`` turns the ``ValueError`` into its error message.  Force, E and jaw
    size are checked in every mode (force=0 used to fail only after the wall was built)."""
    for key in ("force", "E", "nu", "thickness", "jaw", "rigid_closing_mm", "top"):  # also for run(config)
        check_key(key, KEYS[key], config[key])
    if len(config["jaw"]) != 2:
        raise ValueError(f"jaw must be [width, length] in metres, e.g. [0.02, 0.04]; got {config['jaw']!r}")
    if not config["object"]:
        _check_family(config)
    _check_meshes(config)
    check_workers(config["workers"], config["scheduler"])
    if config["locations"] and not config["object"]:
        raise ValueError(
            f"locations={config['locations']} needs object=PATH.obj (the mesh the locations lie on); "
            "without object= the experiment runs the bottle-family maps and would ignore the locations"
        )
    if config["object"]:
        _object_inputs(config)


def _squeeze_object(config: dict, geo, L: np.ndarray, ckpt: Checkpoint) -> float:
    """Squeeze the object's wall at every grasp without a checkpointed row (the wall built only
    then); returns the wall's build time [s] (0 when every row was resumed)."""
    n = len(L) // 2
    todo = [i for i in range(n) if str(i) not in ckpt]
    build_s = 0.0
    if todo:
        wall = geo.build(Material(config["E"], config["nu"]), n_theta=config["mesh"][0])
        build_s = wall.seconds
        for i in tqdm(todo, desc=f"wall stiffness {Path(config['object']).stem}", unit="grasp"):
            (row,) = stiffness_at(
                wall,
                geo,
                L[[i, i + n]],
                force=config["force"],
                jaw=tuple(config["jaw"]),
                rigid_closing=config["rigid_closing_mm"] * 1e-3,
                grasp_ids=[i],
            )
            ckpt.add(str(i), {"grasp": i, **row})
    return build_s


def _object_headline(config: dict, summary: dict, s: np.ndarray, n: int) -> list[str]:
    soft = s[~np.array(summary["rigid"]) & ~np.array(summary["failed"])]
    return [
        f"{Path(config['object']).stem}: {n} grasps, {sum(summary['rigid'])} rigid, "
        f"{sum(summary['failed'])} failed, {sum(summary['non_antipodal'])} not antipodal; "
        + (
            f"stiffness {soft.min():.0f}..{soft.max():.3g} N/m where not rigid"
            if soft.size
            else "none deflects"
        ),
        *(
            [f"{sum(summary['implausible'])} flagged implausible (closing beyond the object's width)"]
            if any(summary["implausible"])
            else []
        ),
        f"discretisation: {summary['mesh_error']['note']}",
    ]


def run_object(config: dict) -> dict:
    """The CLI contract: stiffness of ``object`` at the grasps of ``locations`` (module docstring)."""

    t_start = time.perf_counter()
    out = Path(config["out"])
    mesh, L, measured = _object_inputs(config)
    nz = config["mesh"][1]
    geo = wall_geometry(mesh, thickness=config["thickness"], n_z=nz, top=config["top"])
    grasp_pairs(L, geo.surface, mesh=mesh)  # refuse careless locations before the wall is built
    n = len(L) // 2
    key_cfg = {k: v for k, v in config.items() if k != "out"}
    key_cfg |= {"object_sha": _file_hash(config["object"]), "locations_sha": _file_hash(config["locations"])}
    ckpt = Checkpoint(out / "rows.jsonl", key_cfg, code=code_digest(__name__))
    n_resumed = len(ckpt.rows)
    build_s = _squeeze_object(config, geo, L, ckpt)
    rows = [ckpt.rows[str(i)] for i in range(n)]
    s = np.array([r["stiffness"] for r in rows], dtype=float)
    cols = [
        "grasp",
        "stiffness",
        "fem_stiffness",
        "delta",
        "rigid",
        "failed",
        "non_antipodal",
        "axis_normal_deg",
    ]
    cols += ["reason", "seconds"]
    write_csv(out / "stiffness.csv", cols, [[r.get(c) for c in cols] for r in rows])
    secs = np.array([r["seconds"] for r in rows if r["fem_stiffness"] is not None])
    summary = {
        "object": str(config["object"]),
        "locations": str(config["locations"]),
        "n_grasps": n,
        "stiffness_n_per_m": s.tolist(),
        "rigid": [bool(r["rigid"]) for r in rows],
        "failed": [bool(r["failed"]) for r in rows],
        "implausible": [bool(r.get("implausible", False)) for r in rows],
        "non_antipodal": [bool(r.get("non_antipodal", False)) for r in rows],
        "axis_normal_deg": [r.get("axis_normal_deg") for r in rows],
        "reasons": [r["reason"] for r in rows],
        "closing_mm": (np.array([r["delta"] for r in rows], dtype=float) * 1e3).tolist(),
        "wall": {
            "z_range_m": list(geo.z_range),
            "lip": None if geo.lip is None else vars(geo.lip),
            "top": "lip" if geo.lip else ("clamped" if geo.clamp_top else "free"),
            "n_z": geo.n_z,
        },
        "wall_build_s": build_s,
        "s_per_grasp": {"median": float(np.median(secs)), "max": float(secs.max())} if secs.size else None,
        "n_resumed": n_resumed,
        "mesh_error": mesh_error(config["mesh"], CONVERGENCE_FILE),
        "model": (
            f"linear elastic wall E = {config['E']:.3g} Pa, nu = {config['nu']}, "
            f"t = {config['thickness'] * 1e3} mm, "
            "outer surface r(theta, z) from the mesh by ray casting, clamped at the bottom of the side wall, "
            "top edge per workbench.fem.object_wall (lip ring / clamped shoulder / free); "
            "rigid frictionless jaws; "
            "secant stiffness at the target force"
        ),
    }
    if measured is not None:
        summary["vs_measured_uncalibrated"] = uncalibrated_scores(
            s, measured, rigid=summary["rigid"], failed=summary["failed"]
        )
    summary["headline"] = _object_headline(config, summary, s, n)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _figures(out: Path, family, maps: dict, config: dict) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figs = []
    fig, axes = plt.subplots(1, len(maps), figsize=(4.2 * len(maps), 3.6), squeeze=False)
    for ax, (k, m) in zip(axes[0], maps.items(), strict=True):
        grid = np.array(m["stiffness_N_per_m"], dtype=float) / 1e3
        im = ax.imshow(
            grid,
            origin="lower",
            aspect="auto",
            cmap="viridis",
            extent=[0, 180, m["height_fractions"][0], m["height_fractions"][-1]],
        )
        ax.set_xlabel("grasp axis angle from major axis [deg]")
        ax.set_ylabel("height / H")
        ax.set_title(f"bottle {k}" + (" (asymmetric)" if m["asymmetric"] else ""))
        fig.colorbar(im, ax=ax, label="stiffness [N/mm]")
    fig.tight_layout()
    figs.append(str(save_figure(fig, out / "stiffness_maps.png")))
    try:
        figs.append(str(_render(out, family, maps)))
    except Exception as exc:  # a render is a convenience; the map is the result
        import logging

        logging.getLogger(__name__).warning("offscreen rendering failed: %s", exc)
    return figs


def _render(out: Path, family, maps: dict) -> Path:
    """Bottles coloured by the interpolated stiffness at each wall point (Fig 4.13(a) style)."""
    from scipy.interpolate import RegularGridInterpolator

    from workbench.runner.viz import _pyvista, save_screenshot

    pv = _pyvista()
    pl = pv.Plotter(off_screen=True, window_size=(300 * len(maps), 520))
    for col, (k, m) in enumerate(maps.items()):
        b = Bottle(family[int(k)])
        tm = b.to_trimesh(96, 80)
        H = b.params.height
        ang = np.array(m["angles_rad"])
        grid = np.array(m["stiffness_N_per_m"], dtype=float) / 1e3
        # periodic in the axis angle (period π): wrap one column
        interp = RegularGridInterpolator(
            (np.array(m["height_fractions"]), np.r_[ang, np.pi]),
            np.column_stack([grid, grid[:, :1]]),
            bounds_error=False,
            fill_value=None,
        )
        v = np.asarray(tm.vertices)
        zf = np.clip(v[:, 2] / H, m["height_fractions"][0], m["height_fractions"][-1])
        beta = np.empty(len(v))
        for j, (x, y, z) in enumerate(v):
            c, _, _, phi = b.section(min(max(z, 0.0), H))
            beta[j] = (np.arctan2(y - c[1], x - c[0]) - phi) % np.pi
        mesh = pv.wrap(tm)
        mesh.point_data["stiffness [N/mm]"] = interp(np.column_stack([zf, beta]))
        mesh.translate((0.12 * col, 0.0, 0.0), inplace=True)
        pl.add_mesh(mesh, scalars="stiffness [N/mm]", cmap="viridis", show_scalar_bar=col == 0)
    pl.view_xz()
    pl.camera.elevation = 15
    return save_screenshot(pl, out / "stiffness_render.png")


#: Peak memory of one run against its walls' factors, fitted by benchmarks/bench_memory.py to
#: one-bottle --quick runs (the measurements, the fit's error and its checks:
#: results/benchmarks/memory_model.json).  peak = base_bytes + bytes_per_nnz * nnz, with the
#: factor's non-zeros nnz = nnz_coefficient * free_dofs ** nnz_exponent.
MEMORY_MODEL = {
    "measured_on": "2026-11-29",
    "base_bytes": 5.162e8,
    "bytes_per_nnz": 48.40,
    "nnz_coefficient": 80.76,
    "nnz_exponent": 1.1789,
}


def memory_estimate(config: dict, model: dict | None = None) -> int:
    """Estimated peak resident memory [bytes] of one run of ``config`` (a sweep point, run
    serially in one process), from :data:`MEMORY_MODEL` (or ``model``, the same keys).

    A wall of ``mesh = [n_theta, n_z]`` has ``36 n_theta n_z`` free dofs (one triquadratic hex
    through the wall: ``2 n_theta × 2 n_z × 3`` free nodes above the clamped base).  Walls alive
    at once: the family's maps keep up to two factored walls
    (:func:`workbench.fem.wall_family.bottle_wall`'s cache of two; a wall is factored on first use,
    after the cache has dropped the oldest); the
    mesh-convergence study builds its walls one after another, before the maps.  With
    ``object=`` one wall, of at least ``n_z`` rows (:func:`wall_geometry` adds rows for a lip).
    """
    m = MEMORY_MODEL if model is None else model

    def factor_bytes(mesh: list) -> float:
        dofs = 36.0 * int(mesh[0]) * int(mesh[1])
        return m["bytes_per_nnz"] * m["nnz_coefficient"] * dofs ** m["nnz_exponent"]

    if config["object"]:
        walls = factor_bytes(config["mesh"])
    else:
        maps = min(len(config["bottles"]), 2) * factor_bytes(config["mesh"])
        walls = max([maps, *(factor_bytes(c) for c in config["convergence_meshes"])])
    return int(m["base_bytes"] + walls)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))
