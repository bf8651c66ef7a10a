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
