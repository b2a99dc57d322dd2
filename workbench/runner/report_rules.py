"""The claim record of the thesis-vs-ours report and the rules that judge it.

A :class:`Claim` is one thesis statement: the value exactly as printed, where it is printed,
a function that reads our value from ``results/*/summary.json`` or ``results/benchmarks/*.json``
(through :class:`Summaries`, which records every key path it reads), and a rule that judges
the pair (:class:`Verdict`: match / differs / not comparable).  The rules here
(:func:`within_printed`, :func:`within_pm`, :func:`below_percent`, :func:`not_comparable`,
:func:`trend` and the trend checks) are shared by the per-chapter claim tables
(``report_claims_*.py``); :mod:`workbench.runner.report` evaluates and renders them.

No number in this module is ours or the thesis's: the thesis's are typed in the claim tables.
"""

from __future__ import annotations

import json
import logging
import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

# the report's logger: a summary that cannot be read is the report's warning, wherever it is read
log = logging.getLogger("workbench.runner.report")

MATCH, DIFFERS, NOT_COMPARABLE = "match", "differs", "not comparable"


def anchor(heading: str) -> str:
    """GitHub's anchor of a Markdown heading: lower case, spaces to dashes, other punctuation
    dropped."""
    return re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")


class MissingKey(LookupError):
    """A file or key a claim reads is absent; ``where`` is ``<file>:<key path>``."""

    def __init__(self, where: str) -> None:
        super().__init__(where)
        self.where = where


class Summaries:
    """The JSON files of one results directory, each loaded once.

    ``get(file, path)`` walks a dotted key path (``a.b.0`` indexes lists) and records
    ``file:path`` in :attr:`read`, so every row can name what it read.
    """

    def __init__(self, results_dir: str | os.PathLike[str]) -> None:
        self.root = Path(results_dir)
        self._cache: dict[str, Any] = {}
        self.read: list[str] = []
        #: file -> why it exists but could not be read (a truncated or corrupt summary)
        self.unreadable: dict[str, str] = {}

    def _load(self, file: str) -> Any:
        if file not in self._cache:
            path = self.root / file
            try:
                self._cache[file] = json.loads(path.read_text())
            except FileNotFoundError as exc:
                log.debug("cannot read %s: %s", path, exc)
                self._cache[file] = None
            except (OSError, ValueError) as exc:  # JSONDecodeError, UnicodeDecodeError
                # a file that is there but broken is not "missing": say so once, and in its rows
                self.unreadable[file] = f"{type(exc).__name__}: {exc}"
                log.warning("report: %s exists but cannot be read (%s); rerun its experiment", path, exc)
                self._cache[file] = None
        return self._cache[file]

    def get(self, file: str, path: str) -> Any:
        """The value at dotted ``path`` of ``file`` (relative to the results directory).

        Raises :class:`MissingKey` (``file:path``) when the file or a key is absent.
        """
        where = f"{file}:{path}"
        self.read.append(where)
        node = self._load(file)
        if node is None:
            if file in self.unreadable:
                raise MissingKey(f"{file} (unreadable — {self.unreadable[file]}; rerun its experiment)")
            raise MissingKey(where)
        for part in path.split("."):
            if isinstance(node, dict) and part in node:
                node = node[part]
            elif (
                isinstance(node, list) and part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node)
            ):
                node = node[int(part)]
            else:
                raise MissingKey(where)
        return node

    def num(self, file: str, path: str) -> float:
        """:meth:`get` for a number (a null or a non-number counts as missing)."""
        value = self.get(file, path)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise MissingKey(f"{file}:{path}")
        return float(value)


@dataclass(frozen=True)
class Verdict:
    """A claim judged: ``status`` (match / differs / not comparable), our value as shown,
    and the deviation as shown."""

    status: str
    ours: str
    deviation: str


@dataclass(frozen=True)
class Claim:
    """One thesis statement and how we check it.

    ``thesis`` is the value exactly as printed, ``where`` its place in the thesis; ``ours``
    reads our value from the summaries; ``judge`` compares them under ``rule`` (stated in the
    report).  ``why`` is one line on a known deviation or why a pair is not comparable: it
    holds no typed numbers of ours, but may quote summary values as
    ``{{file|key.path|format}}``.  ``truth`` names the ground truth where it is simulated.
    """

    item: str
    quantity: str
    thesis: str
    where: str
    ours: Callable[[Summaries], Any]
    judge: Callable[[Any], Verdict]
    rule: str
    command: str
    why: str = ""
    truth: str = ""
    figures: tuple[str, ...] = ()


# ---------------------------------------------------------------- formatting and parsing


def fmt_g(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits (integers as integers)."""
    if isinstance(x, int) or (isinstance(x, float) and x.is_integer() and abs(x) < 1e15):
        return f"{int(x):,}"
    return f"{x:.{digits}g}"


def fmt_pct(x: float, digits: int = 2) -> str:
    return f"{100 * x:.{digits}g} %"


def fmt_vec(xs: Sequence[float], digits: int = 4) -> str:
    return "[" + ", ".join("0" if abs(v) < 1e-12 else f"{v:.{digits}g}" for v in xs) + "]"


# a number as printed; not a digit inside a name (S_1, 6DLS, 3D): units such as s, ms, % may follow
_NUMBER = re.compile(r"(?<![A-Za-z_\d.])-?\d[\d,]*(?:\.\d+)?(?![A-Z\d])")


def printed_numbers(text: str) -> list[float]:
    """The numbers in ``text`` as printed (thousands commas allowed; digits inside names such
    as ``6DLS`` or ``S_1`` are not numbers): ``"[0, -0.5657]"`` -> ``[0.0, -0.5657]``."""
    return [float(m.replace(",", "")) for m in _NUMBER.findall(text)]


def printed_half_unit(text: str) -> float:
    """Half a unit of the finest last digit printed in ``text``: the rounding of the
    printed value (``"0.0018"`` -> 5e-5, ``"1592"`` -> 0.5)."""
    decimals = [len(m.split(".")[1]) if "." in m else 0 for m in _NUMBER.findall(text)]
    return 0.5 * 10.0 ** -max(decimals, default=0)


# ---------------------------------------------------------------- comparison rules

RULE_PRINTED = "match if within half a unit of the thesis's last printed digit (its rounding)"
RULE_PM = "match if within the thesis's printed ± (its standard deviation) of its mean"
RULE_NOT_COMPARABLE = "not comparable (see why); the deviation is shown for reference only"


def within_printed(thesis: str, pick: int | None = None) -> Callable[[Any], Verdict]:
    """Rule: each component within the printed rounding of the thesis's value(s) (``pick``:
    compare with that one printed number only)."""
    want = printed_numbers(thesis)
    want = want if pick is None else [want[pick]]
    tol = printed_half_unit(thesis)

    def judge(ours: Any) -> Verdict:
        got = [float(v) for v in (ours if isinstance(ours, (list, tuple)) else [ours])]
        if len(got) != len(want):
            return Verdict(DIFFERS, fmt_vec(got), f"{len(got)} components, the thesis prints {len(want)}")
        dev = max(abs(a - b) for a, b in zip(got, want, strict=True))
        if len(got) > 1:
            shown, text = fmt_vec(got), f"max abs deviation {dev:.2g} (rounding ±{tol:g})"
        else:
            ratio = f", {got[0] / want[0]:.2f}×" if want[0] else ""
            shown, text = f"{got[0]:.5g}", f"{got[0] - want[0]:+.2g}{ratio} (rounding ±{tol:g})"
        return Verdict(MATCH if dev <= tol else DIFFERS, shown, text)

    return judge


def within_pm(thesis: str) -> Callable[[Any], Verdict]:
    """Rule: our mean within the thesis's printed ``mean ± std``. ``ours`` is ``(mean, std)``."""
    mean, pm = printed_numbers(thesis)[:2]

    def judge(ours: Any) -> Verdict:
        m, s = ours
        dev = m - mean
        text = f"{dev:+.2g} ({m / mean:.2f}×; {abs(dev) / pm:.2f} of the thesis's ±)"
        return Verdict(MATCH if abs(dev) <= pm else DIFFERS, f"{m:.4f} ± {s:.4f}", text)

    return judge


def below_percent(thesis: str, factor: float = 1.0) -> Callable[[Any], Verdict]:
    """Rule: our value (a fraction) below ``factor`` × the thesis's printed percentage bound."""
    bound = factor * printed_numbers(thesis)[0] / 100

    def judge(ours: Any) -> Verdict:
        return Verdict(
            MATCH if ours < bound else DIFFERS,
            fmt_pct(ours),
            f"{ours / bound:.2f}× the bound",
        )

    return judge


def not_comparable(
    thesis: str, show: Callable[[Any], str] = lambda v: fmt_g(v, 4)
) -> Callable[[Any], Verdict]:
    """Rule: no comparison (the why line says why); the difference to the first printed
    number is shown when ours is a number."""
    want = printed_numbers(thesis)

    def judge(ours: Any) -> Verdict:
        if isinstance(ours, (int, float)) and want:
            dev = f"{ours - want[0]:+.3g} ({ours / want[0]:.2f}×)" if want[0] else f"{ours - want[0]:+.3g}"
        else:
            dev = "—"
        return Verdict(NOT_COMPARABLE, show(ours), dev)

    return judge


def trend(check: Callable[[Any], tuple[bool, str, str]]) -> Callable[[Any], Verdict]:
    """Rule: a trend check returning (holds, our value as shown, deviation as shown)."""

    def judge(ours: Any) -> Verdict:
        ok, shown, dev = check(ours)
        return Verdict(MATCH if ok else DIFFERS, shown, dev)

    return judge


def mean_std_not_comparable(printed: str) -> Callable[[Any], Verdict]:
    """Not comparable (the why line says why); ours as mean ± std and its mean's difference to
    the printed mean."""
    want = printed_numbers(printed)[0]
    return lambda v: Verdict(NOT_COMPARABLE, f"{v[0]:.2f} ± {v[1]:.2f}", f"{v[0] - want:+.2f} (mean)")


def check_above(label: Callable[[Any, float, float], str]) -> Callable[[Any], tuple[bool, str, str]]:
    """Trend check of ``{key: (a, b)}``: holds when every ``a > b``; each pair shown by
    ``label(key, a, b)``, the deviations ``a − b``."""

    def check(v: Any) -> tuple[bool, str, str]:
        shown = "; ".join(label(k, a, b) for k, (a, b) in v.items())
        dev = "; ".join(f"{a - b:+.3f}" for a, b in v.values())
        return all(a > b for a, b in v.values()), shown, dev

    return check


def check_gain(better: str) -> Callable[[Any], tuple[bool, str, str]]:
    """:func:`check_above` of ``{model: (better's score, model's score)}``."""
    return check_above(lambda m, b, o: f"{better} {b:.3f} vs {m} {o:.3f}")


def check_within_printed_range(printed: str) -> Callable[[Any], tuple[bool, str, str]]:
    """Trend check of a list of our values against the first two numbers printed in ``printed``
    (a range "from lo to hi"): holds when every value lies in [lo, hi] widened by the printed
    rounding (:func:`printed_half_unit`); shows our range and how far it reaches past each end."""
    lo, hi = printed_numbers(printed)[:2]
    tol = printed_half_unit(printed)

    def check(v: Any) -> tuple[bool, str, str]:
        vals = [float(x) for x in v]
        low, high = min(vals), max(vals)
        shown = f"{fmt_g(low)}–{fmt_g(high)} ({len(vals)} values)"
        dev = f"low end {low - lo:+.3g}, high end {high - hi:+.3g}"
        return lo - tol <= low and high <= hi + tol, shown, dev

    return check


def _series(name: str, values: Sequence[float], mean: Sequence[float], turn: float) -> str:
    marks = [
        f"{m:.3f}" + (f" (at {fmt_g(v)})" if v == turn else "") for v, m in zip(values, mean, strict=True)
    ]
    return f"{name} " + " → ".join(marks)


def check_peak_at(turn: float) -> Callable[[Any], tuple[bool, str, str]]:
    """Trend check of ``{name: {"values", "mean", "std"}}`` (a score against a swept setting):
    holds when, for every name, the mean at ``turn`` is above the mean at the first value, and
    no later mean exceeds it by more than the larger of the two standard deviations (over seeds):
    "rises up to ``turn``, then constant or lower"."""

    def check(v: Any) -> tuple[bool, str, str]:
        shown, devs, ok = [], [], True
        for name, c in v.items():
            i = list(c["values"]).index(turn)
            mean, std = c["mean"], c["std"]
            rises = mean[i] > mean[0]
            above = [
                f"{mean[j] - mean[i]:+.3f} at {fmt_g(c['values'][j])}"
                for j in range(i + 1, len(mean))
                if mean[j] > mean[i] + max(std[i], std[j])
            ]
            ok &= rises and not above
            shown.append(_series(name, c["values"], mean, turn))
            devs.append(f"{name}: " + ("; ".join(([] if rises else ["no rise"]) + above) or "as stated"))
        return ok, "; ".join(shown), "; ".join(devs)

    return check


def check_falls_after(turn: float) -> Callable[[Any], tuple[bool, str, str]]:
    """Trend check of ``{name: {"values", "mean", "std"}}``: holds when, for every name, the mean
    at the last value is below the mean at ``turn`` and no step from ``turn`` on rises by more than
    the larger of the two standard deviations: "declines after ``turn``"."""

    def check(v: Any) -> tuple[bool, str, str]:
        shown, devs, ok = [], [], True
        for name, c in v.items():
            i = list(c["values"]).index(turn)
            mean, std = c["mean"], c["std"]
            falls = mean[-1] < mean[i]
            rises = [
                f"{mean[j + 1] - mean[j]:+.3f} to {fmt_g(c['values'][j + 1])}"
                for j in range(i, len(mean) - 1)
                if mean[j + 1] > mean[j] + max(std[j], std[j + 1])
            ]
            ok &= falls and not rises
            shown.append(_series(name, c["values"], mean, turn))
            devs.append(
                f"{name}: {mean[-1] - mean[i]:+.2g} from {fmt_g(turn)} to the last"
                + "".join(f"; {r}" for r in rises)
            )
        return ok, "; ".join(shown), "; ".join(devs)

    return check


__all__ = [
    "DIFFERS",
    "MATCH",
    "NOT_COMPARABLE",
    "RULE_NOT_COMPARABLE",
    "RULE_PM",
    "RULE_PRINTED",
    "Claim",
    "MissingKey",
    "Summaries",
    "Verdict",
    "below_percent",
    "anchor",
    "check_above",
    "check_falls_after",
    "check_gain",
    "check_peak_at",
    "check_within_printed_range",
    "fmt_g",
    "fmt_pct",
    "fmt_vec",
    "mean_std_not_comparable",
    "not_comparable",
    "printed_half_unit",
    "printed_numbers",
    "trend",
    "within_pm",
    "within_printed",
]
