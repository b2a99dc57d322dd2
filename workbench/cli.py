"""``workbench`` console script: ``workbench run <experiment> [--quick] [--out DIR]
[--seed N] [--set key=value ...]`` and ``workbench list``."""

from __future__ import annotations

import argparse
import importlib
import json
import logging
import sys
import time
from pathlib import Path
from typing import Any

#: experiment name -> module in the ``experiments`` package
EXPERIMENTS = {
    "parametric-surfaces": "experiments.parametric_surfaces",
    "discretization": "experiments.discretization",
    "ls-fitting": "experiments.ls_fitting",
    "fem-validation": "experiments.fem_validation",
    "fem-fitting": "experiments.fem_fitting",
    "wall-stiffness": "experiments.wall_stiffness",
    "sensitivity": "experiments.sensitivity",
}


def _parse_value(text: str) -> Any:
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def _parse_sets(items: list[str]) -> dict[str, Any]:
    out = {}
    for item in items:
        if "=" not in item:
            raise SystemExit(f"--set expects key=value; got {item!r}")
        key, value = item.split("=", 1)
        out[key.strip()] = _parse_value(value)
    return out


def build_config(name: str, quick: bool, out: str | None, seed: int | None, sets: dict[str, Any]) -> dict:
    """Experiment config: its defaults, then quick overrides, then CLI values."""
    module = importlib.import_module(EXPERIMENTS[name])
    config = dict(module.DEFAULT_CONFIG)
    if quick:
        config.update(module.QUICK_CONFIG)
    config["quick"] = quick
    config["out"] = str(Path(out) if out else Path("results") / name)
    if seed is not None:
        config["seed"] = seed
    unknown = set(sets) - set(config)
    if unknown:
        raise SystemExit(f"unknown config keys for {name}: {sorted(unknown)}; known: {sorted(config)}")
    config.update(sets)
    return config


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="workbench", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list experiments")
    run = sub.add_parser("run", help="run an experiment and write results/<name>/")
    run.add_argument("experiment", choices=sorted(EXPERIMENTS))
    run.add_argument("--quick", action="store_true", help="small, fast configuration")
    run.add_argument("--out", default=None, help="output directory (default results/<experiment>)")
    run.add_argument("--seed", type=int, default=None)
    run.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    run.add_argument("-v", "--verbose", action="store_true")
    args = parser.parse_args(argv)

    if args.command == "list":
        for name, mod in EXPERIMENTS.items():
            doc = (importlib.import_module(mod).__doc__ or "").strip().splitlines()[0]
            print(f"{name:24s} {doc}")
        return 0

    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING, format="%(levelname)s %(name)s: %(message)s"
    )
    config = build_config(args.experiment, args.quick, args.out, args.seed, _parse_sets(args.sets))
    module = importlib.import_module(EXPERIMENTS[args.experiment])
    t0 = time.perf_counter()
    summary = module.run(config)
    print(f"{args.experiment}: wrote {config['out']}/summary.json in {time.perf_counter() - t0:.1f} s")
    for line in summary.get("headline", []):
        print(f"  {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
