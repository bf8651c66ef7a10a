#!/usr/bin/env bash
# Set-up shared by the figures and test commands: Debian build dependencies when missing, a
# virtual environment in .venv, and the package (C++ kernel included) installed into it.
# Re-running is cheap: the package is rebuilt only when its sources change, incrementally.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${PYFRUSTRATE_VENV:-$ROOT/.venv}"
# libsuitesparse-dev: CHOLMOD, the supernodal sparse Cholesky of the Newton and linear solves;
# libopenblas0-serial: an optimised single-threaded BLAS for its dense supernodes (the reference
# BLAS that libsuitesparse-dev pulls in alone makes the supernodal factorisation no faster).
DEBIAN_PACKAGES=(g++ libeigen3-dev libnlopt-cxx-dev libsuitesparse-dev libopenblas0-serial python3-venv)

source "$ROOT/scripts/debian_packages.sh"
install_missing_debian_packages "[setup]" -- "${DEBIAN_PACKAGES[@]}"

if [ ! -x "$VENV/bin/python" ]; then
  echo "[setup] creating virtual environment $VENV"
  python3 -m venv "$VENV"
fi

# Rebuild only when a source file of the package changed since the last install.
stamp="$VENV/.pyfrustrate-source-hash"
hash=$(bash "$ROOT/scripts/source_hash.sh" "$ROOT")
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$hash" ]; then
  echo "[setup] building and installing pyfrustrate (C++ kernel) into $VENV"
  "$VENV/bin/python" -m pip install -q --upgrade pip
  # The build requirements live in the venv (read from pyproject.toml), not in a throw-away
  # isolated environment: CMake's cache in build/ then stays valid and a rebuild recompiles
  # only what changed (seconds after a Python edit, instead of the whole kernel).
  mapfile -t build_requires < <("$VENV/bin/python" -c 'import sys, tomllib
print("\n".join(tomllib.load(open(sys.argv[1], "rb"))["build-system"]["requires"]))' "$ROOT/pyproject.toml")
  ((${#build_requires[@]})) || { echo "[setup] no build requirements read from pyproject.toml" >&2; exit 1; }
  # setuptools and wheel: without build isolation, dependencies published only as source
  # (snakemake's connection_pool) are built with the venv's own setuptools, which needs both.
  "$VENV/bin/python" -m pip install -q "${build_requires[@]}" cmake ninja setuptools wheel
  "$VENV/bin/python" -m pip install -q --no-build-isolation "$ROOT[test,workflow]"
  echo "$hash" > "$stamp"
fi
