"""Beyond the paper: Fig. 3b's three line scans of annealing runs repeated in a larger box, each
run judged by structure against the predicted ground state of its own box (ell = 5; issue 33,
item 3).

Top row, one panel per scan (the fibre scan at fixed nu, the disk scan at fixed nu, the nu scan
at fixed Gamma): each marker is one run (one per seed), its final energy above the box's
predicted ground state (ground_states.box_candidates: single aggregates, a fibre wrapping the
box, several aggregates apart or joined by necks, the gas) in bulk particle energies e_bulk. Filled: the run's structure
matches the prediction (ground_states.structure_verdict: aggregate count exact, fibre or disk as
predicted, a fibre's width within one row); half filled: it is the structure of another candidate
within the energy gate of the prediction (structure_within_gate); hollow: neither. Each panel's
title counts the runs whose structure matches and those within the gate. Green: within the energy gate
max(EQUILIBRATED_GAP e_bulk, GATE_BONDS bonds) (the grey band and, where two bonds are worth
more, the dashed line); orange: above it. Below: the final state of the first seed at every
distinct point of the scans (a point two scans share is drawn once; at most six a row), each
centred on its largest cluster, all on one scale, titled with its verdict.
"""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.ground_states import EQUILIBRATED_GAP, GATE_BONDS
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job
from pyfrustrate.montecarlo import largest_cluster_extent

SCANS = {"fibre": ("Gamma", plotting.LABELS["Gamma"], "fibre scan"),
         "disk": ("Gamma", plotting.LABELS["Gamma"], "disk scan"),
         "nu": ("nu", plotting.LABELS["nu"], "$\\nu$ scan")}
SEED_MARKERS = "osD^v<>p"
WITHIN, ABOVE = "#1b9e77", "#d95f02"  # runs within the criterion and above it (no phase colour)
SNAPSHOTS_PER_ROW = 6


def rows_of(scale, nu, Gamma):
    """Indices of the runs of the scale summary at (nu, Gamma), by seed."""
    return [k for k in np.argsort(scale["seed"], kind="stable")
            if abs(scale["nu"][k] - nu) < 1e-9 and abs(scale["Gamma"][k] - Gamma) < 1e-9]


def kind_words(kind, count):
    """``count`` aggregates of a kind (``ground_states.aggregate_kind``) in words: "2 disks"."""
    if str(kind) == "fused_disks":
        return "fused disks" if count == 1 else f"{count} clusters of fused disks"
    one, many = {"fiber": ("fibre", "fibres"), "disk": ("disk", "disks")}.get(str(kind), (str(kind), str(kind)))
    return f"{count} {one if count == 1 else many}"


def ground_label(scale, k):
    """The predicted structure of run ``k``'s box in words, written under its point: aggregates
    joined by necks that the classifier reads as fused disks are "4 fused disks"."""
    family = str(scale["ground_family"][k])
    label = plotting.structure_label(family)
    if family.startswith("fused") and str(scale["verdict_kind_predicted"][k]) == "fused_disks":
        label = label.replace("aggregates", "disks")
    return label


def verdict_text(scale, k):
    """A run's structure, the prediction's in brackets where it differs: e.g. "1 fibre, 9 rows (8)",
    "2 disks (1)", "6 fused disks (4)": six disks joined by necks where four are predicted,
    "3 fused disks (1 disk)": where one disk is predicted."""

    def words(kind, count, width, lobes):
        if np.isfinite(lobes) and count == 1:
            return f"{int(lobes)} fused disks"
        return kind_words(kind, count) + (f", {width:.0f} rows" if np.isfinite(width) else "")

    def value(name):  # NaN where the npz has no such column (runs judged before it existed)
        return float(scale[name][k]) if name in scale else np.nan

    count, kind = int(scale["verdict_count"][k]), str(scale["verdict_kind"][k])
    count_predicted, kind_predicted = int(scale["verdict_count_predicted"][k]), str(scale["verdict_kind_predicted"][k])
    width, lobes = value("verdict_width"), value("verdict_lobes")
    width_predicted, lobes_predicted = value("verdict_width_predicted"), value("verdict_lobes_predicted")
    text = words(kind, count, width, lobes)
    if kind != kind_predicted:
        return f"{text} ({words(kind_predicted, count_predicted, width_predicted, lobes_predicted)})"
    # Same kind: only what differs in brackets, the count first, then the size.
    if np.isfinite(lobes) and np.isfinite(lobes_predicted) and int(lobes) != int(lobes_predicted):
        return f"{text} ({int(lobes_predicted)})"
    if np.isfinite(width) and np.isfinite(width_predicted):
        text += f" ({width_predicted:.0f})"
    return text + (f" ({count_predicted})" if count_predicted != count else "")


def main(scale_path, run_paths, points, outputs, provenance=None):
    scale = load_npz(scale_path)
    runs = {(round(float(r["nu"]), 9), round(float(r["Gamma"]), 9), int(r["seed"])): r
            for r in (load_npz(p) for p in run_paths)}
    seeds = sorted({int(s) for s in scale["seed"]})
    n, box = int(scale["n"][0]), int(next(iter(runs.values()))["box"])
    scans = [s for s in SCANS if any(p[0] == s for p in points)]
    # Snapshots of the first seed at each distinct point (the scans share some).
    scans_at = {}
    for scan, nu, G in points:
        scans_at.setdefault((round(float(nu), 9), round(float(G), 9)), []).append(scan)
    shown = [(scans, nu, G, runs.get((nu, G, seeds[0]))) for (nu, G), scans in scans_at.items()]
    shown = [item for item in shown if item[3] is not None]
    # Page layout in cm, from the bottom: the snapshots (square, as wide as a column of them
    # allows, so that no blank band surrounds their drawings) and their three-line titles, room for
    # the scans' axis labels, the scans' axes and their titles.
    # At most SNAPSHOTS_PER_ROW in a row: the paper profile's seven points in one row left 2.5 cm
    # a snapshot, narrower than their titles.
    page_w = plotting.PAGE_WIDTH_CM
    rows = max(1, -(-len(shown) // SNAPSHOTS_PER_ROW))
    per_row = max(1, -(-len(shown) // rows))
    slot = (page_w - 0.3) / per_row
    side = min(slot - 0.15, 4.0)
    scans_bottom = 0.1 + rows * (side + 1.0) + 1.05
    scans_height = 3.9
    page_h = scans_bottom + scans_height + 0.7
    fig = plotting.figure(page_w, page_h)
    for i, scan in enumerate(scans):
        variable, label, title = SCANS[scan]
        ax = fig.add_axes([(1.4 + i * 5.7) / page_w, scans_bottom / page_h, 4.45 / page_w, scans_height / page_h])
        ax.axhspan(-1e9, EQUILIBRATED_GAP, color="0.88", zorder=0)
        ax.axhline(0, color="0.5", lw=0.6, zorder=1)
        xs, highest = [], EQUILIBRATED_GAP
        fixed = None
        for _, nu, G in (p for p in points if p[0] == scan):
            x = G if variable == "Gamma" else nu
            fixed = (r"$\nu$ = " + f"{nu:g}") if variable == "Gamma" else (r"$\Gamma$ = " + f"{G:g}")
            xs.append(x)
            for k in rows_of(scale, nu, G):
                gap, gate = float(scale["gap_ground"][k]), float(scale["verdict_gap_gate"][k])
                if gate > EQUILIBRATED_GAP:  # two bonds are worth more than the band
                    ax.plot([x - 0.04, x + 0.04], [gate, gate], "--", color="0.45", lw=0.7, zorder=2)
                m = SEED_MARKERS[seeds.index(int(scale["seed"][k])) % len(SEED_MARKERS)]
                color = WITHIN if bool(scale["verdict_gap_ok"][k]) else ABOVE
                match = bool(scale["verdict_structure_match"][k])
                # Half filled: the structure of another candidate within the gate of the prediction.
                fill = "full" if match else "left" if bool(scale["verdict_structure_within_gate"][k]) else "none"
                ax.plot(x, gap, m, ms=5, fillstyle=fill, mfc=color, mfcalt="w", mec=color, mew=1.1, zorder=3)
                highest = max(highest, gap, gate)
            ground = [ground_label(scale, k) for k in rows_of(scale, nu, G)][:1]
            if ground:  # a word a line: neighbouring points of the nu scan lie 0.2 apart
                ax.annotate(ground[0].replace(" ", "\n"), (x, 0),
                            xytext=(0, -4), textcoords="offset points", ha="center", va="top", fontsize=6,
                            color="0.35")
        margin = 0.2 * (max(xs) - min(xs) + 0.1)  # the outer structure labels inside the axes
        ax.set_xlim(min(xs) - margin, max(xs) + margin)
        ax.set_ylim(-0.4 * highest - 3, 1.12 * highest)  # room for a three-line structure label
        ax.set_xlabel(label)
        ax.set_ylabel(r"$E - E_\mathrm{ground}$ ($e_{\rm bulk}$)" if i == 0 else "")
        in_scan = [k for _, nu, G in (p for p in points if p[0] == scan) for k in rows_of(scale, nu, G)]
        matched = int(scale["verdict_structure_match"][in_scan].astype(bool).sum())
        gated = int(scale["verdict_gap_ok"][in_scan].astype(bool).sum())
        runs = len(in_scan)
        ax.set_title(f"{title}, {fixed}\n{matched} of {runs} in structure, {gated} in the gate")
        plotting.panel_label(ax, "abc"[i])
        if i == 0 and len(seeds) > 1:
            for s, seed in enumerate(seeds):
                ax.plot([], [], SEED_MARKERS[s % len(SEED_MARKERS)], ms=4, mfc="w", mec="0.3", label=f"seed {seed}")
            ax.legend(loc="upper left", handletextpad=0.2)
    # Each snapshot centred on its largest cluster, all on one scale (the largest extent of any).
    extents = [largest_cluster_extent(run["sites"], box) for *_, run in shown]
    half = max(0.5 * max(x1 - x0, y1 - y0) for (x0, y0), (x1, y1) in extents) + 2.0
    for j, ((scans, nu, G, run), ((x0, y0), (x1, y1))) in enumerate(zip(shown, extents)):
        row, column = divmod(j, per_row)
        in_row = min(per_row, len(shown) - row * per_row)  # a shorter last row is centred
        left = 0.15 + (column + 0.5 * (per_row - in_row)) * slot + 0.5 * (slot - side)
        bottom = 0.1 + (rows - 1 - row) * (side + 1.0)
        ax = fig.add_axes([left / page_w, bottom / page_h, side / page_w, side / page_h])
        plotting.draw_snapshot(run["sites"], box, ax=ax)
        ax.set_xlim(0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half)
        ax.set_ylim(0.5 * (y0 + y1) - half, 0.5 * (y0 + y1) + half)
        ax.set_xticks([])
        ax.set_yticks([])
        k = rows_of(scale, nu, G)[0]
        ax.set_title(f"$\\nu$ = {nu:g}, $\\Gamma$ = {G:g}\n{verdict_text(scale, k)}\n"
                     f"{float(scale['gap_ground'][k]):+.1f} $e_{{\\rm bulk}}$", fontsize=7)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.scale[0], snakemake.input.runs, snakemake.params.points,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
