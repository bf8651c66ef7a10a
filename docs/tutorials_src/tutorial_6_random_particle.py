"""
One random particle: its boundary-layer length three ways
=========================================================

A random-elasticity particle (main text Eq. 14) has a random 9 x 9 elasticity matrix ``M`` over
nine corner distances, drawn by the supplement's procedure: ``(seed, index)`` determines it.
Its boundary-layer length ``ell`` has no closed form (see :doc:`../topics/boundary_layer`):

* ``p.boundary_layer_length``: the exact slowest decaying mode of the half-plane, from the
  layer-to-layer transfer problem (the package's ``ell``);
* :func:`pyfrustrate.random_particles.fitted_boundary_layer_length`: the paper's protocol, a
  log-linear fit of a relaxed strip's excess energy against the distance from its edge;
* ``p.moduli["ell_pred"]``: the supplement's predictor from the pseudo-moduli.
"""

import matplotlib.pyplot as plt
import numpy as np

from pyfrustrate import random_particles as rp

p = rp.RandomHexagon.draw(seed=2025, index=17, eps=1e-3)
ell_exact = p.boundary_layer_length
ell_fit = rp.fitted_boundary_layer_length(p)
ell_pred = float(p.moduli["ell_pred"])
print(f"ell (exact slowest mode) = {ell_exact:.3f}")
print(f"ell (the paper's strip fit) = {ell_fit:.3f}")
print(f"ell_pred (pseudo-moduli)  = {ell_pred:.3f}; nu = {float(p.moduli['nu']):.3f}")

# %%
# The strip's edge profile
# ------------------------
# ``edge_energy_profile`` relaxes a wide strip and returns, row by row, the distance from the
# edge (lattice spacings) and the excess energy per particle over the bulk. Far from the edge it
# decays as ``exp(-d / ell)``.

distance, excess = rp.edge_energy_profile(p, width=80)
near = distance <= 12 * ell_exact
fig, ax = plt.subplots(figsize=(5, 3.6))
ax.semilogy(distance[near], np.abs(excess[near]), "o", ms=3, label="relaxed strip, |excess| per particle")
anchor = np.searchsorted(distance, 3 * ell_exact)
for ell, style, name in ((ell_exact, "-", "exact ell"), (ell_pred, "--", "ell_pred")):
    ax.semilogy(distance[near], abs(excess[anchor]) * np.exp(-(distance[near] - distance[anchor]) / ell), style,
                label=f"exp(-d / {name}), {name} = {ell:.2f}")
ax.set(xlabel="distance from the edge (lattice spacings)", ylabel="excess energy per particle")
ax.legend(frameon=False, fontsize=8)
fig.tight_layout()
