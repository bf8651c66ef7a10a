#!/usr/bin/env bash
# The hash of the package's sources (every file of the kernel and every module of the package,
# subdirectories included), from the repository root given as $1 (default: this script's). One
# definition: scripts/setup.sh rebuilds when it changes, and the tests that need the installed
# package built from the sources they read compare it with the install's stamp.
set -euo pipefail
ROOT="${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}"
cd "$ROOT"
cat pyproject.toml CMakeLists.txt $( (find kernel -type f; find pyfrustrate -name '*.py') | LC_ALL=C sort) |
  sha256sum | cut -d' ' -f1
