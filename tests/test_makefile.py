"""The Makefile's recipes are shell scripts that only `make reproduce` runs end to end (an hour):
check here, in seconds, that every command of its targets parses in sh."""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="no make on this machine")


TARGETS = ["reproduce", "bench", "test", "test-nojit", "lint", "bench-shoulder", "fig3", "grasp-dataset"]


@pytest.mark.parametrize("target", TARGETS)
def test_every_command_of_a_target_parses_in_sh(target):
    # make -n prints the commands (the venv's too, when its stamps are stale) without running them
    script = subprocess.run(
        ["make", "-n", target], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    assert script.strip()
    parsed = subprocess.run(["sh", "-n"], input=script, capture_output=True, text=True)
    assert parsed.returncode == 0, f"make {target}: {parsed.stderr}"


def test_no_recipe_line_is_a_colon_no_op():
    # `: some words` hands its words to sh: a quote or a parenthesis in them is a syntax error,
    # a `;` runs the rest as a command; a recipe says why in `#` lines
    recipe = [ln for ln in (ROOT / "Makefile").read_text().splitlines() if ln.startswith("\t")]
    assert [ln for ln in recipe if ln.strip().startswith(":")] == []
