"""Fig. 3b: phase diagram from the numerical comparison of the pre-made aggregates of Fig. 4a
at ell = 5, with the continuum boundaries of Fig. 3a overlaid. The fibre region is larger than
in the continuum; disk radii jump at the disk-bulk boundary; bulks with holes win only at very
small Gamma."""
from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def main(diagram_path, continuum_path, outputs):
    diagram = load_npz(diagram_path)
    fig = plotting.figure(12.0, 9.0)
    ax = fig.add_axes([0.1, 0.12, 0.66, 0.8])
    cbars = [fig.add_axes([0.8, 0.12, 0.025, 0.8]), fig.add_axes([0.9, 0.12, 0.025, 0.8])]
    plotting.draw_ansatz_diagram(fig, ax, diagram, load_npz(continuum_path), colorbar_axes=cbars)
    ax.text(0.02, 0.02, rf"$\ell = {float(diagram['ell']):g}$", transform=ax.transAxes, fontsize=9, color="w")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
