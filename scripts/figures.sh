#!/usr/bin/env bash
# Regenerates every figure of the paper at the default (quick) scale into results/figures/.
# Extra arguments go to snakemake, e.g. `--configfile config/paper.yaml` for paper scale.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
exec "${PYFRUSTRATE_VENV:-$ROOT/.venv}/bin/snakemake" --cores "${CORES:-$(nproc)}" --rerun-incomplete "$@"
