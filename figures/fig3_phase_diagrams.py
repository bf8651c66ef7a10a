"""Fig. 3: (a) the continuum phase diagram in the (Gamma, nu) plane (main text Eqs. 8, 11, 13),
shaded by the optimal fibre width W*/ell and disk radius R*/ell, each line drawn only where it is
a phase boundary; (b) the phase diagram of the pre-made aggregates of Fig. 4a at ell = 5 on the
same colour scales, with the continuum boundaries dashed, and the Monte Carlo runs at the
numbered symbols (squares: the sparse box; diamonds: the dense one), each drawn below as a
snapshot centred on its largest cluster, all on one length scale.

With ``convention = "supplement"`` (figX_fig3b_supplement_convention) the runs read Gamma in the
supplement's convention, gamma = 4 g/sqrt(3): each is drawn on our diagram at its Gamma in ours
(sqrt(3)/4 = 0.433 times the label), titled with both."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job
from pyfrustrate.montecarlo import largest_cluster_extent

# Marker of each box on the diagram, and the same glyph on its snapshot panels.
BOX_MARKERS = {"sparse": ("s", "\u25a1"), "dense": ("D", "\u25c7")}
WIDTH_CM, COLS = plotting.PAGE_WIDTH_CM, 5
# Vertical layout (cm from the bottom): snapshot rows, then the two diagrams and their legend.
SNAPSHOT_CM, SNAPSHOT_GAP_CM, DIAGRAM_CM = 2.75, 0.55, 5.2
NOTE_CM = 0.6  # two lines of 6 pt text under a snapshot

#: Where a symbol's number may go, in points from the symbol, in order of preference: right of
#: it, right above, right below, left above, left below, left of it.
LABEL_OFFSETS_PT = ((4, -3.5), (4, 3), (4, -11), (-11, 3), (-11, -11), (-11, -3.5))


def label_symbols(ax, symbols):
    """Draw the numbered run symbols of panel (b), 1, 2, ... in order: each number goes to the
    first of ``LABEL_OFFSETS_PT`` where it keeps a gap from the numbers already placed and covers no
    symbol, else where it clashes with fewest (boxes estimated in points at 7 pt: 4.2 pt per digit,
    7 pt high; a symbol 6 pt wide), so that rows of close symbols stay readable at the paper
    profile's density; symbols repeated at one point (seeds) put their numbers side by side."""
    to_points = ax.transData + ax.figure.dpi_scale_trans.inverted()  # data -> inches
    centres = [np.asarray(to_points.transform(point)) * 72 for point, _ in symbols]
    markers = [(c[0] - 3, c[1] - 3, c[0] + 3, c[1] + 3) for c in centres]
    placed, seen = [], {}
    for k, ((point, kind), centre) in enumerate(zip(symbols, centres), start=1):
        ax.plot(*point, BOX_MARKERS[kind][0], ms=5 if kind == "sparse" else 4.5, mfc="w", mec="k", mew=0.7, zorder=6)
        repeat = seen.get(point, 0)
        seen[point] = repeat + 1
        width = 4.2 * len(str(k))

        def box(offset):
            x, y = centre[0] + offset[0] + 6 * repeat, centre[1] + offset[1]
            return x, y, x + width, y + 7

        def clashes(b, gap=2.5):  # numbers closer than a gap read as one number ("123"); symbols: no overlap
            return sum(b[0] - g < o[2] and o[0] < b[2] + g and b[1] < o[3] and o[1] < b[3]
                       for others, g in ((placed, gap), (markers, 0.0)) for o in others)

        offset = min(LABEL_OFFSETS_PT, key=lambda o: clashes(box(o)))  # the first clear one, else the least crowded
        placed.append(box(offset))
        ax.annotate(str(k), point, xytext=(offset[0] + 6 * repeat, offset[1]), textcoords="offset points", fontsize=7,
                    color="w", fontweight="normal", zorder=7)


def run_title(k, run, convention):
    nu, G = float(run["nu"]), float(run["Gamma"])
    seed = f", seed {int(run['seed'])}" if int(run["seed"]) != 1 else ""
    if convention == "measured":
        return rf"{k}: $\Gamma$ = {G:g}, $\nu$ = {nu:g}{seed}"
    return (rf"{k}: $\Gamma_{{\rm paper}}$ = {G:g}, $\nu$ = {nu:g}" "\n"
            rf"(ours: $\Gamma$ = {float(run['Gamma_measured']):.2f}){seed}")


def gap_to_best_single(run, finite) -> float:
    gap = plotting.gap_to_best_single(run, finite)
    if gap is None:
        raise ValueError(f"finite_paths: no prediction for n = {int(run['n'])}, nu = {float(run['nu']):g}")
    return gap


def main(diagram_path, continuum_path, snapshot_paths, finite_paths, dense, sweeps, convention, outputs, provenance=None):
    diagram, continuum = load_npz(diagram_path), load_npz(continuum_path)
    finite = [load_npz(p) for p in finite_paths]
    runs = sorted((load_npz(p) for p in snapshot_paths),
                  key=lambda r: (-float(r["nu"]), float(r["Gamma"]), int(r["seed"])))
    kinds = ["dense" if (int(r["n"]), int(r["box"])) == tuple(dense) else "sparse" for r in runs]
    rows = int(np.ceil(len(runs) / COLS))
    gap_cm = SNAPSHOT_GAP_CM + (0.3 if convention != "measured" else 0.0)  # two-line titles
    snap_top = 0.15 + rows * (SNAPSHOT_CM + gap_cm)
    height = snap_top + 0.55 + 1.0 + DIAGRAM_CM + 1.0
    fig = plotting.figure(WIDTH_CM, height)
    diagram_bottom = snap_top + 0.55 + 1.0

    def rect(left, bottom, w, h):
        return [left / WIDTH_CM, bottom / height, w / WIDTH_CM, h / height]

    ax_a = fig.add_axes(rect(1.1, diagram_bottom, 5.6, DIAGRAM_CM))
    images = plotting.draw_continuum_diagram(ax_a, continuum)
    for text, xy, color in (("fibre", (0.55, 0.85), "w"), ("disk", (0.3, 0.15), "w"), ("bulk", (1.3, 0.6), "w")):
        ax_a.text(*xy, text, color=color, fontsize=8, ha="center", fontweight="bold")
    plotting.panel_label(ax_a, "a")

    ax_b = fig.add_axes(rect(8.0, diagram_bottom, 5.6, DIAGRAM_CM))
    _, phases = plotting.draw_ansatz_diagram(ax_b, diagram, continuum)
    ax_b.text(0.97, 0.04, rf"$\ell$ = {float(diagram['ell']):g}", transform=ax_b.transAxes, color="w", ha="right")
    plotting.panel_label(ax_b, "b")
    plotting.phase_legend(ax_a, phases, dashed_continuum=True, ncol=6, bbox_to_anchor=(1.13, 1.07))
    plotting.size_colorbars(fig, images, (14.6, diagram_bottom, DIAGRAM_CM - 0.45))

    label_symbols(ax_b, [((float(r["Gamma_measured"]), float(r["nu"])), kind) for r, kind in zip(runs, kinds)])

    fig.text(0.1 / WIDTH_CM, (snap_top + 0.1) / height,
             "Monte Carlo snapshots at the symbols of (b).   $\\Delta E$: final energy above the best single aggregate, "
             "in bulk particle energies $e_{\\rm bulk}$", va="bottom", fontsize=7)
    # Every panel on one scale, so that widths compare across panels: the largest extent of any
    # run's largest cluster, placed as draw_snapshot places it (centre in the box).
    # The bottom NOTE_CM of each panel holds its two-line note, under the drawing (a note over it
    # would hide the small clusters and single particles of the sparse box).
    aspect = (SNAPSHOT_CM - NOTE_CM) / (WIDTH_CM / COLS - 0.15)
    extents = [largest_cluster_extent(r["sites"], int(r["box"])) for r in runs]
    half = max(0.5 * max(x1 - x0, (y1 - y0) / aspect) for (x0, y0), (x1, y1) in extents) + 2.0
    panel_w = WIDTH_CM / COLS
    for k, (r, kind, ((x0, y0), (x1, y1))) in enumerate(zip(runs, kinds, extents), start=1):
        i, j = divmod(k - 1, COLS)
        bottom = snap_top - (i + 1) * (SNAPSHOT_CM + gap_cm) + 0.05
        sub = fig.add_axes(rect(j * panel_w + 0.075, bottom + NOTE_CM, panel_w - 0.15, SNAPSHOT_CM - NOTE_CM))
        plotting.draw_snapshot(r["sites"], int(r["box"]), ax=sub)
        sub.set_xlim(0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half)
        sub.set_ylim(0.5 * (y0 + y1) - aspect * half, 0.5 * (y0 + y1) + aspect * half)
        sub.set_axis_on()
        sub.set_xticks([])
        sub.set_yticks([])
        for spine in sub.spines.values():
            spine.set_visible(True)
            spine.set_linewidth(0.4)
            spine.set_color("0.6")
        sub.set_title(run_title(k, r, convention), fontsize=7, pad=2)
        sub.text(0.0, -0.03, f"{BOX_MARKERS[kind][1]} {int(r['n'])} in {plotting.box_label(int(r['box']))}, "
                 f"{sweeps[kind]} sweeps\n" rf"$\Delta E$ = {gap_to_best_single(r, finite):+.1f} $e_{{\rm bulk}}$",
                 transform=sub.transAxes, fontsize=6, va="top")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.diagram, snakemake.input.continuum[0], snakemake.input.snapshots,  # noqa: F821
             snakemake.input.finite,  # noqa: F821
             snakemake.params.dense, snakemake.params.sweeps, snakemake.params.convention,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
