"""Fig. 6: aggregation diagrams of random particles, one panel per group of boundary-layer
lengths. Each horizontal line is one particle (placed at its Poisson ratio nu, supplement
Eq. S25), coloured by the winning aggregate at each Gamma as in Fig. 3b; dashed: the continuum
boundaries of Fig. 3a."""
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from pyfrustrate import plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to


def main(paths, continuum_path, edges, outputs):
    # Snakemake flattens the per-group lists of batch files: regroup them by name.
    group_paths = [[p for p in paths if f"/group{i}_" in str(p)] for i in range(len(edges) - 1)]
    cont = load_npz(continuum_path)
    cmap = ListedColormap([plotting.PHASE_COLORS[p] for p in rp.PHASE_CODES])
    fig = plotting.figure(17.8, 7.5)
    axes = fig.subplots(1, len(group_paths), sharey=True)
    for i, (ax, paths) in enumerate(zip(np.atleast_1d(axes), group_paths)):
        parts = [load_npz(p) for p in paths]
        nu = np.concatenate([p["nu"] for p in parts])
        phase = np.concatenate([p["phase"] for p in parts])
        G = parts[0]["Gamma"]
        order = np.argsort(nu)
        nu, phase = nu[order], phase[order]
        mid = 0.5 * (nu[1:] + nu[:-1])
        nu_edges = np.concatenate([[nu[0] - (mid[0] - nu[0]) if len(nu) > 1 else nu[0] - 0.01], mid,
                                   [nu[-1] + (nu[-1] - mid[-1]) if len(nu) > 1 else nu[-1] + 0.01]])
        G_mid = 0.5 * (G[1:] + G[:-1])
        G_edges = np.concatenate([[0], G_mid, [G[-1]]])
        ax.pcolormesh(G_edges, nu_edges, phase, cmap=cmap, vmin=-0.5, vmax=len(rp.PHASE_CODES) - 0.5,
                      rasterized=True)
        for key in ("fiber_bulk", "disk_bulk", "disk_fiber", "disk_fiber_upper"):
            ax.plot(cont[key], cont["line_nu"], "--", color="w", lw=1.4)
            ax.plot(cont[key], cont["line_nu"], "--", color="k", lw=0.7)
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        ax.set_title(rf"$\ell \in [{edges[i]:g}, {hi})$, {len(nu)} particles", fontsize=8)
        ax.set_xlim(0, G[-1])
        ax.set_ylim(-1, 1)
        ax.set_xlabel(r"line tension $\Gamma$")
    np.atleast_1d(axes)[0].set_ylabel(r"Poisson ratio $\nu$ (pseudo-moduli)")
    handles = [Patch(color=plotting.PHASE_COLORS[p], label=p.replace("_", " ").replace("fiber", "fibre"))
               for p in rp.PHASE_CODES]
    fig.legend(handles=handles, loc="upper center", ncol=4, frameon=False, fontsize=7, bbox_to_anchor=(0.5, 1.04))
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.groups, snakemake.input.continuum[0], snakemake.params.settings["ell_groups"],  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
