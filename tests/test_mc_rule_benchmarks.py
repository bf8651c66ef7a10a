"""scripts/mc_rule_benchmarks.py, the per-rule cost table of the Monte Carlo rules (issue 32, 6(d)):
the benchmark directive copied into an older workflow, the deterministic job sample, the table."""
import csv
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("mc_rule_benchmarks", ROOT / "scripts" / "mc_rule_benchmarks.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

DRY_RUN = """Building DAG of jobs...
rule catalogue:
    output: results/ansatz/catalogue.npz
    jobid: 3
rule montecarlo_run:
    input: results/ansatz/catalogue.npz
    output: results/montecarlo/runs/sparse_nu0.2_G0.5_seed1.npz, results/montecarlo/runs/sparse_nu0.2_G0.5_seed1.json
    log: results/logs/montecarlo/sparse_nu0.2_G0.5_seed1.log
localrule montecarlo_run:
    output: results/montecarlo/runs/dense_nu0.4_G0.5_seed1.npz
rule triangle_montecarlo_run:
    output: results/triangle/runs/sparse_nu0.9_G0.3.npz
rule montecarlo_run:
    output: results/montecarlo/runs/large_nu0.9_G0.5_seed2.npz
"""


def test_sample_takes_the_outputs_of_the_named_rules_only_by_their_paths(tmp_path):
    import zlib

    listing = tmp_path / "dry_run.txt"
    listing.write_text(DRY_RUN)
    rules = ["montecarlo_run", "triangle_montecarlo_run"]
    every_job, counts = bench.sample(listing, 1, rules)
    assert counts == {"montecarlo_run": 3, "triangle_montecarlo_run": 1}
    assert "results/ansatz/catalogue.npz" not in every_job  # an upstream rule's output is not a job to time
    assert every_job == sorted(every_job) and len(every_job) == 4
    assert all(path.endswith(".npz") for path in every_job)  # a job's first output names it
    for every in (2, 3):
        chosen, _ = bench.sample(listing, every, rules)
        assert chosen == [p for p in every_job if zlib.crc32(p.encode()) % every == 0]
    # Another commit's listing with one job more chooses the same jobs among those they share.
    extra = tmp_path / "other.txt"
    extra.write_text(DRY_RUN + "rule montecarlo_run:\n    output: results/montecarlo/runs/new_job.npz\n")
    for every in (2, 3):
        here, _ = bench.sample(listing, every, rules)
        there, _ = bench.sample(extra, every, rules)
        assert [p for p in there if p != "results/montecarlo/runs/new_job.npz"] == here


def _benchmark_file(directory: Path, name: str, cpu: float, seconds: float, rss: float):
    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / f"{name}.tsv", "w", newline="") as fh:
        writer = csv.writer(fh, delimiter="\t")
        writer.writerow(["s", "h:m:s", "max_rss", "max_vms", "max_uss", "max_pss", "io_in", "io_out",
                         "mean_load", "cpu_time"])
        writer.writerow([seconds, "0:00:01", rss, 1, 1, 1, 0, 0, 50, cpu])


def test_table_sums_each_rule_and_estimates_the_profile_from_a_sample(tmp_path):
    _benchmark_file(tmp_path / "bench" / "montecarlo_run", "a", 10.0, 11.0, 100.0)
    _benchmark_file(tmp_path / "bench" / "montecarlo_run", "b", 30.0, 31.0, 300.0)
    _benchmark_file(tmp_path / "bench" / "triangle_montecarlo_run", "c", 5.0, 6.0, 50.0)
    out = tmp_path / "table.csv"
    bench.table(tmp_path / "bench", out, "abc1234", "paper", ["montecarlo_run", "triangle_montecarlo_run"],
                planned={"montecarlo_run": 16, "triangle_montecarlo_run": 8})
    lines = out.read_text().splitlines()
    assert lines[0].startswith("#") and "sample" in lines[0]
    rows = {row["rule"]: row for row in csv.DictReader(lines[1:])}
    assert rows["montecarlo_run"]["jobs"] == "2" and rows["montecarlo_run"]["cpu_s_total"] == "40"
    assert rows["montecarlo_run"]["cpu_s_total_estimated"] == str(20 * 16)  # the sample's mean times the count
    assert rows["all Monte Carlo rules"]["cpu_s_total_estimated"] == str(20 * 16 + 5 * 8)
    assert rows["all Monte Carlo rules"]["max_rss_mb"] == "300"


def test_patch_gives_an_older_rule_the_benchmark_directive(tmp_path):
    new, old = tmp_path / "new", tmp_path / "old"
    new.mkdir(), old.mkdir()
    rule = "rule montecarlo_run:\n    output:\n        \"x.npz\",\n{bench}    script:\n        \"run.py\"\n"
    directive = "    benchmark:\n        \"results/benchmarks/montecarlo_run/x.tsv\"\n"
    (new / "mc.smk").write_text(rule.format(bench=directive))
    (old / "mc.smk").write_text(rule.format(bench=""))
    bench.patch(new, old, ["montecarlo_run"])
    assert "benchmark:" in (old / "mc.smk").read_text()
    with pytest.raises(SystemExit):
        bench.patch(new, old, ["no_such_rule"])


def test_compare_pairs_only_the_jobs_both_commits_ran(tmp_path):
    before, after = tmp_path / "before", tmp_path / "after"
    _benchmark_file(before / "montecarlo_run", "shared", 40.0, 41.0, 100.0)
    _benchmark_file(before / "montecarlo_run", "gone", 500.0, 501.0, 100.0)  # a run the new profile moved away
    _benchmark_file(after / "montecarlo_run", "shared", 10.0, 12.0, 90.0)
    _benchmark_file(after / "montecarlo_run", "new", 700.0, 701.0, 90.0)  # a run the old profile did not have
    _benchmark_file(before / "triangle_montecarlo_run", "t", 2.0, 3.0, 10.0)
    _benchmark_file(after / "triangle_montecarlo_run", "t", 3.0, 4.0, 10.0)
    out = tmp_path / "compare.csv"
    bench.compare(before, after, out, "old1234", "new5678", ["montecarlo_run", "triangle_montecarlo_run"])
    lines = out.read_text().splitlines()
    assert lines[0].startswith("#") and "old1234" in lines[0] and "new5678" in lines[0]
    rows = {row["rule"]: row for row in csv.DictReader(lines[1:])}
    assert rows["montecarlo_run"]["jobs"] == "1"
    assert (rows["montecarlo_run"]["cpu_s_before"], rows["montecarlo_run"]["cpu_s_after"]) == ("40", "10")
    assert rows["montecarlo_run"]["ratio"] == "0.25"
    assert rows["all shared jobs"]["jobs"] == "2" and rows["all shared jobs"]["ratio"] == f"{13 / 42:.2f}"
    # Each job's own ratio: 10 / 40 and 3 / 2, whose spread the totals' 13 / 42 hides.
    assert (rows["all shared jobs"]["job_ratio_min"], rows["all shared jobs"]["job_ratio_max"]) == ("0.25", "1.50")
    with pytest.raises(SystemExit, match="no job"):
        bench.compare(before, after, out, "a", "b", ["montecarlo_validation_sample"])


def test_compare_leaves_out_the_excluded_jobs_and_says_so(tmp_path):
    """A job whose work changed between the commits (same output name, longer schedule) is left out
    by a glob on its benchmark file name, and the table's comment names the glob."""
    before, after = tmp_path / "before", tmp_path / "after"
    for name, old, new in (("sparse_a", 40.0, 30.0), ("large_a", 100.0, 900.0), ("large_b", 100.0, 800.0)):
        _benchmark_file(before / "montecarlo_run", name, old, old + 1, 100.0)
        _benchmark_file(after / "montecarlo_run", name, new, new + 1, 100.0)
    out = tmp_path / "compare.csv"
    bench.compare(before, after, out, "old", "new", ["montecarlo_run"], exclude=("large_*",))
    lines = out.read_text().splitlines()
    assert "large_*" in lines[0]
    rows = {row["rule"]: row for row in csv.DictReader(lines[1:])}
    assert rows["montecarlo_run"]["jobs"] == "1" and rows["montecarlo_run"]["ratio"] == "0.75"
    bench.main(["compare", str(before), str(after), str(out), "--before", "old", "--after", "new",
                "--exclude", "large_*", "montecarlo_run"])
    assert "large_*" in out.read_text().splitlines()[0]
    with pytest.raises(SystemExit, match="no job"):
        bench.compare(before, after, out, "old", "new", ["montecarlo_run"], exclude=("large_*", "sparse_*"))
