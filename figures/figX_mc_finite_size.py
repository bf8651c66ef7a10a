"""Beyond the paper: why the Monte Carlo boxes of Fig. 3b show compact aggregates where the
infinite-system diagram predicts fibres, and what a larger box shows (ell = 5).

(a) Width and (b) length of the largest final aggregate (gyration measure,
topology.gyration_dimensions) along the fibre scan nu = 0.9, for the paper's box of n particles
and a larger one at the same density; lines: the best single aggregate of exactly n particles
(ansatz.finite_aggregates, relaxed compact-to-elongated shapes) and the continuum fibre width
W*(Gamma) (Eq. 14). A fibre of width W* needs about n > 3 W*^2 / (sqrt(3)/2) particles to be
longer than wide; below that the best aggregate is compact.
(c) Snapshots of the larger box: the fibre scan and the nu scan at fixed Gamma, each with its
final energy above the best single aggregate of the same n (a measure of how far annealing got).
"""
import numpy as np

from pyfrustrate import continuum, plotting
from pyfrustrate.ansatz import energy_above_best_single
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.montecarlo import clusters, draw_snapshot
from pyfrustrate.topology import gyration_dimensions, site_positions


def largest_aggregate(run):
    box = int(run["box"])
    coords, rank = clusters(run["sites"], box)[0]
    return coords, rank


def gap_to_best(run, finite):
    """Final Monte Carlo energy minus the best single aggregate of the same n and nu at the run's g,
    in bulk particle energies (None without a matching prediction)."""
    for f in finite:
        if int(f["n"]) == int(run["n"]) and abs(float(f["nu"]) - float(run["nu"])) < 1e-9:
            return energy_above_best_single(run["energy"], run["g"], f)
    return None


def main(run_paths, finite_paths, outputs):
    runs = [load_npz(p) for p in run_paths]
    finite = [load_npz(p) for p in finite_paths]
    nu_fibre = max(float(r["nu"]) for r in runs if str(r["kind"]) == "sparse")
    sizes = sorted({int(r["n"]) for r in runs})
    colors = {n: f"C{k}" for k, n in enumerate(sizes)}
    fig = plotting.figure(17.8, 13.0)
    axes = [fig.add_axes([0.08, 0.58, 0.25, 0.36]), fig.add_axes([0.08, 0.1, 0.25, 0.36])]
    Gamma = np.linspace(0.02, 0.98, 200)
    axes[0].plot(Gamma, 5.0 * continuum.optimal_width(nu_fibre, Gamma), "k--", lw=1,
                 label=r"continuum $W^*$ (Eq. 14)")
    for f in finite:
        if abs(float(f["nu"]) - nu_fibre) > 1e-9:
            continue
        n = int(f["n"])
        best = f["best"]
        for ax, key in zip(axes, ("width", "length")):
            ax.step(f["Gamma"], f[key][best], where="mid", color=colors.get(n, "0.5"), lw=1.2,
                    label=f"best aggregate of {n}")
    for r in runs:
        if abs(float(r["nu"]) - nu_fibre) > 1e-9:
            continue
        coords, rank = largest_aggregate(r)
        width, length = gyration_dimensions(coords)
        marker = "o" if str(r["kind"]) == "sparse" else "s"
        n = int(r["n"])
        for ax, value in zip(axes, (width, length)):
            ax.plot(float(r["Gamma"]), value, marker, ms=6, mfc="w" if rank else colors[n], mec=colors[n], zorder=5,
                    label=f"Monte Carlo, {n} in {int(r['box'])}$^2$")
    for ax, name in zip(axes, ("width", "length")):
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles))
        ax.legend(unique.values(), unique.keys(), fontsize=6, frameon=False, loc="upper left")
        ax.set_xlabel(r"line tension $\Gamma$")
        ax.set_ylabel(f"aggregate {name} (lattice units)")
        ax.set_xlim(0, 1.0)
        # room for the legend above the data: each entry takes ~8 % of the axis height
        ax.set_ylim(0, ax.get_ylim()[1] / max(1 - 0.08 * len(unique), 0.4))
    axes[0].set_title(rf"$\nu = {nu_fibre:g}$, $\ell = {float(runs[0]['ell']):g}$", fontsize=8)
    plotting.panel_label(axes[0], "a")
    plotting.panel_label(axes[1], "b")

    large = sorted((r for r in runs if str(r["kind"]) == "large"),
                   key=lambda r: (-float(r["nu"]), float(r["Gamma"])))
    cols = 3
    rows = max(1, int(np.ceil(len(large) / cols)))
    width, height = 0.6 / cols, 0.9 / rows
    for k, r in enumerate(large):
        i, j = divmod(k, cols)
        sub = fig.add_axes([0.39 + j * width, 0.95 - (i + 1) * height, width * 0.96, height * 0.8])
        box = int(r["box"])
        draw_snapshot(r["sites"], box, ax=sub, outline=False)  # the crop hides the box: its edge would only cross the view
        coords, rank = largest_aggregate(r)
        coords = coords - np.floor(coords.mean(axis=0) / box).astype(int) * box
        xy = site_positions(coords)
        centre, half = 0.5 * (xy.min(axis=0) + xy.max(axis=0)), 0.5 * np.ptp(xy, axis=0).max() + 3
        sub.set_xlim(centre[0] - half, centre[0] + half)
        sub.set_ylim(centre[1] - half, centre[1] + half)
        sub.set_xticks([])
        sub.set_yticks([])
        w, l = gyration_dimensions(coords)
        wrap = ", wraps" if rank else ""
        gap = gap_to_best(r, finite)
        gap = "" if gap is None else rf", $\Delta E$={gap:+.0f}"
        sub.set_title(rf"$\Gamma$={float(r['Gamma']):g}, $\nu$={float(r['nu']):g}: {len(coords)} particles" "\n"
                      rf"$W$={w:.0f}, $L$={l:.0f}{wrap}{gap}", fontsize=6)
    if large:
        fig.text(0.39, 0.97, f"(c) Monte Carlo, {int(large[0]['n'])} particles in {int(large[0]['box'])} x "
                 f"{int(large[0]['box'])} sites: each view cropped around the largest aggregate", fontsize=7)
    fig.text(0.08, -0.01, "Open markers: the aggregate wraps around the box (a periodic fibre). "
             "Cluster translations on (config cluster_moves); widths and lengths from the gyration tensor.\n"
             "$\\Delta E$: final energy above the best single aggregate of the same n, in bulk particle energies.",
             fontsize=6, va="top")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.runs, snakemake.input.finite, [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
