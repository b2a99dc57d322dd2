"""Compare the summaries of two results folders number by number, timings left out.

    python benchmarks/compare_summaries.py BASE_DIR NEW_DIR [--rename EXPERIMENT:OLD=NEW ...]

Every scalar of each ``<experiment>/summary.json`` present in both folders is compared (nested
keys flattened; provenance, configuration, headlines and anything named like a time — ``*_s``,
``*_ms``, ``seconds``, ``speed_ratio``, ... — left out).  ``--rename`` maps a key fragment of BASE
to NEW (regular expression), for keys renamed between the two (renamed contact models, say).  Prints
per experiment how many values were compared, how many differ, the largest relative differences
and the keys found in BASE only; exits 0 (a report, not a verdict).
"""

from __future__ import annotations

import argparse
import json
import math
import re
from pathlib import Path

TIME = re.compile(
    r"(_s|_ms|_us|seconds|time|wall|runtime|speedup|ms_per|s_per|per_query|per_grasp|per_call|"
    r"per_wrench|per_surface|per_curve|_per_profile|speed_ratio)$",
    re.I,
)
SKIP = {  # provenance, settings and prose: not results
    "versions",
    "code",
    "config",
    "ran_on",
    "tasks_ran_on",
    "figures",
    "machine",
    "headline",
    "config_hash",
}


def _flat(d, pre=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _flat(v, (*pre, str(k)))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _flat(v, (*pre, f"[{i}]"))
    else:
        yield pre, d


def _kept(path: tuple) -> bool:
    if any(p in SKIP for p in path):
        return False
    names = [p for p in path if not p.startswith("[")]
    return not any(TIME.search(n) or "seconds" in n or n.startswith("fit_runtime") for n in names)


def _diff(a, b):
    """The relative difference of two numbers (0 when equal or both NaN), inf for other values
    that differ, else None."""
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if a != b and not (math.isnan(a) and math.isnan(b)):
            return abs(a - b) / max(abs(a), abs(b), 1e-300)
        return None
    return math.inf if a != b else None


def _compare_one(fa: dict, fb: dict, rules: list[tuple[str, str]]) -> tuple[list, list, int]:
    """(diffs [(relative difference, key, a, b)], keys of ``fa`` not in ``fb``, values compared)
    of two flattened summaries, ``fa``'s keys renamed by ``rules`` (regex, replacement) until
    found in ``fb``."""
    diffs, unmatched, n = [], [], 0
    for key, a in fa.items():
        kb = key
        for old, rep in rules:
            kb = kb if kb in fb else re.sub(old, rep, kb)
        if kb not in fb:
            unmatched.append(key)
            continue
        b, n = fb[kb], n + 1
        d = _diff(a, b)
        if d is not None:
            diffs.append((d, key, a, b))
    return diffs, unmatched, n


def compare(base: Path, new: Path, renames: dict[str, list[tuple[str, str]]]) -> int:
    total = [0, 0]
    for sa in sorted(base.glob("*/summary.json")):
        name = sa.parent.name
        sb = new / name / "summary.json"
        if not sb.exists():
            print(f"{name}: missing in {new}")
            continue
        fa = {".".join(k): v for k, v in _flat(json.loads(sa.read_text())) if _kept(k)}
        fb = {".".join(k): v for k, v in _flat(json.loads(sb.read_text())) if _kept(k)}
        diffs, unmatched, n = _compare_one(fa, fb, renames.get(name, []))
        diffs.sort(key=lambda d: d[0], reverse=True)
        total[0] += n
        total[1] += len(diffs)
        print(f"{name}: {n} compared, {len(diffs)} differ, {len(unmatched)} in base only")
        for d in diffs[:8]:
            print(f"   {d[0]:.2e}  {d[1]}: {d[2]!r} -> {d[3]!r}")
        for key in unmatched[:4]:
            print(f"   base only: {key}")
    print(f"all: {total[0]} values compared, {total[1]} differ")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("base", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rename", action="append", default=[], help="EXPERIMENT:OLD_REGEX=NEW (repeatable)")
    args = ap.parse_args()
    renames: dict[str, list[tuple[str, str]]] = {}
    for r in args.rename:
        exp, rule = r.split(":", 1)
        old, rep = rule.split("=", 1)
        renames.setdefault(exp, []).append((old, rep))
    return compare(args.base, args.new, renames)


if __name__ == "__main__":
    raise SystemExit(main())
