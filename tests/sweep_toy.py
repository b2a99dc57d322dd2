"""A toy experiment for the sweep tests (registered by monkeypatching ``EXPERIMENTS``):
``y = x²`` after ``sleep`` seconds; raises for ``x > fail_above``."""

import time
from pathlib import Path

from workbench.runner.results import write_summary

NAME = "toy"
DEFAULT_CONFIG = {"seed": 0, "x": 1.0, "fail_above": 10.0, "sleep": 0.0, "tag": "a", "shape": [1, 2]}
QUICK_CONFIG = {"sleep": 0.0}


def run(config: dict) -> dict:
    time.sleep(config["sleep"])
    if config["x"] > config["fail_above"]:
        raise ValueError(f"x = {config['x']} is above fail_above = {config['fail_above']}")
    summary = {
        "y": config["x"] ** 2,
        "nested": {"z": config["x"] + 1.0, "ok": True, "name": config["tag"]},
        "values": [1, 2, 3],  # a short list: columns values.0-2
        "undefined": None,  # a number with no value here (a recall without positives): a NaN column
        "headline": [f"y = {config['x'] ** 2}"],
    }
    return write_summary(Path(config["out"]), NAME, config, summary, 0.0)
