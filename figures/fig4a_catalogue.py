"""Fig. 4a: the catalogue of pre-made aggregates, drawn from relaxed shapes on one length scale
(mismatch exaggerated, particles coloured by deformation energy over the bulk value): bulks with
holes, the three fibre cuts, hexagonal disks including the single particle, and the bulk with
white lines along the three cuts that make the fibres. Under each curved fibre, its radius of
curvature measured on the drawing (a circle fitted to its particle centres)."""
import numpy as np
from matplotlib.colors import Normalize
from matplotlib.patheffects import withStroke

from pyfrustrate import plotting, topology
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job

PANELS = [
    ("holes_honeycomb", "bulk with holes\n(honeycomb)"), ("holes_kagome", "bulk with holes\n(kagome)"),
    ("holes_sqrt7", "bulk with holes\n" r"($\sqrt{7}$ pattern)"), ("fiber_cut0", "fibre, cut 0\n(flat edges)"),
    ("fiber_cut1", "fibre, cut 1\n(zig-zag edges)"), ("fiber_cut2", "fibre, cut 2\n(stepped edges)"),
    ("single", "single particle"), ("disk_R1", "disk, $R$ = 1"), ("disk_R3", "disk, $R$ = 3"), ("bulk", "bulk"),
]
WIDTH_CM, HEIGHT_CM, COLS = plotting.PAGE_WIDTH_CM, 7.6, 5
PANEL_CM, HALF_WINDOW = 2.95, 7.0  # every panel shows 2 x HALF_WINDOW particle spacings across
# Panel heights of the two rows (cm), on the one length scale: the second row's drawings (the
# single particle, small disks, the curled fibre's lowest part) need less height than the first's.
ROW_CM = (2.95, 2.3)


def period_centres(corners, energy):
    """Centre of each repeated period of a drawn fibre: the drawing repeats one relaxed cell, so
    the per-particle energies repeat with the cell's particle count."""
    energy = np.asarray(energy)
    cell = next(p for p in range(1, len(energy) + 1)
                if len(energy) % p == 0 and np.allclose(energy[p:], energy[:-p], rtol=1e-9, atol=1e-12))
    return np.asarray(corners).mean(axis=1).reshape(-1, cell, 2).mean(axis=1)


def curvature_radius(corners, energy) -> float:
    """Radius of the circle through the centres of a drawn fibre's periods (algebraic
    least-squares fit), in particle spacings; infinite when they lie on a line (a bend of less
    than 0.05 spacings over the drawn length)."""
    xy = period_centres(corners, energy)
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    b = (xy ** 2).sum(axis=1)
    (cx, cy, c), *_ = np.linalg.lstsq(A, b, rcond=None)
    radius = float(np.sqrt(c + cx ** 2 + cy ** 2))
    length = np.linalg.norm(xy[-1] - xy[0])
    sagitta = radius - np.sqrt(max(radius ** 2 - (length / 2) ** 2, 0.0))
    return radius if sagitta > 0.05 else np.inf


def draw_cut_lines(ax, centre):
    """White lines through the bulk along the axis of each fibre cut, numbered."""
    for cut in (0, 1, 2):
        direction = topology.cell_positions([topology.fiber_axis(cut)])[0]
        direction /= np.linalg.norm(direction)
        ends = centre + np.outer([-0.55 * HALF_WINDOW, 0.55 * HALF_WINDOW], direction)
        ax.plot(*ends.T, color="w", lw=1.4, zorder=5)
        # Cut 0's number at the left end of its line, the others at the right: cuts 0 and 2 are
        # only 19 degrees apart, and their numbers at one end would touch.
        label = centre + (-0.68 if cut == 0 else 0.68) * HALF_WINDOW * direction
        ax.text(*label, str(cut), color="k", fontsize=7, fontweight="bold", ha="center", va="center", zorder=6,
                path_effects=[withStroke(linewidth=2.0, foreground="w")], gid=plotting.OVER_PARTICLES)


def main(data_path, outputs, provenance=None):
    d = load_npz(data_path)
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)
    norm = Normalize(0, 1.1)
    for n, (name, title) in enumerate(PANELS):
        i, j = divmod(n, COLS)
        left, bottom = 0.15 + j * (PANEL_CM + 0.2), HEIGHT_CM - 1.3 - sum(ROW_CM[:i + 1]) - i * 0.9
        ax = fig.add_axes([left / WIDTH_CM, bottom / HEIGHT_CM, PANEL_CM / WIDTH_CM, ROW_CM[i] / HEIGHT_CM])
        half_height = HALF_WINDOW * ROW_CM[i] / PANEL_CM
        corners = d[f"{name}_corners"]
        polys = plotting.draw_hexagons(ax, corners, d[f"{name}_energy"], cmap="magma", norm=norm, linewidth=0.2)
        centre = np.asarray(corners).reshape(-1, 2).mean(axis=0)
        if name.startswith("fiber"):
            periods = period_centres(corners, d[f"{name}_energy"])
            centre = periods[len(periods) // 2]  # a curved fibre's mean lies off the fibre
            radius = curvature_radius(corners, d[f"{name}_energy"])
            # Just under the drawn fibre (a curled one ends high in its window), inside the window.
            drawn = np.asarray(corners)
            shown = np.abs(drawn.mean(axis=1) - centre).max(axis=1) < HALF_WINDOW  # inside the window
            lowest = max(drawn[shown][:, :, 1].min(), centre[1] - half_height)
            ax.text(centre[0], lowest - 0.3, "straight" if np.isinf(radius) else f"radius of curvature {radius:.0f}",
                    ha="center", va="top", fontsize=6, clip_on=False)
        if name == "bulk":
            draw_cut_lines(ax, centre)
        ax.set_xlim(centre[0] - HALF_WINDOW, centre[0] + HALF_WINDOW)
        ax.set_ylim(centre[1] - half_height, centre[1] + half_height)
        ax.set_title(title, pad=4)  # clear of a fibre that fills its window
        ax.axis("off")
    plotting.panel_label(ax, "a", at_cm=(0.1, HEIGHT_CM - 0.1))
    cax = fig.add_axes([16.0 / WIDTH_CM, 1.0 / HEIGHT_CM, 0.22 / WIDTH_CM, 5.0 / HEIGHT_CM])
    fig.colorbar(polys, cax=cax, extend="max")
    cax.set_ylabel(plotting.LABELS["energy"])
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
