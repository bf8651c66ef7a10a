"""Fig. 5: random-elasticity particles. (a) the nine distances that define a particle's shape,
each labelled at the midpoint of the corner pair it joins (random_particles.DISTANCE_PAIRS):
d1-d3 the yellow triangle, d4-d6 the red one, d7-d9 alternate hexagon sides; (b) the paper's
measurement of ell: a half-plane of particles coloured by deformation energy, and the excess
energy per particle against the distance from the edge, fitted, beside the exact slowest mode of
the layer-to-layer transfer problem; (c) ell against the predictor ell_pred of the supplement,
particles per hexagonal bin, equal axes (beside it, beyond the paper: the strip fit against the
exact ell); (d) the paper's form: the best fibre's W*/ell and disk's R*/ell of every particle
against Gamma, with the continuum lines; (e) beyond the paper: each particle's sizes over its own
continuum prediction (its own nu and ell) against Gamma over its own Gamma_max."""
import numpy as np

from pyfrustrate import continuum, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


def draw_distances(ax):
    eps = 0.15  # exaggerated mismatch, for the drawing only
    # The rest corners with the yellow (odd) slots pushed out and the red (even) ones pulled in.
    radius = np.where(np.arange(6) % 2, 1 + eps, 1 - eps)
    plotting.draw_distance_definitions(ax, rp.REST_CORNERS * radius[:, None], rp.DISTANCE_PAIRS, fontsize=7)
    ax.set_xlim(-0.9, 0.9)
    ax.set_ylim(-0.85, 0.9)
    ax.axis("off")


def draw_profile(fig, strip_ax, ax, fits):
    corners, energy = fits["example_corners"], fits["example_energy"]
    top = corners[:, :, 1].max()
    keep = corners[:, :, 1].mean(axis=1) > top - 10  # the rows near one edge: a half-plane's edge
    keep &= np.abs(corners[:, :, 0].mean(axis=1)) < 11
    polys = plotting.draw_hexagons(strip_ax, corners[keep], energy[keep], cmap="magma", linewidth=0.1)
    polys.set_clim(0, max(1.0, energy[keep].max()))
    strip_ax.axis("off")
    # The axes shrunk to the drawing's own aspect, centred on the profile's height with the colour
    # bar right under it: no blank band between the drawing and its bar.
    (x0, y0), (x1, y1) = corners[keep].reshape(-1, 2).min(axis=0), corners[keep].reshape(-1, 2).max(axis=0)
    strip_ax.set_xlim(x0, x1)
    strip_ax.set_ylim(y0, y1)
    box, fig_w, fig_h = strip_ax.get_position(), *fig.get_size_inches()
    height = box.width * fig_w * (y1 - y0) / (x1 - x0) / fig_h
    bar_gap, bar_height = 0.15 / 2.54 / fig_h, 0.25 / 2.54 / fig_h
    profile = ax.get_position()
    top = profile.y0 + profile.height / 2 + (height + bar_gap + bar_height) / 2
    strip_ax.set_position([box.x0, top - height, box.width, height])
    cax = fig.add_axes([box.x0, top - height - bar_gap - bar_height, box.width, bar_height])
    bar = fig.colorbar(polys, cax=cax, orientation="horizontal")
    bar.set_label(plotting.LABELS["energy"])
    d, excess = fits["example_distance"], np.abs(fits["example_excess"])
    ok = excess > 0
    ax.semilogy(d[ok], excess[ok], "o", ms=2.5, color="k", label="strip rows")
    for length, style, label in ((fits["example_fitted"], "-", "fit"), (fits["example_ell"], "--", "transfer")):
        anchor = np.argmin(np.abs(d - 3 * length))
        ax.semilogy(d, excess[anchor] * np.exp(-(d - d[anchor]) / length), style, color="#d3002d", lw=1,
                    label=rf"{label}: $\ell={length:.2f}$")
    shown_depth = min(d[-1], 8 * fits["example_ell"])
    # The energy range of the rows drawn (deeper rows sink to rounding and would stretch the axis).
    drawn = ok & (d <= shown_depth)
    ax.set_ylim(max(0.3 * excess[drawn].min(), 1e-8), 2 * excess.max())
    ax.set_xlim(-0.05 * shown_depth, shown_depth)  # 0 clear of the corner
    ax.set_xlabel(f"distance from the edge ({plotting.LENGTH_UNIT})")
    ax.set_title("excess energy per particle")
    ax.set_ylabel(r"$|e - e_\mathrm{bulk}|/e_\mathrm{bulk}$")
    ax.legend(loc="lower left")


def draw_ell(ax, summary):
    """The paper's Fig. 5c, on equal logarithmic axes, with the median of ell / ell_pred."""
    ell, pred = summary["plotted_ell"].astype(float), summary["plotted_ell_pred"].astype(float)
    ok = (ell > 0) & (pred > 0)
    lo, hi = 0.05, 10.0
    bins = ax.hexbin(pred[ok], ell[ok], xscale="log", yscale="log", gridsize=40, bins="log", cmap="Greys", mincnt=1,
                     linewidths=0, extent=(np.log10(lo), np.log10(hi), np.log10(lo), np.log10(hi)))
    bar = ax.figure.colorbar(bins, cax=ax.inset_axes([0.55, 0.12, 0.4, 0.045]), orientation="horizontal")
    bar.ax.set_title("particles per bin", pad=2)
    bar.ax.minorticks_off()
    ax.plot([lo, hi], [lo, hi], color="#d3002d", lw=1.2)
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_aspect("equal")
    ax.set_xlabel(r"predicted $\ell^\mathrm{pred}$ (supplement)")
    ax.set_ylabel(r"$\ell$ (transfer problem)")
    r = np.corrcoef(np.log(pred[ok]), np.log(ell[ok]))[0, 1]
    ratio = np.median(ell[ok] / pred[ok])
    ax.text(0.04, 0.96, f"{ok.sum()} particles\ncorrelation of logs {r:.2f}\n"
            rf"median $\ell/\ell^\mathrm{{pred}}$ = {ratio:.2f}", transform=ax.transAxes, va="top")


def draw_fit_check(ax, fits):
    f, e = fits["fitted"], fits["exact"]
    ax.plot(e, f, ".", ms=3, color="#007e94")
    hi = np.nanmax(np.r_[e, f]) * 1.05
    ax.plot([0, hi], [0, hi], color="#d3002d", lw=0.8)
    ax.set_xlim(0, hi)
    ax.set_ylim(0, hi)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$\ell$ (transfer problem, exact)")
    ax.set_ylabel(r"$\ell$ (strip fit, the paper's protocol)")
    ax.text(0.04, 0.96, f"{np.isfinite(f).sum()} particles\nmedian ratio {np.nanmedian(f / e):.3f}",
            transform=ax.transAxes, va="top")


def continuum_size(kind, nu, Gamma):
    """Each particle's own continuum prediction (its nu; Gamma in absolute units), over ell."""
    return continuum.optimal_width(nu, Gamma) if kind == "fiber" else continuum.optimal_radius(nu, Gamma)


#: Fewest particles whose median (e) draws: fewer give one particle's curve, not a trend.
MIN_PARTICLES_PER_MEDIAN = 10


def draw_size_ratios(ax, sizes, kind):
    """W*/W*_continuum and R*/R*_continuum of each particle against its own prediction (its own
    nu and ell), over Gamma / Gamma_max: every particle out to where its bulk takes over. Sizes
    at the catalogue's largest member (capped) and Gamma where the continuum predicts no finite
    aggregate are left out; both are counted."""
    x = sizes["Gamma_relative"]
    key, symbol = ("width", "W") if kind == "fiber" else ("radius", "R")
    G = sizes["Gamma_max"][:, None] * x[None, :]
    with np.errstate(all="ignore"):
        predicted = continuum_size(kind, sizes["nu"][:, None], G) * sizes["ell"][:, None]
        ratio = sizes[f"{key}_relative"] / predicted
    capped = sizes[f"{key}_relative_capped"]
    usable = np.isfinite(ratio) & (ratio > 0) & ~capped & (x[None, :] > 0) & (x[None, :] < 1)
    ratio = np.where(usable, ratio, np.nan)
    colour = plotting.PHASE_COLORS[kind]
    for row in ratio[:60]:
        ax.plot(x, row, color=colour, lw=0.4, alpha=0.3)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for subset, style, label in ((np.ones(len(ratio), bool), "-", "median, all"),
                                     (sizes["ell"] >= 1.5, "--", r"median, $\ell \geq 1.5$")):
            if subset.sum() < MIN_PARTICLES_PER_MEDIAN:
                continue  # a median of a handful of particles is one particle's curve, not a trend
            rows = ratio[subset]
            enough = np.sum(np.isfinite(rows), axis=0) >= max(5, 0.2 * len(rows))
            med = np.nanmedian(rows, axis=0)
            ax.plot(x[enough], med[enough], style, color="k", lw=1.2, label=f"{label} ({subset.sum()})")
            if style == "-":
                lo, hi = np.nanpercentile(rows, 25, axis=0), np.nanpercentile(rows, 75, axis=0)
                ax.fill_between(x[enough], lo[enough], hi[enough], color="k", alpha=0.12, lw=0, label="quartiles, all")
    ax.axhline(1.0, color="#d3002d", lw=1.2, label="own continuum prediction")
    ax.set_yscale("log")
    ax.set_ylim(0.2, 5)
    ticks = [0.25, 0.5, 1, 2, 4]
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_xlim(0, 1)
    ax.set_xlabel(r"$\Gamma/\Gamma_\mathrm{max}$ (each particle's own)")
    ax.set_ylabel(rf"${symbol}^*/{symbol}^*_\mathrm{{continuum}}(\nu, \ell)$")
    defined = np.isfinite(predicted) & (x[None, :] > 0) & (x[None, :] < 1)
    ax.text(0.98, 0.96, f"capped: {100 * capped[defined].mean():.0f} % of defined points\n"
            f"no finite continuum optimum: {100 * (1 - defined[:, 1:-1].mean()):.0f} %",
            transform=ax.transAxes, ha="right", va="top", fontsize=6)  # top right: above every curve's end
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2)


def draw_sizes_over_ell(ax, sizes, kind, nus=(0.0, 0.5, 0.9)):
    """The paper's Fig. 5d: each particle's best fibre width W*/ell (disk radius R*/ell) at each
    Gamma (points; the catalogue's largest member left out: a lower bound only), with the
    continuum optimum in red (one line for fibres, which does not depend on nu; one per nu in
    ``nus`` for disks)."""
    key, symbol = ("width", "W") if kind == "fiber" else ("radius", "R")
    G = sizes["Gamma"]
    value = sizes[key] / sizes["ell"][:, None]
    keep = np.isfinite(value) & (value > 0) & ~sizes[f"{key}_capped"]
    plotting.draw_size_points(ax, G, value, keep, plotting.PHASE_COLORS[kind])
    line = np.linspace(0, 1.2, 400)
    if kind == "fiber":
        ax.plot(line, continuum.optimal_width(0.5, line), color="#d3002d", lw=1.2, label="continuum")
    else:
        for nu, style in zip(nus, ("-", "--", ":")):
            ax.plot(line, continuum.optimal_radius(nu, line), style, color="#d3002d", lw=1.2,
                    label=rf"continuum, $\nu$ = {nu:g}")
    ax.set_xlim(0, 1.2)
    ax.set_ylim(0, 8)
    ax.set_xlabel(plotting.LABELS["Gamma"])
    ax.set_ylabel(plotting.LABELS[symbol])
    ax.legend(loc="upper left")


def main(summary_path, fits_path, size_paths, outputs, provenance=None):
    summary, fits = load_npz(summary_path), load_npz(fits_path)
    parts = [load_npz(p) for p in size_paths]
    sizes = {k: np.concatenate([s[k] for s in parts]) for k in
             ("width_relative", "radius_relative", "width_relative_capped", "radius_relative_capped", "Gamma_max",
              "ell", "nu", "width", "radius", "width_capped", "radius_capped")}
    sizes["Gamma_relative"] = parts[0]["Gamma_relative"]
    sizes["Gamma"] = parts[0]["Gamma"]
    width, height = plotting.PAGE_WIDTH_CM, 23.0
    fig = plotting.figure(width, height)

    def rect(left, bottom, w, h):
        return [left / width, bottom / height, w / width, h / height]

    ax = fig.add_axes(rect(0.2, 18.1, 4.2, 4.4))
    draw_distances(ax)
    plotting.panel_label(ax, "a", at_cm=(0.1, height - 0.1))
    strip = fig.add_axes(rect(4.8, 18.0, 5.6, 4.6))  # height and place set by draw_profile
    profile = fig.add_axes(rect(12.0, 18.7, 5.5, 3.7))
    draw_profile(fig, strip, profile, fits)
    plotting.panel_label(strip, "b", at_cm=(4.8, height - 0.1))

    # The pair of square panels centred on the page, each with room for its axis labels.
    ax = fig.add_axes(rect(3.0, 11.9, 5.1, 5.1))
    draw_ell(ax, summary)
    plotting.panel_label(ax, "c", dx_pt=-6 - (3.0 - 1.4) * 72 / 2.54)  # in line with (d) and (e), whose axes start at 1.4 cm
    draw_fit_check(fig.add_axes(rect(10.8, 11.9, 5.1, 5.1)), fits)

    ax_w, ax_r = fig.add_axes(rect(1.4, 6.6, 6.6, 4.0)), fig.add_axes(rect(10.4, 6.6, 6.6, 4.0))
    draw_sizes_over_ell(ax_w, sizes, "fiber")
    draw_sizes_over_ell(ax_r, sizes, "disk")
    ax_w.set_title(f"best fibre, {len(sizes['ell'])} random particles")
    ax_r.set_title("best disk")
    plotting.panel_label(ax_w, "d")

    ax_w, ax_r = fig.add_axes(rect(1.4, 0.9, 6.6, 3.9)), fig.add_axes(rect(10.4, 0.9, 6.6, 3.9))
    draw_size_ratios(ax_w, sizes, "fiber")
    draw_size_ratios(ax_r, sizes, "disk")
    plotting.panel_label(ax_w, "e", dy_pt=16)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, snakemake.input.fits[0], snakemake.input.sizes,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
