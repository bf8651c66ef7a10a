"""The Monte Carlo rules' cost, per rule, from Snakemake's ``benchmark:`` files (issue 32, 6(d)).

Two commands, used by ``scripts/mc_rule_benchmarks.sh``:

``patch RULES_DIR OTHER_RULES_DIR RULE...``
    Gives each named rule of ``OTHER_RULES_DIR/*.smk`` (an older checkout's workflow) the
    ``benchmark:`` directive the same rule has in ``RULES_DIR`` (this checkout's), where it has
    none, so that a commit from before the directives is timed the same way.

``sample DRY_RUN_OUTPUT EVERY RULE...``
    The output files of the named rules' jobs in a ``snakemake -n`` listing whose CRC-32 is a
    multiple of ``EVERY`` (about one in ``EVERY``), sorted, one per line; on standard error, each
    rule's job count, as ``RULE=COUNT`` lines, for ``table --planned``. The choice depends on a
    job's output path alone, so two commits whose rules name their outputs alike run the same
    jobs even where their profiles differ by a few jobs.

``table BENCHMARK_DIR OUT_CSV --commit C --profile P [--planned RULE=COUNT ...] RULE...``
    One row per rule from ``BENCHMARK_DIR/RULE/*.tsv`` (one file per job): jobs, total and
    median CPU seconds (Snakemake's ``cpu_time``, user + system of the job's processes), total
    wall seconds, largest resident set (MB); written atomically, its first line a ``#`` comment
    saying what was measured (the documentation's ``measured`` role reads it). With
    ``--planned`` (a sample of the jobs was run): the profile's job count per rule and the
    estimated total, the sample's mean times that count.

``compare BEFORE_DIR AFTER_DIR OUT_CSV --before C --after C [--exclude GLOB]... RULE...``
    The jobs both benchmark directories hold (same rule, same benchmark file name, i.e. the same
    output), paired: per rule and over all, the job count and the CPU seconds of both sides and
    their ratio (after / before). Two commits' profiles can differ in their jobs (a scan
    redrawn, a kind of run moved to another rule); only the jobs they share compare the engine.
    ``--exclude`` drops the jobs whose benchmark file name matches a glob (``large_*``): jobs
    of the same name whose work changed between the commits (a longer schedule), which would
    compare two protocols, not one engine; the table's comment line names them.

Standard library only: it runs with any Python, on any commit's results.
"""
from __future__ import annotations

import argparse
import csv
import fnmatch
import os
import platform
import re
import statistics
import sys
import tempfile
import zlib
from pathlib import Path

_RULE = re.compile(r"^rule (\w+):\s*$")
_DIRECTIVE = re.compile(r"^    (\w+):")


def rule_blocks(text: str) -> dict[str, tuple[int, int]]:
    """Each rule's lines ``[start, end)`` in a Snakemake file's lines (a rule ends at the next
    unindented line that is not blank)."""
    lines = text.splitlines(keepends=True)
    blocks, current = {}, None
    for i, line in enumerate(lines):
        if current is not None and line.strip() and not line.startswith((" ", "\t")):
            blocks[current[0]] = (current[1], i)
            current = None
        match = _RULE.match(line)
        if match:
            current = (match.group(1), i)
    if current is not None:
        blocks[current[0]] = (current[1], len(lines))
    return blocks


def directive(lines: list[str], start: int, end: int, name: str) -> list[str] | None:
    """The lines of directive ``name`` of the rule at ``lines[start:end]`` (None: absent)."""
    for i in range(start + 1, end):
        match = _DIRECTIVE.match(lines[i])
        if match and match.group(1) == name:
            j = i + 1
            while j < end and (lines[j].startswith("        ") or not lines[j].strip()):
                j += 1
            while j > i + 1 and not lines[j - 1].strip():
                j -= 1
            return lines[i:j]
    return None


def patch(rules_dir: Path, other_dir: Path, rules: list[str]) -> None:
    wanted = {}
    for smk in sorted(rules_dir.glob("*.smk")):
        lines = smk.read_text().splitlines(keepends=True)
        for rule, (start, end) in rule_blocks(smk.read_text()).items():
            if rule in rules:
                block = directive(lines, start, end, "benchmark")
                if block is None:
                    sys.exit(f"patch: rule {rule} of {smk} has no benchmark directive to copy")
                wanted[rule] = block
    missing = sorted(set(rules) - set(wanted))
    if missing:
        sys.exit(f"patch: no rule {', '.join(missing)} in {rules_dir}")
    found = set()
    for smk in sorted(other_dir.glob("*.smk")):
        text = smk.read_text()
        lines = text.splitlines(keepends=True)
        # From the last rule up, so that inserted lines do not move the blocks still to patch.
        for rule, (start, end) in sorted(rule_blocks(text).items(), key=lambda item: -item[1][0]):
            if rule not in wanted:
                continue
            found.add(rule)
            if directive(lines, start, end, "benchmark") is None:
                lines[start + 1:start + 1] = wanted[rule]
                print(f"patch: {smk.name}: rule {rule} given its benchmark directive")
        smk.write_text("".join(lines))
    if set(wanted) - found:
        sys.exit(f"patch: no rule {', '.join(sorted(set(wanted) - found))} in {other_dir}")


_DRY_RUN_JOB = re.compile(r"^(?:local)?rule (\w+):\s*$")
_DRY_RUN_OUTPUT = re.compile(r"^    output: (.+)$")


def sample(dry_run: Path, every: int, rules: list[str]) -> tuple[list[str], dict[str, int]]:
    """The outputs of the named rules' jobs in a ``snakemake -n`` listing whose CRC-32 is a multiple
    of ``every``, sorted, and each rule's job count."""
    if every < 1:
        sys.exit(f"sample: EVERY must be a positive integer, got {every}")
    outputs = {rule: [] for rule in rules}
    current = None
    for line in dry_run.read_text().splitlines():
        job = _DRY_RUN_JOB.match(line)
        if job:
            current = job.group(1)
            continue
        output = _DRY_RUN_OUTPUT.match(line)
        if output and current in outputs:
            outputs[current].append(output.group(1).split(", ")[0])
            current = None
    chosen = sorted(path for paths in outputs.values() for path in paths if zlib.crc32(path.encode()) % every == 0)
    return chosen, {rule: len(paths) for rule, paths in outputs.items()}


def table(benchmark_dir: Path, out: Path, commit: str, profile: str, rules: list[str],
          planned: dict[str, int] | None = None) -> None:
    rows = []
    for rule in rules:
        records = [record for job in _job_records(benchmark_dir, rule).values() for record in job]
        if not records:
            continue
        cpu = [float(r["cpu_time"]) for r in records]
        rss = [float(r["max_rss"]) for r in records if r["max_rss"] not in ("", "NA", "-")]
        row = dict(commit=commit, profile=profile, rule=rule, jobs=len(records), cpu_s_total=f"{sum(cpu):.0f}",
                   cpu_s_median=f"{statistics.median(cpu):.1f}",
                   wall_s_total=f"{sum(float(r['s']) for r in records):.0f}",
                   max_rss_mb=f"{max(rss):.0f}" if rss else "")
        if planned is not None:
            row["jobs_in_profile"] = planned.get(rule, len(records))
            row["cpu_s_total_estimated"] = f"{statistics.mean(cpu) * row['jobs_in_profile']:.0f}"
        rows.append(row)
    if not rows:
        sys.exit(f"table: no benchmark files of {', '.join(rules)} under {benchmark_dir}")
    total = dict(commit=commit, profile=profile, rule="all Monte Carlo rules", jobs=sum(r["jobs"] for r in rows),
                 cpu_s_total=f"{sum(float(r['cpu_s_total']) for r in rows):.0f}", cpu_s_median="",
                 wall_s_total=f"{sum(float(r['wall_s_total']) for r in rows):.0f}",
                 max_rss_mb=f"{max(float(r['max_rss_mb']) for r in rows if r['max_rss_mb']):.0f}")
    if planned is not None:
        total["jobs_in_profile"] = sum(r["jobs_in_profile"] for r in rows)
        total["cpu_s_total_estimated"] = f"{sum(float(r['cpu_s_total_estimated']) for r in rows):.0f}"
    rows.append(total)
    sampled = " (a deterministic sample of the jobs: jobs_in_profile and the estimated total)" if planned else ""
    _write_csv(out, f"# Monte Carlo rules of the {profile} profile at commit {commit}, one job at a time "
                    f"(scripts/mc_rule_benchmarks.sh){sampled}; {platform.machine()}, {os.cpu_count()} cores\n", rows)


def _job_records(benchmark_dir: Path, rule: str) -> dict[str, list[dict]]:
    """The rows of each job's benchmark file of ``rule`` under ``benchmark_dir``, by file name
    (relative to the rule's directory), in sorted order."""
    jobs = {}
    for tsv in sorted((benchmark_dir / rule).glob("**/*.tsv")):
        with open(tsv, newline="") as fh:
            jobs[str(tsv.relative_to(benchmark_dir / rule))] = list(csv.DictReader(fh, delimiter="\t"))
    return jobs


def _cpu_by_job(benchmark_dir: Path, rule: str) -> dict[str, float]:
    """CPU seconds of each job of ``rule`` under ``benchmark_dir``, by benchmark file name."""
    return {job: sum(float(r["cpu_time"]) for r in records)
            for job, records in _job_records(benchmark_dir, rule).items()}


def compare(before_dir: Path, after_dir: Path, out: Path, before: str, after: str, rules: list[str],
            exclude: tuple[str, ...] = ()) -> None:
    rows, both_before, both_after, every_ratio = [], 0.0, 0.0, []

    def spread(ratios):  # the jobs' own after / before: the total hides how far single jobs move
        return dict(job_ratio_min=f"{min(ratios):.2f}", job_ratio_max=f"{max(ratios):.2f}")

    for rule in rules:
        old, new = _cpu_by_job(before_dir, rule), _cpu_by_job(after_dir, rule)
        shared = sorted(j for j in set(old) & set(new) if not any(fnmatch.fnmatch(j, g) for g in exclude))
        if not shared:
            continue
        cpu_before, cpu_after = sum(old[j] for j in shared), sum(new[j] for j in shared)
        both_before, both_after = both_before + cpu_before, both_after + cpu_after
        ratios = [new[j] / old[j] for j in shared if old[j] > 0]
        every_ratio += ratios
        rows.append(dict(rule=rule, jobs=len(shared), cpu_s_before=f"{cpu_before:.0f}", cpu_s_after=f"{cpu_after:.0f}",
                         ratio=f"{cpu_after / cpu_before:.2f}", **spread(ratios or [float("nan")]), before=before,
                         after=after))
    if not rows:
        sys.exit(f"compare: no job of {', '.join(rules)} in both {before_dir} and {after_dir}")
    rows.append(dict(rule="all shared jobs", jobs=sum(r["jobs"] for r in rows), cpu_s_before=f"{both_before:.0f}",
                     cpu_s_after=f"{both_after:.0f}", ratio=f"{both_after / both_before:.2f}",
                     **spread(every_ratio or [float("nan")]), before=before, after=after))
    excluded = f", jobs matching {' '.join(exclude)} excluded" if exclude else ""
    _write_csv(out, f"# The jobs both commits ran (same rule and output{excluded}), CPU seconds paired: {before} "
                    f"before, {after} after (scripts/mc_rule_benchmarks.py compare); {platform.machine()}, "
                    f"{os.cpu_count()} cores\n", rows)


def _write_csv(out: Path, comment: str, rows: list[dict]) -> None:
    """``rows`` under a ``#`` comment line, written atomically."""
    out.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=out.parent, prefix=f".{out.name}.")
    with os.fdopen(fd, "w", newline="") as fh:
        fh.write(comment)
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, out)
    print(f"wrote {out}")
    for row in rows:
        print("  ".join(f"{k}={v}" for k, v in row.items()))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("patch")
    p.add_argument("rules_dir", type=Path)
    p.add_argument("other_dir", type=Path)
    p.add_argument("rules", nargs="+")
    t = sub.add_parser("table")
    t.add_argument("benchmark_dir", type=Path)
    t.add_argument("out", type=Path)
    t.add_argument("--commit", required=True)
    t.add_argument("--profile", required=True)
    t.add_argument("--planned", nargs="*", default=None, metavar="RULE=COUNT")
    t.add_argument("rules", nargs="+")
    c = sub.add_parser("compare")
    c.add_argument("before_dir", type=Path)
    c.add_argument("after_dir", type=Path)
    c.add_argument("out", type=Path)
    c.add_argument("--before", required=True)
    c.add_argument("--after", required=True)
    c.add_argument("--exclude", action="append", default=[], metavar="GLOB", help="repeat for several")
    c.add_argument("rules", nargs="+")
    s = sub.add_parser("sample")
    s.add_argument("dry_run", type=Path)
    s.add_argument("every", type=int)
    s.add_argument("rules", nargs="+")
    args = ap.parse_args(argv)
    if args.command == "patch":
        patch(args.rules_dir, args.other_dir, args.rules)
    elif args.command == "compare":
        compare(args.before_dir, args.after_dir, args.out, args.before, args.after, args.rules, tuple(args.exclude))
    elif args.command == "sample":
        chosen, counts = sample(args.dry_run, args.every, args.rules)
        print("\n".join(chosen))
        print("\n".join(f"{rule}={count}" for rule, count in counts.items()), file=sys.stderr)
    else:
        planned = None
        if args.planned is not None:
            try:
                planned = {rule: int(count) for rule, count in (item.split("=") for item in args.planned)}
            except ValueError:
                sys.exit(f"table: --planned takes RULE=COUNT pairs, got {args.planned}")
        table(args.benchmark_dir, args.out, args.commit, args.profile, args.rules, planned)


if __name__ == "__main__":
    main()
