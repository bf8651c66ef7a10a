"""Fig. 6: aggregation diagrams of random particles, one panel per group of boundary-layer
lengths. Each horizontal line is one particle (placed at its Poisson ratio nu, supplement
Eq. S25), coloured by the winning aggregate at each Gamma as in Fig. 3b, out to where the bulk
takes over (dotted: the group's median Gamma_max); the Gamma axis is linear to 2 and logarithmic
beyond, where small-ell particles still bind. Dashed: the continuum's disk-fibre boundaries
(Fig. 3a, extended to nu < 0, where disks beat fibres outright), drawn only for the ell >= 1.5
group: the continuum is a theory of ell >> 1, and its bulk boundaries (Gamma = 1 for fibres) do
not describe random particles, whose bulk takes over at their own Gamma_max."""
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from pyfrustrate import continuum, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to


CONTINUUM_FROM_ELL = 1.5  # groups starting at or above it get the continuum overlay
LINEAR_UNTIL = 2.0  # the Gamma axis is linear up to here, logarithmic beyond (as the data grid)
LOG_WIDTH = 0.6  # axis length per e-fold of Gamma beyond LINEAR_UNTIL


def compress(G):
    G = np.asarray(G, float)
    return np.where(G <= LINEAR_UNTIL, G, LINEAR_UNTIL + LOG_WIDTH * np.log(np.maximum(G, LINEAR_UNTIL) / LINEAR_UNTIL))


def expand(X):
    X = np.asarray(X, float)
    return np.where(X <= LINEAR_UNTIL, X, LINEAR_UNTIL * np.exp((np.maximum(X, LINEAR_UNTIL) - LINEAR_UNTIL) / LOG_WIDTH))


def main(paths, edges, outputs):
    # Snakemake flattens the per-group lists of batch files: regroup them by name.
    group_paths = [[p for p in paths if f"/group{i}_" in str(p)] for i in range(len(edges) - 1)]
    line_nu = np.linspace(-0.99, 1.0, 400)
    lines = continuum.critical_line_tensions(line_nu)
    cmap = ListedColormap([plotting.PHASE_COLORS[p] for p in rp.PHASE_CODES])
    fig = plotting.figure(17.8, 7.5)
    axes = fig.subplots(1, len(group_paths), sharey=True)
    for i, (ax, paths) in enumerate(zip(np.atleast_1d(axes), group_paths)):
        parts = [load_npz(p) for p in paths]
        nu = np.concatenate([p["nu"] for p in parts])
        phase = np.concatenate([p["phase"] for p in parts])
        gamma_max = np.concatenate([p["Gamma_max"] for p in parts])
        G = parts[0]["Gamma"]
        order = np.argsort(nu)
        nu, phase = nu[order], phase[order]
        mid = 0.5 * (nu[1:] + nu[:-1])
        nu_edges = np.concatenate([[nu[0] - (mid[0] - nu[0]) if len(nu) > 1 else nu[0] - 0.01], mid,
                                   [nu[-1] + (nu[-1] - mid[-1]) if len(nu) > 1 else nu[-1] + 0.01]])
        G_mid = 0.5 * (G[1:] + G[:-1])
        G_edges = np.concatenate([[0], G_mid, [G[-1]]])
        ax.set_xscale("function", functions=(compress, expand))
        ax.pcolormesh(G_edges, nu_edges, phase, cmap=cmap, vmin=-0.5, vmax=len(rp.PHASE_CODES) - 0.5,
                      rasterized=True)
        if edges[i] >= CONTINUUM_FROM_ELL:
            for key in ("disk_fiber", "disk_fiber_upper"):
                ax.plot(getattr(lines, key), line_nu, "--", color="w", lw=1.4)
                ax.plot(getattr(lines, key), line_nu, "--", color="k", lw=0.7)
        median = float(np.median(gamma_max))
        ax.axvline(median, color="w", lw=1.0, ls=":")
        ax.text(median, 0.02, rf"median $\Gamma_\mathrm{{max}}$ = {median:.2f}", fontsize=6, color="w",
                va="bottom", ha="center", transform=ax.get_xaxis_transform(),
                bbox=dict(boxstyle="round,pad=0.2", fc="0.2", ec="none", alpha=0.8))
        beyond = float(np.mean(gamma_max > G[-1]))
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        ax.set_title(rf"$\ell \in [{edges[i]:g}, {hi})$, {len(nu)} particles"
                     + (f"\n({100 * beyond:.0f} % bind beyond the axis)" if beyond > 0 else ""), fontsize=8)
        ax.set_xlim(0, G[-1])
        ax.set_xticks([0, 0.5, 1, 1.5, 2, 5, 10, 20, 50], ["0", "", "1", "", "2", "5", "10", "20", "50"])
        ax.set_ylim(-1, 1)
        ax.set_xlabel(r"line tension $\Gamma$" + (" (logarithmic beyond 2)" if i == 1 else ""))
    np.atleast_1d(axes)[0].set_ylabel(r"Poisson ratio $\nu$ (pseudo-moduli)")
    handles = [Patch(color=plotting.PHASE_COLORS[p], label=p.replace("_", " ").replace("fiber", "fibre"))
               for p in rp.PHASE_CODES]
    fig.legend(handles=handles, loc="upper center", ncol=4, frameon=False, fontsize=7, bbox_to_anchor=(0.5, 1.04))
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.groups, snakemake.params.ell_groups,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
