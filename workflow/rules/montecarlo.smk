# Monte Carlo annealing of aggregate topologies (Fig. 3b snapshots). One job per run; a run
# interrupted mid-way resumes from its checkpoint.
rule montecarlo_run:
    output:
        "results/montecarlo/runs/{kind}_nu{nu}_G{Gamma}_seed{seed}.npz",
    params:
        nu=lambda w: float(w.nu),
        Gamma=lambda w: float(w.Gamma),
        seed=lambda w: int(w.seed),
        dense=lambda w: w.kind == "dense",
        checkpoint_stem=lambda w: f"results/montecarlo/checkpoints/{w.kind}_nu{w.nu}_G{w.Gamma}_seed{w.seed}",
        settings=MC,
    wildcard_constraints:
        kind="sparse|dense",
    log:
        "results/logs/montecarlo/{kind}_nu{nu}_G{Gamma}_seed{seed}.log",
    script:
        "../scripts/montecarlo_run.py"
