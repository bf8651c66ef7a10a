"""Beyond the paper, which calls it too costly: a Monte Carlo phase diagram at ell = 5. Each
marker is one annealing run, coloured by the kind of its largest final aggregate
(montecarlo.classify_aggregate), over the ansatz diagram of Fig. 3b (pale) and the continuum
boundaries (dashed). With a few hundred particles, aggregates larger than the box allows
(bulks, fibres wider than they are long) read as disks."""
from matplotlib.lines import Line2D

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to

MARKERS = {"disk": "o", "fiber": "s", "bulk": "D", "bulk_with_holes": "^", "gas": "x"}


def main(mc_path, diagram_path, continuum_path, outputs):
    mc = load_npz(mc_path)
    fig = plotting.figure(12.0, 9.0)
    ax = fig.add_axes([0.1, 0.12, 0.62, 0.72])
    meshes = plotting.draw_ansatz_diagram(fig, ax, load_npz(diagram_path), load_npz(continuum_path))
    for mesh in ax.collections:
        mesh.set_alpha(0.35)
    del meshes
    for nu, G, kind, size, n in zip(mc["nu"], mc["Gamma"], mc["kind"], mc["size"], mc["n"]):
        color = plotting.PHASE_COLORS.get(str(kind), "0.5")
        ax.plot(G, nu, MARKERS[str(kind)], ms=9, mfc=color, mec="k", mew=0.8, zorder=6)
        ax.annotate(f"{size}", (G, nu), xytext=(6, -9), textcoords="offset points", fontsize=5.5, zorder=7)
    handles = [Line2D([], [], marker=m, ls="", mfc=plotting.PHASE_COLORS.get(k, "0.5"), mec="k", label=k.replace("_", " "))
               for k, m in MARKERS.items()]
    fig.legend(handles=handles, loc="center right", title="Monte Carlo\n(largest aggregate)", fontsize=7,
               title_fontsize=7, frameon=False)
    fig.text(0.1, -0.14, f"annealing runs of {int(mc['n'][0])} particles (numbers: size of the largest aggregate). "
             "\nA box this small cannot tell a bulk, or a fibre wider than it is long,\n"
             "from a compact aggregate: above Gamma ~ 0.8 every finite aggregate reads as a disk.", fontsize=6)
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.montecarlo[0], snakemake.input.diagram, snakemake.input.continuum[0],  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
