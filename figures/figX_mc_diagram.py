"""Beyond the paper, which calls it too costly: a Monte Carlo phase diagram at ell = 5. Each
marker is one annealing run, coloured by the kind of its largest final aggregate
(montecarlo.classify_aggregate), over the ansatz diagram of Fig. 3b (pale) and the continuum
boundaries (dashed).

A box of a few hundred particles holds neither a bulk nor a fibre wider than it is long, so the
runs are compared with the finite-size prediction too (ansatz.finite_aggregates): a band marks
where the best single aggregate of the same n is elongated, and a hollow marker a run that ended
more than NOT_ANNEALED_GAP bulk particle energies above that best aggregate (annealing stopped in
a worse state; the gaps are in the log of montecarlo_diagram). Runs below it found several
aggregates better than one."""
from matplotlib.lines import Line2D

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to

MARKERS = {"disk": "o", "fiber": "s", "bulk": "D", "bulk_with_holes": "^", "gas": "x"}
#: Final energy above the best single aggregate (bulk particle energies) from which a run
#: counts as not annealed. Paper-scale runs ending in one aggregate of all n particles ended
#: 0-12 above it (a Monte Carlo aggregate is not exactly one of the catalogue's stadium shapes).
NOT_ANNEALED_GAP = 15.0


def draw_elongated_bands(ax, mc):
    """A stripe along each nu row over the Gamma where the best single aggregate is elongated."""
    Gamma = mc["finite_Gamma"]
    for nu, elongated in zip(mc["finite_nu"], mc["finite_elongated"]):
        edges = [i for i in range(1, len(Gamma)) if elongated[i] != elongated[i - 1]]
        starts = ([0] if elongated[0] else []) + [i for i in edges if elongated[i]]
        stops = [i for i in edges if not elongated[i]] + ([len(Gamma)] if elongated[-1] else [])
        for a, b in zip(starts, stops):
            ax.plot([Gamma[a], Gamma[b - 1]], [nu, nu], color=plotting.PHASE_COLORS["fiber"], lw=7, alpha=0.45,
                    solid_capstyle="butt", zorder=5)


def main(mc_path, diagram_path, continuum_path, outputs):
    mc = load_npz(mc_path)
    n = int(mc["n"][0])
    fig = plotting.figure(17.8, 11.0)
    ax = fig.add_axes([0.07, 0.12, 0.68, 0.74])
    plotting.draw_ansatz_diagram(fig, ax, load_npz(diagram_path), load_npz(continuum_path))
    for mesh in ax.collections:
        mesh.set_alpha(0.35)
    draw_elongated_bands(ax, mc)
    for nu, G, kind, size, gap in zip(mc["nu"], mc["Gamma"], mc["kind"], mc["size"], mc["gap"]):
        color = plotting.PHASE_COLORS.get(str(kind), "0.5")
        stuck = gap > NOT_ANNEALED_GAP
        ax.plot(G, nu, MARKERS[str(kind)], ms=8, mfc="w" if stuck else color, mec=color if stuck else "k",
                mew=1.4 if stuck else 0.8, zorder=6)
        ax.annotate(f"{size}", (G, nu), xytext=(5, -9), textcoords="offset points", fontsize=5.5, zorder=7)
    handles = [Line2D([], [], marker=m, ls="", mfc=plotting.PHASE_COLORS.get(k, "0.5"), mec="k", label=k.replace("_", " "))
               for k, m in MARKERS.items()]
    handles.append(Line2D([], [], marker="o", ls="", mfc="w", mec="0.3", mew=1.4,
                          label=f"ended > {NOT_ANNEALED_GAP:g} bulk\nparticle energies above\nthe best single aggregate"))
    handles.append(Line2D([], [], color=plotting.PHASE_COLORS["fiber"], lw=7, alpha=0.45,
                          label=f"best single aggregate\nof {n} is elongated"))
    fig.legend(handles=handles, loc="center right", title="Monte Carlo\n(largest aggregate)", fontsize=6.5,
               title_fontsize=7, frameon=False, labelspacing=0.9)
    fig.text(0.07, -0.1, f"Annealing runs of {n} particles; numbers: size of the largest aggregate. A box this small\n"
             "holds neither a bulk nor a fibre wider than it is long: compare the runs with the band (what the\n"
             "best single aggregate of the same particles is), not only with the infinite-system diagram.",
             fontsize=6)
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.montecarlo[0], snakemake.input.diagram, snakemake.input.continuum[0],  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
