"""The checkout the package runs from, named in one place (workbench.runner.results.CHECKOUT): the
defaults that read beside it (../shared/data, results/benchmarks) and the code's revision.  When
the run machinery and the experiments moved one folder down, their own ``parents[1]`` pointed into
workbench/: the measured-object experiments then looked for their data in a folder that does not
exist and every test of theirs skipped, and ``-dirty`` was never set."""

from __future__ import annotations

import subprocess
from pathlib import Path

from workbench.experiments import minimal_work, wall_nonlinear, wall_stiffness
from workbench.runner import results

REPO = Path(__file__).resolve().parents[1]


def test_the_checkout_is_the_repository_these_tests_belong_to():
    assert results.CHECKOUT == REPO
    assert (results.CHECKOUT / "pyproject.toml").is_file()


def test_data_and_benchmark_defaults_are_beside_the_checkout():
    data = REPO.parent / "shared" / "data" / "deformable_objects"
    assert minimal_work.DEFAULT_CONFIG["data_dir"] == str(data)
    assert wall_nonlinear.DEFAULT_CONFIG["data_dir"] == str(data)
    assert wall_stiffness.CONVERGENCE_FILE == REPO / "results" / "benchmarks" / "shoulder_convergence.json"
    assert wall_stiffness.CONVERGENCE_FILE.is_file()  # committed


def test_the_revision_is_dirty_exactly_when_git_says_the_code_changed():
    git = subprocess.run(["git", "-C", str(REPO), "rev-parse"], capture_output=True)
    if git.returncode != 0:
        import pytest

        pytest.skip("not a git checkout")
    status = subprocess.run(
        ["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no", "--", *results.CODE_PATHS],
        capture_output=True,
        text=True,
    ).stdout
    assert results.code_revision().endswith("-dirty") == bool(status.strip())
