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
  missing=()
  for pkg in "${TEST_DEBIAN_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  if ((${#missing[@]})); then
    echo "[test] installing Debian packages: ${missing[*]}"
    apt-get update -qq
    # --no-install-recommends: the daemons and clients, not the MySQL-backed accounting daemon.
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
fi
cd "$ROOT"
exec "${PYFRUSTRATE_VENV:-$ROOT/.venv}/bin/python" -m pytest "$@"
