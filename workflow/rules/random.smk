# Random-elasticity particles (Figs. 5, 6, S2, S3, S5). The sample of elasticity matrices is drawn
# in batches (matrix i depends only on the seed and i, so batches are independent jobs); a
# summary and a selection are made from all of them; aggregation diagrams are computed for the
# selected particles, a batch per job.
# Names shared with other rules (RANDOM, RANDOM_BATCHES, the diagram files) live in common.smk.

rule random_sample_batch:
    output:
        "results/random/sample/batch{batch}.npz",
    params:
        start=lambda w: int(w.batch) * RANDOM["batch"],
        size=lambda w: min(RANDOM["batch"], RANDOM["draws"] - int(w.batch) * RANDOM["batch"]),
        seed=RANDOM["seed"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/random/sample_batch{batch}.log",
    script:
        "../scripts/random_sample_batch.py"


rule random_summary:
    input:
        [f"results/random/sample/batch{b}.npz" for b in RANDOM_BATCHES],
    output:
        summary="results/random/summary.npz",
        selection="results/random/selection.npz",
    params:
        **pick(RANDOM, "seed", "plotted", "size_particles", "ell_groups", "group_counts", "nu_bins"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/random/summary.log",
    script:
        "../scripts/random_summary.py"


rule random_fits:
    input:
        rules.random_summary.output.summary,
    output:
        "results/random/fits.npz",
    params:
        **pick(RANDOM, "seed", "fits", "fit_eps", "fit_strip_width", "fit_example_ell"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/random/fits.log",
    script:
        "../scripts/random_fits.py"


rule random_diagram_batch:
    input:
        rules.random_summary.output.selection,
    output:
        "results/random/diagrams/{set}_{batch}.npz",
    params:
        batch=lambda w: int(w.batch),
        **pick(RANDOM, "seed", "eps", "diagram_batch", "Gamma_max", "Gamma_count"),
    wildcard_constraints:
        set="sizes|group[0-9]+",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/random/diagram_{set}_{batch}.log",
    script:
        "../scripts/random_diagram_batch.py"


rule fig5_random:
    input:
        summary=rules.random_summary.output.summary,
        fits=rules.random_fits.output,
        sizes=random_diagram_files("sizes"),
    output:
        pdf=f"{FIGURES}/fig5_random.pdf",
        png=figure_png("fig5_random"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig5_random.log",
    script:
        "../../figures/fig5_random.py"


rule figS2_random_sizes:
    input:
        sizes=random_diagram_files("sizes"),
    output:
        pdf=f"{FIGURES}/figS2_random_sizes.pdf",
        png=figure_png("figS2_random_sizes"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS2_random_sizes.log",
    script:
        "../../figures/figS2_random_sizes.py"


rule fig6_random_diagrams:
    input:
        groups=[random_diagram_files(f"group{i}") for i in range(len(RANDOM["group_counts"]))],
    output:
        pdf=f"{FIGURES}/fig6_random_diagrams.pdf",
        png=figure_png("fig6_random_diagrams"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        ell_groups=RANDOM["ell_groups"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig6_random_diagrams.log",
    script:
        "../../figures/fig6_random_diagrams.py"


rule figS3_random_histograms:
    input:
        summary=rules.random_summary.output.summary,
        selection=rules.random_summary.output.selection,
    output:
        pdf=f"{FIGURES}/figS3_random_histograms.pdf",
        png=figure_png("figS3_random_histograms"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        ell_groups=RANDOM["ell_groups"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS3_random_histograms.log",
    script:
        "../../figures/figS3_random_histograms.py"


rule figS5_ell_eigen:
    input:
        summary=rules.random_summary.output.summary,
    output:
        pdf=f"{FIGURES}/figS5_ell_eigen.pdf",
        png=figure_png("figS5_ell_eigen"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS5_ell_eigen.log",
    script:
        "../../figures/figS5_ell_eigen.py"


rule figS4_pseudo_moduli:
    output:
        pdf=f"{FIGURES}/figS4_pseudo_moduli.pdf",
        png=figure_png("figS4_pseudo_moduli"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS4_pseudo_moduli.log",
    script:
        "../../figures/figS4_pseudo_moduli.py"


rule random_ell_definitions:
    output:
        study="results/random/ell_definitions.npz",
        table="results/random/ell_definitions.json",
    params:
        seed=RANDOM["seed"],
        ell_groups=RANDOM["ell_groups"],
        particles=RANDOM["ell_study"]["particles"],
        depths=RANDOM["ell_study"]["depths"],
        eps=RANDOM["ell_study"]["eps"],
        min_shares=RANDOM["ell_study"]["min_shares"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/random/ell_definitions.log",
    script:
        "../scripts/random_ell_definitions.py"


rule figX_ell_definitions:
    input:
        study=rules.random_ell_definitions.output.study,
        table=rules.random_ell_definitions.output.table,
    output:
        pdf=f"{FIGURES}/figX_ell_definitions.pdf",
        png=figure_png("figX_ell_definitions"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        ell_groups=RANDOM["ell_groups"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_ell_definitions.log",
    script:
        "../../figures/figX_ell_definitions.py"
