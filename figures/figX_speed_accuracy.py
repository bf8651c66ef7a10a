"""Beyond the paper: the speed/accuracy knob of `relax`, measured. Relative error of the
relaxed energy against Newton at tol 1e-12, against wall time (min over repeats, no cache), for
the linear solve, Newton and L-BFGS (from the bulk reference or the linear solution), at
tolerances 1e-2 ... 1e-10; one panel per aggregate and particle. Newton's cost hardly depends
on the tolerance: its points stand in a near-vertical line. Dotted: a relative error of 1e-8."""
import csv
import string
from collections import defaultdict

import numpy as np
from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

from pyfrustrate import plotting
from pyfrustrate.io import logging_to
from pyfrustrate.provenance import for_job

# Colour, marker and legend label of each method (colours apart from the phase colours).
STYLES = {"linear": ("k", "s", "linear solve"), "lbfgs": ("#1b9e77", "o", "L-BFGS from the bulk"),
          "lbfgs warm": ("#d95f02", "^", "L-BFGS from the linear solve"), "newton": ("#7570b3", "D", "Newton")}


def family(method, start):
    if method.startswith("newton"):
        return "newton"
    if method.startswith("lbfgs"):
        return "lbfgs warm" if start == "linear" else "lbfgs"
    return "linear"


def main(csv_path, outputs, provenance=None):
    with open(csv_path) as fh:  # the first line is a comment: the run's provenance
        rows = [r for r in csv.DictReader(line for line in fh if not line.startswith("#")) if r["diverged"] == "False"]
    panels = defaultdict(list)
    for r in rows:
        panels[(r["topology"], r["nu"], r["eps"])].append(r)
    keys = sorted(panels, key=lambda k: (k[0], float(k[1]), float(k[2])))
    # One column per mismatch when the benchmark measured several (the full run: each row one
    # aggregate and particle), else two columns.
    eps_count = len({k[2] for k in keys})
    cols = eps_count if eps_count > 1 else min(2, len(keys))
    grid_rows = (len(keys) + cols - 1) // cols
    fig = plotting.figure(plotting.PAGE_WIDTH_CM, min(plotting.MAX_HEIGHT_CM, 1.0 + (5.5 if cols < 3 else 4.6) * grid_rows))
    for n, key in enumerate(keys):
        ax = fig.add_subplot(grid_rows, cols, n + 1)
        series = defaultdict(list)
        for r in panels[key]:
            series[family(r["method"], r["start"])].append((float(r["t_min"]), max(float(r["rel_error"]), 1e-16)))
        for name, points in series.items():
            t, err = np.array(sorted(points, key=lambda p: -p[1])).T
            color, marker, label = STYLES[name]
            ax.loglog(1e3 * t, err, marker=marker, color=color, ms=3.5, lw=0.8, label=label)
        ax.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.axhline(1e-8, color="0.7", lw=0.6, ls=":", zorder=0)
        ax.set_title(rf"{key[0].replace('_', ' ').replace('=', ' = ')}, $\nu$ = {key[1]}, $\epsilon$ = {key[2]}")
        plotting.panel_label(ax, string.ascii_lowercase[n])
        ax.set_xlabel("time (ms)")
        if n % cols == 0:
            ax.set_ylabel("relative energy error")
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="upper center", ncol=4)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.9 / (fig.get_size_inches()[1] * 2.54)))  # 0.9 cm for the legend
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
