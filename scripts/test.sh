#!/usr/bin/env bash
# Runs the whole test suite (after the same set-up as the figures command).
# Extra arguments go to pytest, e.g. `-m slow` for the long statistical checks.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
# tests/test_slurm.py runs the workflow on a single-node SLURM (scripts/slurm_localhost.sh), which
# needs root and these Debian packages: installed here when missing, as root with apt-get only
# (without root the test is skipped, so there is nothing to install).
TEST_DEBIAN_PACKAGES=(slurm-wlm munge)
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
  source "$ROOT/scripts/debian_packages.sh"
  # --no-install-recommends: the daemons and clients, not the MySQL-backed accounting daemon.
  install_missing_debian_packages "[test]" --no-install-recommends -- "${TEST_DEBIAN_PACKAGES[@]}"
fi
cd "$ROOT"
exec "${PYFRUSTRATE_VENV:-$ROOT/.venv}/bin/python" -m pytest "$@"
