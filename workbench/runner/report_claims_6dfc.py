"""The report's claims of the 6DFC paper: Table I (mAP and mAR of physical grasps by robust
quality, 6DFC §V-B) against the real REACH trials (``physical-trials``), as data.

The physical-trials readers are :mod:`workbench.runner.report_claims_ch4`'s (Table 4.1 reads the
same summary).  Every literal is the paper's, quoted as printed next to its citation.
"""

from __future__ import annotations

from .report_claims_ch4 import FIG_PT, RUN_PT, TRUTH_PT, pt_gain, pt_mean_std
from .report_rules import RULE_NOT_COMPARABLE, Claim, check_gain, mean_std_not_comparable, trend

#: 6DFC Table I's rows: our model, mAP and mAR as printed (its "MFE" is the 6D ellipsoid at the
#: maximal force: our 6dls)
TABLE_I = {
    "Point": ("point", "0.80 ± 0.01", "0.50 ± 0.01"),
    "REACH": ("reach", "0.83 ± 0.01", "0.61 ± 0.01"),
    "MFE": ("6dls", "0.83 ± 0.02", "0.60 ± 0.01"),
    "6DFC": ("6dfc", "0.82 ± 0.01", "0.67 ± 0.01"),
}
_WHY_ONE = (
    "one object (a cube: planar faces) of REACH's 21, 125 of its 2,625 trials; "
    "the paper scored 1,500 grasps of 12 objects chosen for nonplanar contacts. AR: the REACH lab's mean "
    "recall over thresholds 0, 0.1, …, 1 (the paper gives no formula). Quality: the fraction of 10 "
    "recomputed pose samples held, 5 seeds"
)

#: 6DFC Table I's rows and its mAR claim, in report order
CLAIMS: tuple[Claim, ...] = (
    *(
        Claim(
            "6DFC Table I",
            f"{name} (`{model}`), {label}",
            printed,
            f"6DFC Table I, row {name}",
            pt_mean_std(model, metric),
            mean_std_not_comparable(printed),
            RULE_NOT_COMPARABLE,
            RUN_PT,
            why=_WHY_ONE,
            truth=TRUTH_PT,
            figures=FIG_PT,
        )
        for name, (model, ap, ar) in TABLE_I.items()
        for metric, printed, label in (("average_precision", ap, "mAP"), ("average_recall", ar, "mAR"))
    ),
    Claim(
        "6DFC Table I",
        "6DFC's mAR above Point, REACH and MFE",
        "6DFC outperforms the point, REACH, and MFE algorithms by 17%, 6%, and 7% in mAR",
        "6DFC §V-B, Table I",
        pt_gain("average_recall", "6dfc", ("point", "reach", "6dls"), "robust_held"),
        trend(check_gain("6dfc")),
        "match if 6dfc's mAR exceeds each of the three's (robust quality: fraction of samples held)",
        RUN_PT,
        why="on a cube both jaws' contacts are flat and alike: 6DFC, 6DLS and REACH ask nearly one question",
        truth=TRUTH_PT,
        figures=FIG_PT,
    ),
)

__all__ = ["CLAIMS", "TABLE_I"]
