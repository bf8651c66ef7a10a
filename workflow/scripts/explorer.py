"""Interactive phase-diagram explorer (issue 34, item 9): one self-contained HTML page, Bokeh
standalone output with its JavaScript inline so that it reads offline. Each distinct winning
aggregate's picture is embedded once (a PNG data URI in the tooltip's formatter), and the points
refer to it by key. For each ell of the inputs, the
catalogue's winners on the (Gamma, nu) plane (Figs. 3b and S1) coloured by phase, with the
continuum's boundaries; hovering a point shows its winning aggregate relaxed and coloured by
per-particle energy, with W* or R* and the winner's energies per particle."""
import base64
import io

import matplotlib.pyplot as plt
import numpy as np
from bokeh.embed import file_html
from bokeh.layouts import column
from bokeh.models import ColumnDataSource, CustomJSHover, Div, HoverTool, TabPanel, Tabs
from bokeh.plotting import figure
from bokeh.resources import INLINE

from pyfrustrate import ansatz, plotting, relaxation
from pyfrustrate.io import atomic_path, load_npz, logging_to
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)


def picture(particle, topology) -> str:
    """The relaxed aggregate coloured by per-particle energy over the bulk's, as a PNG data URI;
    periodic cells drawn over a few periods so that a fibre or a bulk reads as one."""
    images = range(-s["periods"], s["periods"] + 1)
    corners, energies, _ = relaxation.relaxed_drawing(particle, topology, images=images)
    fig, ax = plt.subplots(figsize=(s["picture_inches"], s["picture_inches"]))
    plotting.draw_hexagons(ax, corners, energies / particle.bulk_energy_per_particle, cmap="viridis",
                           linewidth=0.1)
    ax.set_axis_off()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=s["picture_dpi"], bbox_inches="tight", pad_inches=0.02)
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode()


def diagram_panel(diagram_path, catalogue_paths, boundaries):
    """One ell: a point per (nu, Gamma) of the diagram file, with what a hover shows."""
    diagram = load_npz(diagram_path)
    ell, Gamma = float(diagram["ell"]), np.asarray(diagram["Gamma"], float)
    rows = {key: [] for key in ("Gamma", "nu", "phase", "color", "winner", "size", "e_total", "e_def", "image")}
    pictures = {}  # key -> data URI, one per distinct winner
    for i, (nu, path) in enumerate(zip(np.asarray(diagram["nu"], float), catalogue_paths)):
        data = load_npz(path)
        table = ansatz.CatalogueEnergies.from_arrays(data)
        particle = particle_class(str(data["tiling"]) if "tiling" in data else "hexagon")(
            float(data["k"]), float(data["kc"]), float(data["k_area"]), float(data["eps"]))
        # The candidates themselves, to draw a winner: the same catalogue the file was relaxed from.
        sizes = {f: int(table.size[table.family == f].max()) for f in np.unique(table.family)}
        candidates = {(c.family, c.size): c.topology for c in ansatz.catalogue(
            max_radius=sizes.get("disk", 1), max_width=max(v for f, v in sizes.items() if f.startswith("fiber")),
            straight_fibers="fiber_cut0_straight" in sizes)}
        g = ansatz.binding_energy_of(particle, ell, nu, Gamma)
        total = table.total(g)
        drawn = {}
        for j, (family, size) in enumerate(zip(diagram["family"][i], diagram["size"][i])):
            family, size = str(family), int(size)
            index = int(np.flatnonzero((table.family == family) & (table.size == size))[0])
            if (family, size) not in drawn:
                key = f"nu{nu:g}_{family}_{size}"
                pictures[key] = picture(particle, candidates[(family, size)])
                drawn[(family, size)] = key
            phase = str(diagram["phase"][i][j])
            length = float(diagram["length"][i][j])
            rows["Gamma"].append(Gamma[j])
            rows["nu"].append(nu)
            rows["phase"].append(plotting.PHASE_LABELS.get(phase, phase))
            rows["color"].append(plotting.PHASE_COLORS.get(phase, "#888888"))
            rows["winner"].append(family if family in ("bulk", "single") else f"{family}, size {size}")
            rows["size"].append(f"W* = {length:.2f} ({length / ell:.2f} ell)" if family.startswith("fiber")
                                else f"R* = {length:.2f} ({length / ell:.2f} ell)" if family == "disk"
                                else "a single particle" if family == "single" else "no finite size (a bulk)")
            rows["e_total"].append(f"{total[index, j] / particle.bulk_energy_per_particle:.4f}")
            rows["e_def"].append(f"{table.deformation[index] / particle.bulk_energy_per_particle:.4f}")
            rows["image"].append(drawn[(family, size)])
        print(f"ell={ell:g} nu={nu:g}: {len(drawn)} winners drawn")
    # The grid's usual spacing (its last row, nu_max, may sit closer to the one below).
    step_nu = float(np.median(np.diff(np.unique(rows["nu"])))) if len(set(rows["nu"])) > 1 else 0.1
    step_G = Gamma[1] - Gamma[0] if Gamma.size > 1 else 0.1
    plot = figure(width=s["width"], height=s["height"], x_axis_label="Gamma (measured convention, gamma = g)",
                  y_axis_label="nu", title=f"Pre-made aggregates at ell = {ell:g}: the winner at each point",
                  x_range=(-step_G / 2, Gamma[-1] + step_G / 2), tools="pan,wheel_zoom,box_zoom,reset,save")
    points = plot.rect("Gamma", "nu", width=step_G, height=step_nu, fill_color="color", fill_alpha=1.0,
                       line_color=None, source=ColumnDataSource(rows), legend_field="phase")
    for name, G in boundaries.items():
        if name != "line_nu":
            plot.line(G, boundaries["line_nu"], color="white", line_width=2.5, line_dash="dashed")
    plot.add_tools(HoverTool(renderers=[points], tooltips="""
        <div style="width: 230px">
          <img src="@image{custom}" style="max-width: 220px; max-height: 240px; display: block;">
          <b>@winner</b> (@phase)<br>
          nu = @nu{0.00}, Gamma = @Gamma{0.000}<br>
          @size<br>
          total energy per particle: @e_total e_bulk<br>
          deformation energy per particle: @e_def e_bulk
        </div>""", formatters={"@image": CustomJSHover(args=dict(pictures=pictures), code="return pictures[value]")}))
    plot.add_layout(plot.legend[0], "right")
    return TabPanel(child=plot, title=f"ell = {ell:g}")


with logging_to(snakemake.log[0]):  # noqa: F821
    continuum = load_npz(snakemake.input.continuum[0])  # noqa: F821
    kept = plotting.continuum_boundaries(continuum)
    boundaries = {"line_nu": np.asarray(continuum["line_nu"], float), **kept}
    catalogues = list(snakemake.input.catalogues)  # noqa: F821
    per_diagram = len(catalogues) // len(snakemake.input.diagrams)  # noqa: F821
    panels = [diagram_panel(path, catalogues[k * per_diagram:(k + 1) * per_diagram], boundaries)
              for k, path in enumerate(snakemake.input.diagrams)]  # noqa: F821
    provenance = for_job(snakemake)  # noqa: F821
    header = Div(text=(
        "<h2>pyfrustrate: phase-diagram explorer</h2><p>Each square is one point of the numerical "
        "phase diagram of pre-made aggregates (the paper's Figs. 3b and S1): its colour is the "
        "winning aggregate's kind, the dashed white lines are the continuum theory's boundaries. "
        "Hover a square to see the winning aggregate relaxed, coloured by each particle's "
        "deformation energy over the bulk's, with its optimal size and energies.</p>"
        f"<p style='font-size: small'>Made by commit {str(provenance.get('git_commit', '?'))[:10]}"
        f"{' (with uncommitted changes)' if provenance.get('git_dirty') else ''}, pyfrustrate "
        f"{provenance.get('version', '?')}.</p>"), width=s["width"])
    html = file_html(column(header, Tabs(tabs=panels)), INLINE, "pyfrustrate phase-diagram explorer")
    with atomic_path(snakemake.output[0]) as tmp:  # noqa: F821
        with open(tmp, "w") as fh:
            fh.write(html)
