"""Fig. S1: the phase diagram of Fig. 3b at the smaller ell = 2.5: disks give way to bulks
with holes, with no dramatic change of the fibre and bulk regions (supplement S3). Shading: the winning
fibre's W*/ell and disk's R*/ell (colour bars); dashed: the continuum boundaries of Fig. 3a,
each only where it is a boundary."""
from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def main(diagram_path, continuum_path, outputs):
    diagram = load_npz(diagram_path)
    fig = plotting.figure(12.0, 9.0)
    ax = fig.add_axes([0.1, 0.12, 0.6, 0.8])
    meshes = plotting.draw_ansatz_diagram(fig, ax, diagram, load_npz(continuum_path))
    plotting.size_colorbars(fig, meshes, left=0.74, bottom=0.12, height=0.8)
    ax.text(0.02, 0.02, rf"$\ell = {float(diagram['ell']):g}$", transform=ax.transAxes, fontsize=9, color="w")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
