# Comparison of pre-made aggregates (Figs. 3b, 4a, 4b, S1). Each particle's catalogue of relaxed
# energies is computed once, by one job, and kept as a file; diagrams and figures read them.
rule ansatz_catalogue:
    output:
        "results/ansatz/catalogue/ell{ell}_nu{nu}.npz",
    params:
        ell=lambda w: float(w.ell),
        nu=lambda w: float(w.nu),
        tiling="hexagon",
        **pick(ANSATZ, "eps", "method", "tol", "radius_per_ell", "width_per_ell", "min_radius", "min_width"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/ansatz/catalogue_ell{ell}_nu{nu}.log",
    script:
        "../scripts/ansatz_catalogue.py"


rule ansatz_diagram:
    input:
        lambda w: [catalogue_file(w.ell, nu) for nu in DIAGRAM_NU],
    output:
        "results/ansatz/diagram_ell{ell}.npz",
    params:
        ell=lambda w: float(w.ell),
        nu=DIAGRAM_NU,
        **pick(ANSATZ, "Gamma_max", "Gamma_count"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/ansatz/diagram_ell{ell}.log",
    script:
        "../scripts/ansatz_diagram.py"


rule ansatz_sizes:
    input:
        fiber=[catalogue_file(ell, ANSATZ["fiber_nu"]) for ell in ANSATZ["size_ells"]],
        disk=[catalogue_file(ell, ANSATZ["disk_nu"]) for ell in ANSATZ["size_ells"]],
    output:
        "results/ansatz/sizes.npz",
    params:
        **pick(ANSATZ, "size_Gamma_max", "size_Gamma_count", "size_ells", "fiber_nu", "disk_nu"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/ansatz/sizes.log",
    script:
        "../scripts/ansatz_sizes.py"


rule ansatz_line_tension:
    output:
        "results/ansatz/line_tension.json",
    params:
        **pick(ANSATZ, "edge_ells", "edge_nu", "edge_eps"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/ansatz/line_tension.log",
    script:
        "../scripts/ansatz_line_tension.py"


rule ansatz_shapes:
    output:
        "results/ansatz/shapes.npz",
    params:
        **pick(ANSATZ, "drawing_ell", "drawing_nu", "drawing_eps"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/ansatz/shapes.log",
    script:
        "../scripts/ansatz_shapes.py"


rule fig3_phase_diagrams:
    input:
        diagram=f"results/ansatz/diagram_ell{ANSATZ['fig3b_ell']:g}.npz",
        continuum=rules.continuum_phase_diagram.output,
        snapshots=mc_snapshot_files(),
        finite=fig3_finite_files(),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        # (particles, box) of the dense runs (the disk scan), to mark them apart from the sparse ones.
        dense=(MC["dense_n"], MC["dense_box"]),
        # Anneal length of each box kind, written on its snapshots.
        sweeps=dict(sparse=MC["sweeps"], dense=MC["dense_sweeps"]),
        convention="measured",
    output:
        pdf=f"{FIGURES}/fig3_phase_diagrams.pdf",
        png=figure_png("fig3_phase_diagrams"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig3_phase_diagrams.log",
    script:
        "../../figures/fig3_phase_diagrams.py"


# Fig. 3b's Monte Carlo runs with Gamma read in the supplement's convention (gamma = 4 g/sqrt(3)),
# to compare with the published panels; drawn on our diagram at their Gamma in ours.
rule figX_fig3b_supplement_convention:
    input:
        diagram=f"results/ansatz/diagram_ell{ANSATZ['fig3b_ell']:g}.npz",
        continuum=rules.continuum_phase_diagram.output,
        snapshots=mc_snapshot_files("supplement"),
        finite=fig3_finite_files(),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        dense=(MC["dense_n"], MC["dense_box"]),
        sweeps=dict(sparse=MC["sweeps"], dense=MC["dense_sweeps"]),
        convention="supplement",
    output:
        pdf=f"{FIGURES}/figX_fig3b_supplement_convention.pdf",
        png=figure_png("figX_fig3b_supplement_convention"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_fig3b_supplement_convention.log",
    script:
        "../../figures/fig3_phase_diagrams.py"


rule figS1_ansatz:
    input:
        diagram=f"results/ansatz/diagram_ell{ANSATZ['figS1_ell']:g}.npz",
        continuum=rules.continuum_phase_diagram.output,
    output:
        pdf=f"{FIGURES}/figS1_ansatz.pdf",
        png=figure_png("figS1_ansatz"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS1_ansatz.log",
    script:
        "../../figures/figS1_ansatz.py"


rule fig4a_catalogue:
    input:
        rules.ansatz_shapes.output,
    output:
        pdf=f"{FIGURES}/fig4a_catalogue.pdf",
        png=figure_png("fig4a_catalogue"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig4a_catalogue.log",
    script:
        "../../figures/fig4a_catalogue.py"


rule fig4b_sizes:
    input:
        rules.ansatz_sizes.output,
    output:
        pdf=f"{FIGURES}/fig4b_sizes.pdf",
        png=figure_png("fig4b_sizes"),
        # The collapse in words (the caption's generated part; the gallery shows it with the caption).
        summary=report(f"{FIGURES}/fig4b_sizes_summary.json", caption="../report/fig4b_sizes_summary.rst",
                       category="Main text"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig4b_sizes.log",
    script:
        "../../figures/fig4b_sizes.py"
