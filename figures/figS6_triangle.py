"""Fig. S6: triangular particles (supplement, "Triangular particles"; the design of panel (a) is
our reconstruction, docs/topics/triangle.md). (a) The particle: yellow and red node triangles (rest sides 1 +- eps)
and six coupling springs; a bound pair shares the nodes of its common edge. (b) Relaxed
aggregates, particles coloured by deformation energy. (c) In the bulk the sides of the yellow and
red triangles must match. (d) Ansatz diagram at ell = 2.5 with the continuum boundaries and Monte
Carlo snapshots (top row: sparse box, bottom row: dense box). (e) The catalogue of pre-made
aggregates."""
import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import Normalize

from pyfrustrate import ansatz, plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job
from pyfrustrate.montecarlo import clusters
from pyfrustrate.topology import site_positions

TILING = "triangle"
SPRING_COLORS = {"yellow": plotting.YELLOW, "red": plotting.RED_CORNER, "coupling": plotting.BLUE_SPRING}
CATALOGUE = [("single", "single particle"), ("disk_R1", "disk, $R$ = 1"), ("disk_R3", "disk, $R$ = 3"),
             ("fiber_cut0", "fibre, flat edges"), ("fiber_cut1", "fibre, one sawtooth edge"),
             ("fiber_cut2", "fibre, zig-zag edges"), ("bulk", "bulk"), ("holes_vacancy3", "holes (1 in 6)"),
             ("holes_vacancy4", "holes (1 in 8)"), ("holes_hexagonal", "holes (hexagonal)")]


def draw_triangles(ax, corners, energy=None, norm=None, linewidth=0.2):
    """Particles as their yellow triangles (slots 0-2), coloured by energy."""
    polys = PolyCollection(np.asarray(corners)[:, :3], edgecolors="0.25", linewidths=linewidth, cmap="magma", norm=norm)
    if energy is not None:
        polys.set_array(np.asarray(energy))
    else:
        polys.set_facecolor("0.85")
    ax.add_collection(polys)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.axis("off")
    return polys


def draw_springs(ax, corners, springs, kinds, linewidth=1.0, nodes=True, markersize=10):
    """Every spring of every particle, coloured by kind, and the nodes."""
    corners = np.asarray(corners)
    # Red on top of yellow and thinner, so that sides that coincide (the bulk) show both.
    for kind, z, width in (("coupling", 1, 1.0), ("yellow", 2, 1.6), ("red", 3, 0.7)):
        pairs = [(a, b) for (a, b), k in zip(springs, kinds) if k == kind]
        segments = [(c[a], c[b]) for c in corners for a, b in pairs]
        ax.add_collection(LineCollection(segments, colors=SPRING_COLORS[kind], linewidths=width * linewidth, zorder=z))
    if nodes:
        flat = corners.reshape(-1, 6, 2)
        ax.scatter(*flat[:, :3].reshape(-1, 2).T, s=markersize, color=plotting.YELLOW, edgecolor="k", lw=0.3, zorder=4)
        ax.scatter(*flat[:, 3:].reshape(-1, 2).T, s=markersize, color=plotting.RED_CORNER, edgecolor="k", lw=0.3, zorder=4)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.axis("off")


WIDTH_CM, HEIGHT_CM = plotting.PAGE_WIDTH_CM, 22.6
SNAPSHOT_CM, CATALOGUE_HALF_WINDOW = 2.2, 5.0
NOTE_CM = 0.6  # two lines of 6 pt text under a snapshot


def rect(left, bottom, w, h):
    """An axes rectangle from cm on the page."""
    return [left / WIDTH_CM, bottom / HEIGHT_CM, w / WIDTH_CM, h / HEIGHT_CM]


def letter(fig, ax, label, x_cm, top_cm):
    plotting.panel_label(ax, label, at_cm=(x_cm, top_cm))


def panel_particle(fig, d, top):
    springs, kinds = d["springs"], d["spring_kinds"]
    ax = fig.add_axes(rect(0.3, top - 3.6, 2.3, 2.9))
    draw_springs(ax, d["single_corners"], springs, kinds, linewidth=1.4, markersize=18)
    ax.set_title("one particle")
    letter(fig, ax, "a", 0.1, top)
    ax = fig.add_axes(rect(2.8, top - 3.6, 2.6, 2.9))
    draw_springs(ax, d["pair_corners"], springs, kinds, linewidth=1.0, markersize=12)
    ax.set_title("bound pair")
    ax.text(0.5, -0.04, f"{float(d['pair_per_particle']):.4f} bulk energy\nper particle", transform=ax.transAxes,
            ha="center", va="top", fontsize=6.5)


def panel_aggregates(fig, d, norm, top):
    ax = fig.add_axes(rect(6.0, top - 3.9, 2.9, 3.2))
    polys = draw_triangles(ax, d["disk_R3_corners"], d["disk_R3_energy"], norm)
    ax.set_title("disk, $R$ = 3")
    letter(fig, ax, "b", 5.8, top)
    ax = fig.add_axes(rect(9.1, top - 3.9, 3.0, 3.2))
    draw_triangles(ax, d["fiber_cut0_corners"], d["fiber_cut0_energy"], norm)
    ax.set_title("fibre (flat edges)")
    cax = fig.add_axes(rect(12.3, top - 3.7, 0.2, 2.8))
    fig.colorbar(polys, cax=cax)
    cax.set_ylabel(plotting.LABELS["energy"].replace(" per particle", "\nper particle"))  # two lines: 3 cm tall


def panel_bulk(fig, d, top):
    ax = fig.add_axes(rect(14.3, top - 3.7, 3.3, 3.0))
    corners = np.asarray(d["bulk_corners"])
    centre = corners.reshape(-1, 2).mean(axis=0)
    keep = np.linalg.norm(corners.mean(axis=1) - centre, axis=1) < 1.6
    draw_springs(ax, corners[keep], d["springs"], d["spring_kinds"], linewidth=1.0, markersize=8)
    ax.set_title("bulk: sides match")
    letter(fig, ax, "c", 14.0, top)


def panel_diagram(fig, diagram, continuum, runs, top):
    ax = fig.add_axes(rect(1.3, top - 6.0, 7.4, 5.0))
    meshes, phases = plotting.draw_ansatz_diagram(ax, diagram, continuum)
    plotting.phase_legend(ax, sorted(set(phases) | {"gas"}, key=list(plotting.PHASE_LABELS).index),
                          dashed_continuum=True, ncol=3, bbox_to_anchor=(0.7, 1.0))
    plotting.size_colorbars(fig, meshes, (9.4, top - 6.0, 4.3), gap_cm=1.15)
    gas = np.asarray(diagram["gas_Gamma"])
    ax.text(0.98, 0.03, rf"$\ell$ = {float(diagram['ell']):g}", transform=ax.transAxes, color="w", ha="right")
    inset = fig.add_axes(rect(12.2, top - 6.0, 3.6, 4.3))
    inset.semilogx(gas, diagram["nu"], color="k", lw=1.0)
    inset.fill_betweenx(diagram["nu"], 1e-5, gas, color=plotting.PHASE_COLORS["gas"])
    inset.set_xlim(1e-4, 1e-1)
    inset.set_ylim(0, 1)
    inset.set_xlabel(r"$\Gamma$ (logarithmic)")
    inset.set_ylabel(plotting.LABELS["nu"])
    inset.set_title("single particles win (grey)")
    G_max = float(np.max(diagram["Gamma"]))
    for k, r in enumerate(runs, start=1):
        point = (min(float(r["Gamma"]), G_max), float(r["nu"]))
        target = inset if float(r["Gamma"]) < 0.01 else ax
        target.plot(*point, "s", ms=5, mfc="w", mec="k", mew=0.7, zorder=6, clip_on=False)
        # On the side panel the number goes left of its symbol: the boundary runs just right of it.
        target.annotate(str(k), point, xytext=(4, 3) if target is ax else (-4, 3), textcoords="offset points",
                        fontsize=7, zorder=7, color="w" if target is ax else "k",
                        ha="left" if target is ax else "right")
    letter(fig, ax, "d", 0.1, top)


def panel_snapshots(fig, runs, finite, top):
    """Each run centred on its largest cluster, and under it (outside the drawing, so that it
    covers no cluster) its note: the final energy above the best single aggregate of as many
    triangles (Delta E), and that aggregate's width x length (gyration dimensions, particle
    spacings)."""
    cols = 4
    panel_w, panel_h = WIDTH_CM / cols, SNAPSHOT_CM
    for k, r in enumerate(runs, start=1):
        i, j = divmod(k - 1, cols)
        bottom = top - (i + 1) * (panel_h + 0.55)
        sub = fig.add_axes(rect(j * panel_w + 0.1, bottom + NOTE_CM, panel_w - 0.2, panel_h - NOTE_CM))
        box = int(r["box"])
        plotting.draw_snapshot(r["sites"], box, ax=sub, tiling=TILING)
        coords, _ = clusters(r["sites"], box, TILING)[0]
        coords = coords.copy()
        coords[:, :2] -= np.floor(coords[:, :2].mean(axis=0) / box).astype(int) * box
        xy = site_positions(coords, TILING)
        c = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
        aspect = (panel_h - NOTE_CM) / (panel_w - 0.2)
        extent = np.ptp(xy, axis=0)
        half = max(12.0, 0.5 * max(extent[0], extent[1] / aspect) + 2)
        sub.set_xlim(c[0] - half, c[0] + half)
        sub.set_ylim(c[1] - aspect * half, c[1] + aspect * half)
        sub.set_axis_on()
        sub.set_xticks([])
        sub.set_yticks([])
        for spine in sub.spines.values():
            spine.set_visible(True)
            spine.set_color("0.6")
            spine.set_linewidth(0.4)
        sub.set_title(rf"{k}: $\Gamma$ = {float(r['Gamma']):g}, $\nu$ = {float(r['nu']):g}", pad=2)
        prediction = plotting.matching_prediction(r, finite)
        if prediction is None:
            raise ValueError(f"finite_paths: no prediction for n = {int(r['n'])}, nu = {float(r['nu']):g}")
        shapes = ansatz.FiniteAggregates.from_arrays(prediction)
        best = int(shapes.best(float(r["g"])))
        sub.text(0.5, -0.03, rf"$\Delta E$ = {plotting.gap_to_best_single(r, finite):+.1f} $e_{{\rm bulk}}$" "\n"
                 f"best single: {shapes.width[best]:.1f} × {shapes.length[best]:.1f}", transform=sub.transAxes,
                 fontsize=6, ha="center", va="top")


def panel_catalogue(fig, d, norm, top):
    """The catalogue's aggregates on one length scale (CATALOGUE_HALF_WINDOW spacings each way)."""
    cols = 5
    panel_w = WIDTH_CM / cols
    for n, (name, title) in enumerate(CATALOGUE):
        i, j = divmod(n, cols)
        ax = fig.add_axes(rect(j * panel_w + 0.1, top - (i + 1) * 2.5 + 0.1, panel_w - 0.2, 1.65))
        draw_triangles(ax, d[f"{name}_corners"], d[f"{name}_energy"], norm, linewidth=0.15)
        centre = np.asarray(d[f"{name}_corners"]).reshape(-1, 2).mean(axis=0)
        aspect = 1.65 / (panel_w - 0.2)
        ax.set_xlim(centre[0] - CATALOGUE_HALF_WINDOW, centre[0] + CATALOGUE_HALF_WINDOW)
        ax.set_ylim(centre[1] - aspect * CATALOGUE_HALF_WINDOW, centre[1] + aspect * CATALOGUE_HALF_WINDOW)
        ax.set_title(f"{title}:\n{float(d[f'{name}_per_particle']):.2f}")
        if n == 0:
            letter(fig, ax, "e", 0.1, top + 0.1)


def main(shapes_path, diagram_path, continuum_path, snapshot_paths, finite_paths, outputs, provenance=None):
    d = load_npz(shapes_path)
    diagram = load_npz(diagram_path)
    runs = sorted((load_npz(p) for p in snapshot_paths), key=lambda r: (-float(r["nu"]), float(r["Gamma"])))
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)
    norm = Normalize(0, 1.1)
    top = HEIGHT_CM - 0.1
    panel_particle(fig, d, top)
    panel_aggregates(fig, d, norm, top)
    panel_bulk(fig, d, top)
    top -= 4.6
    panel_diagram(fig, diagram, load_npz(continuum_path), runs, top)
    top -= 6.9
    panel_snapshots(fig, runs, [load_npz(p) for p in finite_paths], top)
    top -= 2 * (SNAPSHOT_CM + 0.55) + 0.2
    panel_catalogue(fig, d, norm, top)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.shapes, snakemake.input.diagram, snakemake.input.continuum[0],  # noqa: F821
             snakemake.input.snapshots, snakemake.input.finite,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
