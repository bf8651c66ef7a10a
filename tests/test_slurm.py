"""The workflow on a SLURM cluster: a single-node SLURM started on this machine
(scripts/slurm_localhost.sh), and a sharded part of the workflow submitted to it by Snakemake's
SLURM executor with the repository's profile (workflow/profiles/slurm): three batches of
`random_sample_batch` and `random_summary`, which gathers them, on a copy of the repository with a
small configuration. Checks the outputs, and that every job went through SLURM with the profile's
resources (the controller's job records and its job-completion log). The cluster is stopped
afterwards, also when the test fails, and the test checks that no daemon is left.

Needs root and the Debian packages slurm-wlm and munge (scripts/test.sh installs them as root);
skipped, with the reason, when those are missing or the daemons do not start."""
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from test_workflow_interrupt import repository_copy

yaml = pytest.importorskip("yaml")

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "slurm_localhost.sh"
SNAKEMAKE = Path(sys.prefix) / "bin" / "snakemake"
# Three shards of 1000 matrices (a few seconds each) and their summary.
SMALL = {"random": {"seed": 2025, "draws": 3000, "batch": 1000, "plotted": 500, "size_particles": 20,
                    "group_counts": [5, 5, 5]}}
BATCHES = 3
TARGET = "results/random/summary.npz"
DAEMONS = ("munged", "slurmctld", "slurmd")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A zombie (exited, not yet reaped by its parent) has finished too.
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().rsplit(")", 1)[1].split()[0] == "Z")


@pytest.fixture
def slurm_cluster(tmp_path):
    """A running single-node SLURM with its state in tmp_path, on free ports; stopped afterwards."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("needs root: scripts/slurm_localhost.sh runs slurmctld and slurmd as root")
    missing = [c for c in ("slurmctld", "slurmd", "sbatch", "srun", "squeue", "scontrol", "munged", "munge")
               if shutil.which(c, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin") is None]
    if missing:
        pytest.skip(f"SLURM is not installed (no {', '.join(missing)}): the Debian packages slurm-wlm and "
                    "munge (scripts/test.sh installs them when run as root)")
    if not SNAKEMAKE.exists():
        pytest.skip("snakemake not installed in this environment")
    try:
        import snakemake_executor_plugin_slurm  # noqa: F401
    except ImportError:
        pytest.skip("snakemake-executor-plugin-slurm not installed (pip install '.[workflow]')")
    conf = Path("/etc/slurm/slurm.conf")
    if conf.exists() and not conf.read_text().startswith("# Written by scripts/slurm_localhost.sh"):
        pytest.skip("/etc/slurm/slurm.conf belongs to another SLURM installation: this test does not replace it")

    state = tmp_path / "slurm"
    env = dict(os.environ, PYFRUSTRATE_SLURM_DIR=str(state), PYFRUSTRATE_SLURMCTLD_PORT=str(free_port()),
               PYFRUSTRATE_SLURMD_PORT=str(free_port()))
    pids = {}
    try:
        start = subprocess.run(["bash", str(SCRIPT), "start"], env=env, capture_output=True, text=True, timeout=120)
        pids = {name: int((state / f"{name}.pid").read_text()) for name in DAEMONS
                if (state / f"{name}.pid").exists()}
        if start.returncode != 0:
            pytest.skip(f"the single-node SLURM did not start: {(start.stderr or start.stdout).strip()[-800:]}")
        assert "slurmctld" in pids and "slurmd" in pids, "started, but without pid files for slurmctld and slurmd"
        yield state
    finally:
        stop = subprocess.run(["bash", str(SCRIPT), "stop"], env=env, capture_output=True, text=True, timeout=120)
        left = {name: pid for name, pid in pids.items() if alive(pid)}
        for pid in left.values():  # do not leave daemons behind even when the script failed to stop them
            os.kill(pid, signal.SIGKILL)
        assert stop.returncode == 0, f"scripts/slurm_localhost.sh stop failed: {stop.stderr[-800:]}"
        assert not left, f"daemons still running after stop: {left}"
        assert not conf.exists() or f"state in {state})" not in conf.read_text(), "stop left its slurm.conf"


def megabytes(value):
    """SLURM's memory notation (1000M, 2G) in MB."""
    number, unit = re.fullmatch(r"([0-9.]+)([MGT]?)", value).groups()
    return round(float(number) * {"": 1, "M": 1, "G": 1024, "T": 1024 ** 2}[unit])


def job_records(workdir):
    """The controller's records (scontrol show job) of the jobs that ran in workdir, as dicts."""
    out = subprocess.run(["scontrol", "-o", "show", "job"], capture_output=True, text=True, check=True).stdout
    records = []
    for line in out.splitlines():
        fields = dict(re.findall(r"(\S+?)=(\S*)", line))
        if fields.get("WorkDir") == str(workdir):
            records.append(fields)
    return records


def test_sharded_workflow_through_slurm(slurm_cluster, tmp_path):
    repo = repository_copy(tmp_path / "repo")
    (repo / "config" / "slurm_test.yaml").write_text(yaml.safe_dump(SMALL))
    profile = yaml.safe_load((repo / "workflow" / "profiles" / "slurm" / "config.yaml").read_text())
    command = [str(SNAKEMAKE), "--profile", "workflow/profiles/slurm", "--configfile", "config/slurm_test.yaml",
               # No accounting database here: no accounts to pick or check, and sacct does not answer;
               # squeue sees finished jobs for MinJobAge (600 s in slurm_localhost.sh's slurm.conf).
               "--slurm-no-account", "--slurm-status-command", "squeue",
               # Jobs of a few seconds: the first status check after 2 s, not the default 40 s.
               "--slurm-init-seconds-before-status-checks", "2",
               "--slurm-keep-successful-logs", TARGET]
    started = time.monotonic()
    run = subprocess.run(command, cwd=repo, capture_output=True, text=True, timeout=300)
    elapsed = time.monotonic() - started
    assert run.returncode == 0, f"snakemake through SLURM failed:\n{run.stdout[-2000:]}\n{run.stderr[-3000:]}"
    print(f"workflow through SLURM: {elapsed:.0f} s")

    # The shards: each holds its own range of the sample, computed as the package computes it here.
    from pyfrustrate import random_particles as rp
    from pyfrustrate.io import load_npz
    batch = SMALL["random"]["batch"]
    for b in range(BATCHES):
        data = load_npz(repo / f"results/random/sample/batch{b}.npz")
        np.testing.assert_array_equal(data["index"], np.arange(b * batch, (b + 1) * batch))
        assert int(data["seed"]) == SMALL["random"]["seed"]
        assert np.isfinite(data["ell"]).mean() > 0.99 and np.nanmin(data["ell"]) > 0
        assert np.all(np.abs(data["nu"][np.isfinite(data["nu"])]) <= 1)
    expected = rp.sample_properties(batch, SMALL["random"]["seed"], (BATCHES - 1) * batch)
    for key in ("ell", "ell_pred", "nu"):
        np.testing.assert_allclose(data[key], expected[key].astype(np.float32), rtol=1e-6, err_msg=key)

    # The gathered summary covers every shard.
    summary = load_npz(repo / TARGET)
    selection = load_npz(repo / "results/random/selection.npz")
    assert int(summary["draws"]) == BATCHES * batch
    fractions = [float(summary[f"group{i}_fraction"]) for i in range(3)]
    assert abs(sum(fractions) - 1) < 1e-9 and min(fractions) > 0
    edges = yaml.safe_load((repo / "config" / "config.yaml").read_text())["random"]["ell_groups"]
    for i in range(3):
        ell = selection[f"group{i}_ell"]
        assert len(ell) > 0 and np.all((ell >= edges[i]) & (ell < edges[i + 1]))
        assert np.all((selection[f"group{i}_index"] >= 0) & (selection[f"group{i}_index"] < BATCHES * batch))
    assert len(selection["sizes_index"]) == SMALL["random"]["size_particles"]

    # Every job went through SLURM: the controller's records, one per job, all of this run (the job
    # name is the run's id), completed, with the threads, memory and time limit of the profile.
    records = job_records(repo)
    comments = sorted(r["Comment"] for r in records)
    assert comments == sorted([f"rule_random_sample_batch_wildcards_{b}" for b in range(BATCHES)]
                              + ["rule_random_summary"]), comments
    assert len({r["JobName"] for r in records}) == 1
    assert all(r["JobState"] == "COMPLETED" and r["ExitCode"] == "0:0" for r in records), records
    resources = profile["set-resources"]
    for r in records:
        rule = "random_summary" if r["Comment"] == "rule_random_summary" else "random_sample_batch"
        assert megabytes(r["MinMemoryNode"]) == resources[rule]["mem_mb"], (rule, r["MinMemoryNode"])
        minutes = int(resources[rule]["runtime"])
        assert r["TimeLimit"] == f"{minutes // 60:02d}:{minutes % 60:02d}:00", (rule, r["TimeLimit"])
        assert int(r["NumCPUs"]) == int(profile["set-threads"][rule])
        log = Path(r["StdOut"])
        assert log.is_file() and log.is_relative_to(repo / ".snakemake" / "slurm_logs")
        assert f"Finished jobid: 0 (Rule: {rule})" in log.read_text()
    # The job-completion log keeps the same jobs for good (the controller forgets them after MinJobAge).
    completions = [line for line in (slurm_cluster / "log" / "jobcomp.log").read_text().splitlines()
                   if f"WorkDir={repo} " in line]
    assert len(completions) == len(records)
    assert all("JobState=COMPLETED" in line for line in completions)
