"""
A Monte Carlo run, interrupted and resumed
==========================================

:func:`pyfrustrate.anneal` anneals which sites of a periodic box are occupied; each cluster
sits at its relaxed deformation energy (see :doc:`../topics/montecarlo`). It takes the binding
energy per bond ``g``, not Gamma: we convert the paper's ``Gamma`` with
:func:`pyfrustrate.continuum.particle_parameters` (the measured convention, see
:doc:`../topics/binding`).

A run is resumable: with ``checkpoint=`` it saves its state when interrupted (Ctrl-C, a
scheduler's SIGTERM turned into an exception, or any exception) and picks up from it when called
again with the same parameters. Here a tiny box is interrupted halfway on purpose, then resumed,
and compared with the same run done in one go.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import pyfrustrate as pf
from pyfrustrate import continuum, montecarlo

ell, nu, Gamma, eps = 5.0, 0.9, 0.5, 0.01
particle = pf.Hexagon.from_continuum(ell=ell, nu=nu, eps=eps)
g = float(continuum.particle_parameters(ell, nu, Gamma, k=particle.k, eps=eps).g)
print(f"Gamma = {Gamma} -> g = {g:.3e} per bond")

# A tiny box: 40 particles in 16 x 16 cells, 300 sweeps, Newton cluster energies.
run_options = dict(box=16, n=40, steps=300 * 40, seed=7, method="newton", progress=False)

# %%
# Interrupt the run halfway
# -------------------------
# ``callback(steps_done, total_steps, energy)`` is called after every chunk of the schedule;
# an exception raised there stops the run, after the checkpoint is saved.


class Interrupted(Exception):
    pass


def stop_halfway(steps_done, total_steps, energy):
    if steps_done >= total_steps // 2:
        raise Interrupted(f"stopped at {steps_done} of {total_steps} moves")


checkpoint = Path(tempfile.mkdtemp()) / "run.npz"
try:
    pf.anneal(particle, g=g, checkpoint=checkpoint, callback=stop_halfway, **run_options)
except Interrupted as reason:
    print(reason)
saved = montecarlo.read_checkpoint(checkpoint)
print(f"checkpoint written: {checkpoint.name}")

# %%
# Resume, and compare with the run done in one go
# -----------------------------------------------
# Calling ``anneal`` again with the same parameters and checkpoint continues from the saved
# state. The resumed run takes the same moves as the uninterrupted one; its energies agree to
# the relaxation tolerance (the cache of cluster energies is not saved).

resumed = pf.anneal(particle, g=g, checkpoint=checkpoint, **run_options)
straight = pf.anneal(particle, g=g, **run_options)
print(f"resumed: {resumed.resumed}; bonds {resumed.bonds} (in one go: {straight.bonds}); "
      f"energy {resumed.energy:.6e} (in one go: {straight.energy:.6e})")

fig, (trace, snapshot) = plt.subplots(1, 2, figsize=(8, 3.4))
trace.plot(straight.steps / run_options["n"], straight.energy_trace, label="in one go")
trace.plot(resumed.steps / run_options["n"], resumed.energy_trace, "--", label="interrupted and resumed")
trace.set(xlabel="sweeps", ylabel="box energy", title="energy during the anneal")
trace.legend(frameon=False)
montecarlo.draw_snapshot(resumed.sites, resumed.box, ax=snapshot, particle=particle)
count = len(resumed.clusters())
snapshot.set_title(f"final state: {count} cluster{'' if count == 1 else 's'}")
fig.tight_layout()

# %%
# Other particles
# ---------------
# ``anneal`` takes any particle model: the triangular particle of the supplement (its box
# counts lattice cells, each an up and a down triangle; its ``g`` follows from ``gamma = g / 2``,
# hence ``tiling="triangle"``) and a random-elasticity particle (its own ``ell`` and ``nu`` set
# its ``g``, ``random_particles.binding_energy_of``).

from pyfrustrate import random_particles

triangle = pf.Triangle.from_continuum(ell=2.5, nu=0.5, eps=0.05)
g_triangle = float(continuum.particle_parameters(2.5, 0.5, 0.5, k=triangle.k, eps=triangle.eps, tiling="triangle").g)
random_particle = random_particles.RandomHexagon.draw(seed=2025, index=17, eps=0.01)
g_random = float(random_particles.binding_energy_of(random_particle, random_particle.boundary_layer_length,
                                                    float(random_particle.moduli["nu"]), 0.5))

small = dict(box=12, n=24, steps=200 * 24, seed=3, method="newton", progress=False)
others = {"triangles": pf.anneal(triangle, g=g_triangle, **small),
          "a random particle": pf.anneal(random_particle, g=g_random, **small)}
fig, axes = plt.subplots(1, 2, figsize=(8, 3.4))
for ax, (name, result), model in zip(axes, others.items(), (triangle, random_particle)):
    montecarlo.draw_snapshot(result.sites, result.box, ax=ax, particle=model)
    ax.set_title(f"{name}: {result.bonds} bonds")
fig.tight_layout()
