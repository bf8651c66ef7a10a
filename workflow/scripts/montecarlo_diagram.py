"""Monte Carlo phase diagram (beyond the paper): the kind of the largest aggregate at the end of
each annealing run of the grid (montecarlo.classify_aggregate)."""
import numpy as np

from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.montecarlo import classify_aggregate

with logging_to(snakemake.log[0]):  # noqa: F821
    rows = []
    for path in snakemake.input:  # noqa: F821
        r = load_npz(path)
        kind, size = classify_aggregate(r["sites"], int(r["box"]))
        rows.append((float(r["nu"]), float(r["Gamma"]), kind, size, int(r["n"])))
        print(f"nu={rows[-1][0]:g} Gamma={rows[-1][1]:g}: {kind} (largest cluster {size} of {rows[-1][4]})")
    nu, Gamma, kind, size, n = (np.array(c) for c in zip(*rows))
    save_npz(snakemake.output[0], nu=nu, Gamma=Gamma, kind=kind.astype(str), size=size, n=n)  # noqa: F821
