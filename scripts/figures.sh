#!/usr/bin/env bash
# Regenerates every figure of the paper at the default (quick) scale into results/figures/.
# Extra arguments go to snakemake, e.g. `--configfile config/paper.yaml` for paper scale.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
# A run killed hard (SIGKILL: an OOM kill, a lost node, a pre-empted job) leaves Snakemake's lock
# behind, and the next run would stop with "Directory cannot be locked". When no Snakemake works in
# this directory any more the lock is stale: remove it, so that the same command resumes
# (--rerun-incomplete redoes the jobs the kill cut short; outputs are written atomically).
locks="$ROOT/.snakemake/locks"
if [ -d "$locks" ] && [ -n "$(ls -A "$locks")" ]; then
  active=0
  for pid in $(pgrep -f "bin/snakemake" || true); do
    [ "$(readlink -f "/proc/$pid/cwd" 2>/dev/null)" = "$ROOT" ] && active=1
  done
  if [ "$active" = 0 ]; then
    echo "[figures] removing a stale Snakemake lock (no Snakemake process runs in $ROOT)"
    rm -f "$locks"/*
  fi
fi
exec "${PYFRUSTRATE_VENV:-$ROOT/.venv}/bin/snakemake" --cores "${CORES:-$(nproc)}" --rerun-incomplete "$@"
