rule chain_profiles:
    output:
        "results/chain/profiles.npz",
    params:
        **config["chain"],  # the chain script uses every key of its section
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/chain_profiles.log",
    script:
        "../scripts/chain_profiles.py"


rule fig1_chain:
    input:
        rules.chain_profiles.output,
    output:
        pdf=f"{FIGURES}/fig1_chain.pdf",
        png=figure_png("fig1_chain"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig1_chain.log",
    script:
        "../../figures/fig1_chain.py"
