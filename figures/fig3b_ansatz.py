"""Fig. 3b: phase diagram from the numerical comparison of the pre-made aggregates of Fig. 4a
at ell = 5, shaded by the winning fibre's W*/ell and disk's R*/ell (colour bars), with the
continuum boundaries of Fig. 3a overlaid (dashed, each only where it is a boundary), and Monte
Carlo annealing snapshots at the conditions marked by numbered symbols: fibres at large nu
widening with Gamma (up to the width a box of n particles can hold: figX_mc_finite_size), disks
at nu = 0.4 growing with Gamma (the dense box: diamonds, and a "dense" tag on their panels), and
the transition from disks to elongated aggregates along Gamma = 0.5; two seeds at
(Gamma, nu) = (0.5, 0.9). The paper puts its dense runs in the bottom row; here the panels run
by nu (top to bottom) and Gamma, so the dense runs sit in the row of nu = 0.4.

With ``convention = "supplement"`` (figX_fig3b_supplement_convention) the runs read Gamma in the
supplement's convention, gamma = 4 g/sqrt(3), as the published panels did: each is drawn on our
diagram at its Gamma in ours (sqrt(3)/4 = 0.433 times the label), titled with both."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.montecarlo import draw_snapshot, largest_cluster_extent


# Marker of each box on the diagram, and the same glyph on its snapshot panels.
BOX_MARKERS = {"sparse": ("s", "\u25a1"), "dense": ("D", "\u25c7")}


def main(diagram_path, continuum_path, snapshot_paths, dense, convention, outputs):
    diagram = load_npz(diagram_path)
    runs = sorted((load_npz(p) for p in snapshot_paths),
                  key=lambda r: (-float(r["nu"]), float(r["Gamma"]), int(r["seed"])))
    kinds = ["dense" if (int(r["n"]), int(r["box"])) == tuple(dense) else "sparse" for r in runs]
    cols = 4
    rows = int(np.ceil(len(runs) / cols))
    fig = plotting.figure(17.8, max(10.0, 3.4 * rows + 1.0))
    ax = fig.add_axes([0.06, 0.3, 0.32, 0.6])
    meshes = plotting.draw_ansatz_diagram(fig, ax, diagram, load_npz(continuum_path))
    plotting.size_colorbars(fig, meshes, left=0.395, bottom=0.3, height=0.6, width=0.01, step=0.05, labelsize=7,
                            label_on_top=True)
    ax.text(0.8, 0.04, rf"$\ell = {float(diagram['ell']):g}$", transform=ax.transAxes, fontsize=9, color="w")
    offsets = {}
    for k, (r, kind) in enumerate(zip(runs, kinds), start=1):
        point = (float(r["Gamma_measured"]), float(r["nu"]))
        shift = offsets.get(point, 0)
        offsets[point] = shift + 1
        ax.plot(*point, BOX_MARKERS[kind][0], ms=7 if kind == "sparse" else 6.5, mfc="w", mec="k", mew=0.7, zorder=6)
        ax.annotate(str(k), point, xytext=(4 + 9 * shift, 4), textcoords="offset points", fontsize=6, zorder=7)
    width = 0.5 / cols
    height = 0.82 / rows  # the panels end above the footer
    # Every panel on one scale, so that widths compare across panels: the largest extent of any
    # run's largest cluster, placed as draw_snapshot places it (centre in the box).
    extents = [largest_cluster_extent(r["sites"], int(r["box"])) for r in runs]
    half = max(0.5 * max(x1 - x0, (y1 - y0) / 0.8) for (x0, y0), (x1, y1) in extents) + 2.0
    for k, (r, kind, ((x0, y0), (x1, y1))) in enumerate(zip(runs, kinds, extents), start=1):
        i, j = divmod(k - 1, cols)
        sub = fig.add_axes([0.49 + j * width, 0.97 - (i + 1) * height, width * 0.95, height * 0.82])
        draw_snapshot(r["sites"], int(r["box"]), ax=sub)
        sub.set_xlim(0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half)
        sub.set_ylim(0.5 * (y0 + y1) - 0.8 * half, 0.5 * (y0 + y1) + 0.8 * half)
        sub.set_xticks([])
        sub.set_yticks([])
        seed = f", seed {int(r['seed'])}" if int(r["seed"]) != 1 else ""
        if convention == "measured":
            label = rf"$\Gamma$={float(r['Gamma']):g}"
        else:
            label = rf"$\Gamma_{{\rm paper}}$={float(r['Gamma']):g}"
        if convention == "measured":
            title = rf"{k}: {label}, $\nu$={float(r['nu']):g}{seed}"
        else:  # two lines: the label is longer
            title = rf"{k}: {label}, $\nu$={float(r['nu']):g}" + "\n" + rf"(ours $\Gamma$={float(r['Gamma_measured']):.2f}){seed}"
        sub.set_title(title, fontsize=6)
        box = int(r["box"])
        sub.text(0.02, 0.02, f"{BOX_MARKERS[kind][1]} {kind}, {box} x {box}", transform=sub.transAxes,
                 fontsize=5.5, va="bottom",
                 color="k" if kind == "dense" else "0.35", fontweight="bold" if kind == "dense" else "normal",
                 bbox=dict(boxstyle="round,pad=0.15", fc="w", ec="k" if kind == "dense" else "none", lw=0.5))
    sizes = {kind: (int(r["n"]), int(r["box"])) for r, kind in zip(runs, kinds)}
    numbers = {kind: ", ".join(str(k) for k, other in enumerate(kinds, start=1) if other == kind) for kind in sizes}
    fig.text(0.06, 0.02, "Monte Carlo, " + f"{len(runs)} runs: "
             + "; ".join(f"{kind} box {BOX_MARKERS[kind][1]} (panels {numbers[kind]}): {n} particles in {b} x {b} sites"
                         for kind, (n, b) in sorted(sizes.items(), reverse=True))
             + ".\nThe paper shows its dense runs in its bottom row; here the panels run by nu (top to bottom), "
             "then Gamma.\n"
             "Each panel is centred on its largest cluster (others in other colours), all on one scale;"
             " dotted: edges of the periodic box.\n"
             "At nu = 0.9 a box of 200 particles holds a fibre of the optimal width only below Gamma ~ 0.35; "
             "above, its best aggregate is compact (figX_mc_finite_size)."
             + ("" if convention == "measured" else
                "\nGamma read in the supplement's convention, gamma = 4 g/sqrt(3) (binding energies 0.433 times ours); "
                "markers at the same runs' Gamma in ours, gamma = g."), fontsize=6, va="bottom")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], snakemake.input.snapshots,  # noqa: F821
             snakemake.params.dense, snakemake.params.convention,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
