"""One grand-canonical sample of the Monte Carlo validation (issue 33, item 2): a straight fibre of
the ansatz's best width wrapping a periodic box, held at a temperature and a chemical potential
with outline, surface and bonded moves (montecarlo.grand_canonical.hold_fibre). The chemical
potential is the ansatz's threshold min_W e(W) (its best straight fibre's energy per particle,
binding included) plus an offset, in units of g."""
from pyfrustrate.io import logging_to, save_json
from pyfrustrate.montecarlo import binding, fixed_size, grand_canonical
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = particle_class("hexagon").from_continuum(p.ell, p.nu, eps=p.eps)
    g = binding(particle, Gamma=p.Gamma)
    W_ansatz, fibre_energy = fixed_size.best_straight_fibre(particle, g, max_width=p.ansatz_max_width)
    threshold = float(fibre_energy.min())
    mu = threshold + p.mu_offset_over_g * g
    options = grand_canonical.grand_options(mu, p.outline_moves, p.surface_moves, p.bonded_moves, method=p.method,
                                            tol=p.tol)
    seed = fixed_size.run_seed(p.seed, *p.run_keys, 2)  # role 2: grand-canonical (0 and 1 are the fixed-size runs')
    sample = grand_canonical.hold_fibre(particle, p.length, W_ansatz, seed, g=g, mu=mu, T=p.T_over_g * g,
                                        sweeps=p.sweeps, equilibration=p.equilibration, options=options)
    print(f"T = {p.T_over_g:g} g, mu = threshold {p.mu_offset_over_g:+g} g: <W> = {sample.W_mean:.2f} +- "
          f"{sample.W_std:.2f} rows (seeded {W_ansatz}), <E>/<n> - mu = "
          f"{(sample.energy_per_particle - mu) / g:+.4f} g, {sample.seconds:.1f} s")
    save_json(snakemake.output[0], dict(  # noqa: F821
        nu=p.nu, Gamma=p.Gamma, ell=p.ell, eps=p.eps, g=g, length=p.length, seed=p.seed, T_over_g=p.T_over_g,
        mu_offset_over_g=p.mu_offset_over_g, mu_over_g=mu / g, threshold_over_g=threshold / g, W_ansatz=W_ansatz,
        fibre_energy_per_particle_over_g=(fibre_energy / g).tolist(),
        W_mean=sample.W_mean, W_std=sample.W_std, n_mean=sample.n_mean, n_std=sample.n_std,
        energy_per_particle_over_g=sample.energy_per_particle / g, W_trace=(sample.n / p.length).tolist(),
        wraps=sample.wraps, seconds=sample.seconds, sweeps=p.sweeps, equilibration=p.equilibration,
        counters=sample.counters),
        provenance=for_job(snakemake))  # noqa: F821
