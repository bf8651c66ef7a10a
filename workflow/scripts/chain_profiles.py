"""1D toy model (Fig. 1): relaxed shift profiles against the exact sinh form, a drawn chain, and
the fitted boundary-layer length against main text Eq. (3) over four decades of kc/k."""
import numpy as np

from pyfrustrate import chain, continuum
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    k, eps, n = s["k"], s["eps"], s["n"]
    profiles, exact = [], []
    for ratio in s["profile_kc_over_k"]:
        r = chain.relax(n, k, ratio * k, eps)
        print(f"profile kc/k={ratio}: converged={r.converged} iterations={r.iterations}")
        profiles.append(r.shift)
        exact.append(chain.analytic_shift(n, k, ratio * k, eps))

    drawn = chain.relax(s["drawing_n"], k, s["drawing_kc_over_k"] * k, s["drawing_eps"])

    scan = np.geomspace(s["scan_kc_over_k_min"], s["scan_kc_over_k_max"], s["scan_count"])
    ell_theory = continuum.chain_ell(scan)
    ell_fit = []
    for ratio, ell in zip(scan, ell_theory):
        length = int(2 * max(20, np.ceil(6 * ell)))  # >= 12 ell: both edges' layers fit inside
        r = chain.relax(length, k, ratio * k, eps)
        ell_fit.append(chain.fit_decay_length(r.shift))
        print(f"scan kc/k={ratio:.3g}: n={length} ell={ell:.4g} fitted={ell_fit[-1]:.4g} converged={r.converged}")

    save_npz(snakemake.output[0], provenance=for_job(snakemake),  # noqa: F821
             n=n, eps=eps, profile_kc_over_k=np.array(s["profile_kc_over_k"]), profiles=np.array(profiles),
             exact=np.array(exact), drawing_eps=s["drawing_eps"], drawing_kc_over_k=s["drawing_kc_over_k"],
             drawing_x_up=drawn.x_up, drawing_x_down=drawn.x_down, scan_kc_over_k=scan,
             scan_ell_theory=ell_theory, scan_ell_fit=np.array(ell_fit))
