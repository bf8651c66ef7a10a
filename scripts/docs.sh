#!/usr/bin/env bash
# Builds the documentation site into results/docs/ (open results/docs/index.html), after the same
# set-up as the figures and test commands plus the `docs` extra. Warnings are errors (-W), and
# the tutorials are executed on the way (sphinx-gallery), so a broken example fails the build.
# Extra arguments go to sphinx-build (e.g. -j 2, or -E to rebuild every page).
# `bash scripts/docs.sh --snapshot` instead copies the measured-number files this checkout has
# written under results/ (registered in docs/conf.py) into docs/_generated/, the snapshot a fresh
# clone's build reads, to be committed with the change that moved them.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "${1:-}" = "--snapshot" ]; then
  cd "$ROOT"
  mapfile -t sources < <(python3 -c 'import ast, sys
tree = ast.parse(open("docs/conf.py").read())
for node in tree.body:
    if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "measured_sources" for t in node.targets):
        print("\n".join(ast.literal_eval(node.value)))')
  ((${#sources[@]})) || { echo "[docs] no measured_sources read from docs/conf.py" >&2; exit 1; }
  for path in "${sources[@]}"; do
    if [ -f "$path" ]; then
      mkdir -p "docs/_generated/$(dirname "$path")"
      cp "$path" "docs/_generated/$path"
      echo "[docs] snapshot: $path"
    else
      echo "[docs] not measured in this checkout, snapshot kept: $path"
    fi
  done
  exit 0
fi
VENV="${PYFRUSTRATE_VENV:-$ROOT/.venv}"
bash "$ROOT/scripts/setup.sh"

# The docs extra, installed when pyproject.toml's list changed since the last install (a stamp,
# as setup.sh keeps for the package itself).
stamp="$VENV/.pyfrustrate-docs-hash"
mapfile -t docs_requires < <("$VENV/bin/python" -c 'import sys, tomllib
print("\n".join(tomllib.load(open(sys.argv[1], "rb"))["project"]["optional-dependencies"]["docs"]))' "$ROOT/pyproject.toml")
((${#docs_requires[@]})) || { echo "[docs] no docs requirements read from pyproject.toml" >&2; exit 1; }
hash=$(printf '%s\n' "${docs_requires[@]}" | sha256sum | cut -d' ' -f1)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$hash" ]; then
  echo "[docs] installing the documentation requirements into $VENV"
  "$VENV/bin/python" -m pip install -q "${docs_requires[@]}"
  echo "$hash" > "$stamp"
fi

cd "$ROOT"
# The API pages are regenerated from the package at each build: none may outlive its module.
rm -rf docs/api/generated
# Agg: the tutorials draw without a display; one BLAS thread, as everywhere in this project.
export MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
# -P: the installed package (with its compiled kernel), not the source tree in the working directory.
"$VENV/bin/python" -P -m sphinx -W --keep-going -b html "$@" docs results/docs
echo "[docs] built $ROOT/results/docs/index.html"
