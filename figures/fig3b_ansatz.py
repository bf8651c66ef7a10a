"""Fig. 3b: phase diagram from the numerical comparison of the pre-made aggregates of Fig. 4a
at ell = 5, with the continuum boundaries of Fig. 3a overlaid (dashed), and Monte Carlo
annealing snapshots at the conditions marked by numbered squares: fibres at large nu widening
with Gamma (up to the width a box of n particles can hold: figX_mc_finite_size), disks at nu = 0.4 growing with Gamma (bottom row, dense box), and the transition
from disks to elongated aggregates along Gamma = 0.5; two seeds at (Gamma, nu) = (0.5, 0.9)."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.montecarlo import clusters, draw_snapshot
from pyfrustrate.topology import site_positions


def main(diagram_path, continuum_path, snapshot_paths, outputs):
    diagram = load_npz(diagram_path)
    runs = sorted((load_npz(p) for p in snapshot_paths),
                  key=lambda r: (-float(r["nu"]), float(r["Gamma"]), int(r["seed"])))
    cols = 4
    rows = int(np.ceil(len(runs) / cols))
    fig = plotting.figure(17.8, max(9.0, 3.4 * rows))
    ax = fig.add_axes([0.06, 0.3, 0.36, 0.6])
    plotting.draw_ansatz_diagram(fig, ax, diagram, load_npz(continuum_path))
    ax.text(0.8, 0.04, rf"$\ell = {float(diagram['ell']):g}$", transform=ax.transAxes, fontsize=9, color="w")
    offsets = {}
    for k, r in enumerate(runs, start=1):
        point = (float(r["Gamma"]), float(r["nu"]))
        shift = offsets.get(point, 0)
        offsets[point] = shift + 1
        ax.plot(*point, "s", ms=7, mfc="w", mec="k", mew=0.7, zorder=6)
        ax.annotate(str(k), point, xytext=(4 + 9 * shift, 4), textcoords="offset points", fontsize=6, zorder=7)
    width = 0.55 / cols
    height = 0.92 / rows
    # Every panel on one scale, so that widths compare across panels: the largest extent of any
    # run's largest cluster, placed as draw_snapshot places it (centre in the box).
    extents = []
    for r in runs:
        box = int(r["box"])
        coords, _ = max(clusters(r["sites"], box), key=lambda c: len(c[0]))
        xy = site_positions(coords - np.floor(coords.mean(axis=0) / box).astype(int) * box)
        extents.append((xy.min(axis=0), xy.max(axis=0)))
    half = max(0.5 * max(x1 - x0, (y1 - y0) / 0.8) for (x0, y0), (x1, y1) in extents) + 2.0
    for k, (r, ((x0, y0), (x1, y1))) in enumerate(zip(runs, extents), start=1):
        i, j = divmod(k - 1, cols)
        sub = fig.add_axes([0.44 + j * width, 0.97 - (i + 1) * height, width * 0.95, height * 0.82])
        draw_snapshot(r["sites"], int(r["box"]), ax=sub)
        sub.set_xlim(0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half)
        sub.set_ylim(0.5 * (y0 + y1) - 0.8 * half, 0.5 * (y0 + y1) + 0.8 * half)
        sub.set_xticks([])
        sub.set_yticks([])
        seed = f", seed {int(r['seed'])}" if int(r["seed"]) != 1 else ""
        sub.set_title(rf"{k}: $\Gamma$={float(r['Gamma']):g}, $\nu$={float(r['nu']):g}{seed}", fontsize=6)
    sizes = sorted({(int(r["n"]), int(r["box"])) for r in runs})
    fig.text(0.06, 0.02, "Monte Carlo: " + "; ".join(f"{n} particles in {b} x {b} sites" for n, b in sizes)
             + f"; {len(runs)} runs.\nEach panel is centred on its largest cluster (others in other colours), all on one scale;"
             " dotted: edges of the periodic box.\n"
             "At nu = 0.9 a box of 200 particles holds a fibre of the optimal width only below Gamma ~ 0.35; "
             "above, its best aggregate is compact (figX_mc_finite_size).", fontsize=6, va="bottom")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], snakemake.input.snapshots,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
