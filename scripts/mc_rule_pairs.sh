#!/usr/bin/env bash
# Two commits' Monte Carlo jobs timed in pairs (issue 32, 6(d)): each job runs at BEFORE, then at
# AFTER, then the next job, so that the two runs of a pair share the machine's load (a shared
# machine's load moves CPU times by tens of per cent over an hour); then the pairs are compared
# (`scripts/mc_rule_benchmarks.py compare`: CPU seconds per rule, before, after, ratio).
#
#   MC_PAIR_WORK=DIR bash scripts/mc_rule_pairs.sh BEFORE AFTER [quick|paper] OUT.csv OUTPUT...
#
# OUTPUT: the jobs' output files (results/montecarlo/runs/....npz, results/triangle/runs/....npz).
# Each commit is checked out and built once under DIR/<commit> (scripts/mc_rule_benchmarks.sh with
# MC_BENCH_WORK and MC_TARGETS); the same command run again skips the pairs already timed.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage="usage: MC_PAIR_WORK=DIR mc_rule_pairs.sh BEFORE AFTER [quick|paper] OUT.csv OUTPUT..."
[ "$#" -ge 5 ] || { echo "$usage" >&2; exit 2; }
BEFORE="$(git -C "$ROOT" rev-parse --short "$1^{commit}")"
AFTER="$(git -C "$ROOT" rev-parse --short "$2^{commit}")"
PROFILE="$3"
OUT="$(realpath -m "$4")"
shift 4
WORK="$(realpath -m "${MC_PAIR_WORK:?$usage}")"
read -r -a RULES <<< "${MC_RULES:-montecarlo_run triangle_montecarlo_run}"

timed() {  # whether commit $1 holds a benchmark file for output $2
  local name
  name="$(basename "${2%.npz}")"
  compgen -G "$WORK/$1/src/results/benchmarks/*/$name.tsv" > /dev/null
}
for target in "$@"; do
  if timed "$BEFORE" "$target" && timed "$AFTER" "$target"; then
    echo "[mc_rule_pairs] $target: timed at both commits"
    continue
  fi
  for commit in "$BEFORE" "$AFTER"; do
    echo "[mc_rule_pairs] $target at $commit"
    MC_BENCH_WORK="$WORK/$commit" MC_TARGETS="$target" bash "$ROOT/scripts/mc_rule_benchmarks.sh" "$commit" "$PROFILE" \
      "$WORK/table_$commit.csv"
  done
done
python3 "$ROOT/scripts/mc_rule_benchmarks.py" compare "$WORK/$BEFORE/src/results/benchmarks" \
  "$WORK/$AFTER/src/results/benchmarks" "$OUT" --before "$BEFORE" --after "$AFTER" "${RULES[@]}"
