"""Fig. S2: optimal fibre width W* and disk radius R* of random particles in numbers of
particles, against Gamma / Gamma_max: without the rescaling by ell of Fig. 5d the sizes scatter
widely at equal line tension."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def main(size_paths, outputs):
    parts = [load_npz(p) for p in size_paths]
    d = {k: np.concatenate([s[k] for s in parts]) for k in ("width_relative", "radius_relative", "ell")}
    x = parts[0]["Gamma_relative"]
    fig = plotting.figure(17.8, 7.0)
    for col, (key, symbol, kind) in enumerate((("width_relative", "W", "fiber"), ("radius_relative", "R", "disk"))):
        ax = fig.add_subplot(1, 2, col + 1)
        for row in d[key]:
            ax.step(x[:-1], row[:-1], where="mid", lw=0.5, alpha=0.4, color=plotting.PHASE_COLORS[kind])
        ax.set_xlim(0, 1)
        ax.set_ylim(0, None)
        ax.set_xlabel(r"$\Gamma/\Gamma_\mathrm{max}$")
        ax.set_ylabel(rf"${symbol}^*$ (particle spacings)")
        ax.set_title(f"best {'fibre' if kind == 'fiber' else 'disk'}, {len(d['ell'])} random particles", fontsize=8)
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.sizes, [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
