"""Flat experiment scripts, one per thesis experiment: ``run(config) -> results``."""
