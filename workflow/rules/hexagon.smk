rule hexagon_aggregates:
    output:
        "results/hexagon/aggregates.npz",
    params:
        **config["hexagon_figure"],  # every key of the section is used
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/hexagon_aggregates.log",
    script:
        "../scripts/hexagon_aggregates.py"


rule fig2_hexagon:
    input:
        rules.hexagon_aggregates.output,
    output:
        pdf=f"{FIGURES}/fig2_hexagon.pdf",
        png=figure_png("fig2_hexagon"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig2_hexagon.log",
    script:
        "../../figures/fig2_hexagon.py"
