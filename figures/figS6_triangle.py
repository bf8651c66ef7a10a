"""Fig. S6: triangular particles (supplement, "Triangular particles"; the design of panel (a) is
our reconstruction, README). (a) The particle: yellow and red node triangles (rest sides 1 +- eps)
and six coupling springs; a bound pair shares the nodes of its common edge. (b) Relaxed
aggregates, particles coloured by deformation energy. (c) In the bulk the sides of the yellow and
red triangles must match. (d) Ansatz diagram at ell = 2.5 with the continuum boundaries and Monte
Carlo snapshots (top row: sparse box, bottom row: dense box). (e) The catalogue of pre-made
aggregates."""
import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import Normalize

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.montecarlo import clusters, draw_snapshot
from pyfrustrate.topology import site_positions

TILING = "triangle"
SPRING_COLORS = {"yellow": plotting.YELLOW, "red": plotting.RED_CORNER, "coupling": plotting.BLUE_SPRING}
CATALOGUE = [("single", "single particle"), ("disk_R1", "disk R = 1"), ("disk_R3", "disk R = 3"),
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


def panel_particle(fig, d):
    springs, kinds = d["springs"], d["spring_kinds"]
    ax = fig.add_axes([0.03, 0.76, 0.13, 0.18])
    draw_springs(ax, d["single_corners"], springs, kinds, linewidth=1.4, markersize=18)
    plotting.panel_label(ax, "a")
    ax.set_title("one particle", fontsize=7)
    ax = fig.add_axes([0.17, 0.76, 0.15, 0.18])
    draw_springs(ax, d["pair_corners"], springs, kinds, linewidth=1.0, markersize=12)
    ax.set_title(f"bound pair: {float(d['pair_per_particle']):.4f}\nbulk energy per particle", fontsize=7)


def panel_aggregates(fig, d, norm):
    ax = fig.add_axes([0.35, 0.76, 0.15, 0.2])
    polys = draw_triangles(ax, d["disk_R3_corners"], d["disk_R3_energy"], norm)
    plotting.panel_label(ax, "b")
    ax.set_title("disk R = 3", fontsize=7)
    ax = fig.add_axes([0.51, 0.76, 0.2, 0.2])
    draw_triangles(ax, d["fiber_cut0_corners"], d["fiber_cut0_energy"], norm)
    ax.set_title("fibre (flat edges), a few periods", fontsize=7)
    cax = fig.add_axes([0.715, 0.78, 0.008, 0.16])
    fig.colorbar(polys, cax=cax, label="energy / bulk")
    cax.yaxis.label.set_size(6)
    cax.tick_params(labelsize=6)


def panel_bulk(fig, d):
    ax = fig.add_axes([0.78, 0.76, 0.2, 0.2])
    corners = np.asarray(d["bulk_corners"])
    centre = corners.reshape(-1, 2).mean(axis=0)
    keep = np.linalg.norm(corners.mean(axis=1) - centre, axis=1) < 1.6
    draw_springs(ax, corners[keep], d["springs"], d["spring_kinds"], linewidth=1.0, markersize=8)
    ax.text(-0.12, 1.0, "(c)", transform=ax.transAxes, ha="right", va="bottom", fontweight="bold")
    ax.set_title("bulk: yellow and red sides match\n(shared nodes; rest lengths $1 \\pm \\epsilon$)", fontsize=7)


def panel_diagram(fig, diagram, continuum, runs):
    ax = fig.add_axes([0.07, 0.33, 0.36, 0.33])
    _, phases = plotting.draw_ansatz_diagram(ax, diagram, continuum)
    plotting.phase_legend(ax, phases, dashed_continuum=True)
    gas = np.asarray(diagram["gas_Gamma"])
    ax.text(0.98, 0.03, rf"$\ell = {float(diagram['ell']):g}$", transform=ax.transAxes, fontsize=9, color="w", ha="right")
    inset = ax.inset_axes([0.69, 0.5, 0.28, 0.3])
    inset.semilogx(gas, diagram["nu"], color=plotting.PHASE_COLORS["gas"], lw=1.2)
    inset.fill_betweenx(diagram["nu"], 1e-5, gas, color=plotting.PHASE_COLORS["gas"], alpha=0.6)
    inset.set_xlim(1e-4, 1e-1)
    inset.set_ylim(0, 1)
    inset.set_xlabel(r"$\Gamma$ (log)", fontsize=5, labelpad=1)
    inset.set_ylabel(r"$\nu$", fontsize=5, labelpad=1)
    inset.tick_params(labelsize=5, pad=1)
    inset.set_title("single particles win (grey)", fontsize=5, pad=2)
    inset.patch.set_alpha(0.9)
    for k, r in enumerate(runs, start=1):
        point = (float(r["Gamma"]), float(r["nu"]))
        ax.plot(*point, "s", ms=6, mfc="w", mec="k", mew=0.7, zorder=6)
        ax.annotate(str(k), point, xytext=(4, 4), textcoords="offset points", fontsize=6, zorder=7)
    ax.text(-0.14, 1.0, "(d)", transform=ax.transAxes, ha="right", va="bottom", fontweight="bold")


def panel_snapshots(fig, runs):
    cols, rows = 4, 2
    width, height = 0.52 / cols, 0.34 / rows
    for k, r in enumerate(runs, start=1):
        i, j = divmod(k - 1, cols)
        sub = fig.add_axes([0.5 + j * width * 0.93, 0.66 - (i + 1) * height, width * 0.9, height * 0.84])
        box = int(r["box"])
        draw_snapshot(r["sites"], box, ax=sub, tiling=TILING)
        coords, _ = clusters(r["sites"], box, TILING)[0]
        coords = coords.copy()
        coords[:, :2] -= np.floor(coords[:, :2].mean(axis=0) / box).astype(int) * box
        xy = site_positions(coords, TILING)
        c = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
        half = max(12.0, 0.5 * np.ptp(xy, axis=0).max() + 2)
        sub.set_xlim(c[0] - half, c[0] + half)
        sub.set_ylim(c[1] - 0.8 * half, c[1] + 0.8 * half)
        sub.set_title(rf"{k}: $\Gamma$={float(r['Gamma']):g}", fontsize=6)
        if j == 0:
            sub.text(-0.08, 0.5, rf"$\nu$={float(r['nu']):g}" + f"\n{int(r['n'])} in {box}x{box}", transform=sub.transAxes,
                     ha="right", va="center", fontsize=6)


def panel_catalogue(fig, d, norm):
    cols = 5
    for n, (name, title) in enumerate(CATALOGUE):
        i, j = divmod(n, cols)
        ax = fig.add_axes([0.02 + j * 0.19, 0.14 - i * 0.13, 0.17, 0.11])
        draw_triangles(ax, d[f"{name}_corners"], d[f"{name}_energy"], norm, linewidth=0.15)
        ax.set_title(f"{title}: {float(d[f'{name}_per_particle']):.2f}", fontsize=6)
        if n == 0:
            plotting.panel_label(ax, "e")


def main(shapes_path, diagram_path, continuum_path, snapshot_paths, outputs):
    d = load_npz(shapes_path)
    diagram = load_npz(diagram_path)
    runs = sorted((load_npz(p) for p in snapshot_paths), key=lambda r: (-float(r["nu"]), float(r["Gamma"])))
    fig = plotting.figure(17.8, 21.0)
    norm = Normalize(0, 1.1)
    panel_particle(fig, d)
    panel_aggregates(fig, d, norm)
    panel_bulk(fig, d)
    panel_diagram(fig, diagram, load_npz(continuum_path), runs)
    panel_snapshots(fig, runs)
    panel_catalogue(fig, d, norm)
    sizes = sorted({(int(r["n"]), int(r["box"])) for r in runs})
    fig.text(0.02, -0.01,
             "(b, c, e) relaxed at " + rf"$\ell={float(d['ell']):g}$, $\nu={float(d['nu']):g}$, "
             rf"$\epsilon={float(d['eps']):g}$ (exaggerated); titles in (e): energy per particle over the bulk's. "
             "(d) Monte Carlo: " + "; ".join(f"{n} particles in {b} x {b} cells ({2 * b * b} triangle sites)"
                                             for n, b in sizes) + ".",
             fontsize=6, va="top")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.shapes, snakemake.input.diagram, snakemake.input.continuum[0],  # noqa: F821
             snakemake.input.snapshots, [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
