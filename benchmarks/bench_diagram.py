"""Full ell = 5 ansatz diagram at paper scale (21 nu from 0 to 0.99, disks R <= 25, fibres of
widths up to 35 for the three cuts plus straight cut-0 fibres, bulks with holes, 321 Gamma) on a
pool of worker processes: wall time with the linear solve and with L-BFGS (from the linear
solution), and how many (nu, Gamma) cells change winner between them.

    python benchmarks/bench_diagram.py [--processes 2] [--quick]

Goals (issue #4): under 2 minutes (linear), under 15 minutes (L-BFGS) on 2 cores.
"""
from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from pyfrustrate import Hexagon, ansatz

ELL, EPS = 5.0, 0.01


def catalogue_for(args):
    nu, method, max_radius, max_width = args
    particle = Hexagon.from_continuum(ELL, nu, eps=EPS)
    table = ansatz.relax_catalogue(particle, ansatz.catalogue(max_radius, max_width, straight_fibers=True), method=method)
    return particle, table


def diagram(method, nus, Gamma, processes, max_radius, max_width):
    start = time.perf_counter()
    with ProcessPoolExecutor(processes) as pool:
        results = list(pool.map(catalogue_for, [(nu, method, max_radius, max_width) for nu in nus]))
    seconds = time.perf_counter() - start
    winners, phases, unconverged = [], [], 0
    for nu, (particle, table) in zip(nus, results):
        families = [f for f in np.unique(table.family) if f != "fiber_cut0_straight"]
        win = table.winners(ansatz.binding_energy_of(particle, ELL, nu, Gamma), families=families)
        winners.append([f"{table.family[w]}:{table.size[w]}" for w in win])
        phases.append([ansatz.FAMILY_PHASE[table.family[w]] for w in win])
        unconverged += int((~table.converged).sum())
    return seconds, np.array(winners), np.array(phases), unconverged


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="5 nu, R <= 10, widths <= 14 (smoke run)")
    args = parser.parse_args()
    nu_count, max_radius, max_width = (5, 10, 14) if args.quick else (21, 25, 35)
    nus = np.minimum(np.linspace(0, 1, nu_count), 0.99)
    Gamma = np.linspace(0, 1.6, 321)
    print(f"ell = {ELL}, {nu_count} nu, R <= {max_radius}, widths <= {max_width}, {len(Gamma)} Gamma, "
          f"{args.processes} processes")
    rows = {}
    for method in ("linear", "lbfgs"):
        rows[method] = diagram(method, nus, Gamma, args.processes, max_radius, max_width)
        print(f"  {method:7s} {rows[method][0]:8.1f} s   unconverged candidates: {rows[method][3]}")
    changed = rows["linear"][1] != rows["lbfgs"][1]
    changed_phase = rows["linear"][2] != rows["lbfgs"][2]
    print(f"L-BFGS / linear time ratio: {rows['lbfgs'][0] / rows['linear'][0]:.2f}")
    print(f"cells whose winner (kind and size) changes: {changed.sum()} of {changed.size} "
          f"({100 * changed.mean():.1f} %); whose aggregate kind changes: {changed_phase.sum()}")
    for i, nu in enumerate(nus):
        if changed_phase[i].any():
            print(f"  nu = {nu:.2f}: kind changes at Gamma = {np.round(Gamma[changed_phase[i]], 3)}")


if __name__ == "__main__":
    main()
