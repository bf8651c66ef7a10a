"""Optimal fibre width W* (nu = fiber_nu) and disk radius R* (nu = disk_nu) against Gamma for
several ell (Fig. 4b): the best member of each family, in lattice units and over ell, with the
continuum prediction."""
import numpy as np

from pyfrustrate import Hexagon, ansatz, continuum
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    Gamma = np.linspace(0.0, s["size_Gamma_max"], s["size_Gamma_count"] + 1)[1:]
    out = {"Gamma": Gamma, "ells": np.array(s["size_ells"], float)}
    kinds = {"fiber": ("fiber_nu", ["fiber_cut0", "fiber_cut1", "fiber_cut2"], continuum.optimal_width),
             "disk": ("disk_nu", ["single", "disk"], continuum.optimal_radius)}
    for kind, (nu_key, families, theory) in kinds.items():
        nu = float(s[nu_key])
        sizes, lengths, at_cap = [], [], []
        for path in snakemake.input[kind]:  # noqa: F821
            data = load_npz(path)
            table = ansatz.CatalogueEnergies.from_arrays(data)
            particle = Hexagon(float(data["k"]), float(data["kc"]), float(data["k_area"]), float(data["eps"]))
            ell = float(data["ell"])
            win = table.winners(ansatz.binding_energy_of(particle, ell, nu, Gamma), families=families)
            sizes.append(table.size[win])
            lengths.append(table.length[win])
            at_cap.append(table.size[win] == table.size[np.isin(table.family, families)].max())
            print(f"{kind} ell={ell:g}: sizes {sizes[-1][::10]}, at catalogue cap {int(at_cap[-1].sum())}")
        out[f"{kind}_nu"] = nu
        out[f"{kind}_size"] = np.array(sizes)
        out[f"{kind}_length"] = np.array(lengths)
        out[f"{kind}_at_cap"] = np.array(at_cap)
        out[f"{kind}_theory"] = theory(nu, Gamma)
    save_npz(snakemake.output[0], provenance=for_job(snakemake), **out)  # noqa: F821
