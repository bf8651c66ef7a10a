"""One Monte Carlo annealing run (main text, "Monte-Carlo validation of the phase diagram"):
particles at random in a periodic box, moves of single particles (with probability
bonded_moves to a site next to another particle; with probability surface_moves a particle
with an empty neighbour to an empty site next to a particle) and, with probability cluster_moves, of bonded
sets grown with link probability cluster_link; Metropolis-Hastings on the topology with relaxed
cluster energies, temperature lowered linearly from g to 0. The run's kind picks the box: sparse (n, box), dense
(dense_*: the bottom row of Fig. 3b) or large (large_*: figX_mc_finite_size); its convention how
Gamma maps to g (continuum.BINDING_CONVENTIONS). Gamma_measured is the run's Gamma in the
measured convention (gamma = g), where the ansatz and continuum diagrams are drawn.

With exchange["rounds"] > 0, at Gamma_measured >= exchange["Gamma_min"], the anneal's final
configuration then seeds every replica of a low-temperature replica exchange
(pyfrustrate.replica_exchange, exchange["replicas"] temperatures from exchange["temperatures"][0] g
to [1] g, geometric, the same moves): the hot replicas find the outline with the most bonds, which
the linear schedule leaves one bond short where it is favoured only below ~0.09 g (docs/results_log.md), and
the swaps carry it down. The run's result is then the coldest replica after its T = 0 descent;
the anneal's own energy and bonds are kept as anneal_energy and anneal_bonds.

The large box's runs (rule montecarlo_large_run) get a `collective` param: collective isometry
moves (shift_moves, rotation_moves, reflection_moves, isometry_link), vacancy moves (vacancy_moves:
holes filled and dug) and, in place of the linear
schedule, pyfrustrate.montecarlo.window_schedule from g through the reshaping window (`window`, in
units of g; `dwell` and `quench` the fractions of the sweeps there and at T = 0), and after the
schedule a descent at T = 0 in rounds of `descent_sweeps` sweeps until a round gains less than a
hundredth of a bond (pyfrustrate.montecarlo.descend; at most `descent_rounds` rounds), so that the
run's energy is that of a local minimum of its moves, not of a state still on its way down; before
it, as many rounds at `descent_temperature` g, where moves that break bonds are screened out by
their bond count instead of relaxed one by one (0: none). The
other kinds' rule has no such param. It also passes `relaxation`, fields of MonteCarloOptions for its chain
(parent_factor: a move that changes the box's one large aggregate by a few particles relaxes it on
its parent's modified factor)."""
import hashlib
import json
import os
import time

import numpy as np

from pyfrustrate import anneal, continuum
from pyfrustrate.montecarlo import MonteCarloOptions, descend, geometric_temperatures, replica_exchange, window_schedule
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
    collective = getattr(p, "collective", None)  # only the large box's rule passes it
    collective_moves = {key: collective[key] for key in ("shift_moves", "rotation_moves", "reflection_moves",
                                                         "isometry_link", "vacancy_moves") if key in collective
                        } if collective else {}
    relaxation = dict(getattr(p, "relaxation", None) or {})  # only the large box's rule passes it (parent_factor)
    # One chain for both stages: the anneal and the exchange after it make the same moves.
    options = MonteCarloOptions(method=method, tol=p.tol, cluster_moves=cluster_moves, cluster_link=cluster_link,
                                bonded_moves=bonded_moves, surface_moves=surface_moves, **collective_moves, **relaxation)
    # Named by everything that defines the run, so a changed configuration starts afresh while an
    # interrupted run of the same configuration resumes: the stem (kind, nu, Gamma, seed), the size
    # and a digest of the rest (the chain's options, as their signature, and the schedule). A
    # checkpoint written before an option existed has another signature, which anneal would refuse
    # to resume; under the digest such a run starts afresh instead of failing. The digest keeps
    # the name under the file system's 255 bytes, which the options spelled out had passed.
    defines = dict(options=options.signature(), eps=p.eps, sweeps=sweeps,
                   schedule={key: collective[key] for key in ("window", "dwell", "quench")} if collective else None)
    digest = hashlib.sha256(json.dumps(defines, sort_keys=True, default=str).encode()).hexdigest()[:12]
    checkpoint = f"{p.checkpoint_stem}_{n}in{box}_{sweeps}sweeps_{digest}.npz"
    chain = dict(g=g, box=box, n=n, seed=p.seed, options=options, progress=True)
    schedule = dict(steps=n * sweeps)
    if collective:
        low, high = collective["window"]
        schedule = dict(schedule=window_schedule((low * g, high * g), n, sweeps=sweeps, T0=g, dwell=collective["dwell"],
                                                 quench=collective["quench"]))
    cpu_start = time.process_time()
    r = anneal(particle, checkpoint=checkpoint, **schedule, **chain)
    if r.resumed:
        print(f"resumed from checkpoint {checkpoint}")
    final, exchange, exchange_checkpoint, descent = r, {}, None, {}
    if collective:
        # First rounds at descent_temperature (in units of g; 0: none), where moves that break bonds
        # are screened out by their bond count instead of relaxed and refused one by one as at
        # T = 0; then the descent at T = 0, which certifies the minimum.
        near, screened_rounds = r, 0
        if collective["descent_temperature"] > 0:
            near, screened_rounds, _ = descend(particle, r, options=options, sweeps_per_round=collective["descent_sweeps"],
                                               max_rounds=collective["descent_rounds"],
                                               temperature=collective["descent_temperature"] * g)
        final, descent_rounds, still = descend(particle, near, options=options, sweeps_per_round=collective["descent_sweeps"],
                                       max_rounds=collective["descent_rounds"])
        print(f"descent at T = 0 after the schedule: energy {r.energy:.6g} -> {final.energy:.6g}, bonds {r.bonds} -> "
              f"{final.bonds}, {screened_rounds} rounds at {collective['descent_temperature']:g} g then {descent_rounds} "
              f"at T = 0, of {collective['descent_sweeps']} sweeps each, "
              + ("a local minimum" if still else "still descending when the rounds ran out"))
        descent = dict(schedule_energy=r.energy, schedule_bonds=r.bonds, descent_screened_rounds_run=screened_rounds,
                       descent_rounds_run=descent_rounds, descent_converged=still)
    rounds = p.exchange["rounds"]
    # Gamma_measured comes back from the g it was mapped to, a few ulps off the grid's value: a run
    # at exactly Gamma_min must take the stage.
    if rounds and Gamma_measured < p.exchange["Gamma_min"] * (1 - 1e-9):
        print(f"no replica exchange after the anneal: Gamma {Gamma_measured:.4g} (measured convention) is below "
              f"exchange_Gamma_min {p.exchange['Gamma_min']:g}")
        rounds = 0
    if rounds:
        (T_low, T_high), replicas = p.exchange["temperatures"], p.exchange["replicas"]
        ladder = geometric_temperatures(T_low * g, T_high * g, replicas)
        exchange_checkpoint = (f"{checkpoint[:-4]}_exchange{rounds}_K{replicas}"
                               f"_T{T_low:g}-{T_high:g}.npz")
        x = replica_exchange(particle, ladder, rounds=rounds, initial_sites=r.sites, checkpoint=exchange_checkpoint,
                             threads=snakemake.threads, **chain)  # noqa: F821 (the job's cores: the rule's threads)
        print(f"replica exchange after the anneal, {replicas} temperatures {T_low:g}-{T_high:g} g, "
              f"{rounds} rounds: energy {r.energy:.6g} -> {x.energy:.6g}, bonds {r.bonds} -> "
              f"{x.bonds}; swap acceptance {', '.join(f'{a:.2f}' for a in x.swap_acceptance)}; "
              f"{x.round_trips} round trips; {x.elapsed:.1f} s")
        exchange = dict(exchange_rounds=rounds, exchange_temperatures=ladder,
                        exchange_swap_acceptance=x.swap_acceptance, exchange_round_trips=x.round_trips,
                        exchange_elapsed=x.elapsed, anneal_energy=r.energy, anneal_bonds=r.bonds)
        final = x
    cpu_seconds = time.process_time() - cpu_start  # this job's own (a resumed run: since it resumed)
    sizes = sorted((len(c) for c in final.clusters()), reverse=True)
    print(f"nu={p.nu} Gamma={p.Gamma} n={n} box={box} seed={p.seed} method={method} cluster_moves={cluster_moves:g} cluster_link={cluster_link:g} bonded_moves={bonded_moves:g} surface_moves={surface_moves:g} {collective or ''}: energy {final.energy:.6g}, "
          f"acceptance {r.acceptance:.3g}, cache hit rate {r.cache_hit_rate:.3f}, {r.elapsed:.1f} s "
          f"({cpu_seconds:.1f} s of CPU); clusters {sizes[:8]}")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), sites=final.sites, box=box, n=n, nu=p.nu, Gamma=p.Gamma, ell=p.ell,  # noqa: F821
             seed=p.seed, g=g, energy=final.energy, bonds=final.bonds, energy_trace=r.energy_trace, temperature=r.temperature,
             steps=r.steps, acceptance=r.acceptance, stage_acceptance=r.stage_acceptance, method=method,
             cluster_sizes=np.array(sizes), cluster_moves=cluster_moves,
             cluster_link=cluster_link, bonded_moves=bonded_moves, surface_moves=surface_moves, kind=p.kind, tiling=p.tiling,
             convention=p.convention, Gamma_measured=Gamma_measured, cpu_seconds=cpu_seconds, elapsed=r.elapsed,
             **{f"collective_{key}": value for key, value in (collective or {}).items()},
             **{f"relaxation_{key}": value for key, value in relaxation.items()}, **descent, **exchange)
    for path in (checkpoint, exchange_checkpoint):  # the result is saved: nothing left to resume
        if path is not None:
            os.remove(path)
