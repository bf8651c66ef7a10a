"""
A first relaxation: a disk and a fibre against the continuum
=============================================================

We relax aggregates of the paper's hexagonal particle at fixed topology and compare their
deformation energy with the continuum theory (main text Eqs. 8-13) at the same boundary-layer
length ``ell`` and Poisson ratio ``nu``.

Two conventions matter here:

* ``topology.fiber(width)`` counts **lattice lines**; the continuum width is
  ``W = width * sqrt(3) / 2`` lattice spacings. A disk ``topology.disk(R)`` holds
  ``1 + 3 R (R + 1)`` particles, each of area ``sqrt(3) / 2``: its continuum radius is that of a
  circle of the same area.
* :func:`pyfrustrate.relax` returns the **deformation energy** only, so it is compared with the
  continuum at ``Gamma = 0`` (no line tension).
"""

import numpy as np
import matplotlib.pyplot as plt

import pyfrustrate as pf
from pyfrustrate import continuum, topology

ell, nu = 5.0, 0.5
particle = pf.Hexagon.from_continuum(ell=ell, nu=nu, eps=0.01)
e_bulk = particle.bulk_energy_per_particle  # energy per particle of the infinite bulk
print(particle)

# %%
# One relaxation
# --------------
# The default method is Newton, to a largest force of ``tol`` times the particle's force scale.

disk = pf.relax(particle, topology.disk(6))
print(f"disk R = 6: {disk.n_particles} particles, converged: {disk.converged}, "
      f"energy per particle = {disk.energy_per_particle / e_bulk:.4f} e_bulk")

# %%
# Fibres of growing width and disks of growing radius
# ---------------------------------------------------
# ``continuum.fiber_energy(w, nu, Gamma)`` and ``continuum.disk_energy(r, nu, Gamma)`` give the
# energy per area in units of the bulk energy density, with sizes in units of ``ell``; per
# particle in units of ``e_bulk`` it is the same number.

widths = np.arange(2, 31, 2)
fibre_energy = [pf.relax(particle, topology.fiber(int(w), cut=0)).energy_per_particle / e_bulk for w in widths]
W = widths * np.sqrt(3) / 2  # lattice lines -> continuum width
fibre_continuum = continuum.fiber_energy(w=W / ell, nu=nu, Gamma=0.0)

radii = np.arange(1, 11)
disk_energy = [pf.relax(particle, topology.disk(int(R))).energy_per_particle / e_bulk for R in radii]
n_particles = 1 + 3 * radii * (radii + 1)
R_continuum = np.sqrt(n_particles * topology.area_per_particle() / np.pi)
disk_continuum = continuum.disk_energy(r=R_continuum / ell, nu=nu, Gamma=0.0)

fig, (left, right) = plt.subplots(1, 2, figsize=(8, 3.2), sharey=True)
left.plot(W / ell, fibre_energy, "o", label="relaxed fibre (cut 0)")
left.plot(W / ell, fibre_continuum, "-", label="continuum")
left.set(xlabel="W / ell", ylabel="deformation energy per particle / e_bulk", title="fibres")
right.plot(R_continuum / ell, disk_energy, "s", color="C2", label="relaxed disk")
right.plot(R_continuum / ell, disk_continuum, "-", color="C3", label="continuum")
right.set(xlabel="R / ell", title="disks")
for ax in (left, right):
    ax.legend(frameon=False)
fig.tight_layout()

# %%
# The relaxed energies follow the continuum, and approach it as aggregates grow; the small
# differences come from the lattice (edges are not smooth on the scale of a particle).
print(f"widest fibre: relaxed {fibre_energy[-1]:.4f}, continuum {float(fibre_continuum[-1]):.4f} (per e_bulk)")
print(f"largest disk: relaxed {disk_energy[-1]:.4f}, continuum {float(disk_continuum[-1]):.4f} (per e_bulk)")
