"""Beyond the paper: why the Monte Carlo boxes of Fig. 3b show compact aggregates where the
infinite-system diagram predicts fibres, and what a larger box shows (ell = 5).

(a) Width and (b) length of the largest final aggregate (gyration measure,
topology.gyration_dimensions; for a fibre, that of the straight strip of its rows and particles,
so that a bent fibre is measured by its arms) along the fibre scan nu = 0.9, for the paper's box of n particles
and a larger one at the same density; lines: the best single aggregate of exactly n particles
(ansatz.finite_aggregates, relaxed compact-to-elongated shapes) and the continuum fibre width
W*(Gamma) (Eq. 11). A fibre of width W* needs about n > 3 W*^2 / (sqrt(3)/2) particles to be
longer than wide; below that the best aggregate is compact.
(c) Snapshots of the larger box: the fibre scan and the nu scan at fixed Gamma, each with the
structure of its largest aggregate (ground_states.aggregate_structure: a fibre's width in rows, as
the large runs are judged) and its final energy above the best single aggregate of the same n (a
measure of how far annealing got).
"""
import numpy as np

from pyfrustrate import continuum, plotting
from pyfrustrate.ansatz import FiniteAggregates
from pyfrustrate.ground_states import aggregate_structure
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job
from pyfrustrate.montecarlo import clusters
from pyfrustrate.topology import gyration_dimensions, site_positions


def largest_aggregate(run):
    box = int(run["box"])
    coords, rank = clusters(run["sites"], box)[0]
    return coords, rank


def largest_aggregate_words(run):
    """The largest aggregate of a run as the large runs are judged (ground_states.aggregate_structure):
    "fibre, 9 rows" (the strip of as many particles and exposed sides: a bent fibre reads its arms'
    width, where the gyration extent reads the bend's span), "3 fused disks", "disk"."""
    _, kind, size = aggregate_structure(run["sites"], int(run["box"]))
    if kind == "fiber":
        return f"fibre, {size:.0f} rows"
    if kind == "fused_disks":
        return f"{size} fused disks"
    return plotting.PHASE_LABELS.get(kind, kind)


def strip_dimensions(rows, particles):
    """Gyration width and length of the straight strip of ``rows`` rows holding ``particles``
    particles: what (a) and (b) plot for an aggregate read as a fibre, so that a bent fibre is
    measured by its arms, as its title and the large runs' verdict read it."""
    rows = max(1, int(round(rows)))
    length = max(rows, int(round(particles / rows)))
    # Each row shifted back by half a step (i - j // 2): a rectangle, not a parallelogram.
    return gyration_dimensions(np.array([(i - j // 2, j) for j in range(rows) for i in range(length)]))


def plotted_dimensions(run):
    """(width, length) of a run's largest aggregate for (a) and (b): its gyration measure, or for a
    fibre that of the straight strip of its rows (strip_dimensions)."""
    coords, _ = largest_aggregate(run)
    _, kind, size = aggregate_structure(run["sites"], int(run["box"]))
    return strip_dimensions(size, len(coords)) if kind == "fiber" else gyration_dimensions(coords)


#: The band under a step where the best aggregate is a ring (a hole at its core).
RING_BAND = dict(lw=5, alpha=0.3, solid_capstyle="butt")


def main(run_paths, finite_paths, outputs, provenance=None):
    runs = [load_npz(p) for p in run_paths]
    finite = [load_npz(p) for p in finite_paths]
    nu_fibre = max(float(r["nu"]) for r in runs if str(r["kind"]) == "sparse")
    sizes = sorted({int(r["n"]) for r in runs})
    colors = {n: c for n, c in zip(sizes, ("#1b9e77", "#d95f02", "#7570b3", "#e7298a"))}
    width_cm, height_cm = plotting.PAGE_WIDTH_CM, 13.0
    fig = plotting.figure(width_cm, height_cm)
    axes = [fig.add_axes([1.3 / width_cm, 7.4 / height_cm, 4.6 / width_cm, 4.8 / height_cm]),
            fig.add_axes([1.3 / width_cm, 1.0 / height_cm, 4.6 / width_cm, 4.8 / height_cm])]
    Gamma = np.linspace(0.02, 0.98, 200)
    ell = float(runs[0]["ell"])
    axes[0].plot(Gamma, ell * continuum.optimal_width(nu_fibre, Gamma), "k--", lw=1,
                 label=r"continuum $W^*$, Eq. (11)")
    for f in finite:
        if abs(float(f["nu"]) - nu_fibre) > 1e-9:
            continue
        n = int(f["n"])
        best = f["best"]
        # Where the best aggregate is a ring (a hole at its core), its step is underlaid by a band.
        ring = FiniteAggregates.from_arrays(f).hole[best] > 0
        for ax, key in zip(axes, ("width", "length")):
            ax.step(f["Gamma"], f[key][best], where="mid", color=colors.get(n, "0.5"), lw=1.2,
                    label=f"best aggregate of {n}")
            if ring.any():
                ax.step(f["Gamma"], np.where(ring, f[key][best], np.nan), where="mid", color=colors.get(n, "0.5"),
                        **RING_BAND)
                # One legend entry for every size's band, in neutral grey.
                ax.plot([], [], color="0.5", **RING_BAND, label="band: the best is a ring")
    for r in runs:
        if abs(float(r["nu"]) - nu_fibre) > 1e-9:
            continue
        _, rank = largest_aggregate(r)
        width, length = plotted_dimensions(r)
        marker = "o" if str(r["kind"]) == "sparse" else "s"
        n = int(r["n"])
        for ax, value in zip(axes, (width, length)):
            ax.plot(float(r["Gamma"]), value, marker, ms=6, mfc="w" if rank else colors[n], mec=colors[n], zorder=5,
                    label=f"Monte Carlo, {n} in {plotting.box_label(int(r['box']))}")
    for ax, name in zip(axes, ("width", "length")):
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles))
        if "band: the best is a ring" in unique:  # last, after every step and marker it explains
            unique["band: the best is a ring"] = unique.pop("band: the best is a ring")
        ax.legend(unique.values(), unique.keys(), loc="upper left")
        ax.set_xlabel(plotting.LABELS["Gamma"])
        ax.set_ylabel(f"aggregate {name} ({plotting.LENGTH_UNIT})")
        ax.set_xlim(0, 1.0)
        # room for the legend above the data: each entry takes ~8 % of the axis height
        ax.set_ylim(0, ax.get_ylim()[1] / max(1 - 0.08 * len(unique), 0.4))
    axes[0].set_title(rf"$\nu$ = {nu_fibre:g}, $\ell$ = {ell:g}")
    plotting.panel_label(axes[0], "a")
    plotting.panel_label(axes[1], "b")

    large = sorted((r for r in runs if str(r["kind"]) == "large"),
                   key=lambda r: (-float(r["nu"]), float(r["Gamma"])))
    # At most three columns, as few rows as that allows, the rows filled evenly (4 runs: 2 x 2).
    rows = max(1, int(np.ceil(len(large) / 3)))
    cols = max(1, int(np.ceil(len(large) / rows)))
    panel, top = (width_cm - 7.0) / cols, height_cm - 0.9
    step = (top - 0.2) / rows
    for k, r in enumerate(large):
        i, j = divmod(k, cols)
        sub = fig.add_axes([(7.0 + j * panel) / width_cm, (top - (i + 1) * step + 0.1) / height_cm,
                            (panel - 0.15) / width_cm, (step - 1.0) / height_cm])
        box = int(r["box"])
        plotting.draw_snapshot(r["sites"], box, ax=sub)
        coords, rank = largest_aggregate(r)
        coords = coords - np.floor(coords.mean(axis=0) / box).astype(int) * box
        xy = site_positions(coords)
        centre, half = 0.5 * (xy.min(axis=0) + xy.max(axis=0)), 0.5 * np.ptp(xy, axis=0).max() + 3
        aspect = (step - 1.0) / (panel - 0.15)
        sub.set_xlim(centre[0] - half / min(aspect, 1), centre[0] + half / min(aspect, 1))
        sub.set_ylim(centre[1] - half * max(aspect, 1), centre[1] + half * max(aspect, 1))
        sub.set_xticks([])
        sub.set_yticks([])
        wrap = ", wraps" if rank else ""
        gap = plotting.gap_to_best_single(r, finite)
        gap = "" if gap is None else rf", $\Delta E$ = {gap:+.0f}"
        sub.set_title(rf"$\Gamma$ = {float(r['Gamma']):g}, $\nu$ = {float(r['nu']):g}" "\n"
                      f"{largest_aggregate_words(r)}{wrap}{gap}")
    if large:
        sub0 = fig.axes[2]
        plotting.panel_label(sub0, "c", dy_pt=22)
        fig.text(7.5 / width_cm, (height_cm - 0.2) / height_cm,
                 f"Monte Carlo, {int(large[0]['n'])} particles in {plotting.box_label(int(large[0]['box']))} sites",
                 va="top")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.runs, snakemake.input.finite, [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
