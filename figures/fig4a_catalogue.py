"""Fig. 4a: the catalogue of pre-made aggregates, drawn from relaxed shapes (mismatch
exaggerated, particles coloured by deformation energy over the bulk value): bulks with holes,
the three fibre cuts (cut 0 is left-right asymmetric and curves), hexagonal disks including the
single particle, and the bulk."""
from matplotlib.colors import Normalize

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to

PANELS = [
    ("holes_honeycomb", "bulk with holes\n(honeycomb: zero energy)"), ("holes_kagome", "bulk with holes\n(kagome)"),
    ("holes_sqrt7", r"bulk with holes ($\sqrt{7}$)"), ("fiber_cut0", "fibre, cut 0\n(asymmetric, curves)"),
    ("fiber_cut1", "fibre, cut 1\n(symmetric)"), ("fiber_cut2", "fibre, cut 2\n(stepped edges)"),
    ("single", "single particle"), ("disk_R1", "disk R = 1"), ("disk_R3", "disk R = 3"), ("bulk", "bulk"),
]


def main(data_path, outputs):
    d = load_npz(data_path)
    fig = plotting.figure(17.8, 8.5)
    norm = Normalize(0, 1.1)
    for n, (name, title) in enumerate(PANELS):
        ax = fig.add_subplot(2, 5, n + 1)
        polys = plotting.draw_hexagons(ax, d[f"{name}_corners"], d[f"{name}_energy"], cmap="magma", norm=norm,
                                       linewidth=0.2)
        ax.set_title(title, fontsize=7)
        ax.axis("off")
    cax = fig.add_axes([0.93, 0.15, 0.012, 0.7])
    fig.colorbar(polys, cax=cax, label="particle energy / bulk")
    fig.text(0.5, 0.01, rf"relaxed at $\ell={float(d['ell']):g}$, $\nu={float(d['nu']):g}$, "
             rf"$\epsilon={float(d['eps']):g}$ (exaggerated to show the shapes)", ha="center", fontsize=7)
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
