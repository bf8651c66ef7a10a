"""Every result records what made it (pyfrustrate.provenance): the package version, the git
commit and whether the checkout was dirty, the kernel's build hash, the parameters and the seed;
each file format keeps the record where io.read_provenance finds it."""
from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

from pyfrustrate import _kernel, plotting, provenance
from pyfrustrate.io import load_npz, provenance_line, read_provenance, save_json, save_npz

ROOT = Path(__file__).resolve().parents[1]


def _git(cwd, *args):
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout.strip()


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_git_state_follows_commits_and_edits(tmp_path):
    assert provenance.git_state(tmp_path) == ("unknown", None)  # not a checkout
    _git(tmp_path, "init", "-q")
    (tmp_path / "a.txt").write_text("one\n")
    _git(tmp_path, "add", "a.txt")
    _git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "one")
    head = _git(tmp_path, "rev-parse", "HEAD")
    assert provenance.git_state(tmp_path) == (head, False)
    (tmp_path / "a.txt").write_text("two\n")
    assert provenance.git_state(tmp_path) == (head, True)


def test_kernel_build_hash_is_the_hash_of_the_sources_it_was_built_from():
    """Recomputed here from kernel/ and the compiler: a build older than its sources fails."""
    compiler = shutil.which("g++") or shutil.which("c++")
    if compiler is None or not (ROOT / "kernel").is_dir():
        pytest.skip("no source tree or compiler to recompute the hash from")
    version = subprocess.run([compiler, "-dumpfullversion"], capture_output=True, text=True).stdout.strip()
    text = f"GNU {version} Release"
    for source in sorted([*ROOT.glob("kernel/*.cpp"), *ROOT.glob("kernel/*.hpp"), *ROOT.glob("kernel/montecarlo/*.hpp")],
                         key=str):
        text += f" {source.relative_to(ROOT / 'kernel').as_posix()}:{hashlib.sha256(source.read_bytes()).hexdigest()}"
    assert _kernel.build_hash == hashlib.sha256(text.encode()).hexdigest()


def test_describe_records_version_parameters_and_seed():
    record = provenance.describe({"n": np.int64(3), "box": (60, 60), "eps": np.float64(0.01)}, seed=np.int64(7), rule="r")
    assert record["version"] == metadata.version("pyfrustrate")
    assert record["kernel_build_hash"] == _kernel.build_hash
    assert record["parameters"] == {"n": 3, "box": [60, 60], "eps": 0.01}
    assert record["seed"] == 7 and record["rule"] == "r"
    assert json.loads(json.dumps(record)) == record  # plain JSON, nothing lost
    assert provenance.describe() == provenance.describe()  # no clock, no machine: reproducible


def test_every_format_keeps_the_record(tmp_path):
    record = provenance.describe({"nu": 0.9}, seed=1, rule="test")
    save_npz(tmp_path / "a.npz", provenance=record, x=np.arange(3))
    assert read_provenance(tmp_path / "a.npz") == record
    assert set(load_npz(tmp_path / "a.npz")) == {"x"}  # readers of the arrays do not see it
    save_json(tmp_path / "a.json", {"y": 1}, provenance=record)
    assert read_provenance(tmp_path / "a.json") == record
    (tmp_path / "a.csv").write_text(provenance_line(record) + "a,b\n1,2\n")
    assert read_provenance(tmp_path / "a.csv") == record
    fig = plotting.figure()
    fig.add_subplot().plot([0, 1])
    plotting.save(fig, [tmp_path / "f.png", tmp_path / "f.pdf"], provenance=record)
    assert read_provenance(tmp_path / "f.png") == record
    assert record["kernel_build_hash"].encode() in (tmp_path / "f.pdf").read_bytes()
    save_npz(tmp_path / "plain.npz", x=np.arange(3))
    assert read_provenance(tmp_path / "plain.npz") is None


def test_reserved_names_and_unknown_formats_are_refused(tmp_path):
    with pytest.raises(ValueError, match="provenance"):
        save_json(tmp_path / "a.json", [1, 2], provenance={})
    with pytest.raises(ValueError, match=r"\.txt"):
        read_provenance(tmp_path / "a.txt")


SNAKEMAKE = Path(sys.executable).with_name("snakemake")


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside this Python")
def test_a_workflow_job_records_its_rule_params_and_wildcards(tmp_path):
    """A real job of the workflow (a Monte Carlo finite-size prediction, made small)."""
    for name in ("workflow", "config", "figures", "benchmarks"):
        shutil.copytree(ROOT / name, tmp_path / name)
    target = "results/montecarlo/finite/n200_nu0.9.npz"
    (tmp_path / "small.yaml").write_text("montecarlo:\n  finite_Gamma_count: 5\n")
    done = subprocess.run([str(SNAKEMAKE), "--cores", "1", target, "--configfile", "small.yaml"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    record = read_provenance(tmp_path / target)
    assert record["rule"] == "montecarlo_finite_aggregates"
    assert record["parameters"]["finite_Gamma_count"] == 5 and record["parameters"]["n"] == 200
    assert record["parameters"]["wildcards"] == {"n": "200", "nu": "0.9"}
    assert record["kernel_build_hash"] == _kernel.build_hash
    assert len(load_npz(tmp_path / target)["Gamma"]) == 5
