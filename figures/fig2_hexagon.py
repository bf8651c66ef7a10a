"""Fig. 2: the 2D particle model. (a) One particle at rest with its springs (mismatch
exaggerated): yellow and red triangles, blue connecting sides. (b) A small relaxed aggregate,
mismatch exaggerated: regular (bulk-like) hexagons inside, particles near the edge relaxing
towards their ill-fitting rest shape. (c) A relaxed hexagonal disk and (d) a relaxed fibre,
several ell across, each particle coloured by its deformation energy over the bulk value:
bulk-like centres, a cheaper shallow-bulk layer about ell inside the edge, and edges back near
the bulk value (where the stretched connecting springs carry the energy)."""
from matplotlib.colors import Normalize

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


WIDTH_CM, HEIGHT_CM = plotting.PAGE_WIDTH_CM, 6.0


def note(ax, text):
    """A short line under a drawing: what it is drawn at."""
    ax.text(0.5, -0.02, text, transform=ax.transAxes, ha="center", va="top")


def main(data_path, outputs, provenance=None):
    d = load_npz(data_path)
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)
    norm = Normalize(0.3, 1.1)
    cmap = "magma"
    eps = float(d["drawing_eps"])

    def rect(left, bottom, w, h):
        return [left / WIDTH_CM, bottom / HEIGHT_CM, w / WIDTH_CM, h / HEIGHT_CM]

    ax = fig.add_axes(rect(0.3, 1.2, 2.4, 3.6))
    plotting.draw_particle_springs(ax, d["rest_corners"])
    note(ax, rf"at rest, $\epsilon$ = {eps:g}")
    ax.axis("off")
    plotting.panel_label(ax, "a", at_cm=(0.1, HEIGHT_CM - 0.15))

    ax = fig.add_axes(rect(3.0, 0.6, 4.0, 4.9))
    plotting.draw_particle_springs(ax, d["small_corners"], linewidth=0.7, markersize=3)
    note(ax, rf"relaxed, $\epsilon$ = {eps:g}, $\ell$ = {float(d['drawing_ell']):g}")
    ax.axis("off")
    plotting.panel_label(ax, "b", at_cm=(3.0, HEIGHT_CM - 0.15))

    ax = fig.add_axes(rect(7.4, 0.6, 4.6, 4.9))
    plotting.draw_hexagons(ax, d["disk_corners"], d["disk_energy"], cmap=cmap, norm=norm, linewidth=0.1)
    note(ax, f"disk: mean {float(d['disk_mean']):.2f}")
    ax.axis("off")
    plotting.panel_label(ax, "c", at_cm=(7.4, HEIGHT_CM - 0.15))

    ax = fig.add_axes(rect(12.2, 0.6, 3.6, 4.9))
    polys = plotting.draw_hexagons(ax, d["fiber_corners"], d["fiber_energy"], cmap=cmap, norm=norm, linewidth=0.1)
    note(ax, f"fibre: mean {float(d['fiber_mean']):.2f}")
    ax.axis("off")
    plotting.panel_label(ax, "d", at_cm=(12.2, HEIGHT_CM - 0.15))

    cax = fig.add_axes(rect(16.1, 1.0, 0.25, 4.0))
    fig.colorbar(polys, cax=cax, extend="both")
    cax.set_ylabel(plotting.LABELS["energy"])
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
