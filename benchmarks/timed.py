"""Time one step of ``make reproduce`` and record it in results/benchmarks/reproduce.json
(the per-experiment split of its wall time).

    python benchmarks/timed.py LABEL -- COMMAND [ARGS...]

runs COMMAND, then merges ``{LABEL: {seconds, command, exit_code}}`` into the split of the
current ``make reproduce`` (``REPRODUCE_RUN``, set once by the Makefile; a new value starts a
new split, so the file holds one run's steps, and moves the split it replaces to
``reproduce.previous.json``: one step timed by hand cannot wipe a whole run's) with their total
and the machine: cores and
the FMA roofline of benchmarks/bench_wrench.py, measured once per run (DEVELOPERS.md:
every timing beside the machine's measured limit).  The file is rewritten atomically; the
command's exit code is passed on, so a failing step still stops ``make``.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "benchmarks" / "reproduce.json"


def _previous(out: Path) -> Path:
    """Where the split a new run replaces is kept (one: the last run before this one)."""
    return out.with_name(out.stem + ".previous.json")


def _children_cpu_s() -> float:
    """User + system CPU seconds of this process's finished children (and theirs, once reaped)."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main(argv: list[str]) -> int:
    if len(argv) < 3 or argv[1] != "--":
        print(__doc__, file=sys.stderr)
        return 2
    label, cmd = argv[0], argv[2:]
    run_id = os.environ.get("REPRODUCE_RUN", "manual")
    cpu0 = _children_cpu_s()
    t0 = time.perf_counter()
    code = subprocess.call(cmd)
    seconds = time.perf_counter() - t0
    cpu_s = _children_cpu_s() - cpu0

    from workbench.runner.results import code_revision, write_json

    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    if data.get("run") != run_id:  # a new make reproduce: a new split
        from bench_wrench import machine_roofline  # the sibling benchmark's FMA roofline

        if data:
            write_json(_previous(OUT), data)

        data = {
            "benchmark": "make reproduce, wall time per step (budget: <= 45 min on this 2-core machine)",
            "run": run_id,
            "code_revision": code_revision(),
            "machine": {"cpu_count": os.cpu_count(), **machine_roofline(quick=True)},
            "steps": {},
        }
    data["steps"][label] = {
        "seconds": seconds,
        # the step's processes (driver, Dask nannies and workers): cpu / wall is how many of the
        # machine's cores it kept busy — below the core count, a core idled through part of it
        "cpu_seconds": cpu_s,
        "cores_busy": cpu_s / seconds if seconds > 0 else float("nan"),
        "command": " ".join(cmd),
        "exit_code": code,
    }
    data["total_seconds"] = sum(s["seconds"] for s in data["steps"].values())
    data["total_cpu_seconds"] = sum(s.get("cpu_seconds", 0.0) for s in data["steps"].values())
    write_json(OUT, data)
    total_min = data["total_seconds"] / 60
    print(
        f"[timed] {label}: {seconds:.0f} s, {cpu_s / seconds:.2f} cores busy (run total {total_min:.1f} min)",
        file=sys.stderr,
    )
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
