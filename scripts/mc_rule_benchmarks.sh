#!/usr/bin/env bash
# The Monte Carlo rules' cost at one commit (issue 32, 6(d)): checks COMMIT out in a temporary
# worktree, builds it into its own virtual environment, runs the Monte Carlo rules (and only them:
# `--until`) that the profile's figures need, one job at a time, and writes the per-rule table
# (jobs, total and median CPU seconds, largest resident set) from Snakemake's benchmark files.
#
#   bash scripts/mc_rule_benchmarks.sh COMMIT [quick|paper] [OUT.csv]
#
# quick: the default configuration (~10-20 min per commit on one core); paper: config/paper.yaml
# (~5 h). A commit from before the rules had their `benchmark:` directives gets this checkout's.
# OUT defaults to results/benchmarks/mc_rules_<profile>_<commit>.csv. CORES (default 1) jobs run
# side by side; MC_BENCH_VENV reuses a virtual environment (else a temporary one, built ~3 min);
# MC_RULES (space-separated) replaces the rule list; KEEP=1 keeps the temporary worktree (its results/ hold every run's output and log).
# MC_SAMPLE=K runs about one in K of the rules' jobs (chosen by a checksum of the output path, so two
# commits run the same jobs) and adds the profile's job count and the estimated total to the table: the paper profile's
# Monte Carlo is ~12 h of CPU per commit, a sample of 1 in 8 about 1.5 h. Two commits' profiles can
# differ in their jobs; `python3 scripts/mc_rule_benchmarks.py compare BEFORE/results/benchmarks
# AFTER/results/benchmarks OUT.csv --before C --after C RULE...` pairs the jobs both ran.
# MC_TARGETS="OUTPUT..." runs exactly those jobs afresh (with MC_BENCH_WORK; scripts/mc_rule_pairs.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
COMMIT="${1:?usage: mc_rule_benchmarks.sh COMMIT [quick|paper] [OUT.csv]}"
PROFILE="${2:-quick}"
SHORT="$(git -C "$ROOT" rev-parse --short "$COMMIT^{commit}")"
OUT="$(realpath -m "${3:-$ROOT/results/benchmarks/mc_rules_${PROFILE}_${SHORT}.csv}")"
# The rules both sides of the redesign have; MC_RULES names others (e.g. the fixed-size
# validation's montecarlo_validation_point, _sample and _two_sided, which have directives too).
read -r -a RULES <<< "${MC_RULES:-montecarlo_run triangle_montecarlo_run}"
case "$PROFILE" in
  quick) CONFIG=() ;;
  paper) CONFIG=(--configfile config/paper.yaml) ;;
  *) echo "mc_rule_benchmarks: profile must be quick or paper, got '$PROFILE'" >&2; exit 2 ;;
esac

# MC_BENCH_WORK=DIR works in DIR and keeps it: the same command run again resumes there (Snakemake
# redoes only the jobs that did not finish), for a paper-profile measurement longer than one sitting.
if [ -n "${MC_BENCH_WORK:-}" ]; then
  WORK="$(realpath -m "$MC_BENCH_WORK")"
  mkdir -p "$WORK"
  KEEP=1
else
  WORK="$(mktemp -d "${TMPDIR:-/tmp}/mc-rule-benchmarks.XXXXXX")"
fi
cleanup() {
  if [ "${KEEP:-0}" = 1 ]; then
    echo "[mc_rule_benchmarks] kept $WORK"
  else
    git -C "$ROOT" worktree remove --force "$WORK/src" 2>/dev/null || true
    rm -rf "$WORK"
  fi
}
trap cleanup EXIT
if [ -d "$WORK/src" ]; then
  [ "$(git -C "$WORK/src" rev-parse --short HEAD)" = "$SHORT" ] \
    || { echo "mc_rule_benchmarks: $WORK/src holds another commit than $SHORT" >&2; exit 2; }
  echo "[mc_rule_benchmarks] resuming in $WORK"
  rm -rf "$WORK/src/.snakemake/locks"  # left by a run killed hard; this directory is this script's alone
else
  git -C "$ROOT" worktree add --quiet --detach "$WORK/src" "$SHORT"
fi
python3 "$ROOT/scripts/mc_rule_benchmarks.py" patch "$ROOT/workflow/rules" "$WORK/src/workflow/rules" "${RULES[@]}"

export PYFRUSTRATE_VENV="${MC_BENCH_VENV:-$WORK/venv}"
cd "$WORK/src"
bash scripts/setup.sh
echo "[mc_rule_benchmarks] $SHORT, $PROFILE profile: the Monte Carlo jobs"
PLANNED=()
if [ -n "${MC_TARGETS:-}" ]; then
  # Exactly these jobs, afresh: their outputs, logs, benchmark files and checkpoints go first (a
  # finished checkpoint would return at once). scripts/mc_rule_pairs.sh runs two commits' jobs
  # alternately this way, so that each pair shares the machine's load.
  read -r -a TARGETS <<< "$MC_TARGETS"
  for target in "${TARGETS[@]}"; do
    stem="${target%.npz}"
    name="${stem##*/}"
    rm -f "$target" "${stem/\/runs\//\/checkpoints\/}"_*.npz results/benchmarks/*/"$name".tsv
  done
  "$PYFRUSTRATE_VENV/bin/snakemake" "${TARGETS[@]}" --cores "${CORES:-1}" --rerun-incomplete "${CONFIG[@]}"
elif [ -n "${MC_SAMPLE:-}" ]; then
  # --forceall: every job of the rules, done or not, so that a resumed measurement samples (and
  # counts) the same jobs as the first sitting.
  "$PYFRUSTRATE_VENV/bin/snakemake" -n --forceall "${CONFIG[@]}" --until "${RULES[@]}" > "$WORK/dry_run.txt"
  python3 "$ROOT/scripts/mc_rule_benchmarks.py" sample "$WORK/dry_run.txt" "$MC_SAMPLE" "${RULES[@]}" \
    > "$WORK/targets.txt" 2> "$WORK/planned.txt"
  mapfile -t TARGETS < "$WORK/targets.txt"
  mapfile -t PLANNED < "$WORK/planned.txt"
  echo "[mc_rule_benchmarks] a sample of ${#TARGETS[@]} jobs (about 1 in ${MC_SAMPLE}; in the profile: ${PLANNED[*]})"
  # The targets first: --configfile takes every word after it.
  "$PYFRUSTRATE_VENV/bin/snakemake" "${TARGETS[@]}" --cores "${CORES:-1}" --rerun-incomplete "${CONFIG[@]}"
  PLANNED=(--planned "${PLANNED[@]}")
else
  "$PYFRUSTRATE_VENV/bin/snakemake" -n --quiet rules "${CONFIG[@]}" --until "${RULES[@]}"
  "$PYFRUSTRATE_VENV/bin/snakemake" --cores "${CORES:-1}" --rerun-incomplete "${CONFIG[@]}" --until "${RULES[@]}"
fi
python3 "$ROOT/scripts/mc_rule_benchmarks.py" table results/benchmarks "$OUT" --commit "$SHORT" --profile "$PROFILE" \
  "${PLANNED[@]}" "${RULES[@]}"
