"""One Monte Carlo annealing run (main text, "Monte-Carlo validation of the phase diagram"):
particles at random in a periodic box, moves of single particles (with probability
bonded_moves to a site next to another particle; with probability surface_moves a particle
with an empty neighbour to an empty site next to a particle) and, with probability cluster_moves, of bonded
sets grown with link probability cluster_link; Metropolis-Hastings on the topology with relaxed
cluster energies, temperature lowered linearly from g to 0. The run's kind picks the box: sparse (n, box), dense
(dense_*: the bottom row of Fig. 3b) or large (large_*: figX_mc_finite_size); its convention how
Gamma maps to g (continuum.BINDING_CONVENTIONS). Gamma_measured is the run's Gamma in the
measured convention (gamma = g), where the ansatz and continuum diagrams are drawn."""
import os

import numpy as np

from pyfrustrate import anneal, continuum
from pyfrustrate.io import logging_to, save_npz, sigterm_raises
from pyfrustrate.provenance import for_job
from pyfrustrate.particles import particle_class

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
# A cancelled job (SIGTERM) saves its checkpoint on the way out; the next run resumes from it.
with logging_to(snakemake.log[0]), sigterm_raises():  # noqa: F821
    particle = particle_class(p.tiling).from_continuum(p.ell, p.nu, eps=p.eps)
    g = float(continuum.particle_parameters(p.ell, p.nu, p.Gamma, eps=p.eps, tiling=p.tiling,
                                            convention=p.convention).g)
    Gamma_measured = float(continuum.mapping(particle.k, particle.kc, particle.k_area, g, p.eps,
                                             tiling=p.tiling).Gamma)
    n, box, method, sweeps = p.n, p.box, p.method, p.sweeps
    cluster_moves, cluster_link, bonded_moves, surface_moves = p.cluster_moves, p.cluster_link, p.bonded_moves, p.surface_moves
    # Named by everything that defines the run, so a changed configuration starts afresh while an
    # interrupted run of the same configuration resumes.
    checkpoint = (f"{p.checkpoint_stem}_{n}in{box}_{sweeps}sweeps_{method}_tol{p.tol:g}_eps{p.eps:g}"
                  f"_cm{cluster_moves:g}_link{cluster_link:g}_bonded{bonded_moves:g}_surface{surface_moves:g}.pkl")
    r = anneal(particle, g, box=box, n=n, steps=n * sweeps, seed=p.seed, method=method, tol=p.tol,
               checkpoint=checkpoint, progress=True, cluster_moves=cluster_moves, cluster_link=cluster_link,
               bonded_moves=bonded_moves, surface_moves=surface_moves)
    if r.resumed:
        print(f"resumed from checkpoint {checkpoint}")
    sizes = sorted((len(c) for c in r.clusters()), reverse=True)
    print(f"nu={p.nu} Gamma={p.Gamma} n={n} box={box} seed={p.seed} method={method} cluster_moves={cluster_moves:g} cluster_link={cluster_link:g} bonded_moves={bonded_moves:g} surface_moves={surface_moves:g}: energy {r.energy:.6g}, "
          f"acceptance {r.acceptance:.3g}, cache hit rate {r.cache_hit_rate:.3f}, {r.elapsed:.1f} s; clusters {sizes[:8]}")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), sites=r.sites, box=box, n=n, nu=p.nu, Gamma=p.Gamma, ell=p.ell,  # noqa: F821
             seed=p.seed, g=g, energy=r.energy, energy_trace=r.energy_trace, temperature=r.temperature,
             steps=r.steps, acceptance=r.acceptance, stage_acceptance=r.stage_acceptance, method=method,
             cluster_sizes=np.array(sizes), cluster_moves=cluster_moves,
             cluster_link=cluster_link, bonded_moves=bonded_moves, surface_moves=surface_moves, kind=p.kind, tiling=p.tiling,
             convention=p.convention, Gamma_measured=Gamma_measured)
    os.remove(checkpoint)  # the result is saved: nothing left to resume
