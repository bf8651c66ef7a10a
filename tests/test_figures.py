"""The figure check (plotting.check_figure): what a machine can check of a figure at print size.

1. The checker itself, on figures made to pass and made to fail each check (page size, type size,
   overlapping text, text off the page, an empty axes).
2. Figures drawn from scratch by their own scripts on small inputs computed here by the
   workflow's own scripts (Fig. 1: the chain; Fig. S4, which needs none; the continuum diagram,
   panel (a) of Fig. 3), as Snakemake runs them: a ``snakemake`` object with the rule's input,
   output, params and log.
3. Every figure of a workflow build found in ``results/figures/`` (``bash scripts/figures.sh``):
   its page size from the PNG, and the findings ``plotting.save`` stored in it when it drew the
   figure. Skipped on a clone that has not built the figures.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")

from pyfrustrate import plotting  # noqa: E402
from script_jobs import Named, run_script  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BUILT = sorted((ROOT / "results" / "figures").glob("*.png"))


def _figure(width_cm=plotting.COLUMN_WIDTH_CM, height_cm=6.0):
    fig = plotting.figure(width_cm, height_cm)
    ax = fig.add_axes([0.2, 0.2, 0.7, 0.65])
    ax.plot([0, 1], [0, 1])
    ax.set_xlabel(plotting.LABELS["Gamma"])
    ax.set_ylabel(plotting.LABELS["nu"])
    plotting.panel_label(ax, "a")
    return fig, ax


def test_checker_passes_a_good_figure():
    fig, _ = _figure()
    assert plotting.check_figure(fig) == []


def test_checker_finds_a_page_too_wide():
    fig, _ = _figure()
    fig.set_size_inches(24.9 / 2.54, 6.0 / 2.54)  # Fig. S6 as it was
    assert any("wider" in p for p in plotting.check_figure(fig))


def test_checker_finds_small_type():
    fig, ax = _figure()
    ax.tick_params(labelsize=4.5)
    ax.text(0.5, 0.5, "note", fontsize=5, transform=ax.transAxes)
    problems = plotting.check_figure(fig)
    assert any("under 7 pt" in p for p in problems)  # tick labels
    assert any("'note' at 5 pt, under 6 pt" in p for p in problems)


def test_checker_finds_overlapping_text():
    fig, ax = _figure()
    ax.text(0.3, 0.5, "first label", transform=ax.transAxes)
    ax.text(0.35, 0.5, "second label", transform=ax.transAxes)
    assert any("overlap" in p and "first label" in p for p in plotting.check_figure(fig))


def test_checker_finds_text_off_the_page():
    fig, ax = _figure()
    ax.text(1.1, 0.5, "a long note beyond the right edge", transform=ax.transAxes)
    assert any("leaves the page" in p for p in plotting.check_figure(fig))


def _snapshot(note_at):
    """A drawn row of ten hexagons (particle centres at x = 0..9, y = 0) and a note at ``note_at``
    (data coordinates)."""
    from pyfrustrate import topology

    fig = plotting.figure(plotting.COLUMN_WIDTH_CM, 4.0)
    ax = fig.add_axes([0.05, 0.05, 0.9, 0.9])
    angles = np.pi / 6 + np.arange(6) * np.pi / 3
    hexagon = np.column_stack([np.cos(angles), np.sin(angles)]) / np.sqrt(3)
    centres = topology.site_positions(np.column_stack([np.arange(10), np.zeros(10, int)]))
    plotting.draw_hexagons(ax, centres[:, None, :] + hexagon[None])
    ax.set_xlim(-1, 10)
    ax.set_ylim(-3, 3)
    ax.axis("off")
    note = ax.text(*note_at, "a note", ha="center", va="center", fontsize=7)
    return fig, note


def test_checker_finds_text_over_drawn_particles():
    fig, _ = _snapshot((4.5, 0.0))
    assert any("'a note' covers" in p and "drawn particles" in p for p in plotting.check_figure(fig))


def test_checker_passes_text_beside_drawn_particles_or_over_them_on_purpose():
    fig, _ = _snapshot((4.5, -2.2))
    assert plotting.check_figure(fig) == []
    fig, note = _snapshot((4.5, 0.0))
    note.set_gid(plotting.OVER_PARTICLES)
    assert plotting.check_figure(fig) == []


def test_checker_finds_an_empty_axes():
    fig, _ = _figure()
    fig.add_axes([0.6, 0.6, 0.2, 0.2])
    assert any("empty axes" in p for p in plotting.check_figure(fig))


def test_figure_refuses_a_width_between_columns():
    with pytest.raises(ValueError, match="width_cm"):
        plotting.figure(12.0, 9.0)
    with pytest.raises(ValueError, match="height_cm"):
        plotting.figure(plotting.PAGE_WIDTH_CM, 24.0)


def _drawn(tmp_path, name, script, inputs, params=None):
    """Draw ``script`` on ``inputs``; return the findings stored in its PNG and its page size (cm)."""
    png, pdf = tmp_path / f"{name}.png", tmp_path / f"{name}.pdf"
    run_script(script, name, tmp_path, inputs, Named(pdf=str(pdf), png=str(png)), params)
    return _stored_check(png)


def _stored_check(png: Path):
    from PIL import Image

    with Image.open(png) as image:
        assert plotting.CHECK_KEY in image.text, f"{png.name} was drawn without the figure check: rebuild it"
        problems = json.loads(image.text[plotting.CHECK_KEY])
        dpi = image.info.get("dpi", (matplotlib.rcParams["savefig.dpi"],) * 2)[0]
        size_cm = tuple(n / dpi * 2.54 for n in image.size)
    return problems, size_cm


def _assert_print_size(size_cm):
    width, height = size_cm
    assert min(abs(width - plotting.COLUMN_WIDTH_CM), abs(width - plotting.PAGE_WIDTH_CM)) < 0.05, size_cm
    assert height <= plotting.MAX_HEIGHT_CM + 0.05, size_cm


def test_fig1_drawn_from_scratch(tmp_path):
    data = tmp_path / "profiles.npz"
    params = dict(n=40, k=1.0, eps=0.01, profile_kc_over_k=[0.5, 0.05, 0.005], drawing_kc_over_k=0.1,
                  drawing_n=12, drawing_eps=0.12, scan_kc_over_k_min=1e-3, scan_kc_over_k_max=1.0, scan_count=5)
    run_script("workflow/scripts/chain_profiles.py", "chain_profiles", tmp_path, Named([str(data)]), Named([str(data)]),
         params)
    problems, size_cm = _drawn(tmp_path, "fig1_chain", "figures/fig1_chain.py", Named([str(data)]))
    assert problems == []
    _assert_print_size(size_cm)


def test_figS4_drawn_from_scratch(tmp_path):
    """Fig. S4 computes its own inputs (the pseudo-moduli of a simple particle)."""
    problems, size_cm = _drawn(tmp_path, "figS4_pseudo_moduli", "figures/figS4_pseudo_moduli.py", Named())
    assert problems == []
    _assert_print_size(size_cm)


def _load(path: Path):
    """A script of the repository (a figure, a docs extension) imported as a module, by its path."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _figure_script(name: str):
    return _load(ROOT / "figures" / f"{name}.py")


def _gallery():
    return _load(ROOT / "docs" / "_ext" / "figure_gallery.py")


def test_gallery_fills_captions_from_the_profile_that_made_the_figure():
    """The gallery renders a caption's values from config/config.yaml with config/PROFILE.yaml over
    it, as Snakemake's report does from its run's configuration, and leaves out the paragraph
    naming the profile (the gallery states it from the PNG)."""
    import yaml

    gallery = _gallery()
    caption = (ROOT / "workflow" / "report" / "fig3_phase_diagrams.rst").read_text()
    quick = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["montecarlo"]["sweeps"]
    paper = yaml.safe_load((ROOT / "config" / "paper.yaml").read_text())["montecarlo"]["sweeps"]
    assert quick != paper
    for profile, sweeps in ((None, quick), ("quick", quick), ("paper", paper)):
        text = gallery.rendered_caption(caption, ROOT, profile)
        assert "{{" not in text and "{%" not in text and "Made by the" not in text
        assert f"simulated anneal of {sweeps} sweeps" in text, profile
    # Each profile has its own paragraph on how far the runs are from equilibrium.
    assert "smoke test" in gallery.rendered_caption(caption, ROOT, "quick")
    paper_text = gallery.rendered_caption(caption, ROOT, "paper")
    assert "smoke test" not in paper_text and "because the box is finite" in paper_text


def test_gallery_shows_a_rule_summary_as_written(tmp_path):
    """A rule's summary sentence reaches the gallery page as its own text: the characters that are
    reStructuredText markup (``W*``, ``n_mc``, ``|``, backquotes) are escaped, line breaks joined,
    so docutils renders the sentence verbatim and without a warning."""
    import json

    import docutils.core

    gallery = _gallery()
    sentence = "W*_mc = 4 | n_mc in [12, 15] for `seed` 1, *all* 3 seeds <ok>\nsecond line_"
    path = tmp_path / "figX_summary.json"
    path.write_text(json.dumps({"summary": sentence}))
    rest = f"| **In numbers:** {gallery.generated_summary(path)}\n"
    tree = docutils.core.publish_doctree(rest, settings_overrides={"report_level": 5, "warning_stream": False})
    warnings = [node for node in tree.findall() if node.tagname == "system_message"]
    assert not warnings
    assert tree.astext() == "In numbers: " + " ".join(sentence.split())
    # Unescaped, the same sentence does not come through as written.
    raw = docutils.core.publish_doctree(f"| **In numbers:** {sentence}\n",
                                        settings_overrides={"report_level": 5, "warning_stream": False})
    assert raw.astext() != "In numbers: " + " ".join(sentence.split())


@pytest.mark.parametrize("profile", ["quick", "paper"])
def test_figure_records_the_profile_the_gallery_shows(tmp_path, profile):
    """A figure rule passes the configuration's profile as a param; the figure's provenance
    records it, and the documentation's gallery reads it back from the PNG."""
    from pyfrustrate.io import read_provenance

    _drawn(tmp_path, "figS4_pseudo_moduli", "figures/figS4_pseudo_moduli.py", Named(), dict(profile=profile))
    record = read_provenance(tmp_path / "figS4_pseudo_moduli.png")
    assert record["parameters"]["profile"] == profile
    assert record["rule"] == "figS4_pseudo_moduli"
    shown = _gallery().profile_of(tmp_path / "figS4_pseudo_moduli.png")
    other = {"quick": "paper", "paper": "quick"}[profile]
    assert f"**{profile}** profile" in shown and other not in shown


def test_continuum_diagram_drawn_from_scratch(tmp_path):
    """Fig. 3a's panel, at its size in Fig. 3, on a coarse continuum diagram computed here."""
    data = tmp_path / "phase_diagram.npz"
    params = dict(nu_count=41, Gamma_max=1.6, Gamma_count=65)
    run_script("workflow/scripts/continuum_phase_diagram.py", "continuum_phase_diagram", tmp_path, Named(),
         Named([str(data)]), params)
    from pyfrustrate.io import load_npz

    fig = plotting.figure(plotting.COLUMN_WIDTH_CM, 7.0)
    ax = fig.add_axes([1.1 / 8.6, 1.0 / 7.0, 5.0 / 8.6, 5.0 / 7.0])
    images = plotting.draw_continuum_diagram(ax, load_npz(data))
    plotting.size_colorbars(fig, images, (6.3, 1.0, 4.5), gap_cm=1.2)
    plotting.panel_label(ax, "a")
    assert plotting.check_figure(fig) == []


@pytest.mark.skipif(not BUILT, reason="no built figures in results/figures (bash scripts/figures.sh)")
@pytest.mark.parametrize("png", BUILT, ids=[p.stem for p in BUILT])
def test_built_figure(png):
    problems, size_cm = _stored_check(png)
    _assert_print_size(size_cm)
    assert problems == []


def _two_disks(radius, gap_rows=0, box=60):
    """Two hexagonal disks of ``radius`` side by side along a1, touching (``gap_rows`` 0) at the
    ends of their middle rows, placed in the middle of ``box``."""
    from pyfrustrate import topology

    disk = topology.hexagon_sites(radius)
    width = np.ptp(disk[:, 0]) + 1
    return np.unique(np.vstack([disk + 20, disk + (20 + width + gap_rows, 20)]), axis=0)


def test_classifier_tells_disks_fused_by_a_neck_from_a_fibre():
    """Two compact disks fused at a neck are elongated enough to pass the gyration threshold (two
    touching circles of radius r: principal variances 5 r^2/4 and r^2/4, anisotropy sqrt(5) =
    2.24), so the shape alone would call them a fibre; eroding the surface splits them into two
    compact lobes, so they are fused disks. Straight fibres of every width keep at most one lobe."""
    from pyfrustrate import topology
    from pyfrustrate.montecarlo import ELONGATION_THRESHOLD, classify_aggregate
    from pyfrustrate.montecarlo.analysis import compact_lobes

    box = 80
    for radius in (2, 3, 5):
        fused = _two_disks(radius)
        xy = topology.site_positions(fused)
        small, large = np.linalg.eigvalsh(np.cov(xy.T))
        assert np.sqrt(large / small) > ELONGATION_THRESHOLD
        assert classify_aggregate(fused, box) == ("fused_disks", len(fused))
        lobes = compact_lobes(fused)
        assert len(lobes) == 2 and len(lobes[0]) == len(lobes[1]) == len(topology.hexagon_sites(radius - 1))
        assert classify_aggregate(topology.hexagon_sites(radius) + 20, box)[0] == "disk"
    # Three disks touching corner to corner in a triangle: compact as a whole, three lobes.
    disk = topology.hexagon_sites(3)
    ring = np.unique(np.vstack([disk + 20, disk + (27, 20), disk + (20, 27)]), axis=0)
    assert len(compact_lobes(ring)) == 3
    assert classify_aggregate(ring, box)[0] == "fused_disks"
    for rows in (3, 4, 5, 8):
        fibre = np.array([(i - r // 2 + 10, r + 10) for r in range(rows) for i in range(40)])
        assert classify_aggregate(fibre, box, open_networks=False)[0] == "fiber", rows
        assert len(compact_lobes(fibre)) == (rows >= 5)
        # A notch two rows deep leaves a fibre of three or four rows in strips too thin for a lobe.
        notched = np.array([(i - r // 2 + 10, r + 10) for r in range(rows) for i in range(40)
                            if not (i in (19, 20) and r >= rows - 2)])
        if rows <= 4:
            assert compact_lobes(notched) == []
            assert classify_aggregate(notched, box, open_networks=False)[0] == "fiber", rows


def test_mc_diagram_summary_explains_exactly_the_fused_runs_within_the_criterion():
    """figX_mc_diagram's generated summary speaks of a run called a fibre where the best single
    aggregate is compact only when it is within the criterion, and says "reads that shape" only when
    the run lies below that aggregate (otherwise the marker could be a wrong prediction)."""
    figure = _figure_script("figX_mc_diagram")
    from pyfrustrate.ground_states import EQUILIBRATED_GAP

    within, above = 0.5 * EQUILIBRATED_GAP, 2.0 * EQUILIBRATED_GAP
    mc = {"nu": np.array([0.2, 0.5, 0.8, 0.9, 0.3]), "Gamma": np.array([0.2, 0.3, 0.4, 0.5, 0.6]),
          "kind": np.array(["fiber", "fiber", "fiber", "disk", "fused_disks"]), "single_kind": np.array(["disk"] * 5),
          "gap": np.array([-3.0, 1.0, -2.0, -1.0, -0.5]), "gap_ground": np.array([within, within, above, within, within]),
          "ground_family": np.array(["aggregates2", "single", "single", "single", "single"])}
    lines = figure.fused_runs_explained(mc, 200)
    assert len(lines) == 3  # one per group: fused below, called a fibre below, called a fibre above

    def line_of(place):
        found = [line for line in lines if place in line]
        assert len(found) <= 1, place
        return found[0] if found else None

    assert "reads a shape" in line_of("(0.2, 0.2)") and "2 aggregates" in line_of("(0.2, 0.2)")
    assert "asterisk" in line_of("(0.2, 0.2)")
    assert "reads a shape" not in line_of("(0.5, 0.3)") and "one aggregate" in line_of("(0.5, 0.3)")
    assert "fused by necks" in line_of("(0.3, 0.6)") and "asterisk" not in line_of("(0.3, 0.6)")
    assert line_of("(0.8, 0.4)") is None and line_of("(0.9, 0.5)") is None  # above the criterion; a disk


def test_colour_ramps_start_at_a_visible_tint():
    """The smallest size in a phase diagram still reads as its phase, not as the white page."""
    from matplotlib.colors import to_rgb

    for phase in ("fiber", "disk"):
        start = np.array(plotting.shaded_colormap(plotting.PHASE_COLORS[phase])(0.0)[:3])
        assert np.abs(start - 1.0).max() > 0.15, phase
        end = np.array(plotting.shaded_colormap(plotting.PHASE_COLORS[phase])(1.0)[:3])
        assert np.allclose(end, to_rgb(plotting.PHASE_COLORS[phase]), atol=0.01)


def test_cluster_colours_stay_apart_from_phase_colours():
    """A Monte Carlo cluster is never drawn in a colour that means a phase elsewhere."""
    from matplotlib.colors import to_rgb

    phases = [np.array(to_rgb(c)) for c in plotting.PHASE_COLORS.values()]
    for colour in plotting.CLUSTER_COLORS:
        rgb = np.array(to_rgb(colour))
        assert min(np.linalg.norm(rgb - p) for p in phases) > 0.3, colour


def test_contour_labels_sit_at_the_chosen_height_and_skip_squeezed_levels():
    """Fig. 3a's size contours are labelled once each, on the level, at the chosen nu; a level
    confined to a sliver of nu (a corner of the fibre region) gets no label."""
    import matplotlib.pyplot as plt

    x, y = np.linspace(0, 1, 201), np.linspace(0, 1, 201)
    X, Y = np.meshgrid(x, y)
    field = np.where((X < 0.3) & (Y < 0.95), np.nan, X)  # level 0.2 only where y >= 0.95
    fig, ax = plt.subplots()
    try:
        contours = ax.contour(x, y, field, levels=[0.2, 0.5, 0.8])
        places = plotting.contour_label_places(contours, nu=0.4)
    finally:
        plt.close(fig)
    assert len(places) == 2
    assert np.allclose([p[0] for p in places], [0.5, 0.8], atol=0.01)
    assert np.allclose([p[1] for p in places], 0.4, atol=0.01)


def test_fused_predictions_are_one_cluster_in_the_mc_figures():
    """A box whose predicted ground state is aggregates fused by necks (ground_states' fused{m}) is
    one cluster: figX_mc_diagram counts a run in one cluster as in its structure, not one in two,
    and names the prediction in words; figX_mc_scale writes it under its point as fused disks when
    the classifier reads it so, as fused aggregates otherwise."""
    diagram, scale = _figure_script("figX_mc_diagram"), _figure_script("figX_mc_scale")
    mc = {"structure": np.array(["single", "aggregates2", "aggregates2", "single"]),
          "ground_family": np.array(["fused2", "fused2", "aggregates2", "single"])}
    assert diagram.in_ground_structure(mc).tolist() == [True, False, True, True]
    runs = {"ground_family": np.array(["fused4", "fused4", "single"]),
            "verdict_kind_predicted": np.array(["fused_disks", "fiber", "disk"])}
    assert [scale.ground_label(runs, k) for k in range(3)] == ["4 fused disks", "4 fused aggregates", "one aggregate"]
    fused = {"verdict_count": np.array([1, 1]), "verdict_kind": np.array(["fused_disks"] * 2),
             "verdict_count_predicted": np.array([1, 1]), "verdict_kind_predicted": np.array(["fused_disks"] * 2),
             "verdict_width": np.full(2, np.nan), "verdict_width_predicted": np.full(2, np.nan),
             "verdict_lobes": np.array([6.0, 4.0]), "verdict_lobes_predicted": np.array([4.0, 4.0])}
    assert [scale.verdict_text(fused, k) for k in range(2)] == ["6 fused disks (4)", "4 fused disks"]
    nan = np.nan
    mixed = {"verdict_count": np.array([1, 2, 1]), "verdict_kind": np.array(["fused_disks", "disk", "fiber"]),
             "verdict_count_predicted": np.array([1, 1, 1]),
             "verdict_kind_predicted": np.array(["disk", "disk", "fiber"]),
             "verdict_width": np.array([nan, nan, 9.2]), "verdict_width_predicted": np.array([nan, nan, 9.8]),
             "verdict_lobes": np.array([3.0, nan, nan]), "verdict_lobes_predicted": np.full(3, nan)}
    assert [scale.verdict_text(mixed, k) for k in range(3)] == ["3 fused disks (1 disk)", "2 disks (1)",
                                                               "1 fibre, 9 rows (10)"]


def test_mc_validation_fits_the_paper_profiles_two_sided_checks():
    """figX_mc_validation's panel (c) at the paper profile's shape: its eight two-sided checks
    (config/paper.yaml), three seeds each, one a failure, drawn into the figure's own layout
    beside a key of three Gamma pass the figure check: no tick label overlaps another or the key.
    The energies are placeholders; only the page is checked."""
    import yaml

    module = _figure_script("figX_mc_validation")
    paper = yaml.safe_load((ROOT / "config" / "paper.yaml").read_text())["montecarlo"]["validation"]
    words = {("disk", "two_disks"): ("one disk", "two disks"),
             ("disk", "other_kind"): ("one disk", "a fibre wrapping the box"),
             ("fibre", "other_kind"): ("a fibre wrapping the box", "one disk")}
    checks = []
    for k, point in enumerate(paper["two_sided"]):
        predicted, competitor = words[point["scan"], point["competitor"]]
        checks.append(dict(nu=point["nu"], Gamma=point["Gamma"], predicted_state=predicted, competitor_state=competitor,
                           predicted_energy_over_g=[0.0, 0.0, 0.0], competitor_energy_over_g=[3.0 + k, 5.0, -1.0 * (k == 2)],
                           persists=[True, True, k != 2]))
    colors = dict(zip(paper["Gamma"], ("#1b9e77", "#d95f02", "#7570b3")))
    fig, axes, grand_axes, key_axes = module.layout()
    try:
        module.draw_two_sided(axes[2], checks, colors)
        assert len(axes[2].get_xticks()) == 4  # disk vs 2 disks, fibre vs disk at nu 0.9 and 0.6, disk vs fibre
        for ax in axes[:2] + grand_axes:
            ax.plot([0, 1], [0, 1])
        module.draw_key(key_axes, colors, [1, 2, 3])
        assert plotting.check_figure(fig) == []
    finally:
        matplotlib.pyplot.close(fig)
