"""Continuum phase diagram (Fig. 3a): lowest energy per unit area among bulk, fibre of optimal
width and disk of optimal radius (main text Eqs. 8, 10, 13) on a (Gamma, nu) grid."""
import numpy as np

from pyfrustrate import continuum
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    nu = np.linspace(0.0, 1.0, s["nu_count"])
    Gamma = np.linspace(0.0, s["Gamma_max"], s["Gamma_count"])
    NU, G = np.meshgrid(nu, Gamma, indexing="ij")
    phase = continuum.phase(NU, G)
    width = continuum.optimal_width(NU, G)
    radius = continuum.optimal_radius(NU, G)
    fine_nu = np.linspace(0.0, 1.0, 4 * s["nu_count"] + 1)
    lines = continuum.critical_line_tensions(fine_nu)
    for name in ("bulk", "fiber", "disk"):
        print(f"{name}: {np.mean(phase == name):.3f} of the grid")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), nu=nu, Gamma=Gamma, phase=phase.astype(str), width=width, radius=radius,  # noqa: F821
             line_nu=fine_nu, fiber_bulk=lines.fiber_bulk, disk_bulk=lines.disk_bulk, disk_fiber=lines.disk_fiber,
             disk_fiber_upper=lines.disk_fiber_upper)
