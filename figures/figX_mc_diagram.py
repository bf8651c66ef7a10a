"""Beyond the paper, which calls it too costly: a Monte Carlo phase diagram at ell = 5. Each
marker is one annealing run, coloured by the kind of its largest final aggregate
(montecarlo.classify_aggregate), over the ansatz diagram of Fig. 3b (pale) and the continuum
boundaries (dashed).

A box of a few hundred particles holds neither a bulk nor a fibre wider than it is long, so the
runs are compared with the finite-size prediction too: a band marks where the best single
aggregate of the same n is elongated (ansatz.finite_aggregates), and a hollow marker a run that
ended more than EQUILIBRATED_GAP bulk particle energies above the box's predicted ground state
(the best of ground_states.box_candidates: single aggregates, a fibre wrapping the box, several
aggregates apart or joined by necks, the gas), i.e. not equilibrated; the gaps are in the log of montecarlo_diagram."""
import numpy as np
from matplotlib.lines import Line2D

from pyfrustrate import plotting, topology
from pyfrustrate.ground_states import EQUILIBRATED_GAP, family_structure
from pyfrustrate.io import load_npz, logging_to, save_json
from pyfrustrate.provenance import for_job

MARKERS = {"disk": "o", "fused_disks": "h", "fiber": "s", "bulk": "D", "bulk_with_holes": "^", "gas": "x"}


def draw_elongated_bands(ax, mc):
    """A stripe along each nu row over the Gamma where the best single aggregate is elongated."""
    Gamma = mc["finite_Gamma"]
    for nu, elongated in zip(mc["finite_nu"], mc["finite_elongated"]):
        edges = [i for i in range(1, len(Gamma)) if elongated[i] != elongated[i - 1]]
        starts = ([0] if elongated[0] else []) + [i for i in edges if elongated[i]]
        stops = [i for i in edges if not elongated[i]] + ([len(Gamma)] if elongated[-1] else [])
        for a, b in zip(starts, stops):
            ax.plot([Gamma[a], Gamma[b - 1]], [nu, nu], color=plotting.PHASE_COLORS["fiber"], lw=7, alpha=0.45,
                    solid_capstyle="butt", zorder=5)


def in_ground_structure(mc):
    """Runs whose structure (from their clusters alone) is their box's predicted ground state's:
    aggregates fused by necks are one cluster (``ground_states.family_structure``)."""
    return mc["structure"] == np.array([family_structure(f) for f in mc["ground_family"]])


def merged_where_compact(mc):
    """Runs whose largest aggregate is disks fused by necks, or is called a fibre, where the best
    single aggregate of as many particles is compact: pieces merged, not a fibre phase."""
    return (mc["kind"] == "fused_disks") | ((mc["kind"] == "fiber") & (mc["single_kind"] != "fiber"))


def hollow_markers_explained(mc, n):
    """Caption lines: what the runs that ended above the criterion got wrong, read from their final
    clusters: the structure (one aggregate, several, ...) or, within the right structure, the shape."""
    stuck = mc["gap_ground"] > EQUILIBRATED_GAP
    if not stuck.any():
        return ["Every run ended within the criterion."]
    right = stuck & in_ground_structure(mc)
    # Disks fused by necks are not "pieces merged" where the prediction itself fuses them.
    unrounded = right & merged_where_compact(mc) & ~np.char.startswith(mc["ground_family"].astype(str), "fused")
    rest = right & ~unrounded
    gaps = mc["gap_ground"][rest]
    other = int((stuck & ~right).sum())
    lines = [
        f"Hollow markers ({int(stuck.sum())}): {int(right.sum())} end in their ground state's structure but not its shape: "
        f"{int(unrounded.sum())} disks fused by necks or elongated where the best aggregate of {n} is compact",
        "(pieces merged, not yet rounded)"
        + (f", {int(rest.sum())} of the best aggregate's kind but {gaps.min():.1f}-{gaps.max():.1f} above (outline not yet "
           "relaxed)" if rest.any() else "")
        + (f"; {other} in another structure." if other else "."),
    ]
    short, value = mc["bond_deficit"][stuck], mc["bond_energy"][stuck]
    few = stuck & (mc["bond_deficit"] >= 1) & (mc["bond_deficit"] <= 3)
    worth = f"one bond is worth {value.min():.1f}-{value.max():.1f} bulk particle energies there"
    if few.any():
        lines.append(f"{int(few.sum())} of the {int(stuck.sum())} hold 1-3 bonds fewer than the ground state "
                     f"({int(short.min())} to {int(short.max())} in all), and {worth}:")
        lines.append("the criterion asks for the best outline to within a bond or two.")
    else:  # "0 of the 5 hold 1-3 bonds fewer" would point at a cause none of them has
        lines.append(f"They hold {int(short.min())} to {int(short.max())} bonds fewer than the ground state; {worth}.")
    sides = topology.complete_hexagon_sides(n)
    last_bond = stuck & (mc["bond_deficit"] == 1) & (mc["ground_bonds"] == topology.most_bonds(n))
    if sides and last_bond.any():
        lines.append(f"{int(last_bond.sum())} of the hollow markers miss only the last bond of the complete hexagon of {n} "
                     f"(sides {', '.join(map(str, sides))}), the one outline with the most bonds {n} particles can hold:")
        lines.append("it is favoured over the many outlines one bond short only at temperatures where the runs no "
                     "longer reshape.")
    return lines


def fused_runs_explained(mc, n):
    """Caption lines on the runs within the criterion that end in fused disks, or that the classifier
    calls fibres, where the best single aggregate of ``n`` is compact, one line per group (the shape
    read, and whether the run lies below that aggregate): where (nu, Gamma), how far from that
    aggregate (``gap``) and from the box's predicted ground state (``gap_ground``). A run below the
    best compact aggregate holds a shape that family lacks (the prediction, not the marker, says so);
    one above it may be a wrong prediction, so that line does not excuse it."""
    fused = (mc["gap_ground"] <= EQUILIBRATED_GAP) & merged_where_compact(mc)
    named = mc["kind"] == "fused_disks"
    below = mc["gap"] < 0
    lines = []
    for is_named in (True, False):
        for is_below in (True, False):
            group = np.flatnonzero(fused & (named == is_named) & (below == is_below))
            if not len(group):
                continue
            called = "end in disks fused by necks" if is_named else "are called fibres (asterisk)"
            gap, ground = np.abs(mc["gap"][group]), mc["gap_ground"][group]
            families = sorted({plotting.structure_label(str(mc["ground_family"][k])) for k in group})
            places = ", ".join(f"({mc['nu'][k]:g}, {mc['Gamma'][k]:g})" for k in group)
            count = "One run" if len(group) == 1 else f"{len(group)} runs"
            lines.append(
                f"{count} within the criterion {called} where the best single aggregate of {n} is compact, "
                f"at (ν, Γ) = {places}: {_span(gap)} bulk particle energies {'below' if is_below else 'above'} "
                "that aggregate and "
                f"{_span(ground)} above the box's predicted ground state (predicted: {', '.join(families)})"
                + (": below the best compact aggregate, so the marker reads a shape that family lacks, not a wrong "
                   "prediction." if is_below else "."))
    return lines


def _span(values):
    """'1.2' or '-0.8 to 4.5': the range of a group's values, to one decimal."""
    low, high = f"{float(np.min(values)):.1f}", f"{float(np.max(values)):.1f}"
    return low if low == high else f"{low} to {high}"


def protocol(mc, n):
    """How the runs were made: annealing, then (montecarlo_run.py) low-temperature replica exchange."""
    rounds = np.asarray(mc.get("exchange_rounds", np.zeros(len(mc["Gamma"]))), int)
    if not rounds.any():
        return f"Annealing runs of {n} particles"
    taken = sorted(set(rounds[rounds > 0].tolist()))
    where = "" if rounds.all() else f", at Γ ≥ {np.min(mc['Gamma'][rounds > 0]):g},"
    return (f"Annealing runs of {n} particles, then{where} {'/'.join(map(str, taken))} rounds of replica exchange "
            "at low temperature")


def summary(mc, n) -> str:
    """The runs in numbers, for the caption: how many ended within the criterion and in their
    ground state's structure, the protocol, and what the runs above the criterion got wrong."""
    within = int((mc["gap_ground"] <= EQUILIBRATED_GAP).sum())
    same = int(in_ground_structure(mc).sum())
    counts = (f"{within} of {len(mc['gap_ground'])} runs end within {EQUILIBRATED_GAP:g} bulk particle energies of "
              f"their box's predicted ground state; {same} in its structure. {protocol(mc, n)}.")
    return " ".join([counts, *fused_runs_explained(mc, n), *hollow_markers_explained(mc, n)])


def main(mc_path, diagram_path, continuum_path, outputs, provenance=None, summary_path=None):
    mc = load_npz(mc_path)
    n = int(mc["n"][0])
    width, height = plotting.PAGE_WIDTH_CM, 9.6
    fig = plotting.figure(width, height)
    ax = fig.add_axes([1.3 / width, 0.95 / height, 9.6 / width, 7.3 / height])
    _, phases = plotting.draw_ansatz_diagram(ax, load_npz(diagram_path), load_npz(continuum_path))
    plotting.phase_legend(ax, phases, dashed_continuum=True, ncol=5, title="ansatz diagram (pale)")
    for mesh in ax.collections:
        mesh.set_alpha(0.35)
    draw_elongated_bands(ax, mc)
    # A run the classifier calls a fibre (elongated, without necks) where the best single aggregate
    # of as many particles is compact: disks fused by wide contacts still read as a fibre
    # (montecarlo.analysis.compact_lobes finds only necks of one or two rows; tests/test_figures.py).
    elongated_not_fibre = (mc["kind"] == "fiber") & (mc["single_kind"] != "fiber")
    for nu, G, kind, size, gap, flag in zip(mc["nu"], mc["Gamma"], mc["kind"], mc["size"], mc["gap_ground"],
                                            elongated_not_fibre):
        color = plotting.PHASE_COLORS.get(str(kind), "0.5")
        stuck = gap > EQUILIBRATED_GAP
        ax.plot(G, nu, MARKERS[str(kind)], ms=7, mfc="w" if stuck else color, mec=color if stuck else "k",
                mew=1.4 if stuck else 0.8, zorder=6)
        # The size only where it says something: a largest aggregate short of all n particles.
        label = (f"{size}" if size < n else "") + ("*" if flag else "")
        if label:
            ax.annotate(label, (G, nu), xytext=(5, -9), textcoords="offset points", fontsize=6, zorder=7)
    handles = [Line2D([], [], marker=m, ls="", mfc=plotting.PHASE_COLORS.get(k, "0.5"), mec="k",
                      label=plotting.PHASE_LABELS.get(k, k)) for k, m in MARKERS.items()
               if k in set(mc["kind"].astype(str))]  # a key to what is drawn, not to every kind there is
    handles.append(Line2D([], [], marker="o", ls="", mfc="w", mec="0.3", mew=1.4,
                          label=f"ended > {EQUILIBRATED_GAP:g} bulk particle\nenergies above the box's\n"
                                "predicted ground state"))
    handles.append(Line2D([], [], color=plotting.PHASE_COLORS["fiber"], lw=7, alpha=0.45,
                          label=f"best single aggregate\nof {n} particles is elongated"))
    if elongated_not_fibre.any():
        handles.append(Line2D([], [], ls="", marker="$*$", color="k",
                              label=f"elongated, but the best single\naggregate of {n} is compact"))
    fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(11.6 / width, 8.3 / height),
               title="Monte Carlo runs:\nlargest final aggregate", alignment="left", labelspacing=0.8)
    plotting.save(fig, outputs, provenance)
    # The counts and the protocol go beside the figure, not into it: the caption's generated part
    # (the gallery shows it under the caption; the report lists the file with the figure).
    text = summary(mc, n)
    print(text)
    if summary_path is not None:
        save_json(summary_path, {"summary": text, "runs": int(len(mc["gap_ground"])),
                                 "within": int((mc["gap_ground"] <= EQUILIBRATED_GAP).sum()),
                                 "same_structure": int(in_ground_structure(mc).sum())},
                  provenance=provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.montecarlo[0], snakemake.input.diagram, snakemake.input.continuum[0],  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png], provenance=for_job(snakemake),  # noqa: F821
             summary_path=snakemake.output.summary)  # noqa: F821
