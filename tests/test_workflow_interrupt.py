"""The figures command after a hard kill (SIGKILL: an OOM kill, a lost node, a pre-empted job):
running the same command again must resume, not stop on Snakemake's stale lock.

Runs the real command (scripts/figures.sh) on a copy of the repository with the test's own
environment (the package is installed from identical sources, so set-up rebuilds nothing), on
the cheapest target, killed while its job runs."""
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
TARGET = "results/chain/profiles.npz"


PARTS = ("workflow", "config", "figures", "benchmarks", "scripts", "kernel", "pyfrustrate", "pyproject.toml", "CMakeLists.txt")


def repository_copy(dest):
    """The parts of the repository the figures command reads; skips the test when the installed
    package was not built from these sources (set-up would then rebuild it from the copy)."""
    for part in PARTS:
        src = ROOT / part
        if src.is_dir():
            shutil.copytree(src, dest / part, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            shutil.copy2(src, dest / part)
    source_hash = subprocess.run(["bash", str(ROOT / "scripts" / "source_hash.sh"), str(dest)], capture_output=True,
                                 text=True, check=True).stdout.split()[0]  # as scripts/setup.sh computes it
    stamp = Path(sys.prefix) / ".pyfrustrate-source-hash"
    if not stamp.exists() or stamp.read_text().strip() != source_hash:
        pytest.skip("the installed package is not built from these sources (run scripts/setup.sh)")
    return dest


@pytest.mark.skipif(not Path("/proc/self/cwd").exists() or shutil.which("pgrep") is None,
                    reason="needs /proc and pgrep (Linux)")
@pytest.mark.skipif(not (Path(sys.prefix) / "bin" / "snakemake").exists(), reason="snakemake not installed")
def test_figures_command_resumes_after_sigkill(tmp_path):
    repo = repository_copy(tmp_path / "repo")
    env = dict(os.environ, PYFRUSTRATE_VENV=sys.prefix, CORES="1")
    command = ["bash", "scripts/figures.sh", TARGET]
    run = subprocess.Popen(command, cwd=repo, env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    log = repo / "results" / "logs" / "chain_profiles.log"
    deadline = time.monotonic() + 240
    while not log.exists() and run.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    if run.poll() is not None:
        pytest.fail(f"the first run ended (code {run.returncode}) before its job started")
    os.killpg(run.pid, signal.SIGKILL)
    run.wait()
    assert list((repo / ".snakemake" / "locks").iterdir()), "a SIGKILL leaves Snakemake's lock behind"
    again = subprocess.run(command, cwd=repo, env=env, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr[-2000:]
    assert "stale Snakemake lock" in again.stdout
    with np.load(repo / TARGET) as data:
        assert len(data.files) > 0


MC_TARGET = "results/montecarlo/runs/sparse_nu0.9_G0.5_seed1.npz"
# A Monte Carlo run long enough to be cancelled mid-way (about 20 s on one core).
SMALL_MC = "montecarlo:\n  n: 100\n  box: 40\n  sweeps: 12000\n"


@pytest.mark.skipif(not (Path(sys.prefix) / "bin" / "snakemake").exists(), reason="snakemake not installed")
def test_figures_command_resumes_after_sigterm_from_the_checkpoint(tmp_path):
    """SIGTERM to the command's whole process group, as a scheduler's cancel or pre-emption, a
    container stop or a closed terminal sends it: the finished job is kept, the cancelled Monte
    Carlo job leaves its checkpoint and no output, and the same command then reruns only that
    job, resuming from the checkpoint. (SIGTERM to Snakemake alone lets the running jobs finish
    first: "Will exit after finishing currently running jobs".)"""
    repo = repository_copy(tmp_path / "repo")
    (repo / "small.yaml").write_text(SMALL_MC)
    env = dict(os.environ, PYFRUSTRATE_VENV=sys.prefix, CORES="2")
    command = ["bash", "scripts/figures.sh", TARGET, MC_TARGET, "--configfile", "small.yaml"]
    run = subprocess.Popen(command, cwd=repo, env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    mc_log = repo / "results/logs/montecarlo/sparse_nu0.9_G0.5_seed1.log"
    deadline = time.monotonic() + 300
    while not ((repo / TARGET).exists() and mc_log.exists() and "anneal" in mc_log.read_text()):
        if run.poll() is not None or time.monotonic() > deadline:
            pytest.fail(f"the first run ended (code {run.poll()}) or stalled before both jobs had started")
        time.sleep(0.1)
    time.sleep(2)  # some moves done
    os.killpg(run.pid, signal.SIGTERM)
    assert run.wait(timeout=120) != 0
    assert not (repo / MC_TARGET).exists(), "a cancelled job must leave no output"
    checkpoints = list((repo / "results/montecarlo/checkpoints").glob("*.npz"))
    assert len(checkpoints) == 1, "the cancelled run saves its checkpoint on SIGTERM"
    chain_made = (repo / TARGET).stat().st_mtime_ns

    again = subprocess.run(command, cwd=repo, env=env, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr[-3000:]
    ran = {line.split()[0] for line in again.stderr.split("Job stats:")[1].split("\n\n")[0].splitlines()[3:]
           if line.strip() and not line.startswith("total")}
    assert ran == {"montecarlo_run"}, f"rerun: {ran}"
    assert (repo / TARGET).stat().st_mtime_ns == chain_made  # the finished job was not redone
    assert "resumed from checkpoint" in mc_log.read_text()
    with np.load(repo / MC_TARGET) as data:
        assert int(data["steps"][-1]) == 100 * 12000 and int(data["n"]) == 100
    assert not list((repo / "results/montecarlo/checkpoints").glob("*.npz")), "a finished run removes its checkpoint"
