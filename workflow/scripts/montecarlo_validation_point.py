"""One point of the fixed-size Monte Carlo validation (issue 33, item 1): the ansatz's and the
continuum's optimal size at (scan, nu, Gamma), the sizes the scan samples around the ansatz's,
and the hold temperature of the reshaping window, read from a heating ladder of the seed of the
ansatz's size (montecarlo.fixed_size.reshaping_temperature)."""
import numpy as np

from pyfrustrate.io import logging_to, save_json
from pyfrustrate.montecarlo import binding, fixed_size
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = particle_class("hexagon").from_continuum(p.ell, p.nu, eps=p.eps)
    g = binding(particle, Gamma=p.Gamma)
    W_ansatz, fibre_energy = fixed_size.best_straight_fibre(particle, g, max_width=p.ansatz_max_width)
    n_ansatz, R_ansatz, disk_energy = fixed_size.best_disk(particle, g, max_radius=p.ansatz_max_radius)
    optimum = W_ansatz if p.scan == "fibre" else n_ansatz
    sizes = fixed_size.scan_sizes(p.scan, optimum, p.steps)
    options = fixed_size.fixed_size_options(p.bonded_moves, p.surface_moves, method=p.method, tol=p.tol)
    sites, box = fixed_size.scan_seed(p.scan, optimum, fibre_length=p.fibre_length, disk_margin=p.disk_margin)
    seed = fixed_size.run_seed(p.seed, optimum, 0)
    ladder, reference = fixed_size.heating_ladder(particle, sites, box, seed, g=g, options=options,
                                                  sweeps=p.window_sweeps,
                                                  temperatures=np.asarray(p.window_temperatures) * g)
    T_hold, stages = fixed_size.reshaping_temperature(ladder.temperature, ladder.energy_trace, ladder.accepted,
                                                      n=len(sites), g=g, reference_energy=reference,
                                                      max_excess=p.window_max_excess,
                                                      min_acceptance=p.window_min_acceptance)
    print(f"{p.scan} nu={p.nu} Gamma={p.Gamma}: W_ansatz={W_ansatz} rows, n_ansatz={n_ansatz} (R={R_ansatz}); "
          f"sizes {sizes}; hold at T = {T_hold / g:.3g} g ({ladder.elapsed:.1f} s of ladder)")
    for s in stages:
        print(f"  T = {s['T'] / g:.3g} g: excess {s['excess']:.4f} bonds/particle, acceptance {s['acceptance']:.4f}, "
              f"holds {s['holds']}, reshapes {s['reshapes']}")
    save_json(snakemake.output[0], dict(  # noqa: F821
        scan=p.scan, nu=p.nu, Gamma=p.Gamma, ell=p.ell, eps=p.eps, g=g, W_ansatz=W_ansatz, n_ansatz=n_ansatz,
        R_ansatz=R_ansatz, fibre_energy_per_particle=fibre_energy, disk_energy_per_particle=disk_energy,
        continuum=fixed_size.continuum_optima(p.ell, p.nu, p.Gamma), sizes=sizes, hold_temperature=T_hold,
        hold_temperature_over_g=T_hold / g, window=[dict(s, T_over_g=s["T"] / g) for s in stages],
        ladder_seconds=ladder.elapsed, reference_energy=reference),
        provenance=for_job(snakemake))  # noqa: F821
