"""Fig. 6: aggregation diagrams of random particles, one panel per group of boundary-layer
lengths. Each horizontal line is one particle (placed at its Poisson ratio nu, supplement
Eq. S25), coloured by the winning aggregate at each Gamma as in Fig. 3b, fibres and disks shaded
by their width W*/ell and radius R*/ell on Fig. 3's scale (type and width, as the paper says), out to where the bulk
takes over (dotted: the group's median Gamma_max); the Gamma axis is linear to 2 and logarithmic
beyond, where small-ell particles still bind. Dashed: the continuum's disk-fibre boundaries
(Fig. 3a, extended to nu < 0, where disks beat fibres outright), drawn only for the ell >= 1.5
group: the continuum is a theory of ell >> 1, and its bulk boundaries (Gamma = 1 for fibres) do
not describe random particles, whose bulk takes over at their own Gamma_max."""
import numpy as np
from matplotlib.colors import ListedColormap

from pyfrustrate import continuum, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


CONTINUUM_FROM_ELL = 1.5  # groups starting at or above it get the continuum overlay
LINEAR_UNTIL = 2.0  # the Gamma axis is linear up to here, logarithmic beyond (as the data grid)
LOG_WIDTH = 0.6  # axis length per e-fold of Gamma beyond LINEAR_UNTIL


def compress(G):
    G = np.asarray(G, float)
    return np.where(G <= LINEAR_UNTIL, G, LINEAR_UNTIL + LOG_WIDTH * np.log(np.maximum(G, LINEAR_UNTIL) / LINEAR_UNTIL))


def expand(X):
    X = np.asarray(X, float)
    return np.where(X <= LINEAR_UNTIL, X, LINEAR_UNTIL * np.exp((np.maximum(X, LINEAR_UNTIL) - LINEAR_UNTIL) / LOG_WIDTH))


def main(paths, edges, outputs, provenance=None):
    # Snakemake flattens the per-group lists of batch files: regroup them by name.
    group_paths = [[p for p in paths if f"/group{i}_" in str(p)] for i in range(len(edges) - 1)]
    line_nu = np.linspace(-0.99, 1.0, 400)
    lines = continuum.critical_line_tensions(line_nu)
    cmap = ListedColormap([plotting.PHASE_COLORS[p] for p in rp.PHASE_CODES])
    width_cm, height_cm = plotting.PAGE_WIDTH_CM, 7.3  # room for two-line titles under the legend
    fig = plotting.figure(width_cm, height_cm)
    panel_w, gap = 4.2, 0.4
    axes = [fig.add_axes([(1.45 + i * (panel_w + gap)) / width_cm, 1.1 / height_cm, panel_w / width_cm, 4.9 / height_cm])
            for i in range(len(group_paths))]
    for i, (ax, paths) in enumerate(zip(axes, group_paths)):
        parts = [load_npz(p) for p in paths]
        nu = np.concatenate([p["nu"] for p in parts])
        phase = np.concatenate([p["phase"] for p in parts])
        ell = np.concatenate([p["ell"] for p in parts])
        length = np.where(phase == rp.PHASE_CODES.index("fiber"), np.concatenate([p["width"] for p in parts]),
                          np.concatenate([p["radius"] for p in parts])) / ell[:, None]
        gamma_max = np.concatenate([p["Gamma_max"] for p in parts])
        G = parts[0]["Gamma"]
        order = np.argsort(nu)
        nu, phase, length = nu[order], phase[order], length[order]
        mid = 0.5 * (nu[1:] + nu[:-1])
        nu_edges = np.concatenate([[nu[0] - (mid[0] - nu[0]) if len(nu) > 1 else nu[0] - 0.01], mid,
                                   [nu[-1] + (nu[-1] - mid[-1]) if len(nu) > 1 else nu[-1] + 0.01]])
        G_mid = 0.5 * (G[1:] + G[:-1])
        G_edges = np.concatenate([[0], G_mid, [G[-1]]])
        ax.set_xscale("function", functions=(compress, expand))
        meshes = plotting.shade_phases(ax, G_edges, nu_edges, np.asarray(rp.PHASE_CODES)[phase], length,
                                       rasterized=True)
        if edges[i] >= CONTINUUM_FROM_ELL:
            for key in ("disk_fiber", "disk_fiber_upper"):
                ax.plot(getattr(lines, key), line_nu, "--", color="w", lw=1.4)
                ax.plot(getattr(lines, key), line_nu, "--", color="k", lw=0.7)
        median = float(np.median(gamma_max))
        ax.axvline(median, color="w", lw=1.0, ls=":")
        beyond = float(np.mean(gamma_max > G[-1]))
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        # The median in the title, not on the panel, where it would cover the phases.
        ax.set_title(rf"$\ell \in [{edges[i]:g}, {hi})$, {len(nu)} particles" "\n"
                     rf"median $\Gamma_\mathrm{{max}}$ {median:.2f}; {100 * beyond:.0f} % > {G[-1]:g}")  # every title on two lines: the panels align
        ax.set_xlim(0, G[-1])
        ax.set_xticks([0, 0.5, 1, 1.5, 2, 5, 10, 20, 50], ["0", "", "1", "", "2", "5", "10", "20", ""])  # 50 would touch the next panel's 0
        ax.set_ylim(-1, 1)
        ax.set_xlabel(plotting.LABELS["Gamma"])
        if i:
            ax.tick_params(labelleft=False)
        plotting.panel_label(ax, "abcdef"[i])
    axes[0].set_ylabel(r"Poisson ratio $\nu$ (pseudo-moduli)")
    plotting.phase_legend(axes[1], rp.PHASE_CODES, dashed_continuum=True, ncol=5, loc="upper center",
                          bbox_to_anchor=(0.5, (height_cm - 0.05 - 1.1) / 4.9))  # at the page's top
    plotting.size_colorbars(fig, meshes, (15.5, 1.1, 4.4), gap_cm=1.1)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.groups, snakemake.params.ell_groups,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
