# The speed/accuracy knob, measured on this machine: relative energy error against time for the
# linear solve, Newton and L-BFGS at several tolerances (benchmarks/bench_tradeoff.py).
rule speed_accuracy:
    input:
        # The benchmark's own code: editing it reruns the measurement.
        script="benchmarks/bench_tradeoff.py",
        common="benchmarks/_common.py",
    output:
        "results/benchmarks/speed_accuracy.csv",
    params:
        quick="--quick" if config["speed_accuracy"]["quick"] else "",
        python=sys.executable,
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/speed_accuracy.log",
    shell:
        "{params.python} benchmarks/bench_tradeoff.py {params.quick} --csv {output} > {log} 2>&1"


rule fig_speed_accuracy:
    input:
        rules.speed_accuracy.output,
    output:
        pdf=f"{FIGURES}/figX_speed_accuracy.pdf",
        png=figure_png("figX_speed_accuracy"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/fig_speed_accuracy.log",
    script:
        "../../figures/figX_speed_accuracy.py"
