"""Beyond the paper (issue 33): single aggregates sampled at fixed size against the ansatz
(pyfrustrate.montecarlo.fixed_size; results/montecarlo/validation.json).

(a) Energy per particle including binding of the quenched fibres against their width W (markers,
one per seed; the panels' shared key is the figure's bottom-right slot), relative to the ansatz's best straight fibre, with the ansatz's straight fibres
(line) and its and the continuum's optimal widths (vertical lines). (b) The same for disks of n
particles, the ansatz's compact hexagons as the line. (c) The two-sided checks: the final energy of the run
seeded as the competitor minus that of the run seeded as the predicted state, a column per pair
of states and nu, a colour per Gamma, a marker per seed (as in (a)); a cross where the predicted
state did not persist.
(d) Grand-canonical sampling of one fibre (outline moves): its mean width <W>
(bars: its standard deviation there) against the chemical potential mu, relative to the ansatz's
threshold min_W e(W), one marker per seed, a colour per temperature; the ansatz's width at T = 0
(the width whose last row's energy is mu, steps), its W* (dotted) and the threshold (vertical);
stars: W* read where the scan crosses its own threshold. (e) That crossing: <E>/<n> - mu against mu.
"""
import json

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from pyfrustrate import plotting
from pyfrustrate.io import logging_to
from pyfrustrate.provenance import for_job

SEED_MARKERS = ("o", "s", "^", "D", "v")


def load(path):
    with open(path) as f:
        return json.load(f)


SHORT_STATE = {"one disk": "disk", "two disks": "2 disks", "a fibre wrapping the box": "fibre"}


def two_sided_columns(checks):
    """The checks grouped into columns, one per (predicted state, competitor, nu) in the order they
    come: the paper profile's three Gamma of one pair share a column (told apart by colour), so
    that eight checks fit a panel of print width."""
    columns = {}
    for check in checks:
        columns.setdefault((check["predicted_state"], check["competitor_state"], check["nu"]), []).append(check)
    return list(columns.items())


def draw_two_sided(ax, checks, colors):
    """One column per pair of states and nu, one marker per check and seed: the competitor's final
    energy minus the predicted run's with the same seed (above zero: the prediction holds on that
    side), filled where the predicted state persisted, a cross where it did not. A check at a Gamma
    without a colour of (a)-(b) is grey, its Gamma written under its column."""
    columns = two_sided_columns(checks)
    labels = []
    for x, ((predicted, competitor, nu), group) in enumerate(columns):
        spread = np.linspace(-0.3, 0.3, len(group)) if len(group) > 1 else np.zeros(1)
        width = 0.24 / len(group)  # each check's seeds within its share of the column
        for dx_check, check in zip(spread, group):
            color = colors.get(check["Gamma"], "0.3")
            margin = np.array(check["competitor_energy_over_g"]) - np.array(check["predicted_energy_over_g"])
            offsets = np.linspace(-width, width, len(margin)) if len(margin) > 1 else np.zeros(1)
            for k, (dx, value, kept) in enumerate(zip(offsets, margin, check["persists"])):
                ax.plot(x + dx_check + dx, value, SEED_MARKERS[k % len(SEED_MARKERS)] if kept else "x", ms=4,
                        color=color, mec=color if kept else "#b2182b")
        label = (f"{SHORT_STATE.get(predicted, predicted)} vs\n{SHORT_STATE.get(competitor, competitor)}\n"
                 rf"$\nu$ = {nu:g}")
        uncoloured = sorted({c["Gamma"] for c in group if c["Gamma"] not in colors})
        if uncoloured:
            label += "\n" + rf"$\Gamma$ = {', '.join(f'{G:g}' for G in uncoloured)}"
        labels.append(label)
    ax.axhline(0.0, color="0.4", lw=0.6)
    low, high = ax.get_ylim()
    ax.set_ylim(min(low, -0.1 * high), max(high, 1.0) * 1.15)  # zero, the line a failure would cross, in view
    ax.set_xticks(range(len(columns)))
    ax.set_xticklabels(labels)
    ax.set_xlim(-0.5, max(len(columns), 1) - 0.5)
    ax.set_ylabel(r"$(E_{\rm competitor} - E_{\rm predicted})\,/\,g$")
    ax.set_title("two-sided checks")


def draw_key(ax, colors, seeds):
    """The key of (a)-(c), in the figure's sixth slot, so that no legend covers data: a colour per
    Gamma, the line styles of the ansatz and its optima, a marker per seed (in every panel)."""
    ax.axis("off")
    handles = [Line2D([], [], color=c, lw=1, label=rf"ansatz, $\Gamma$ = {G:g}") for G, c in colors.items()]
    handles += [Line2D([], [], color="0.3", lw=0.8, ls=":", label="ansatz optimum"),
                Line2D([], [], color="0.3", lw=0.8, ls="--", label="continuum optimum")]
    handles += [Line2D([], [], ls="none", marker=SEED_MARKERS[k % len(SEED_MARKERS)], ms=4, mfc="w", mec="0.3",
                       label=f"Monte Carlo, seed {seed}") for k, seed in enumerate(seeds)]
    ax.legend(handles=handles, loc="upper left", frameon=False, borderaxespad=0.0, handlelength=1.8,
              title="(a)-(c); seeds: every panel", alignment="left")


def grand_panels(axes, validation):
    """(d) <W>(mu) and (e) <E>/<n> - mu of the grand-canonical samples, mu relative to the
    ansatz's threshold."""
    samples, found = validation["grand_canonical"], validation["grand_canonical_W_star"]
    ax_width, ax_gap = axes
    if not samples:
        return
    threshold = found[0]["threshold_ansatz_over_g"]
    row_energy = np.array(found[0]["ansatz_row_energy_over_g"]) - threshold
    widths = np.arange(1, row_energy.size + 1)
    offsets = np.array([s["mu_over_g"] for s in samples]) - threshold
    # The ansatz's widths over the scan's range of mu, up to a few rows beyond the widest sample
    # (its last rows' energies crowd together as W grows).
    widest = max(s["W_mean"] + s["W_std"] for s in samples)
    shown = (row_energy >= offsets.min() - 0.05) & (row_energy <= offsets.max() + 0.05) & (widths <= widest + 6)
    # The ansatz's lines are labelled where they are drawn, the temperatures in (e)'s legend.
    ax_width.step(row_energy[shown], widths[shown], where="post", color="0.5", lw=1)
    ax_width.annotate(r"ansatz, $T$ = 0", (row_energy[shown][-1], widths[shown][-1]), xytext=(-4, 0),
                      textcoords="offset points", ha="right", va="top", color="0.4")
    ax_width.axhline(found[0]["W_ansatz"], color="0.5", lw=0.8, ls=":")
    ax_width.annotate(rf"ansatz $W^*$ = {found[0]['W_ansatz']}", (0.02, found[0]["W_ansatz"]),
                      xycoords=("axes fraction", "data"), xytext=(0, 2), textcoords="offset points", va="bottom",
                      color="0.4")
    temperatures = sorted({s["T_over_g"] for s in samples})
    colors = dict(zip(temperatures, ("#e7298a", "#66a61e", "#e6ab02")))
    seeds = sorted({s["seed"] for s in samples})
    for T in temperatures:
        for k, seed in enumerate(seeds):
            scan = [s for s in samples if s["T_over_g"] == T and s["seed"] == seed]
            mu = np.array([s["mu_over_g"] for s in scan]) - threshold
            marker = SEED_MARKERS[k % len(SEED_MARKERS)]  # the seeds' markers are the key's
            label = rf"$T$ = {T:g} g" if k == 0 else None
            ax_width.errorbar(mu, [s["W_mean"] for s in scan], yerr=[s["W_std"] for s in scan], fmt=marker, ms=4,
                              mfc="w", mec=colors[T], ecolor=colors[T], elinewidth=0.8, label=label)
            ax_gap.plot(mu, [s["energy_per_particle_over_g"] - s["mu_over_g"] for s in scan], marker + "-", ms=4,
                        mfc="w", mec=colors[T], color=colors[T], lw=0.8)
        record = next(r for r in found if r["T_over_g"] == T)
        for W, mu in zip(record["W_star"], record["mu_threshold_over_g"]):
            if W is not None:
                ax_width.plot(mu - threshold, W, "*", color=colors[T], ms=8)
                ax_gap.plot(mu - threshold, 0.0, "*", color=colors[T], ms=8)
    for ax in axes:
        ax.axvline(0.0, color="0.5", lw=0.8, ls="--")
        ax.set_xlabel(r"$(\mu - \min_W e)\,/\,g$")
    ax_gap.axhline(0.0, color="0.5", lw=0.8)
    ax_width.set_ylabel(r"fibre width $\langle W \rangle$ (rows)")
    ax_gap.set_ylabel(r"$(\langle E\rangle/\langle n\rangle - \mu)\,/\,g$")
    ax_width.set_title(rf"grand canonical, $\nu$ = {samples[0]['nu']:g}, $\Gamma$ = {samples[0]['Gamma']:g}")
    ax_gap.set_title(r"threshold: $\langle E\rangle/\langle n\rangle = \mu$")
    ax_width.yaxis.set_major_locator(MaxNLocator(integer=True))  # widths are whole rows
    star = Line2D([], [], ls="none", marker="*", ms=8, color="0.3",
                  label=r"$W^*$: $\langle E\rangle/\langle n\rangle = \mu$")
    handles, _ = ax_width.get_legend_handles_labels()
    ax_gap.legend(handles=handles + [star], loc="upper right", frameon=False)  # the crossing falls to the right


def layout():
    """The page at print width: (a)-(c) on top, (d)-(e) below, the key in the sixth slot."""
    width_cm, height_cm = plotting.PAGE_WIDTH_CM, 12.4
    fig = plotting.figure(width_cm, height_cm)

    def slot(column, bottom):
        return fig.add_axes([(1.5 + 5.8 * column) / width_cm, bottom / height_cm, 4.3 / width_cm, 4.3 / height_cm])

    return fig, [slot(k, 7.3) for k in range(3)], [slot(k, 1.1) for k in range(2)], slot(2, 1.1)


def main(validation_path, point_paths, outputs, provenance=None):
    validation = load(validation_path)
    points = {(p["scan"], p["nu"], p["Gamma"]): p for p in map(load, point_paths)}
    fig, axes, grand_axes, key_axes = layout()
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
            ax.plot(ansatz_sizes[shown], ansatz[shown] - reference, "-", color=color, lw=1)
            for k, energy in enumerate(record["energy_per_particle_over_g"]):
                ax.plot(sizes, np.array(energy) - reference, SEED_MARKERS[k % len(SEED_MARKERS)], ms=4, mfc="w",
                        mec=color)
            ax.axvline(best, color=color, lw=0.8, ls=":")
            ax.axvline(continuum, color=color, lw=0.8, ls="--")
        ax.set_xlabel("fibre width W (rows)" if scan == "fibre" else "disk size n (particles)")
        ax.set_ylabel(r"$(e - e^*_{\rm ansatz})\,/\,g$ per particle")
        nu = next(r["nu"] for r in validation["points"] if r["scan"] == scan)
        ax.set_title(("straight fibres" if scan == "fibre" else "disks") + rf", $\nu$ = {nu:g}")
        low, high = ax.get_ylim()
        ax.set_ylim(min(low, 0), high)
    draw_two_sided(axes[2], validation["two_sided"], colors)
    grand_panels(grand_axes, validation)
    seeds = sorted({seed for r in validation["points"] for seed in r["seeds"]})
    draw_key(key_axes, colors, seeds)
    for ax, letter in zip(axes + grand_axes, "abcde"):
        plotting.panel_label(ax, letter)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.validation[0], snakemake.input.points,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png], provenance=for_job(snakemake))  # noqa: F821
