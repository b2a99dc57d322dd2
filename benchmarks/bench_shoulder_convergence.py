"""Mesh convergence of the wall stiffness at shoulder grasps.

A new user measured on their own revolved bottle that, near the shoulder, the default wall mesh
``[48, 24]`` (hexes around, along the height) gives a stiffness 25-37 % above ``[96, 48]``'s,
more than the 12-14 % discretisation error the README states.  This measures it: walls with a
shoulder, squeezed (10 N per jaw, rigid 20 x 40 mm jaws) at heights on the body, just below
the shoulder and on the shoulder, at two grasp-axis angles, on meshes ``[24, 12]`` ..
``[96, 48]`` (``[120, 60]`` when the machine's free memory allows; ``[144, 72]`` needs more
than 11 GiB and is refused).

The walls, one at a time (never two meshes at once):

* bottles of the thesis family (:func:`workbench.fem.bottle.bottle_family`, seed 0), built and
  squeezed exactly as ``workbench/experiments/wall_stiffness.py`` does (``bottle_wall``, ``grasp_axis``,
  :func:`workbench.fem.wall.squeeze`: clamped base, free top edge, PET 2.5 GPa, 0.5 mm);
  the shoulder starts at ``z_s``, the lowest height of the upper half above which the
  section's major semi-axis shrinks faster than ``SHOULDER_SLOPE`` all the way up;
* a bottle revolved with :func:`trimesh.creation.revolve` (a 60 mm cylinder body, a conical
  shoulder rounded at both ends to a 25 mm neck, :func:`revolved_bottle`), whose wall comes
  from its mesh as a user's does (:func:`workbench.fem.object_wall.wall_geometry`,
  ``top="auto"``: closed above, so the neck's top is clamped) and is squeezed through the
  CLI's path, :func:`workbench.fem.wall_grasps.stiffness_at` (``fem_stiffness``: the squeeze's
  value also where a closing would be called rigid).

Heights (:func:`shoulder_heights`): the body; the jaw's top edge at ``z_s``
(``below_shoulder``); the jaw centred on ``z_s`` and its bottom edge at ``z_s`` (``shoulder``).
A flat rigid jaw touches a wall that is not straight along the height at its outermost points
only: on bottle 5 both ``below_shoulder`` and the centred ``shoulder`` jaw touch the apex of the
bulge below the shoulder (two contact nodes), so they give one value; on the revolved bottle's
cylinder the jaw bears on a column of nodes.  The case ``revolved_scan`` squeezes the revolved
bottle at one angle every 5 mm from the jaw's top edge 10 mm below ``z_s`` to its bottom edge
15 mm above it: how the error varies with where the jaw's edges fall.  Both axis angles lie on
a node column at every mesh here (``n_theta`` a multiple of 8), so the numbers isolate the
height direction; the column effect around the wall (up to 14 % at 48 around) is the README's
separate statement.

``--variants`` adds meshes outside the sequence, compared with its finest: ``NTxNZ`` (e.g.
``48x48``: the default with twice the rows; ``96x24``: twice the columns) and ``NTxNZ/gB``,
rows ``B`` times finer within a jaw length of ``z_s`` and as coarse as ``NZ`` rows elsewhere
(:func:`graded_rows`; built by giving :func:`workbench.fem.wall.build_wall` the outer surface
with its heights re-parametrised, no library change).

Per location: the stiffness per mesh, its change relative to the finest mesh, and a
Richardson extrapolation ``s(h) = s* + C h^p`` (``h = 1 / n_theta``; ``n_z = n_theta / 2``
throughout) through the three finest meshes, with the observed order ``p`` — flagged
``justified: false`` (and no estimate) when the three values are not monotone, or ``p`` is
outside ``P_RANGE``.  The ratio-2 triple ``[24, 12]``, ``[48, 24]``, ``[96, 48]`` is given as a
cross-check.  Per mesh: each wall's build (meshing, assembly, factorisation) and each grasp's
seconds, on one thread (``OMP_NUM_THREADS=1 NUMBA_NUM_THREADS=1``; other jobs share the
machine), beside the machine's measured FMA limit (``bench_wrench.machine_roofline``).

Writes results/benchmarks/shoulder_convergence.json (atomically, after every mesh, with
``complete: false`` until the last); ``--resume`` keeps the (mesh, case) results of that file
whose case has the same locations and runs the rest; ``runs`` records every invocation.
``regions`` summarises the designed locations (the scan left out), ``regions_by_case`` each
case.  Run (the time it took: ``runs`` in the JSON):

    python benchmarks/bench_shoulder_convergence.py [--variants 48x48,96x24,48x24/g2]
"""

from __future__ import annotations

import os

# one thread (the machine is shared); before NumPy / Numba are imported
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse  # noqa: E402
import gc  # noqa: E402
import resource  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "benchmarks" / "shoulder_convergence.json"
MESHES = ((24, 12), (48, 24), (72, 36), (96, 48), (120, 60))
DEFAULT_MESH = (48, 24)
#: the largest mesh this benchmark builds: [144, 72] needs > 11 GiB (memory_model.json)
MAX_CELLS = 120 * 60
#: the family bottles (indices into bottle_family(seed=0)) with a shoulder below an open top:
#: 1 (a straight body, 0.45-0.75 H, then a shoulder to 0.6x its radius) and 5 (one of the
#: experiment's default bottles: a bulge at 0.65 H, then a shoulder to half its radius)
FAMILY = {1: 0.55, 5: 0.25}  # bottle -> body height as a fraction of H (its flattest stretch)
#: the shoulder starts where the major semi-axis shrinks by more than this per unit height (~6°)
SHOULDER_SLOPE = 0.1
#: observed orders of convergence accepted for an extrapolation (outside: not justified)
P_RANGE = (0.5, 6.0)
FORCE = 10.0  # N per jaw (thesis)
JAW = (0.02, 0.04)  # width (horizontal), length (vertical) [m]
E, NU, THICKNESS = 2.5e9, 0.4, 0.5e-3  # the experiment's PET wall

#: the revolved bottle [m]: body radius, neck radius, shoulder from z_s to z_n, top z_t, and the
#: radius of the rounded corners at both ends of the cone
REVOLVED = {"R": 0.030, "r": 0.0125, "z_s": 0.120, "z_n": 0.150, "z_t": 0.170, "round": 0.006}


def revolved_bottle(sections: int = 256):
    """The revolved test bottle (:data:`REVOLVED`) as a watertight ``trimesh.Trimesh`` in metres:
    the closed profile (axis, base, body, rounded cone, neck, top) turned about z."""
    import trimesh

    g = REVOLVED
    R, r, zs, zn, zt, f = g["R"], g["r"], g["z_s"], g["z_n"], g["z_t"], g["round"]
    cone = np.array([r - R, zn - zs]) / np.hypot(r - R, zn - zs)  # unit direction up the cone

    def corner(p0, p1, p2, n=16):  # a quadratic Bézier between two straight pieces
        t = np.linspace(0, 1, n)[1:-1, None]
        p0, p1, p2 = map(np.asarray, (p0, p1, p2))
        return list((1 - t) ** 2 * p0 + 2 * t * (1 - t) * p1 + t**2 * p2)

    a, b = np.array([R, zs]) + f * cone, np.array([r, zn]) - f * cone
    pts = [(0.0, 0.0), (R, 0.0), (R, zs - f), *corner((R, zs - f), (R, zs), a), a, b]
    pts += [*corner(b, (r, zn), (r, zn + f)), (r, zn + f), (r, zt), (0.0, zt)]
    mesh = trimesh.creation.revolve(np.array(pts, float), sections=sections)
    if not mesh.is_watertight:  # the profile closes on the axis: not expected
        raise RuntimeError("the revolved bottle is not watertight")
    return mesh


def shoulder_start(bottle) -> float:
    """``z_s`` [m]: the lowest height of the upper half above which the major semi-axis
    shrinks faster than ``SHOULDER_SLOPE`` all the way to the top."""
    H = bottle.params.height
    z = np.linspace(0.5 * H, H, 501)
    dA, _ = bottle.semi_axes(z, 1)
    steep = dA < -SHOULDER_SLOPE
    if not steep[-1]:
        raise ValueError("no shoulder: the wall does not lean in at the top")
    k = len(z) - 1
    while k > 0 and steep[k - 1]:
        k -= 1
    return float(z[k])


def _row_phase(z: float, z_range: tuple[float, float], n_z: int) -> float:
    """Where height ``z`` falls between node rows (quadratic elements: a row every half
    element), as a fraction 0..1 of that spacing: how a jaw edge meets the mesh."""
    h = (z_range[1] - z_range[0]) / (2 * n_z)
    return float(((z - z_range[0]) / h) % 1.0)


# --- cases: a wall per mesh and its grasp locations ------------------------------------


def shoulder_heights(zs: float) -> list[tuple[str, float]]:
    """Grasp-axis heights [m] about a shoulder starting at ``zs``: the jaw's top edge at it
    (``below_shoulder``), the jaw centred on it and its bottom edge at it (``shoulder``: the jaw
    bears on the shoulder with its lower edge, the grasp the user's report is about)."""
    half = JAW[1] / 2
    return [("below_shoulder", zs - half), ("shoulder", zs), ("shoulder", zs + half)]


def family_case(i: int, body_fraction: float) -> dict:
    """Bottle ``i`` of the family: body, just below the shoulder, on the shoulder."""
    from workbench.fem.bottle import Bottle, bottle_family

    b = Bottle(bottle_family(seed=0)[i])
    H = b.params.height
    zs = shoulder_start(b)
    half = JAW[1] / 2
    locations = [("body", body_fraction * H), *shoulder_heights(zs)]
    if locations[-1][1] + half > H:
        raise ValueError(f"bottle {i}: the shoulder grasp's jaw reaches above the wall's top")
    return {
        "name": f"family_{i}",
        "kind": "thesis bottle family (seed 0), workbench/experiments/wall_stiffness.py's wall and squeeze",
        "height_m": H,
        "shoulder_start_m": zs,
        "z_range_m": [0.0, H],
        "top": "free (open)",
        "locations": [(region, z, a) for region, z in locations for a in (0.0, np.pi / 2)],
    }


def revolved_case() -> dict:
    """The revolved bottle: body, below the shoulder, across and on the shoulder."""
    g = REVOLVED
    locations = [("body", 0.5 * g["z_s"]), *shoulder_heights(g["z_s"])]
    return {
        "name": "revolved",
        "kind": "trimesh.creation.revolve bottle, object_wall (top='auto') + wall_grasps.stiffness_at",
        "geometry_m": dict(g),
        "shoulder_start_m": g["z_s"],  # the cone's start (its rounding begins round below it)
        "top": "clamped (closed above the side wall)",
        "locations": [(region, z, a) for region, z in locations for a in (0.0, np.pi / 4)],
    }


def revolved_scan_case() -> dict:
    """The revolved bottle at one axis angle and heights every 5 mm about the shoulder (jaw top
    edge from 10 mm below the shoulder's start to 45 mm above it): how the default mesh's error
    varies with where the jaw's edges fall.  Regions by the jaw's top edge: below the rounding's
    start ``body``, within the rounding ``below_shoulder``, above it ``shoulder``."""
    g = REVOLVED
    half = JAW[1] / 2
    heights = g["z_s"] + np.arange(-30, 26, 5) * 1e-3
    lo, hi = g["z_s"] - g["round"], g["z_s"] + g["round"]

    def region(z: float) -> str:
        top = z + half
        return "body" if top <= lo else ("below_shoulder" if top <= hi else "shoulder")

    return {
        **revolved_case(),
        "name": "revolved_scan",
        "locations": [(region(z), float(z), 0.0) for z in heights],
    }


def parse_mesh(text: str) -> tuple[int, int, float | None]:
    """``"NTxNZ"`` (uniform rows) or ``"NTxNZ/gB"`` (rows B times finer in the shoulder band,
    :func:`graded_rows`) -> (n_theta, n_z, B or None)."""
    body, _, grade = text.partition("/g")
    nt, nz = (int(v) for v in body.split("x"))
    return nt, nz, float(grade) if grade else None


def graded_rows(z_range: tuple[float, float], zs: float, n_z: int, beta: float):
    """A wall's rows ``beta`` times finer in the band ``zs ± JAW[1]`` (every shoulder grasp's
    jaw) than ``n_z`` uniform rows, as coarse outside.  Returns ``(rows, g)``: the row count and
    ``g``, the map from :func:`workbench.fem.wall.wall_mesh`'s uniform heights in ``z_range``
    to the graded ones (piecewise linear: the density steps from 1 to ``beta`` at the band)."""
    z0, z1 = z_range
    a, b = max(z0, zs - JAW[1]), min(z1, zs + JAW[1])
    knots = np.array([z0, a, b, z1])
    cum = np.r_[0.0, np.cumsum(np.diff(knots) * np.array([1.0, beta, 1.0]))]  # ∫ density
    rows = int(round(n_z * cum[-1] / (z1 - z0)))

    def g(z: np.ndarray) -> np.ndarray:
        u = (np.asarray(z, float) - z0) / (z1 - z0) * cum[-1]
        return np.interp(u, cum, knots)

    return rows, g


def _reparametrised(surface, g):
    """The outer-surface callable ``(θ, s) -> surface(θ, g(s))`` (rows placed by ``g``)."""

    def outer(theta, s):
        return surface(theta, g(s))

    return outer


def _squeeze_rows(case: dict, squeeze_one, z_range, n_z: int | None) -> list[dict]:
    rows = []
    for region, z, a in case["locations"]:
        t0 = time.perf_counter()
        row = {"region": region, "z_m": z, "angle_rad": a, **squeeze_one(z, a)}
        row["jaw_edge_row_phase"] = (
            None
            if n_z is None
            else [_row_phase(z - JAW[1] / 2, z_range, n_z), _row_phase(z + JAW[1] / 2, z_range, n_z)]
        )
        row.setdefault("seconds", time.perf_counter() - t0)
        rows.append(row)
    return rows


def run_family(case: dict, i: int, spec: tuple) -> tuple[dict, list[dict]]:
    """Build bottle ``i``'s wall at ``spec`` (:func:`parse_mesh`) and squeeze it at the case's
    locations; uniform rows through the experiment's own
    :func:`workbench.fem.wall_family.bottle_wall`."""
    from workbench.fem.bottle import Bottle, bottle_family
    from workbench.fem.material import Material
    from workbench.fem.wall import build_wall, squeeze
    from workbench.fem.wall_family import bottle_wall, grasp_axis

    nt, nz, beta = spec
    z_range = (0.0, case["height_m"])
    t0 = time.perf_counter()
    if beta is None:
        b, wall = bottle_wall(0, i, E, NU, THICKNESS, nt, nz)
        rows_z = nz
    else:
        b = Bottle(bottle_family(seed=0)[i])
        rows_z, g = graded_rows(z_range, case["shoulder_start_m"], nz, beta)
        wall = build_wall(
            _reparametrised(b.points_normals, g),
            Material(E, NU),
            thickness=THICKNESS,
            n_theta=nt,
            n_z=rows_z,
            z_range=z_range,
        )
    build = {"wall_build_s": wall.seconds, "wall_total_s": time.perf_counter() - t0}
    build |= {"free_dofs": int(wall.free.size), "n_z_rows": rows_z}

    def one(z: float, a: float) -> dict:
        r = squeeze(wall, *grasp_axis(b, z, a), force=FORCE, jaw=JAW)
        return {
            "stiffness": None if r.implausible else float(r.stiffness),
            "closing_mm": r.delta * 1e3,
            "contact_nodes": r.contact_nodes,
            "converged": r.converged,
            "on_clamp": r.on_clamp,
            "compliance_solves": r.compliance_solves,
        }

    rows = _squeeze_rows(case, one, z_range, None if beta else nz)
    bottle_wall.cache_clear()  # the factor goes before the next mesh's is built
    return build, rows


def run_revolved(case: dict, mesh, spec: tuple) -> tuple[dict, list[dict]]:
    """Build the revolved bottle's wall at ``spec`` and squeeze it as the CLI does
    (:func:`workbench.fem.wall_grasps.stiffness_at`)."""
    from workbench.fem.material import Material
    from workbench.fem.object_wall import wall_geometry
    from workbench.fem.wall import build_wall
    from workbench.fem.wall_grasps import stiffness_at

    nt, nz, beta = spec
    t0 = time.perf_counter()
    geo = wall_geometry(mesh, thickness=THICKNESS, n_z=nz, top="auto")
    if beta is None:
        wall = geo.build(Material(E, NU), n_theta=nt)
        rows_z = geo.n_z
    else:
        rows_z, g = graded_rows(geo.z_range, case["shoulder_start_m"], geo.n_z, beta)
        wall = build_wall(
            _reparametrised(geo.outer, g),
            Material(E, NU),
            thickness=geo.thickness,  # no lip on a closed bottle: one thickness
            n_theta=nt,
            n_z=rows_z,
            z_range=geo.z_range,
            clamp_top=geo.clamp_top,
        )
    build = {"wall_build_s": wall.seconds, "wall_total_s": time.perf_counter() - t0}
    build |= {"free_dofs": int(wall.free.size), "z_range_m": list(geo.z_range), "n_z_rows": rows_z}
    case["z_range_m"] = list(geo.z_range)

    def one(z: float, a: float) -> dict:
        p, _ = geo.surface(np.array([a, a + np.pi]), np.full(2, z))
        (r,) = stiffness_at(wall, geo, p, force=FORCE, jaw=JAW)
        fem = r["fem_stiffness"]
        return {
            "stiffness": None if fem is None or not np.isfinite(fem) else float(fem),
            "closing_mm": r["delta"] * 1e3,
            **{k: r[k] for k in ("rigid", "failed", "non_antipodal", "axis_normal_deg", "reason", "seconds")},
        }

    rows = _squeeze_rows(case, one, geo.z_range, None if beta else geo.n_z)
    return build, rows


# --- analysis ---------------------------------------------------------------------------


def richardson(n: list[int], s: list[float]) -> dict:
    """Extrapolation ``s(h) = s* + C h^p`` through three (``h = 1/n``, coarse to fine) values,
    or why not: not monotone, or ``p`` outside ``P_RANGE`` (or no root)."""
    h = 1.0 / np.asarray(n, float)
    s1, s2, s3 = s[2], s[1], s[0]  # fine, medium, coarse
    h1, h2, h3 = h[2], h[1], h[0]
    d21, d32 = s2 - s1, s3 - s2
    out: dict = {"meshes_n_theta": list(n), "justified": False}
    if d21 == 0 or d21 * d32 <= 0:
        out["why_not"] = "not monotone: the change reverses (or vanishes) between the three meshes"
        return out
    target = d32 / d21

    def gap(p: float) -> float:
        return (h3**p - h2**p) / (h2**p - h1**p) - target

    lo, hi = 0.05, 12.0
    if gap(lo) * gap(hi) > 0:
        out["why_not"] = f"no order p in [{lo}, {hi}] fits the ratio of changes {target:.3g}"
        return out
    p = brentq(gap, lo, hi)
    est = s1 - d21 / ((h2 / h1) ** p - 1)
    out |= {"order_p": p, "estimate": est}
    if not (P_RANGE[0] <= p <= P_RANGE[1]):
        out["why_not"] = f"observed order {p:.2f} outside {list(P_RANGE)}: the sequence is not asymptotic"
        return out
    out["justified"] = True
    return out


def _sequence(per_mesh: dict) -> list[str]:
    """The finished meshes of the refinement sequence (uniform, ``n_z = n_theta / 2``), coarse
    to fine; the others are variants."""
    seq = []
    for tag, entry in per_mesh.items():
        nt, nz, beta = parse_mesh(tag)
        if entry.get("complete") and beta is None and 2 * nz == nt:
            seq.append(tag)
    return sorted(seq, key=lambda t: parse_mesh(t)[0])


def _stats(x: np.ndarray) -> dict | None:
    return {"min": float(x.min()), "median": float(np.median(x)), "max": float(x.max())} if x.size else None


def location_table(cases: list[dict], per_mesh: dict) -> list[dict]:
    """Per location: stiffness per mesh, change vs the finest, Richardson (finest three and
    the ratio-2 triple), the default mesh's error, and every variant mesh's."""
    seq = _sequence(per_mesh)
    ns = [parse_mesh(t)[0] for t in seq]
    dflt = f"{DEFAULT_MESH[0]}x{DEFAULT_MESH[1]}"
    variants = [t for t, e in per_mesh.items() if e.get("complete") and t not in seq]
    table = []
    for case in cases:
        for k, (region, z, a) in enumerate(case["locations"]):

            def value(tag: str, k=k, name=case["name"]) -> float | None:
                return per_mesh[tag]["cases"][name]["grasps"][k]["stiffness"]

            row = {"case": case["name"], "region": region, "z_m": z, "angle_rad": a}
            row["stiffness"] = {t: value(t) for t in seq}
            vals = [value(t) for t in seq]
            if not seq or any(v is None for v in vals):
                row["note"] = "a mesh gave no stiffness (implausible or failed)"
                table.append(row)
                continue
            fin = vals[-1]
            row["finest"] = seq[-1]
            row["rel_to_finest"] = {t: v / fin - 1 for t, v in zip(seq, vals, strict=True)}
            d = np.diff(vals)
            row["monotone"] = bool((d > 0).all() or (d < 0).all())
            if len(seq) >= 3:
                row["richardson_finest3"] = richardson(ns[-3:], vals[-3:])
            if {24, 48, 96} <= set(ns):
                row["richardson_24_48_96"] = richardson(
                    [24, 48, 96], [value(f"{n}x{n // 2}") for n in (24, 48, 96)]
                )
            rich = row.get("richardson_finest3", {})
            if dflt in seq:
                row["default_rel_to_finest"] = value(dflt) / fin - 1
                if rich.get("justified"):
                    row["default_rel_to_extrapolated"] = value(dflt) / rich["estimate"] - 1
                    row["finest_rel_to_extrapolated"] = fin / rich["estimate"] - 1
            # the finer meshes' scatter about the finest: how far the finest itself can be trusted
            fine = np.array([v / fin - 1 for t, v in zip(seq, vals, strict=True) if parse_mesh(t)[0] >= 72])
            row["meshes_72_up_spread_rel"] = float(fine.max() - fine.min()) if fine.size else None
            row["variants"] = {}
            for t in variants:
                v = value(t)
                row["variants"][t] = {
                    "stiffness": v,
                    "rel_to_finest": None if v is None else v / fin - 1,
                    "rel_to_extrapolated": v / rich["estimate"] - 1
                    if v is not None and rich.get("justified")
                    else None,
                }
            table.append(row)
    return table


def region_summary(table: list[dict]) -> dict:
    """Per region: the default mesh's (and each variant's) error against the finest mesh and
    against the extrapolation where justified, over all cases and angles: min, median, max."""
    out = {}
    variants = sorted({t for r in table for t in r.get("variants", {})})
    for region in dict.fromkeys(r["region"] for r in table):
        rows = [r for r in table if r["region"] == region and "default_rel_to_finest" in r]
        ext = np.array([r["default_rel_to_extrapolated"] for r in rows if "default_rel_to_extrapolated" in r])
        out[region] = {
            "n_locations": len(rows),
            "default_rel_to_finest": _stats(np.array([r["default_rel_to_finest"] for r in rows])),
            "n_extrapolation_justified": int(ext.size),
            "default_rel_to_extrapolated": _stats(ext),
            "n_not_monotone": sum(not r.get("monotone", True) for r in rows),
            "meshes_72_up_spread_rel_max": max(
                (r["meshes_72_up_spread_rel"] for r in rows if r["meshes_72_up_spread_rel"] is not None),
                default=None,
            ),
            "variants_rel_to_finest": {
                t: _stats(
                    np.array(
                        [
                            r["variants"][t]["rel_to_finest"]
                            for r in rows
                            if r["variants"][t]["rel_to_finest"] is not None
                        ]
                    )
                )
                for t in variants
            },
        }
    return out


def summarise(result: dict, cases: list[dict]) -> None:
    """``locations`` (:func:`location_table`), ``regions`` over the designed locations (the
    height scan left out: it would weigh one bottle many times) and ``regions_by_case``."""
    table = location_table(cases, result["per_mesh"])
    result["locations"] = table
    result["regions"] = region_summary([r for r in table if r["case"] != "revolved_scan"])
    result["regions_by_case"] = {
        c["name"]: region_summary([r for r in table if r["case"] == c["name"]]) for c in cases
    }


def mem_available() -> int:
    """Bytes the kernel reports available now (``MemAvailable`` of /proc/meminfo)."""
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no MemAvailable in /proc/meminfo")


def _parse_args() -> tuple[argparse.Namespace, list[str]]:
    """The command line and the meshes to run (the sequence, then the variants), each refused
    beyond ``MAX_CELLS``."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument(
        "--meshes",
        default=",".join(f"{a}x{b}" for a, b in MESHES),
        help="the refinement sequence n_theta x n_z (n_z = n_theta / 2), coarse to fine",
    )
    ap.add_argument(
        "--variants",
        default="",
        help="other meshes, compared with the sequence: NTxNZ, or NTxNZ/gB for rows B times finer "
        "within a jaw length of the shoulder's start (graded_rows)",
    )
    ap.add_argument("--cases", default="family_1,family_5,revolved,revolved_scan")
    ap.add_argument(
        "--resume",
        action="store_true",
        help="keep the finished meshes of --out (same cases and locations) and run only the others",
    )
    args = ap.parse_args()
    specs = [m for m in (args.meshes + "," + args.variants).split(",") if m]
    for m in specs:
        nt, nz, beta = parse_mesh(m)
        if nt * nz * (beta or 1.0) > MAX_CELLS:
            ap.error(
                f"mesh {m}: beyond {MAX_CELLS} cells ([120, 60]) needs more than ~11 GiB: not on this machine"
            )
    return args, specs


def _resume(result: dict, cases: list[dict], out: Path) -> None:
    """Keep in ``result`` each (mesh, case) of the file ``out`` whose case has the same
    locations, and its runs."""
    import json

    old = json.loads(out.read_text())
    result["runs"] = old.get("runs", [])
    before = {c["name"]: c for c in old.get("cases", [])}
    same = {
        c["name"]
        for c in cases
        if c["name"] in before and before[c["name"]]["locations"] == [list(x) for x in c["locations"]]
    }
    for c in cases:
        if c["name"] in same and before[c["name"]].get("z_range_m"):
            c["z_range_m"] = before[c["name"]]["z_range_m"]
    for t, e in old.get("per_mesh", {}).items():
        kept = {n: v for n, v in e.get("cases", {}).items() if n in same}
        if kept:
            result["per_mesh"][t] = {**e, "cases": kept, "complete": len(kept) == len(cases)}


def _run_mesh(result: dict, tag: str, cases: list[dict], mesh, out: Path) -> bool:
    """Squeeze on mesh ``tag`` every case ``result`` lacks, into ``result["per_mesh"][tag]``;
    False when nothing ran (all kept, or skipped for want of memory)."""
    from workbench.experiments.wall_stiffness import memory_estimate

    nt, nz, beta = parse_mesh(tag)
    have = result["per_mesh"].get(tag, {}).get("cases", {})
    todo = [c for c in cases if c["name"] not in have]
    if not todo:
        print(f"{tag}: kept from {out}", flush=True)
        return False
    need = memory_estimate({"object": "x", "mesh": [nt, int(np.ceil(nz * (beta or 1.0)))]})
    avail = mem_available()
    if 1.25 * need > avail:
        result["per_mesh"][tag] = {
            "complete": False,
            "skipped": f"estimated peak {need / 2**30:.1f} GiB (x 1.25) over the "
            f"{avail / 2**30:.1f} GiB available",
        }
        print(f"{tag}: skipped ({result['per_mesh'][tag]['skipped']})", flush=True)
        return False
    entry: dict = result["per_mesh"].get(tag, {"cases": {}})
    entry |= {"complete": False, "mem_available_gib_before": avail / 2**30}
    entry.setdefault("measured_at", {})
    if not isinstance(entry["measured_at"], dict):  # a file of one run: one time for all cases
        entry["measured_at"] = dict.fromkeys(entry["cases"], entry["measured_at"])
    result["per_mesh"][tag] = entry
    for case in todo:
        _run_case(entry, tag, case, mesh, (nt, nz, beta))
    entry["peak_rss_gib_so_far"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 2**30
    entry["load_average_1min_after"] = os.getloadavg()[0]
    entry["complete"] = True
    return True


def _run_case(entry: dict, tag: str, case: dict, mesh, grid: tuple) -> None:
    """Squeeze ``case`` on the mesh ``grid`` = (n_theta, n_z, beta) into ``entry["cases"]``."""
    entry["measured_at"][case["name"]] = time.strftime("%Y-%m-%dT%H:%M:%S")
    if case["name"].startswith("revolved"):
        build, rows = run_revolved(case, mesh, grid)
    else:
        build, rows = run_family(case, int(case["name"].split("_")[1]), grid)
    gc.collect()
    secs = [r["seconds"] for r in rows]
    entry["cases"][case["name"]] = {
        **build,
        "s_per_grasp": {"median": float(np.median(secs)), "max": float(np.max(secs))},
        "grasps": rows,
    }
    print(
        f"{tag} {case['name']:13s} build {build['wall_build_s']:6.1f} s, per grasp median "
        f"{np.median(secs):.2f} s: " + " ".join(f"{r['stiffness'] or float('nan'):.0f}" for r in rows),
        flush=True,
    )


def _print_regions(result: dict) -> None:
    """The default mesh's error per region, against the finest and the extrapolation."""
    for region, r in result["regions"].items():
        fin, ext = r["default_rel_to_finest"], r["default_rel_to_extrapolated"]
        if fin is None:  # the default mesh was not run
            continue
        print(
            f"{region:15s} default vs finest {fin['min']:+.1%}..{fin['max']:+.1%}"
            + (
                f", vs extrapolated {ext['min']:+.1%}..{ext['max']:+.1%} "
                f"({r['n_extrapolation_justified']} justified)"
                if ext
                else ", no justified extrapolation"
            )
        )


def main() -> int:
    args, specs = _parse_args()
    sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench_wrench
    from bench_wrench import machine_roofline

    from workbench.runner.results import code_revision, versions, write_json

    wanted = args.cases.split(",")
    cases = [family_case(i, f) for i, f in FAMILY.items() if f"family_{i}" in wanted]
    cases += [make() for make in (revolved_case, revolved_scan_case) if make.__name__[:-5] in wanted]
    mesh = revolved_bottle() if any(c["name"].startswith("revolved") for c in cases) else None
    t_start = time.perf_counter()
    result: dict = {
        "benchmark": "wall stiffness convergence at shoulder grasps",
        "complete": False,
        "model": f"linear elastic wall E = {E:.3g} Pa, nu = {NU}, t = {THICKNESS * 1e3} mm; "
        f"rigid frictionless jaws {JAW[0] * 1e3:g} x {JAW[1] * 1e3:g} mm at {FORCE:g} N each; "
        "secant stiffness f / closing [N/m]",
        "default_mesh": list(DEFAULT_MESH),
        "threads": {k: os.environ.get(k) for k in ("OMP_NUM_THREADS", "NUMBA_NUM_THREADS")},
        "machine": {"cores": os.cpu_count(), **machine_roofline(quick=True)},
        "cases": cases,
        "per_mesh": {},
        # one record per invocation (a --resume run adds one): its wall time, its machine
        "runs": [],
    }
    started = time.strftime("%Y-%m-%dT%H:%M:%S")
    if args.resume and args.out.is_file():
        _resume(result, cases, args.out)  # keep each (mesh, case) whose case has the same locations
    for tag in specs:
        if _run_mesh(result, tag, cases, mesh, args.out):
            summarise(result, cases)
            result["wall_time_s"] = time.perf_counter() - t_start
            write_json(args.out, result)  # after every mesh: a killed run keeps what it measured
    summarise(result, cases)
    result |= {
        "complete": True,
        "load_average_1min_at_end": os.getloadavg()[0],
        "code_revision": code_revision(),
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t_start,  # this invocation's; every one's in runs
    }
    result["runs"].append(
        {
            "started": started,
            "argv": sys.argv[1:],
            "wall_time_s": result["wall_time_s"],
            "load_average_1min_at_end": result["load_average_1min_at_end"],
            "fma_gflops_measured": result["machine"]["fma_gflops_measured"],
            "code_revision": result["code_revision"],
        }
    )
    write_json(args.out, result)
    _print_regions(result)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
