"""The paper's route to ell (Fig. 5b): the edge energy profile of a relaxed strip, fitted, for a
subsample of random particles, beside the exact transfer-problem ell; and one example profile."""
import numpy as np
from tqdm.auto import tqdm

from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.relaxation import relaxed_drawing
from pyfrustrate.topology import fiber

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
FIT_EPS = s["fit_eps"]  # the fit reads excess energies down to ~1e-4 of the bulk value: stay linear
with logging_to(snakemake.log[0]):  # noqa: F821
    summary = load_npz(snakemake.input[0])  # noqa: F821
    index = summary["plotted_index"][: s["fits"]]
    fitted = np.full(len(index), np.nan)
    for k, i in enumerate(tqdm(index, desc="strip fits", unit="particle", mininterval=2)):
        try:
            fitted[k] = rp.fitted_boundary_layer_length(rp.RandomHexagon.draw(s["seed"], int(i), eps=FIT_EPS))
        except RuntimeError as err:
            print(f"particle {i}: {err}")
    exact = summary["plotted_ell"][: s["fits"]].astype(float)
    print(f"fitted/exact: median {np.nanmedian(fitted / exact):.4f}, failed fits {int(np.isnan(fitted).sum())}")

    # Example (panel b): the particle of the subsample with ell nearest fit_example_ell.
    example = int(summary["plotted_index"][np.argmin(np.abs(summary["plotted_ell"] - s["fit_example_ell"]))])
    particle = rp.RandomHexagon.draw(s["seed"], example, eps=FIT_EPS)
    width = s["fit_strip_width"]
    distance, excess = rp.edge_energy_profile(particle, width)
    top = fiber(width, 0, curved=False)
    periods = range(-12, 13)  # enough images of the one-column cell to draw a patch of the strip
    corners, energy, _ = relaxed_drawing(particle, top, periods, method="linear")
    energy = energy / particle.bulk_energy_per_particle
    save_npz(snakemake.output[0], provenance=for_job(snakemake), index=index, fitted=fitted, exact=exact,  # noqa: F821
             example_index=example, example_ell=particle.boundary_layer_length,
             example_fitted=rp.fitted_boundary_layer_length(particle), example_distance=distance,
             example_excess=excess, example_corners=corners, example_energy=energy)
