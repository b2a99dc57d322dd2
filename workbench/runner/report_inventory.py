"""Every table and numbered figure of the thesis's chapters 3–4 and of the 6DFC paper, each with
what the report does with it: the claim sections that judge it, or one line why it is not
comparable, out of scope, or not yet reproduced.

The list is data (:data:`INVENTORY`); ``tests/test_report_inventory.py`` checks it against the
captions in the seeds' text, so an item the thesis prints cannot be left out.  The report
(:func:`workbench.runner.report.write_report`) renders it as its first table
(:func:`render_inventory`): a judged item with the count of its rows by status and a link to
each section, any other with its reason, and our own figure of the item where one exists.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from .report_rules import DIFFERS, MATCH, NOT_COMPARABLE, anchor

#: the inventory's statuses besides ``NOT_COMPARABLE`` (the report's own word for a picture or
#: other hardware)
JUDGED, OUT_OF_SCOPE, NOT_YET = "judged", "out of scope", "not yet reproduced"
STATUSES = (JUDGED, NOT_COMPARABLE, OUT_OF_SCOPE, NOT_YET)


@dataclass(frozen=True)
class Entry:
    """One table or numbered figure.

    item : its name in the report ("Fig 3.8", "Table 4.2", "6DFC Fig 3", "6DFC Table I");
    what : its caption, shortened; status : one of :data:`STATUSES`;
    sections : for ``judged``, the report sections (``workbench.runner.report.ITEMS`` keys)
        whose claims judge it (for ``not yet reproduced``, those judging a part of it);
    why : one line, required for every other status (and a remark for a judged one);
    ours : our figures of the item, paths relative to the results directory (linked when present)."""

    item: str
    what: str
    status: str
    why: str = ""
    sections: tuple[str, ...] = ()
    ours: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"{self.item}: status must be one of {STATUSES}; got {self.status!r}")
        if (self.status == JUDGED and not self.sections) or (
            self.status not in (JUDGED, NOT_YET) and self.sections
        ):
            raise ValueError(
                f"{self.item}: a judged item names its sections; one not yet reproduced may name those "
                "that judge a part; no other does"
            )
        if self.status != JUDGED and not self.why:
            raise ValueError(f"{self.item}: a {self.status!r} item says why in one line")


_PICTURE = "a picture with no printed values"
_ROBOT = "physical trials on the thesis's robot; no data of them is available"

#: every table and numbered figure of chapters 3–4 and the 6DFC paper, in print order
INVENTORY: tuple[Entry, ...] = (
    Entry(
        "Fig 3.1", "nonplanar surface contacts of soft jaws", OUT_OF_SCOPE, "photographs and renders: no data"
    ),
    Entry(
        "Fig 3.2",
        "screw motion and the local frictional force",
        OUT_OF_SCOPE,
        "a schematic of Eq. 3.3's terms",
    ),
    Entry(
        "Fig 3.3",
        "local friction directions: rotation about −y, sliding along −z",
        JUDGED,
        "the figure's rotation is Example 3.2.5's; its numbers are judged there",
        sections=("Example 3.2.5",),
        ours=("parametric-surfaces/friction_example-3.2.5.png",),
    ),
    Entry("Fig 3.4", "3D projections of an ellipsoidal and a quartic 6DLS fit", NOT_COMPARABLE, _PICTURE),
    Entry(
        "Fig 3.5",
        "the linearised hulls of the two 6DLS models",
        NOT_COMPARABLE,
        f"{_PICTURE}; the linearisations' gaps are measured in benchmarks/limit_surface.json",
    ),
    Entry("Fig 3.6", "a 3D projection of a 6D friction cone", NOT_COMPARABLE, _PICTURE),
    Entry(
        "Fig 3.7",
        "six parametric contact surfaces S1–S6",
        OUT_OF_SCOPE,
        "inputs, not results: typed in workbench/sources/surface_catalog.py",
        ours=tuple(f"parametric-surfaces/friction_S{i}.png" for i in range(1, 7)),
    ),
    Entry(
        "Table 3.1",
        "parametric forms of the contact surfaces",
        OUT_OF_SCOPE,
        "inputs, not results: typed in workbench/sources/surface_catalog.py",
    ),
    Entry("Table 3.2", "maximal frictional wrench of S1, three models", JUDGED, sections=("Table 3.2",)),
    Entry("Fig 3.8", "wrench error rate against the number of elements", JUDGED, sections=("Fig 3.8",)),
    Entry("Fig 3.9", "6DLS wrench error and runtime, 100–1,000 wrenches", JUDGED, sections=("Fig 3.9",)),
    Entry(
        "Fig 3.10",
        "3D cross-sections of the quartic and the ellipsoidal fit",
        NOT_COMPARABLE,
        _PICTURE,
        ours=("ls-fitting/fig_3_10_cross_sections.png",),
    ),
    Entry(
        "Fig 3.11",
        "FEM study: object generator, 24 objects, a solution, contact profiles",
        JUDGED,
        "(b): fem-fitting presses the thesis's own 24 meshes (counted here); (a) is the thesis's "
        "generator (we read its meshes), (c)–(d) are pictures of ANSYS solutions",
        sections=("Fig 3.11",),
        ours=("fem-fitting/thesis_objects.png", "fem-fitting/family.png"),
    ),
    Entry(
        "Table 3.3",
        "6DLS fitting error on 2,932 FEM contact profiles",
        JUDGED,
        "on the thesis's 24 meshes and, beside them, our parametric bottle family",
        sections=("Table 3.3",),
        ours=("fem-fitting/table_3_3_histogram.png",),
    ),
    Entry(
        "Fig 4.1",
        "KUKA set-up and ten 3D-printed objects",
        OUT_OF_SCOPE,
        "the robot and its objects; the type I objects' contacts are modelled in workbench/sources/scenes.py",
    ),
    Entry(
        "Fig 4.2",
        "fin-ray jaw on an elliptic cylinder (FEM) and the power-law pressure",
        JUDGED,
        "(d) is judged on our pad; (a)–(c) are ANSYS pictures of a fin-ray jaw, which we do not model",
        sections=("Fig 4.2",),
        ours=("power-law/fig_4_2d_power_law.png",),
    ),
    Entry(
        "Table 4.1",
        "prediction of 1,035 physical grasps by each contact model",
        JUDGED,
        sections=("Table 4.1", "Table 4.1 (engine)", "Table 4.1 (engine, bottle family)"),
        ours=("sensitivity/precision_recall.png",),
    ),
    Entry("Fig 4.3", "2D projections of a 6D grasp wrench space", NOT_COMPARABLE, _PICTURE),
    Entry(
        "Fig 4.4",
        "precision and recall against threshold, k, μ and contact length",
        JUDGED,
        sections=("Fig 4.4",),
    ),
    Entry(
        "Fig 4.5",
        "contact profiles estimated by REACH",
        NOT_COMPARABLE,
        _PICTURE,
        ours=("physical-trials/grasp_panels.png",),
    ),
    Entry("Fig 4.6", "robot set-up and a contact close up", OUT_OF_SCOPE, "photographs of the robot"),
    Entry("Fig 4.7", "the physical objects of the KUKA trials", OUT_OF_SCOPE, "photographs of objects"),
    Entry(
        "Table 4.2",
        "prediction of physical grasps (KUKA) and runtime per grasp",
        JUDGED,
        "its mAP and mAR are KUKA trials (no data); its runtimes are judged",
        sections=("Tables 4.2/4.3",),
    ),
    Entry(
        "Table 4.3",
        "prediction of physical grasps (ABB YuMi) and runtime per grasp",
        JUDGED,
        "its mAP and mAR are 6DFC Table I's data, judged there on the REACH cube trials",
        sections=("Tables 4.2/4.3", "6DFC Table I"),
    ),
    Entry(
        "Fig 4.8",
        "grasp axis between the jaws' centres or their bottoms",
        JUDGED,
        "on the flattest of our meshes lying down (the EGAD object is not at hand)",
        sections=("Figs 4.8/4.9",),
        ours=("grasp-dataset/fig_4_9_quality_map.png",),
    ),
    Entry(
        "Fig 4.9",
        "grasp maps and the best grasp of four contact models",
        JUDGED,
        "on the flattest of our meshes lying down (the EGAD object is not at hand)",
        sections=("Figs 4.8/4.9",),
        ours=("grasp-dataset/fig_4_9_quality_map.png", "grasp-dataset/fig_4_9_best_grasps.png"),
    ),
    Entry("Fig 4.10", "32 objects of the planning trials", OUT_OF_SCOPE, "photographs of objects"),
    Entry(
        "Table 4.4",
        "planned grasps, eight training objects",
        OUT_OF_SCOPE,
        f"{_ROBOT} (a GQ-CNN planner; training it needs a GPU)",
    ),
    Entry(
        "Table 4.5",
        "planned grasps, 24 novel and five flat objects",
        OUT_OF_SCOPE,
        f"{_ROBOT} (a GQ-CNN planner; training it needs a GPU)",
    ),
    Entry(
        "Fig 4.11",
        "the plastic cup example of the minimal-work metric",
        NOT_COMPARABLE,
        f"{_PICTURE}; ours is the robot-measured cup's stiffness map",
        ours=("minimal-work/fig_stiffness_map_plastic_cup.png",),
    ),
    Entry(
        "Fig 4.12",
        "a REACH contact profile, enlarged",
        NOT_COMPARABLE,
        _PICTURE,
        ours=("physical-trials/grasp_panels.png",),
    ),
    Entry(
        "Fig 4.13",
        "planned grasps of three objects by three quality metrics",
        NOT_COMPARABLE,
        f"{_PICTURE}; the metrics' balanced accuracy is Table 4.6",
        ours=("minimal-work/fig_4_13_work.png",),
    ),
    Entry(
        "Table 4.6",
        "balanced accuracy of three quality metrics",
        JUDGED,
        sections=("Table 4.6", "Table 4.6 (engine)"),
        ours=("minimal-work-engine/table_4_6_engine.png",),
    ),
    Entry(
        "6DFC Fig 1",
        "a nonplanar contact, its REACH profile and a 6D cone projection",
        NOT_COMPARABLE,
        _PICTURE,
        ours=("physical-trials/grasp_panels.png",),
    ),
    Entry(
        "6DFC Fig 2", "friction cones of point, soft point and area contacts", OUT_OF_SCOPE, "schematic cones"
    ),
    Entry("6DFC Table I", "mAP and mAR of physical grasps", JUDGED, sections=("6DFC Table I",)),
    Entry(
        "6DFC Fig 3",
        "mAP and mAR against N_r and σ_r; sampler and per-grasp runtimes",
        JUDGED,
        "(a)–(b) on the REACH cube trials, (c)–(d) the runtimes on our elliptic-cylinder contact",
        sections=("6DFC Fig 3",),
        ours=("physical-trials/fig_3_6dfc.png",),
    ),
    Entry(
        "6DFC Fig 4",
        "grasps where 6DFC and Point disagree",
        OUT_OF_SCOPE,
        "photographs of physical planning trials",
    ),
)


def _judged(entry: Entry, counts: Mapping[str, Mapping[str, int]]) -> str:
    """``[section](#anchor): 4 match, 1 differs`` for each of a judged entry's sections."""
    parts = []
    for section in entry.sections:
        c = counts.get(section, {})
        tally = ", ".join(f"{c[s]} {s}" for s in (MATCH, DIFFERS, NOT_COMPARABLE, "missing") if c.get(s))
        parts.append(f"[{section}](#{anchor(section)}): {tally or 'no rows'}")
    return "; ".join(parts)


def render_inventory(
    counts: Mapping[str, Mapping[str, int]],
    results_dir: str | Path,
    link_prefix: str = "",
    inventory: Sequence[Entry] = INVENTORY,
) -> list[str]:
    """The report's table of every item: ``counts`` are the claim rows by section and status
    (``{section: {status: n}}``); our figures that exist under ``results_dir`` are linked
    (``link_prefix`` + path), the others named as not found."""
    root = Path(results_dir)
    tally = {s: sum(e.status == s for e in inventory) for s in STATUSES}
    lines = [
        "",
        "## Every table and figure",
        "",
        f"The {len(inventory)} tables and numbered figures of the thesis's chapters 3–4 and the 6DFC paper: "
        + ", ".join(f"{n} {s}" for s, n in tally.items())
        + ". A judged item links the sections whose rows judge it.",
        "",
        "| item | what | status | judged in, or why not | ours |",
        "|---|---|---|---|---|",
    ]
    for e in inventory:
        where = _judged(e, counts) if e.sections else ""
        reason = "; ".join(x for x in (where, e.why) if x)
        figures = [
            f"[{Path(f).name}]({link_prefix}{f})" if (root / f).is_file() else f"`{f}` (not found)"
            for f in e.ours
        ]
        cells = [e.item, e.what, f"**{e.status}**", reason, ", ".join(figures) or "—"]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return lines


__all__ = ["INVENTORY", "JUDGED", "NOT_YET", "OUT_OF_SCOPE", "STATUSES", "Entry", "render_inventory"]
