#!/usr/bin/env bash
# The runs behind benchmarks/results/large_nucleation.csv and large_merging.csv (issue 33, item 3;
# docs/topics/montecarlo.md, "Why the runs at nu = 0.4 end in rafts"), one at a time, niced.
# CANDIDATES: the workflow's finite-size prediction of the quick profile's large box (rule
# montecarlo_finite_aggregates), for the seeded hold and the structure verdict; default: a build's
# results/ in the current directory. PYTHON: the interpreter with pyfrustrate installed.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python}
# (The default through a variable: the braces of the file pattern would close ${...:-...}.)
default_candidates='results/montecarlo/finite/n{n}_nu{nu:g}.npz'
CANDIDATES=${CANDIDATES:-$default_candidates}
R=benchmarks/results/large_nucleation
trace() { nice -n 2 "$PYTHON" benchmarks/bench_large_nucleation.py --nu 0.4 --every 20 --candidates "$CANDIDATES" "$@"; }
for T in 0.7 0.6 0.5 0.4; do
    trace --Gamma 0.5 --schedule stages --stages 1:50 "$T:1500" --label "hold${T}_G0.5" --csv "$R/hold${T}_G0.5.csv"
done
trace --Gamma 0.5 --schedule stages --stages 1:50 0.45:1000 --label hold0.45_G0.5 --csv $R/hold0.45_G0.5.csv
trace --Gamma 0.5 --seeded --schedule stages --stages 0.45:1000 --label seeded0.45_G0.5 --csv $R/seeded0.45_G0.5.csv
trace --Gamma 0.5 --label window_G0.5 --csv $R/window_G0.5.csv
trace --Gamma 0.8 --label window_G0.8 --csv $R/window_G0.8.csv
trace --Gamma 0.5 --moves cluster_moves=0.0 --label no_cluster_moves_G0.5 --csv $R/no_cluster_moves_G0.5.csv
trace --Gamma 0.5 --moves isometry_link=0.9 rotation_moves=0.0 reflection_moves=0.0 --label whole_set_shifts_G0.5 \
    --csv $R/whole_set_shifts_G0.5.csv
nice -n 2 "$PYTHON" benchmarks/bench_large_merging.py --variants workflow --points 0.4,0.5 0.4,0.8 --seeds 1 2 3 \
    --candidates "$CANDIDATES" --csv benchmarks/results/large_merging.csv
# What was tried beyond the holds: a slow ramp, the window raised to 0.25-0.4 g, the carry move
# (carry_moves) with either window, and the end of the failing Gamma = 0.8 run held at 0.35 g.
trace --Gamma 0.5 --schedule stages --stages 1:200 0.8:200 0.6:200 0.5:400 0.45:600 0.4:800 0.35:800 0.3:800 \
    --label slow_ramp_G0.5 --csv $R/slow_ramp_G0.5.csv
trace --Gamma 0.5 --window 0.25 0.4 --label window0.25-0.4_G0.5 --csv $R/window0.25-0.4_G0.5.csv
trace --Gamma 0.5 --moves carry_moves=0.05 --label carry_G0.5 --csv $R/carry_G0.5.csv
trace --Gamma 0.5 --window 0.25 0.4 --moves carry_moves=0.05 --label carry_window0.25-0.4_G0.5 \
    --csv $R/carry_window0.25-0.4_G0.5.csv
# RUNS: the workflow's run files of a quick build (rule montecarlo_large_run), default results/montecarlo/runs.
trace --Gamma 0.8 --sites-from "${RUNS:-results/montecarlo/runs}/large_nu0.4_G0.8_seed1.npz" --schedule stages \
    --stages 0.35:1000 --label pair_held0.35_G0.8 --csv $R/pair_held0.35_G0.8.csv
