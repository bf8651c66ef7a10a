#!/usr/bin/env bash
# Runs the whole test suite (after the same set-up as the figures command).
# Extra arguments go to pytest, e.g. `-m slow` for the long statistical checks.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
exec "${PYFRUSTRATE_VENV:-$ROOT/.venv}/bin/python" -m pytest "$@"
