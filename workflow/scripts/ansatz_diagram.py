"""Numerical phase diagram (Fig. 3b, S1): at each (nu, Gamma) the candidate of lowest total
energy per particle wins; its aggregate kind and continuum size are recorded."""
import numpy as np

from pyfrustrate import Hexagon, ansatz
from pyfrustrate.io import load_npz, logging_to, save_npz

s = snakemake.params.settings  # noqa: F821
ell, nus = snakemake.params.ell, snakemake.params.nu  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    Gamma = np.linspace(0.0, s["Gamma_max"], s["Gamma_count"])
    phase, family, size, length = [], [], [], []
    for nu, path in zip(nus, snakemake.input):  # noqa: F821
        data = load_npz(path)
        table = ansatz.CatalogueEnergies.from_arrays(data)
        particle = Hexagon(float(data["k"]), float(data["kc"]), float(data["k_area"]), float(data["eps"]))
        # Straight cut-0 fibres are kept for comparison only: the free fibre takes its curvature.
        families = [f for f in np.unique(table.family) if f != "fiber_cut0_straight"]
        win = table.winners(ansatz.binding_energy_of(particle, ell, nu, Gamma), families=families)
        family.append(table.family[win])
        phase.append([ansatz.FAMILY_PHASE[f] for f in table.family[win]])
        size.append(table.size[win])
        length.append(table.length[win])
        kinds, counts = np.unique(phase[-1], return_counts=True)
        print(f"nu={nu:g}: " + ", ".join(f"{k} {c}" for k, c in zip(kinds, counts)))
    save_npz(snakemake.output[0], ell=ell, nu=np.array(nus), Gamma=Gamma, phase=np.array(phase),  # noqa: F821
             family=np.array(family), size=np.array(size), length=np.array(length))
