"""benchmarks/timed.py: a make-reproduce step's wall time, its processes' CPU seconds and the
cores they kept busy, merged into one run's split."""

import importlib.util
import json
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"

# two processes, each spinning ~0.6 s of CPU: the step's CPU seconds count both (children of
# the timed command, reaped by it), whatever the machine does meanwhile
TWO_SPINNERS = (
    "import subprocess, sys, time\n"
    "spin = 'import time\\nt = time.process_time()\\nwhile time.process_time() - t < 0.6: pass'\n"
    "ps = [subprocess.Popen([sys.executable, '-c', spin]) for _ in range(2)]\n"
    "[p.wait() for p in ps]\n"
)


def _timed(monkeypatch, tmp_path):
    spec = importlib.util.spec_from_file_location("timed", BENCH / "timed.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    monkeypatch.setattr(mod, "OUT", tmp_path / "reproduce.json")
    # the roofline is measured once per run (seconds of FMA loops): a stand-in here
    fake = type(sys)("bench_wrench")
    fake.machine_roofline = lambda quick: {"fma_gflops_measured": 1.0}
    monkeypatch.setitem(sys.modules, "bench_wrench", fake)
    return mod


def test_a_step_records_its_processes_cpu_and_the_cores_it_kept_busy(monkeypatch, tmp_path):
    mod = _timed(monkeypatch, tmp_path)
    monkeypatch.setenv("REPRODUCE_RUN", "test-run")
    assert mod.main(["spin", "--", sys.executable, "-c", TWO_SPINNERS]) == 0
    assert mod.main(["fail", "--", sys.executable, "-c", "raise SystemExit(3)"]) == 3  # passed on
    data = json.loads((tmp_path / "reproduce.json").read_text())
    spin = data["steps"]["spin"]
    assert spin["cpu_seconds"] >= 1.2  # both spinners' 0.6 s
    assert spin["cores_busy"] == spin["cpu_seconds"] / spin["seconds"]
    assert data["steps"]["fail"]["exit_code"] == 3
    assert data["total_cpu_seconds"] == spin["cpu_seconds"] + data["steps"]["fail"]["cpu_seconds"]
    # a new run starts a new split; the one it replaces is kept beside it
    monkeypatch.setenv("REPRODUCE_RUN", "next-run")
    mod.main(["again", "--", sys.executable, "-c", "pass"])
    assert list(json.loads((tmp_path / "reproduce.json").read_text())["steps"]) == ["again"]
    assert json.loads((tmp_path / "reproduce.previous.json").read_text()) == data
