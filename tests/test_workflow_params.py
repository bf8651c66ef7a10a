"""Precise reruns: every rule gets exactly the config values it uses through named params, so
changing one key reruns only the jobs that read it (and, downstream, what reads their outputs).

The workflow is copied to a temporary directory, every output is created empty and marked up to
date by Snakemake itself (``--touch --forceall``, which records each job's params), then one key
is changed in a copy of the configuration and ``snakemake -n`` says which jobs it would rerun and
why. Nothing is computed, so the test takes seconds.
"""
from __future__ import annotations

import fnmatch
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")

pytestmark = pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside this Python")


def _snakemake(cwd: Path, *args: str) -> str:
    done = subprocess.run([str(SNAKEMAKE), *args], cwd=cwd, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def touched_workflow(tmp_path_factory) -> tuple[Path, list[str]]:
    """A copy of the workflow whose every output exists and is up to date, with its metadata."""
    work = tmp_path_factory.mktemp("workflow")
    for name in ("workflow", "config", "figures", "benchmarks"):
        shutil.copytree(ROOT / name, work / name)
    summary = _snakemake(work, "--summary")
    outputs = [line.split("\t")[0] for line in summary.splitlines()[1:] if line.strip()]
    assert len(outputs) > 100, summary
    for out in outputs:
        (work / out).parent.mkdir(parents=True, exist_ok=True)
        (work / out).touch()
    _snakemake(work, "--cores", "1", "--touch", "--forceall", "all")
    assert "Nothing to be done" in _snakemake(work, "-n")
    return work, outputs


def _changed_config(work: Path, section: list[str], key: str) -> Path:
    config = yaml.safe_load((work / "config" / "config.yaml").read_text())
    node = config
    for name in section:
        node = node[name]
    value = node[key]
    node[key] = [*value, value[-1] * 1.5] if isinstance(value, list) else value * 2 + 1
    changed = work / f"changed_{'_'.join(section)}_{key}.yaml"
    changed.write_text(yaml.safe_dump(config))
    return changed


def _rerun_by_params(work: Path, configfile: Path) -> tuple[set[str], set[str]]:
    """The outputs ``snakemake -n`` would remake because their params changed, and the reasons
    given for every other job."""
    by_params, other_reasons = set(), set()
    outputs: list[str] = []
    for line in _snakemake(work, "-n", "--configfile", str(configfile)).splitlines():
        line = line.strip()
        if line.startswith("rule "):
            outputs = []
        elif line.startswith("output:"):
            outputs = [out.strip() for out in line[len("output:"):].split(",")]
        elif line.startswith("reason:"):
            reason = line[len("reason:"):].strip()
            if reason.startswith("Params have changed"):
                by_params.update(outputs)
            else:
                other_reasons.add(reason.split(":")[0])
    return by_params, other_reasons


@pytest.mark.parametrize(
    ("section", "key", "expected"),
    [
        (["montecarlo"], "large_sweeps", ["results/montecarlo/runs/large_*"]),
        (["montecarlo"], "dense_sweeps", ["results/montecarlo/runs/dense_*"]),
        (["montecarlo"], "tol", ["results/montecarlo/runs/*"]),
        # The fixed-size samples and two-sided checks, not their points (validation.json,
        # downstream, reruns too).
        (["montecarlo", "validation"], "hold_sweeps",
         ["results/montecarlo/validation/*/size*", "results/montecarlo/validation/*/two_sided*"]),
        # The grand-canonical samples alone (validation.json, downstream, reruns too).
        (["montecarlo", "validation", "grand"], "sweeps", ["results/montecarlo/validation/grand_*"]),
        (["montecarlo"], "exchange_Gamma_min", ["results/montecarlo/runs/sparse_*"]),
        # The triangle's finite-size predictions (Fig. S6) use the same Gamma grid.
        (["montecarlo"], "finite_Gamma_count", ["results/montecarlo/finite/*", "results/triangle/finite/*"]),
        (["triangle", "montecarlo"], "sweeps", ["results/triangle/runs/sparse_*"]),
        (["random"], "fits", ["results/random/fits.npz"]),
        (["ansatz"], "edge_nu", ["results/ansatz/line_tension.json"]),
        (["ansatz"], "Gamma_count", ["results/ansatz/diagram_*"]),
    ],
)
def test_changing_one_key_reruns_only_the_jobs_that_use_it(touched_workflow, section, key, expected):
    work, outputs = touched_workflow
    by_params, other_reasons = _rerun_by_params(work, _changed_config(work, section, key))
    want = {out for out in outputs if any(fnmatch.fnmatch(out, pattern) for pattern in expected)}
    assert want, f"no output matches {expected}"
    assert by_params == want, (f"changing {'.'.join(section + [key])} reruns {sorted(by_params - want)} "
                               f"needlessly and misses {sorted(want - by_params)}")
    # Everything else rerun only reads what those jobs remake.
    assert other_reasons <= {"Input files updated by another job"}, other_reasons
