"""Numerical phase diagram (Fig. 3b, S1): at each (nu, Gamma) the candidate of lowest total
energy per particle wins; its aggregate kind and continuum size are recorded."""
import numpy as np

from pyfrustrate import ansatz
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.particles import particle_class

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
ell, nus = snakemake.params.ell, snakemake.params.nu  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    Gamma = np.linspace(0.0, s["Gamma_max"], s["Gamma_count"])
    phase, family, size, length, gas_Gamma = [], [], [], [], []
    for nu, path in zip(nus, snakemake.input):  # noqa: F821
        data = load_npz(path)
        table = ansatz.CatalogueEnergies.from_arrays(data)
        tiling = str(data["tiling"]) if "tiling" in data else "hexagon"
        particle = particle_class(tiling)(float(data["k"]), float(data["kc"]), float(data["k_area"]), float(data["eps"]))
        # Straight cut-0 fibres are kept for comparison only: the free fibre takes its curvature.
        families = [f for f in np.unique(table.family) if f != "fiber_cut0_straight"]
        g = ansatz.binding_energy_of(particle, ell, nu, Gamma)
        win = table.winners(g, families=families)
        family.append(table.family[win])
        phase.append([ansatz.winning_phase(f, gv) for f, gv in zip(table.family[win], g)])
        size.append(table.size[win])
        length.append(table.length[win])
        # Below this line tension no aggregate pays for its deformation: single particles win
        # (exact: every total energy is linear in g; zero for hexagons, whose honeycomb bulk with
        # holes binds at no cost).
        bound = table.bonds > 0
        gas_Gamma.append(float(np.min(table.deformation[bound] / table.bonds[bound]))
                         / float(ansatz.binding_energy_of(particle, ell, nu, 1.0)))
        kinds, counts = np.unique(phase[-1], return_counts=True)
        print(f"nu={nu:g}: " + ", ".join(f"{k} {c}" for k, c in zip(kinds, counts)))
    save_npz(snakemake.output[0], provenance=for_job(snakemake), ell=ell, nu=np.array(nus), Gamma=Gamma, phase=np.array(phase),  # noqa: F821
             family=np.array(family), size=np.array(size), length=np.array(length), gas_Gamma=np.array(gas_Gamma))
