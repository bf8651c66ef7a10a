"""Fig. S1: the phase diagram of Fig. 3b at the smaller ell = 2.5: disks give way to bulks
with holes, with no dramatic change of the fibre and bulk regions (supplement S3). Shading: the
winning fibre's W*/ell and disk's R*/ell on Fig. 3's scales; dashed: the continuum boundaries of
Fig. 3a, each only where it is a boundary."""
from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job

WIDTH_CM, HEIGHT_CM = plotting.COLUMN_WIDTH_CM, 7.4


def main(diagram_path, continuum_path, outputs, provenance=None):
    diagram = load_npz(diagram_path)
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)
    ax = fig.add_axes([1.1 / WIDTH_CM, 1.0 / HEIGHT_CM, 4.8 / WIDTH_CM, 5.0 / HEIGHT_CM])
    meshes, phases = plotting.draw_ansatz_diagram(ax, diagram, load_npz(continuum_path))
    plotting.phase_legend(ax, phases, dashed_continuum=True, ncol=3, bbox_to_anchor=(0.6, 1.0))
    plotting.size_colorbars(fig, meshes, (6.3, 1.0, 4.5), gap_cm=1.2)
    ax.text(0.97, 0.04, rf"$\ell$ = {float(diagram['ell']):g}", transform=ax.transAxes, color="w", ha="right")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
