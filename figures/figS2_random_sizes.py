"""Fig. S2: optimal fibre width W* and disk radius R* of random particles in numbers of
particles, against Gamma / Gamma_max: without the rescaling by ell of Fig. 5d the sizes scatter
widely at equal line tension. Sizes at the catalogue's largest member (the optimum may lie
beyond) are drawn in grey and counted: they are the vertical bundles."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


def main(size_paths, outputs, provenance=None):
    parts = [load_npz(p) for p in size_paths]
    d = {k: np.concatenate([s[k] for s in parts]) for k in
         ("width_relative", "radius_relative", "width_relative_capped", "radius_relative_capped", "ell")}
    x = parts[0]["Gamma_relative"]
    fig = plotting.figure(plotting.PAGE_WIDTH_CM, 7.0)
    for col, (key, symbol, kind) in enumerate((("width_relative", "W", "fiber"), ("radius_relative", "R", "disk"))):
        ax = fig.add_subplot(1, 2, col + 1)
        for row, capped in zip(d[key], d[f"{key}_capped"]):
            free = np.where(capped, np.nan, row)
            ax.step(x[:-1], free[:-1], where="mid", lw=0.5, alpha=0.4, color=plotting.PHASE_COLORS[kind])
            ax.plot(x[:-1][capped[:-1]], row[:-1][capped[:-1]], ".", ms=1.5, color="0.6")
        share = d[f"{key}_capped"][:, 1:-1].mean()
        name = "fibre" if kind == "fiber" else "disk"
        ax.set_xlim(0, 1)
        ax.set_ylim(0, None)
        ax.set_xlabel(r"$\Gamma/\Gamma_\mathrm{max}$")
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
