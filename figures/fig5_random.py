"""Fig. 5: random-elasticity particles. (a) the nine distances that define a particle's shape;
(b) the paper's measurement of ell: excess energy per particle against the distance from the
edge of a half-plane (a wide strip), fitted, beside the exact slowest mode of the
layer-to-layer transfer problem; (c) ell against the predictor ell_pred of the supplement
(inset: the strip fit against the exact ell); (d) optimal fibre width and disk radius over ell
against Gamma, with the continuum predictions (red)."""
import numpy as np

from pyfrustrate import continuum, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to


def draw_distances(ax):
    eps = 0.15  # exaggerated mismatch, for the drawing only
    angles = np.deg2rad(30 + 60 * np.arange(6))
    radius = np.where(np.arange(6) % 2, 1 + eps, 1 - eps) / np.sqrt(3)
    c = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
    hexagon = np.vstack([c, c[:1]])
    ax.plot(*hexagon.T, color=plotting.BLUE_SPRING, lw=0.6, ls=":", zorder=0)
    for i, ((a, b), color) in enumerate(zip(rp.DISTANCE_PAIRS, plotting.DISTANCE_COLORS)):
        ax.plot(*c[[a, b]].T, color=color, lw=1.6, zorder=1)
        # Label beside the segment, on the side away from the centre.
        mid = 0.5 * (c[a] + c[b])
        normal = np.array([-(c[b] - c[a])[1], (c[b] - c[a])[0]])
        normal /= np.linalg.norm(normal)
        normal *= np.sign(normal @ mid) if abs(normal @ mid) > 1e-9 else 1
        offset = 0.11 if i >= 6 else 0.07
        ax.text(*(mid + offset * normal), rf"$d_{i + 1}$", ha="center", va="center", fontsize=7,
                color="k", bbox=dict(boxstyle="round,pad=0.05", fc="w", ec="none", alpha=0.7))
    ax.scatter(*c.T, c=plotting.CORNER_COLORS, s=22,
               edgecolors="k", linewidths=0.5, zorder=2)
    ax.set_aspect("equal")
    ax.set_xlim(-0.85, 0.85)
    ax.set_ylim(-0.8, 0.85)
    ax.axis("off")


def draw_profile(fig, strip_ax, ax, fits):
    corners, energy = fits["example_corners"], fits["example_energy"]
    top = corners[:, :, 1].max()
    keep = corners[:, :, 1].mean(axis=1) > top - 10  # the rows near one edge: a half-plane's edge
    keep &= np.abs(corners[:, :, 0].mean(axis=1)) < 11
    polys = plotting.draw_hexagons(strip_ax, corners[keep], energy[keep], cmap="magma", linewidth=0.1)
    polys.set_clim(0, max(1.0, energy[keep].max()))
    strip_ax.axis("off")
    bar = fig.colorbar(polys, ax=strip_ax, orientation="horizontal", fraction=0.08, pad=0.03, aspect=30)
    bar.set_label(r"deformation energy $e/e_\mathrm{bulk}$", fontsize=7)
    bar.ax.tick_params(labelsize=6)
    d, excess = fits["example_distance"], np.abs(fits["example_excess"])
    ok = excess > 0
    ax.semilogy(d[ok], excess[ok], "o", ms=2.5, color="k", label="strip rows")
    for length, style, label in ((fits["example_fitted"], "-", "fit"), (fits["example_ell"], "--", "transfer")):
        anchor = np.argmin(np.abs(d - 3 * length))
        ax.semilogy(d, excess[anchor] * np.exp(-(d - d[anchor]) / length), style, color="#d3002d", lw=1,
                    label=rf"{label}: $\ell={length:.2f}$")
    ax.set_ylim(max(excess[ok].min(), 1e-8), 2 * excess.max())
    ax.set_xlim(0, min(d[-1], 8 * fits["example_ell"]))
    ax.set_xlabel("distance from the edge")
    ax.set_ylabel(r"$|e - e_\mathrm{bulk}|/e_\mathrm{bulk}$")
    ax.legend(frameon=False, fontsize=6)


def draw_ell(ax, summary):
    ell, pred = summary["plotted_ell"].astype(float), summary["plotted_ell_pred"].astype(float)
    ok = (ell > 0) & (pred > 0)
    ax.hexbin(pred[ok], ell[ok], xscale="log", yscale="log", gridsize=45, bins="log", cmap="Greys", mincnt=1,
              linewidths=0)
    line = np.array([0.05, 20])
    ax.plot(line, line, color="#d3002d", lw=1.2)
    ax.set_xlim(0.05, 10)
    ax.set_ylim(0.1, 10)
    ax.set_xlabel(r"$\ell^\mathrm{pred}$ (supplement Eq. S23)")
    ax.set_ylabel(r"$\ell$ (transfer problem)")
    r = np.corrcoef(np.log(pred[ok]), np.log(ell[ok]))[0, 1]
    ax.text(0.04, 0.96, f"{ok.sum()} particles\ncorr(log) = {r:.2f}", transform=ax.transAxes, va="top", fontsize=6)


def draw_fit_check(ax, fits):
    f, e = fits["fitted"], fits["exact"]
    ax.plot(e, f, ".", ms=3, color="#007e94")
    hi = np.nanmax(np.r_[e, f]) * 1.05
    ax.plot([0, hi], [0, hi], color="#d3002d", lw=0.8)
    ax.set_xlim(0, hi)
    ax.set_ylim(0, hi)
    ax.set_xlabel(r"$\ell$ (transfer problem, exact)")
    ax.set_ylabel(r"$\ell$ (strip fit, the paper's protocol)")
    ax.text(0.04, 0.96, f"{np.isfinite(f).sum()} particles\nmedian ratio {np.nanmedian(f / e):.3f}",
            transform=ax.transAxes, va="top", fontsize=6)


def draw_sizes(ax, sizes, kind):
    G = sizes["Gamma"]
    key, symbol = ("width", "W") if kind == "fiber" else ("radius", "R")
    values = np.where(G[None, :] < sizes["Gamma_max"][:, None], sizes[key] / sizes["ell"][:, None], np.nan)
    for row in values[:60]:
        ax.step(G, row, where="mid", color=plotting.PHASE_COLORS[kind], lw=0.4, alpha=0.35)
    with np.errstate(all="ignore"):
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            median = np.nanmedian(values, axis=0)
    enough = np.sum(np.isfinite(values), axis=0) >= max(5, 0.2 * len(values))
    ax.plot(G[enough], median[enough], color="k", lw=1.2, label="median")
    if kind == "fiber":
        ax.plot(G, continuum.optimal_width(0.5, G), color="#d3002d", lw=1.4, label="continuum")
    else:
        for nu, style in ((0.0, "-"), (0.5, "--")):
            ax.plot(G, continuum.optimal_radius(nu, G), style, color="#d3002d", lw=1.2, label=rf"continuum $\nu={nu:g}$")
    ax.set_xlim(0, 1.3)
    ax.set_ylim(0, 6)
    ax.set_xlabel(r"$\Gamma$")
    ax.set_ylabel(rf"${symbol}^*/\ell$")
    ax.legend(frameon=False, fontsize=6, loc="upper left")


def main(summary_path, fits_path, size_paths, outputs):
    summary, fits = load_npz(summary_path), load_npz(fits_path)
    parts = [load_npz(p) for p in size_paths]
    sizes = {k: np.concatenate([s[k] for s in parts]) for k in ("width", "radius", "Gamma_max", "ell")}
    sizes["Gamma"] = parts[0]["Gamma"]
    fig = plotting.figure(17.8, 16.0)
    grid = fig.add_gridspec(3, 4, height_ratios=[1, 1.1, 1], hspace=0.7, wspace=0.6)
    ax = fig.add_subplot(grid[0, 0])
    draw_distances(ax)
    plotting.panel_label(ax, "a")
    strip = fig.add_subplot(grid[0, 1:3])
    profile = fig.add_subplot(grid[0, 3])
    draw_profile(fig, strip, profile, fits)
    plotting.panel_label(strip, "b")
    ax = fig.add_subplot(grid[1, 0:2])
    draw_ell(ax, summary)
    plotting.panel_label(ax, "c")
    draw_fit_check(fig.add_subplot(grid[1, 2:4]), fits)
    ax_w, ax_r = fig.add_subplot(grid[2, 0:2]), fig.add_subplot(grid[2, 2:4])
    draw_sizes(ax_w, sizes, "fiber")
    draw_sizes(ax_r, sizes, "disk")
    ax_w.set_title(f"best fibre, {len(sizes['ell'])} random particles", fontsize=7)
    ax_r.set_title("best disk", fontsize=7)
    plotting.panel_label(ax_w, "d")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, snakemake.input.fits[0], snakemake.input.sizes,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
