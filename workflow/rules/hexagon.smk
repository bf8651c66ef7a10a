rule hexagon_aggregates:
    output:
        "results/hexagon/aggregates.npz",
    params:
        settings=config["hexagon_figure"],
    log:
        "results/logs/hexagon_aggregates.log",
    script:
        "../scripts/hexagon_aggregates.py"


rule fig2_hexagon:
    input:
        rules.hexagon_aggregates.output,
    output:
        pdf=f"{FIGURES}/fig2_hexagon.pdf",
        png=f"{FIGURES}/fig2_hexagon.png",
    log:
        "results/logs/fig2_hexagon.log",
    script:
        "../../figures/fig2_hexagon.py"
