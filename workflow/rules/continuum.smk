rule continuum_phase_diagram:
    output:
        "results/continuum/phase_diagram.npz",
    params:
        **config["continuum"],  # every key of the section is used
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/continuum_phase_diagram.log",
    script:
        "../scripts/continuum_phase_diagram.py"


rule fig3a_continuum:
    input:
        rules.continuum_phase_diagram.output,
    output:
        pdf=f"{FIGURES}/fig3a_continuum.pdf",
        png=figure_png("fig3a_continuum"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig3a_continuum.log",
    script:
        "../../figures/fig3a_continuum.py"
