"""Beyond the paper (issue 33): single aggregates sampled at fixed size against the ansatz
(pyfrustrate.montecarlo.fixed_size; results/montecarlo/validation.json).

(a) Energy per particle including binding of the quenched fibres against their width W (markers,
one per seed), relative to the ansatz's best straight fibre, with the ansatz's straight fibres
(line) and its and the continuum's optimal widths (vertical lines). (b) The same for disks of n
particles, the ansatz's compact hexagons as the line. (c) The two-sided checks: per check, the final
energy of the run seeded as the competitor minus that of the run seeded as the predicted state,
per seed (markers as in (a)); a cross where the predicted state did not persist.
"""
import json

import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import logging_to
from pyfrustrate.provenance import for_job

SEED_MARKERS = ("o", "s", "^", "D", "v")


def load(path):
    with open(path) as f:
        return json.load(f)


SHORT_STATE = {"one disk": "disk", "two disks": "2 disks", "a fibre wrapping the box": "fibre"}


def draw_two_sided(ax, checks, colors):
    """One column per check: the competitor's final energy minus the predicted run's with the same
    seed (above zero: the prediction holds on that side), a filled marker where the predicted
    state persisted, a cross where it did not."""
    for x, check in enumerate(checks):
        color = colors.get(check["Gamma"], "0.3")
        margin = np.array(check["competitor_energy_over_g"]) - np.array(check["predicted_energy_over_g"])
        offsets = np.linspace(-0.15, 0.15, len(margin)) if len(margin) > 1 else np.zeros(1)
        for k, (dx, value, kept) in enumerate(zip(offsets, margin, check["persists"])):
            ax.plot(x + dx, value, SEED_MARKERS[k % len(SEED_MARKERS)] if kept else "x", ms=4,
                    color=color, mec=color if kept else "#b2182b")
    ax.axhline(0.0, color="0.4", lw=0.6)
    low, high = ax.get_ylim()
    ax.set_ylim(min(low, -0.1 * high), max(high, 1.0) * 1.15)  # zero, the line a failure would cross, in view
    ax.set_xticks(range(len(checks)))
    ax.set_xticklabels([f"{SHORT_STATE.get(c['predicted_state'], c['predicted_state'])} vs\n"
                        f"{SHORT_STATE.get(c['competitor_state'], c['competitor_state'])}\n"
                        rf"$\nu$ = {c['nu']:g}" for c in checks])
    ax.set_xlim(-0.5, max(len(checks), 1) - 0.5)
    ax.set_ylabel(r"$(E_{\rm competitor} - E_{\rm predicted})\,/\,g$")
    ax.set_title("two-sided checks")


def main(validation_path, point_paths, outputs, provenance=None):
    validation = load(validation_path)
    points = {(p["scan"], p["nu"], p["Gamma"]): p for p in map(load, point_paths)}
    width_cm, height_cm = plotting.PAGE_WIDTH_CM, 6.2
    fig = plotting.figure(width_cm, height_cm)
    axes = [fig.add_axes([(1.5 + 5.8 * k) / width_cm, 1.1 / height_cm, 4.3 / width_cm, 4.3 / height_cm])
            for k in range(3)]
    gammas = sorted({r["Gamma"] for r in validation["points"]})
    colors = dict(zip(gammas, ("#1b9e77", "#d95f02", "#7570b3")))
    for ax, scan in zip(axes, ("fibre", "disk")):
        for record in (r for r in validation["points"] if r["scan"] == scan):
            point = points[scan, record["nu"], record["Gamma"]]
            color = colors[record["Gamma"]]
            sizes = np.array(record["sizes"])
            if scan == "fibre":
                ansatz = np.array(point["fibre_energy_per_particle"]) / record["g"]
                ansatz_sizes = np.arange(1, ansatz.size + 1)
                best, continuum = record["W_ansatz"], record["W_continuum"]
            else:
                ansatz = np.array(point["disk_energy_per_particle"]) / record["g"]
                radii = np.arange(1, ansatz.size + 1)
                ansatz_sizes = 1 + 3 * radii * (radii + 1)
                best, continuum = record["n_ansatz"], record["n_continuum"]
            reference = ansatz.min()
            shown = (ansatz_sizes >= 0.8 * sizes.min()) & (ansatz_sizes <= 1.2 * sizes.max())
            ax.plot(ansatz_sizes[shown], ansatz[shown] - reference, "-", color=color, lw=1,
                    label=rf"ansatz, $\Gamma$ = {record['Gamma']:g}")
            for k, (seed, energy) in enumerate(zip(record["seeds"], record["energy_per_particle_over_g"])):
                ax.plot(sizes, np.array(energy) - reference, SEED_MARKERS[k % len(SEED_MARKERS)], ms=4, mfc="w",
                        mec=color, label=f"Monte Carlo, seed {seed}")
            ax.axvline(best, color=color, lw=0.8, ls=":", label="ansatz optimum")
            ax.axvline(continuum, color=color, lw=0.8, ls="--", label="continuum optimum")
        ax.set_xlabel("fibre width W (rows)" if scan == "fibre" else "disk size n (particles)")
        ax.set_ylabel(r"$(e - e^*_{\rm ansatz})\,/\,g$ per particle")
        nu = next(r["nu"] for r in validation["points"] if r["scan"] == scan)
        ax.set_title(("straight fibres" if scan == "fibre" else "disks") + rf", $\nu$ = {nu:g}")
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles))
        ax.legend(unique.values(), unique.keys(), loc="upper center", frameon=True, facecolor="w", edgecolor="none")
        low, high = ax.get_ylim()
        ax.set_ylim(min(low, 0), high + 1.0 * (high - min(low, 0)))  # room for the legend above the data
    draw_two_sided(axes[2], validation["two_sided"], colors)
    for ax, letter in zip(axes, "abc"):
        plotting.panel_label(ax, letter)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.validation[0], snakemake.input.points,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png], provenance=for_job(snakemake))  # noqa: F821
