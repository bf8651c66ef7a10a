#!/usr/bin/env bash
# Runs once, inside the freshly created environment, from the directory Snakemake works in
# (the repository's root): builds the package against the environment's libraries.
set -euo pipefail
if ! grep -q '^name = "pyfrustrate"' pyproject.toml 2>/dev/null; then
  echo "pyfrustrate's conda environment: run snakemake from the repository's root (found no pyproject.toml of pyfrustrate in $PWD)" >&2
  exit 1
fi
CMAKE_PREFIX_PATH="$CONDA_PREFIX" SUITESPARSE_ROOT="$CONDA_PREFIX" \
  python -m pip install --no-deps --no-build-isolation --no-cache-dir .
