"""Fig. S2: optimal fibre width W* and disk radius R* of random particles in particle spacings,
against the line tension: the data of Fig. 5d without the rescaling by ell, so that the sizes
scatter widely at equal line tension. Sizes at the catalogue's largest member (the optimum may
lie beyond) are drawn in grey and counted."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job

GAMMA_SHOWN = 1.2  # the line tensions of Fig. 5d


def main(size_paths, outputs, provenance=None):
    parts = [load_npz(p) for p in size_paths]
    d = {k: np.concatenate([s[k] for s in parts]) for k in ("width", "radius", "width_capped", "radius_capped", "ell")}
    G = parts[0]["Gamma"]
    fig = plotting.figure(plotting.PAGE_WIDTH_CM, 7.0)
    for col, (key, symbol, kind) in enumerate((("width", "W", "fiber"), ("radius", "R", "disk"))):
        ax = fig.add_subplot(1, 2, col + 1)
        value, capped = d[key], d[f"{key}_capped"]
        shown = np.isfinite(value) & (value > 0) & (G <= GAMMA_SHOWN)[None, :]
        plotting.draw_size_points(ax, G, value, shown & ~capped, plotting.PHASE_COLORS[kind])
        plotting.draw_size_points(ax, G, value, shown & capped, "0.55", alpha=0.5)
        share = (shown & capped).sum() / max(shown.sum(), 1)
        name = "fibre" if kind == "fiber" else "disk"
        ax.set_xlim(0, GAMMA_SHOWN)
        ax.set_ylim(0, None)
        ax.set_xlabel(plotting.LABELS["Gamma"])
        ax.set_ylabel(rf"${symbol}^*$ ({plotting.LENGTH_UNIT})")
        ax.set_title(f"best {name}, {len(d['ell'])} random particles\n"
                     f"grey: at the catalogue's largest {name} ({100 * share:.0f} % of points)")
        plotting.panel_label(ax, "ab"[col])
    fig.tight_layout(h_pad=0, w_pad=2)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.sizes, [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
