"""
Speed against accuracy: one scene by each method and tolerance
===============================================================

:func:`pyfrustrate.relax` has three methods (see :doc:`../topics/relaxation`): Newton (the
default), L-BFGS, and a single linear solve whose error is of order ``eps**2``. The exact methods
stop when the largest force is below ``tol`` times ``particle.force_scale``. Here one disk is
relaxed by each, and the relative energy error against a tight reference is set against the
time taken. (The workflow's ``figX_speed_accuracy`` does the same on larger scenes.)
"""

import time
import warnings

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter, ScalarFormatter

import pyfrustrate as pf
from pyfrustrate import topology

particle = pf.Hexagon.from_continuum(ell=5, nu=0.9, eps=0.02)
scene = topology.disk(12)
reference = pf.relax(particle, scene, method="newton", tol=1e-12).energy


def timed(**options):
    """Best of three wall-clock times of one relaxation, and its relative energy error."""
    times = []
    for _ in range(3):
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pf.ConvergenceWarning)
            result = pf.relax(particle, scene, **options)
        times.append(time.perf_counter() - start)
    return min(times), abs(result.energy - reference) / reference


tolerances = [1e-2, 1e-3, 1e-4, 1e-6, 1e-8]
rows = {"linear": [timed(method="linear")]}
rows["newton"] = [timed(method="newton", tol=t) for t in tolerances]
rows["lbfgs"] = [timed(method="lbfgs", tol=t) for t in tolerances]
for method, points in rows.items():
    for i, (seconds, error) in enumerate(points):
        tol = "-" if method == "linear" else f"{tolerances[i]:g}"
        print(f"{method:7s} tol {tol:>6s}: {seconds * 1e3:7.2f} ms, relative error {error:.1e}")

# %%
# Newton reaches round-off accuracy in a few steps; the linear solve is the fastest and its
# error is set by ``eps`` alone; L-BFGS needs more iterations for the same tolerance.

fig, ax = plt.subplots(figsize=(5, 3.6))
for method, marker in (("linear", "s"), ("newton", "o"), ("lbfgs", "^")):
    seconds, errors = np.array(rows[method]).T
    ax.loglog(seconds * 1e3, np.maximum(errors, 1e-16), marker + "-", label=method)
ax.xaxis.set_major_formatter(ScalarFormatter())
ax.xaxis.set_minor_formatter(NullFormatter())
ax.set(xlabel="time per relaxation (ms)", ylabel="relative energy error",
       title=f"disk of {scene.n_particles} particles, eps = {particle.eps}")
ax.legend(frameon=False)
fig.tight_layout()
