#!/usr/bin/env bash
# The kernel under AddressSanitizer and UndefinedBehaviorSanitizer: builds it with
# -fsanitize=address,undefined into its own virtual environment (.venv-sanitize, build dir
# build/sanitize) and runs the Python tests that drive it (extra arguments go to pytest; default:
# the kernel's tests). Any memory error or undefined behaviour in the kernel aborts the run.
#   bash scripts/sanitize.sh                      # relaxations, topologies, Monte Carlo, extremes
#   bash scripts/sanitize.sh tests/test_extremes.py -m slow
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv-sanitize"
bash "$ROOT/scripts/setup.sh"   # Debian packages and the build requirements' versions
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
mapfile -t build_requires < <("$VENV/bin/python" -c 'import sys, tomllib
print("\n".join(tomllib.load(open(sys.argv[1], "rb"))["build-system"]["requires"]))' "$ROOT/pyproject.toml")
"$VENV/bin/python" -m pip install -q "${build_requires[@]}" cmake ninja setuptools wheel
"$VENV/bin/python" -m pip install -q --no-build-isolation \
  -C cmake.define.PYFRUSTRATE_SANITIZE=ON -C cmake.build-type=RelWithDebInfo -C build-dir=build/sanitize "$ROOT[test]"
# Python itself is not instrumented: the sanitizer runtimes are preloaded, and leak detection is
# off (the interpreter keeps its allocations to the end by design).
ASAN_LIB="$(g++ -print-file-name=libasan.so)"
UBSAN_LIB="$(g++ -print-file-name=libubsan.so)"
cd "$ROOT"
if [ "$#" -eq 0 ]; then
  set -- tests/test_extremes.py tests/test_relaxation_engine.py tests/test_hexagon.py tests/test_topology.py \
    tests/test_montecarlo.py tests/test_random_particles.py tests/test_triangle.py tests/test_particle_contract.py
fi
LD_PRELOAD="$ASAN_LIB:$UBSAN_LIB" \
ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1" \
UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1" \
  exec "$VENV/bin/python" -m pytest -q -p no:cacheprovider "$@"
